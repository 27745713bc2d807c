// Aligned, page-cache-bypassing writes of large files (block_file.hpp).
#include "ppohdem/io/block_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <new>
#include <system_error>

#include "ppohdem/error.hpp"
#include "ppohdem/io/atomic_file.hpp"

namespace ppohdem {
namespace {

// 4 MiB blocks: large enough that each write() costs little, and a multiple of every logical
// block size O_DIRECT may require (512 B to 4 KiB), as is the alignment.
constexpr std::size_t kBlock = std::size_t{4} << 20;
constexpr std::size_t kAlign = 4096;

}  // namespace

BlockFileWriter::BlockFileWriter(std::filesystem::path target, bool bypass_cache) : target_(std::move(target)) {
  const auto dir = target_.has_parent_path() ? target_.parent_path() : std::filesystem::path(".");
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) {
    throw InputError(target_.string(), 0, "cannot write: directory '" + dir.string() + "' does not exist");
  }
  temp_ = atomic_temp_path(target_);
  if (bypass_cache) fd_ = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC | O_DIRECT, 0666);
  direct_ = fd_ >= 0;
  if (fd_ < 0 && (!bypass_cache || errno == EINVAL)) {
    fd_ = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  }
  if (fd_ < 0) throw InputError(target_.string(), 0, "cannot write: unable to create a file in '" + dir.string() + "'");
  buffer_ = static_cast<char*>(std::aligned_alloc(kAlign, kBlock));
  if (buffer_ == nullptr) {
    ::close(fd_);
    ::unlink(temp_.c_str());
    throw std::bad_alloc();
  }
}

BlockFileWriter::~BlockFileWriter() {
  std::free(buffer_);
  if (fd_ >= 0) ::close(fd_);
  if (!committed_) ::unlink(temp_.c_str());
}

void BlockFileWriter::fail(const char* what) const {
  throw InputError(target_.string(), 0, std::string(what) + " (" + std::strerror(errno) + "); target left unchanged");
}

void BlockFileWriter::write(const char* data, std::size_t size) {
  while (size > 0) {
    const std::size_t n = std::min(size, kBlock - used_);
    std::memcpy(buffer_ + used_, data, n);
    used_ += n;
    data += n;
    size -= n;
    if (used_ == kBlock) flush_blocks(false);
  }
}

// Writes the whole aligned blocks of the buffer; with `all`, the unaligned tail too (after
// turning O_DIRECT off, which needs aligned sizes).
void BlockFileWriter::flush_blocks(bool all) {
  const std::size_t aligned = direct_ ? used_ / kAlign * kAlign : used_;
  auto put = [this](const char* p, std::size_t n) {
    while (n > 0) {
      const ssize_t w = ::write(fd_, p, n);
      if (w < 0 && errno == EINTR) continue;
      if (w < 0 && errno == EINVAL && direct_) {  // opened, but this file system refuses it
        if (::fcntl(fd_, F_SETFL, ::fcntl(fd_, F_GETFL) & ~O_DIRECT) != 0) fail("write failed");
        direct_ = false;
        continue;
      }
      if (w <= 0) fail("write failed (disk full or I/O error)");
      p += w;
      n -= static_cast<std::size_t>(w);
    }
  };
  put(buffer_, aligned);
  std::size_t rest = used_ - aligned;
  if (all && rest > 0) {
    if (::fcntl(fd_, F_SETFL, ::fcntl(fd_, F_GETFL) & ~O_DIRECT) != 0) fail("cannot write the file's tail");
    direct_ = false;
    put(buffer_ + aligned, rest);
    rest = 0;
  }
  std::memmove(buffer_, buffer_ + (used_ - rest), rest);
  used_ = rest;
}

void BlockFileWriter::commit(bool sync_to_disk) {
  flush_blocks(true);
  if (sync_to_disk && ::fsync(fd_) != 0) fail("write failed (fsync)");
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) fail("write failed (close)");
  std::error_code ec;
  std::filesystem::rename(temp_, target_, ec);
  if (ec) throw InputError(target_.string(), 0, "cannot rename temp file into place: " + ec.message());
  committed_ = true;
  if (sync_to_disk) {
    const auto dir = target_.has_parent_path() ? target_.parent_path() : std::filesystem::path(".");
    const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
    if (dfd >= 0) {
      (void)::fsync(dfd);  // the rename itself; best effort (some file systems refuse)
      ::close(dfd);
    }
  }
}

}  // namespace ppohdem
