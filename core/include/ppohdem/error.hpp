#pragma once
/// \file error.hpp
/// Errors users see. Every bad input becomes an InputError that names the file, the line (or
/// record) and what was expected: "mesh.stl:12: expected 'vertex', found 'endloop'".
#include <cstddef>
#include <stdexcept>
#include <string>

namespace ppohdem {

/// A problem with user input (file contents, command-line values, scene parameters).
class InputError : public std::runtime_error {
 public:
  /// \param file  the file the problem is in (empty if none)
  /// \param line  1-based line number, or 0 if the format has no lines (binary) or it is unknown
  /// \param message what was expected and what was found
  InputError(std::string file, std::size_t line, const std::string& message);
  explicit InputError(const std::string& message) : InputError({}, 0, message) {}

  const std::string& file() const noexcept { return file_; }
  std::size_t line() const noexcept { return line_; }
  const std::string& message() const noexcept { return message_; }

 private:
  std::string file_;
  std::size_t line_;
  std::string message_;
};

}  // namespace ppohdem
