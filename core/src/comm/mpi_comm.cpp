/// \file mpi_comm.cpp
/// The ONLY file that includes <mpi.h>. MpiComm wraps MPI_COMM_WORLD behind the Comm interface.
#include <mpi.h>

#include <limits>
#include <stdexcept>
#include <string>

#include "ppohdem/comm/comm.hpp"

namespace ppohdem {

namespace {

void check(int code, const char* what) {
  if (code != MPI_SUCCESS) throw std::runtime_error(std::string("MPI error in ") + what);
}

int to_int_count(std::size_t n) {
  if (n > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    throw std::runtime_error("MPI gather: block of " + std::to_string(n) + " values exceeds INT_MAX");
  }
  return static_cast<int>(n);
}

class MpiComm final : public Comm {
 public:
  int rank() const override {
    int r = 0;
    check(MPI_Comm_rank(MPI_COMM_WORLD, &r), "MPI_Comm_rank");
    return r;
  }
  int size() const override {
    int s = 1;
    check(MPI_Comm_size(MPI_COMM_WORLD, &s), "MPI_Comm_size");
    return s;
  }
  void barrier() const override { check(MPI_Barrier(MPI_COMM_WORLD), "MPI_Barrier"); }

  std::vector<double> gather_to_root(std::span<const double> local) const override {
    return gather<double>(local, MPI_DOUBLE);
  }
  std::vector<float> gather_to_root(std::span<const float> local) const override {
    return gather<float>(local, MPI_FLOAT);
  }
  double max_over_ranks(double value) const override { return reduce(value, MPI_MAX); }
  double sum_over_ranks(double value) const override { return reduce(value, MPI_SUM); }
  double broadcast_from_root(double value) const override {
    check(MPI_Bcast(&value, 1, MPI_DOUBLE, 0, MPI_COMM_WORLD), "MPI_Bcast");
    return value;
  }

 private:
  double reduce(double value, MPI_Op op) const {
    double result = 0.0;
    check(MPI_Allreduce(&value, &result, 1, MPI_DOUBLE, op, MPI_COMM_WORLD), "MPI_Allreduce");
    return result;
  }

  template <typename T>
  std::vector<T> gather(std::span<const T> local, MPI_Datatype type) const {
    const int ranks = size();
    const int me = rank();
    const int count = to_int_count(local.size());
    std::vector<int> counts(static_cast<std::size_t>(ranks), 0);
    check(MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD), "MPI_Gather");
    std::vector<int> offsets(static_cast<std::size_t>(ranks), 0);
    std::vector<T> all;
    if (me == 0) {
      std::size_t total = 0;
      for (int r = 0; r < ranks; ++r) {
        offsets[static_cast<std::size_t>(r)] = to_int_count(total);
        total += static_cast<std::size_t>(counts[static_cast<std::size_t>(r)]);
      }
      to_int_count(total);
      all.resize(total);
    }
    check(MPI_Gatherv(local.data(), count, type, all.data(), counts.data(), offsets.data(), type, 0,
                      MPI_COMM_WORLD),
          "MPI_Gatherv");
    return all;
  }
};

}  // namespace

bool mpi_available() { return true; }

CommEnvironment::CommEnvironment(int* argc, char*** argv) {
  int initialised = 0;
  check(MPI_Initialized(&initialised), "MPI_Initialized");
  if (!initialised) {
    int provided = 0;
    check(MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
    finalize_ = true;
  }
  world_ = std::make_unique<MpiComm>();
}

CommEnvironment::~CommEnvironment() {
  if (finalize_) {
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (!finalized) MPI_Finalize();
  }
}

}  // namespace ppohdem
