#include "ppohdem/io/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <system_error>

#include "ppohdem/error.hpp"

namespace ppohdem {
namespace {
std::atomic<unsigned> g_temp_counter{0};
}

std::filesystem::path atomic_temp_path(const std::filesystem::path& target) {
  std::filesystem::path temp = target;
  temp += ".tmp." + std::to_string(::getpid()) + "." + std::to_string(g_temp_counter++);
  return temp;
}

AtomicFileWriter::AtomicFileWriter(std::filesystem::path target, bool binary)
    : target_(std::move(target)) {
  const auto dir = target_.has_parent_path() ? target_.parent_path() : std::filesystem::path(".");
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) {
    throw InputError(target_.string(), 0, "cannot write: directory '" + dir.string() + "' does not exist");
  }
  temp_ = atomic_temp_path(target_);
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

namespace {
// fsync a file or directory by path (the ofstream has no descriptor to offer) [POSIX].
bool sync_path(const std::filesystem::path& path, bool directory) {
  const int fd = ::open(path.c_str(), directory ? O_RDONLY | O_DIRECTORY : O_RDONLY);
  if (fd < 0) return false;
  const bool ok = ::fsync(fd) == 0;
  ::close(fd);
  return ok;
}
}  // namespace

void AtomicFileWriter::commit(bool sync_to_disk) {
  out_.flush();
  const bool ok = static_cast<bool>(out_);
  out_.close();
  if (!ok || out_.fail() || (sync_to_disk && !sync_path(temp_, false))) {
    throw InputError(target_.string(), 0, "write failed (disk full or I/O error); target left unchanged");
  }
  std::error_code ec;
  std::filesystem::rename(temp_, target_, ec);
  if (ec) {
    throw InputError(target_.string(), 0, "cannot rename temp file into place: " + ec.message());
  }
  committed_ = true;
  if (sync_to_disk) {
    const auto dir = target_.has_parent_path() ? target_.parent_path() : std::filesystem::path(".");
    sync_path(dir, true);  // the rename itself; best effort (some file systems refuse)
  }
}

}  // namespace ppohdem
