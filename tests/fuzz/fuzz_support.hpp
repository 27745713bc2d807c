#pragma once
/// \file fuzz_support.hpp
/// Shared by the libFuzzer targets: what counts as an expected answer to bad input, invariant
/// checks on accepted input, and per-process scratch files in tmpfs for the path-based readers.
///
/// A reader given arbitrary bytes may only return a value or throw ppohdem::InputError. Any
/// other exception escapes LLVMFuzzerTestOneInput and std::terminate aborts: libFuzzer reports
/// it as a crash, as it does for sanitizer reports, leaks, timeouts and oversized allocations.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "ppohdem/error.hpp"

namespace ppohdem::fuzz {

inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

/// Runs `read()`; an InputError is the documented answer to bad input and is swallowed.
template <class Read>
void run_reader(Read&& read) {
  try {
    read();
  } catch (const InputError&) {
    // expected for malformed input
  }
}

/// An accepted input broke a promise of the reader's interface: report it as a crash.
#define PPOHDEM_FUZZ_CHECK(condition)                                                         \
  do {                                                                                        \
    if (!(condition)) {                                                                       \
      std::fprintf(stderr, "%s:%d: invariant violated: %s\n", __FILE__, __LINE__, #condition); \
      std::abort();                                                                           \
    }                                                                                         \
  } while (false)

/// A directory unique to this process, in tmpfs (/dev/shm) when there is one so that writing
/// each input to a file costs no disk I/O; removed at normal exit.
class ScratchDir {
 public:
  ScratchDir() {
    std::error_code ec;
    const std::filesystem::path shm = "/dev/shm";
    const std::filesystem::path base =
        std::filesystem::is_directory(shm, ec) ? shm : std::filesystem::temp_directory_path();
    dir_ = base / ("ppohdem-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  const std::filesystem::path& path() const { return dir_; }

  /// Writes `bytes` to `name` in the directory (replacing it) and returns its path.
  std::filesystem::path write(const std::string& name, std::string_view bytes) const {
    const std::filesystem::path file = dir_ / name;
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!out) {
      std::fprintf(stderr, "fuzz harness: cannot write %s\n", file.c_str());
      std::abort();
    }
    return file;
  }

 private:
  std::filesystem::path dir_;
};

inline const ScratchDir& scratch() {
  static const ScratchDir dir;
  return dir;
}

}  // namespace ppohdem::fuzz
