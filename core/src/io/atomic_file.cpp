#include "ppohdem/io/atomic_file.hpp"

#include <unistd.h>

#include <atomic>
#include <system_error>

#include "ppohdem/error.hpp"

namespace ppohdem {
namespace {
std::atomic<unsigned> g_temp_counter{0};
}

AtomicFileWriter::AtomicFileWriter(std::filesystem::path target, bool binary)
    : target_(std::move(target)) {
  const auto dir = target_.has_parent_path() ? target_.parent_path() : std::filesystem::path(".");
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) {
    throw InputError(target_.string(), 0, "cannot write: directory '" + dir.string() + "' does not exist");
  }
  temp_ = target_;
  temp_ += ".tmp." + std::to_string(::getpid()) + "." + std::to_string(g_temp_counter++);
  out_.open(temp_, binary ? std::ios::out | std::ios::binary | std::ios::trunc : std::ios::out | std::ios::trunc);
  if (!out_) {
    throw InputError(target_.string(), 0, "cannot write: unable to create a file in '" + dir.string() + "'");
  }
}

AtomicFileWriter::~AtomicFileWriter() {
  if (!committed_) {
    out_.close();
    std::error_code ec;
    std::filesystem::remove(temp_, ec);
  }
}

void AtomicFileWriter::commit() {
  out_.flush();
  const bool ok = static_cast<bool>(out_);
  out_.close();
  if (!ok || out_.fail()) {
    throw InputError(target_.string(), 0, "write failed (disk full or I/O error); target left unchanged");
  }
  std::error_code ec;
  std::filesystem::rename(temp_, target_, ec);
  if (ec) {
    throw InputError(target_.string(), 0, "cannot rename temp file into place: " + ec.message());
  }
  committed_ = true;
}

}  // namespace ppohdem
