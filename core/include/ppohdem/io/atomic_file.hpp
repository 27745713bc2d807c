#pragma once
/// \file atomic_file.hpp
/// Write a file so that it is never seen half-written: write to "<name>.tmp.<pid>.<n>" in the
/// same directory, flush, then rename over the target (atomic on POSIX). If the writer is
/// destroyed without commit() (an exception while writing), the temp file is removed and
/// any existing target is left untouched.
#include <filesystem>
#include <fstream>

namespace ppohdem {

/// A new temp name "<target>.tmp.<pid>.<n>" beside the target (unique in this process).
std::filesystem::path atomic_temp_path(const std::filesystem::path& target);

class AtomicFileWriter {
 public:
  /// Opens the temp file; throws InputError if the directory does not exist or is not
  /// writable (naming the target path).
  explicit AtomicFileWriter(std::filesystem::path target, bool binary = false);
  ~AtomicFileWriter();
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;

  std::ostream& stream() { return out_; }
  /// Flush, close, check for write errors, rename onto the target. Throws on failure.
  /// The rename is atomic for other processes and survives a crash or SIGKILL of this one.
  /// With sync_to_disk the data are also fsync'ed before the rename and the directory after
  /// it, so the new file survives a power loss or kernel crash too (checkpoints use it).
  void commit(bool sync_to_disk = false);

 private:
  std::filesystem::path target_;
  std::filesystem::path temp_;
  std::ofstream out_;
  bool committed_ = false;
};

}  // namespace ppohdem
