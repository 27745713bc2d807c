#pragma once
// The frame of a test program that mpirun starts on every rank (ppohdem_add_mpi_test,
// tests/CMakeLists.txt): MPI started and finalised, a scratch directory for the rank count, and
// failures that each rank prints and counts, combined over the ranks into the exit code.
#include <cstdio>
#include <filesystem>
#include <string>

#include "ppohdem/comm/comm.hpp"

namespace ppohdem::test {

class MpiCase {
 public:
  MpiCase(int* argc, char*** argv) : environment_(argc, argv) {}

  const Comm& comm() const { return environment_.world(); }
  int rank() const { return comm().rank(); }
  int ranks() const { return comm().size(); }

  /// <build dir>/tests_scratch/<name>/<ranks>: rank 0 empties it and calls `fill(dir)`, and no
  /// rank goes on before that is done (a collective).
  template <class Fill>
  std::filesystem::path scratch(const std::string& name, Fill fill) const {
    const std::filesystem::path dir =
        std::filesystem::path(PPOHDEM_BINARY_DIR) / "tests_scratch" / name / std::to_string(ranks());
    if (rank() == 0) {
      std::filesystem::remove_all(dir);
      std::filesystem::create_directories(dir);
      fill(dir);
    }
    comm().barrier();
    return dir;
  }
  std::filesystem::path scratch(const std::string& name) const {
    return scratch(name, [](const std::filesystem::path&) {});
  }

  /// Prints "rank r: what" and counts a failure of this rank.
  void fail(const std::string& what) {
    std::printf("rank %d: %s\n", rank(), what.c_str());
    ++failures_;
  }
  void expect(bool ok, const std::string& what) {
    if (!ok) fail(what);
  }

  /// The failures of all ranks (a collective: every rank calls it).
  int failures_over_ranks() const { return static_cast<int>(comm().sum_over_ranks(static_cast<double>(failures_))); }
  /// 0 if no rank failed, else 1: main's return value (a collective).
  int exit_code() const { return failures_over_ranks() == 0 ? 0 : 1; }

 private:
  CommEnvironment environment_;
  int failures_ = 0;
};

}  // namespace ppohdem::test
