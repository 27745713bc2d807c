#pragma once
/// \file block_file.hpp
/// A large output file written in aligned blocks that bypass the page cache (O_DIRECT), with
/// the same promise as AtomicFileWriter (atomic_file.hpp): written to "<name>.tmp.<pid>.<n>",
/// renamed over the target by commit(), removed if never committed.
///
/// Why: on the development VM buffered writes of a new large file are several times slower
/// than the same bytes written with O_DIRECT from one reused buffer (docs/performance.md
/// "I/O: particle files"). File systems without O_DIRECT (tmpfs before
/// Linux 6.6) get plain buffered writes; so does the unaligned tail of the file.
#include <cstddef>
#include <filesystem>

namespace ppohdem {

class BlockFileWriter {
 public:
  /// Opens the temp file; throws InputError naming the target if it cannot. With
  /// bypass_cache false, plain buffered writes (the path of file systems without O_DIRECT).
  explicit BlockFileWriter(std::filesystem::path target, bool bypass_cache = true);
  ~BlockFileWriter();
  BlockFileWriter(const BlockFileWriter&) = delete;
  BlockFileWriter& operator=(const BlockFileWriter&) = delete;

  /// Appends `size` bytes (buffered; full blocks go to the file).
  void write(const char* data, std::size_t size);
  /// Writes the rest, optionally fsyncs (file, then the directory after the rename), closes
  /// and renames onto the target. Throws InputError on any failure (target unchanged).
  void commit(bool sync_to_disk = false);
  /// True if the file was opened with O_DIRECT (information, for tests and reports).
  bool direct() const { return direct_; }

 private:
  void flush_blocks(bool all);
  [[noreturn]] void fail(const char* what) const;

  std::filesystem::path target_;
  std::filesystem::path temp_;
  int fd_ = -1;
  bool direct_ = false;
  bool committed_ = false;
  char* buffer_ = nullptr;  // kBlock bytes, aligned for O_DIRECT
  std::size_t used_ = 0;
};

}  // namespace ppohdem
