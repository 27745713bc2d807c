#include "ppohdem/error.hpp"

namespace ppohdem {
namespace {
std::string compose(const std::string& file, std::size_t line, const std::string& message) {
  std::string where = file;
  if (line > 0) {
    where.append(where.empty() ? "line " : ":");
    where.append(std::to_string(line));
  }
  return where.empty() ? message : where + ": " + message;
}
}  // namespace

InputError::InputError(std::string file, std::size_t line, const std::string& message)
    : std::runtime_error(compose(file, line, message)),
      file_(std::move(file)),
      line_(line),
      message_(message) {}

}  // namespace ppohdem
