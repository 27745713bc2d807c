/// \file mpi_comm.cpp
/// The ONLY file that includes <mpi.h>. MpiComm wraps MPI_COMM_WORLD behind the Comm interface.
#include <mpi.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
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

/// The combine function of the allreduce in progress (combine_over_ranks): only the master
/// thread calls MPI (MPI_THREAD_FUNNELED), so one slot serves.
CombineWords current_combine = nullptr;

/// The MPI operation behind combine_over_ranks: `len` records of the contiguous type `type`.
void apply_combine(void* in, void* inout, int* len, MPI_Datatype* type) {
  int bytes = 0;
  MPI_Type_size(*type, &bytes);
  const auto words = static_cast<std::size_t>(bytes) / sizeof(std::int64_t);
  const auto* from = static_cast<const std::int64_t*>(in);
  auto* to = static_cast<std::int64_t*>(inout);
  for (int k = 0; k < *len; ++k) current_combine(from + k * words, to + k * words, words);
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
  void barrier() const override {
    ++collectives_;
    check(MPI_Barrier(MPI_COMM_WORLD), "MPI_Barrier");
  }

  std::vector<double> gather_to_root(std::span<const double> local) const override {
    return gather<double>(local, MPI_DOUBLE);
  }
  std::vector<float> gather_to_root(std::span<const float> local) const override {
    return gather<float>(local, MPI_FLOAT);
  }
  double max_over_ranks(double value) const override { return reduce(value, MPI_MAX); }
  double sum_over_ranks(double value) const override { return reduce(value, MPI_SUM); }
  void sum_over_ranks(std::span<std::int64_t> values) const override {
    ++collectives_;
    check(MPI_Allreduce(MPI_IN_PLACE, values.data(), to_int_count(values.size()), MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD),
          "MPI_Allreduce");
  }
  // The record is ONE element of a contiguous type, so that no algorithm of the allreduce cuts
  // it into pieces (a segmented ring would otherwise apply the operation to parts of records).
  // The type and the operation are made once (a record keeps its size for a run) and kept until
  // MPI_Finalize, which frees them: this object outlives it (CommEnvironment).
  void combine_over_ranks(std::span<std::int64_t> record, CombineWords combine) const override {
    ++collectives_;
    if (combine_op_ == MPI_OP_NULL) check(MPI_Op_create(&apply_combine, /*commute=*/1, &combine_op_), "MPI_Op_create");
    if (record_words_ != record.size()) {
      if (record_type_ != MPI_DATATYPE_NULL) check(MPI_Type_free(&record_type_), "MPI_Type_free");
      check(MPI_Type_contiguous(to_int_count(record.size()), MPI_INT64_T, &record_type_), "MPI_Type_contiguous");
      check(MPI_Type_commit(&record_type_), "MPI_Type_commit");
      record_words_ = record.size();
    }
    current_combine = combine;
    const int code = MPI_Allreduce(MPI_IN_PLACE, record.data(), 1, record_type_, combine_op_, MPI_COMM_WORLD);
    current_combine = nullptr;
    check(code, "MPI_Allreduce");
  }
  double broadcast_from_root(double value) const override {
    ++collectives_;
    check(MPI_Bcast(&value, 1, MPI_DOUBLE, 0, MPI_COMM_WORLD), "MPI_Bcast");
    return value;
  }

  // Counts first (MPI_Alltoall), then the bytes (MPI_Alltoallv). Every rank takes part even
  // with nothing to send; for the few ranks of this machine the dense count exchange is cheap.
  std::vector<Bytes> exchange(const std::vector<Bytes>& to) const override {
    const int ranks = size();
    if (to.size() != static_cast<std::size_t>(ranks)) throw std::runtime_error("exchange: one block per rank expected");
    std::vector<int> send_counts(static_cast<std::size_t>(ranks)), recv_counts(static_cast<std::size_t>(ranks));
    std::vector<int> send_offsets(static_cast<std::size_t>(ranks)), recv_offsets(static_cast<std::size_t>(ranks));
    std::size_t send_total = 0;
    for (std::size_t r = 0; r < to.size(); ++r) {
      send_counts[r] = to_int_count(to[r].size());
      send_offsets[r] = to_int_count(send_total);
      send_total += to[r].size();
    }
    collectives_ += 2;  // the counts' MPI_Alltoall and the bytes' MPI_Alltoallv
    check(MPI_Alltoall(send_counts.data(), 1, MPI_INT, recv_counts.data(), 1, MPI_INT, MPI_COMM_WORLD),
          "MPI_Alltoall");
    std::size_t recv_total = 0;
    for (std::size_t r = 0; r < recv_counts.size(); ++r) {
      recv_offsets[r] = to_int_count(recv_total);
      recv_total += static_cast<std::size_t>(recv_counts[r]);
    }
    Bytes send(send_total), recv(recv_total);
    for (std::size_t r = 0; r < to.size(); ++r) {
      std::copy(to[r].begin(), to[r].end(), send.begin() + send_offsets[r]);
    }
    check(MPI_Alltoallv(send.data(), send_counts.data(), send_offsets.data(), MPI_BYTE, recv.data(),
                        recv_counts.data(), recv_offsets.data(), MPI_BYTE, MPI_COMM_WORLD),
          "MPI_Alltoallv");
    messages_sent_ += 2 * static_cast<std::uint64_t>(ranks - 1);
    std::vector<Bytes> from(static_cast<std::size_t>(ranks));
    for (std::size_t r = 0; r < from.size(); ++r) {
      from[r].assign(recv.begin() + recv_offsets[r], recv.begin() + recv_offsets[r] + recv_counts[r]);
    }
    return from;
  }

  std::vector<double> sum_each_over_ranks(std::vector<double> values) const override {
    return reduce_each(std::move(values), MPI_SUM);
  }
  std::vector<double> max_each_over_ranks(std::vector<double> values) const override {
    return reduce_each(std::move(values), MPI_MAX);
  }

  // Nonblocking sends and receives with the peers (tag 1: counts, tag 2: bytes); a rank
  // talks to its peers only, so the cost does not grow with the number of ranks.
  std::vector<Bytes> exchange_with(const std::vector<int>& peers, const std::vector<Bytes>& to,
                                   const std::vector<std::size_t>* sizes) const override {
    if (to.size() != peers.size()) throw std::runtime_error("exchange_with: one block per peer expected");
    const std::size_t n = peers.size();
    std::vector<std::uint64_t> recv_counts(n, 0), send_counts(n, 0);
    std::vector<MPI_Request> requests;
    requests.reserve(2 * n);
    if (sizes != nullptr) {
      if (sizes->size() != n) throw std::runtime_error("exchange_with: one size per peer expected");
      for (std::size_t i = 0; i < n; ++i) recv_counts[i] = (*sizes)[i];
    } else {
      for (std::size_t i = 0; i < n; ++i) {
        send_counts[i] = to[i].size();
        requests.emplace_back();
        check(MPI_Irecv(&recv_counts[i], 1, MPI_UINT64_T, peers[i], 1, MPI_COMM_WORLD, &requests.back()), "MPI_Irecv");
      }
      for (std::size_t i = 0; i < n; ++i) {
        requests.emplace_back();
        check(MPI_Isend(&send_counts[i], 1, MPI_UINT64_T, peers[i], 1, MPI_COMM_WORLD, &requests.back()), "MPI_Isend");
      }
      check(MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE), "MPI_Waitall");
      messages_sent_ += n;
      requests.clear();
    }
    // With the sizes known, an empty block is neither sent nor awaited (both sides know it is
    // empty); with the counts exchanged every block goes, so that the counts are matched.
    std::vector<Bytes> from(n);
    post_blocks(peers, to, recv_counts, /*tag=*/2, /*skip_empty=*/sizes != nullptr, from, requests);
    check(MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE), "MPI_Waitall");
    return from;
  }

  /// The requests of a posted exchange; tag 3, so that they never match exchange_with's.
  struct MpiPostedExchange final : PostedExchange {
    std::vector<MPI_Request> requests;
  };

  std::unique_ptr<PostedExchange> post_exchange_with(const std::vector<int>& peers, const std::vector<Bytes>& to,
                                                     const std::vector<std::size_t>& sizes) const override {
    const std::size_t n = peers.size();
    if (to.size() != n || sizes.size() != n) throw std::runtime_error("post_exchange_with: one block and one size per peer expected");
    auto posted = std::make_unique<MpiPostedExchange>();
    posted->from.resize(n);
    posted->requests.reserve(2 * n);
    // As exchange_with with the sizes known: no empty blocks.
    post_blocks(peers, to, sizes, /*tag=*/3, /*skip_empty=*/true, posted->from, posted->requests);
    return posted;
  }
  void progress_exchange(PostedExchange& posted) const override {
    auto& requests = static_cast<MpiPostedExchange&>(posted).requests;
    int done = 0;
    check(MPI_Testall(static_cast<int>(requests.size()), requests.data(), &done, MPI_STATUSES_IGNORE), "MPI_Testall");
  }
  void finish_exchange(PostedExchange& posted) const override {
    auto& requests = static_cast<MpiPostedExchange&>(posted).requests;
    check(MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE), "MPI_Waitall");
    requests.clear();
  }

  [[noreturn]] void abort(int code) const override {
    MPI_Abort(MPI_COMM_WORLD, code);
    std::abort();  // MPI_Abort does not return; in case it does
  }

  std::vector<Bytes> allgather(const Bytes& local) const override {
    const int ranks = size();
    int count = to_int_count(local.size());
    std::vector<int> counts(static_cast<std::size_t>(ranks)), offsets(static_cast<std::size_t>(ranks));
    collectives_ += 2;  // the counts' MPI_Allgather and the bytes' MPI_Allgatherv
    check(MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD), "MPI_Allgather");
    std::size_t total = 0;
    for (std::size_t r = 0; r < counts.size(); ++r) {
      offsets[r] = to_int_count(total);
      total += static_cast<std::size_t>(counts[r]);
    }
    Bytes all(total);
    check(MPI_Allgatherv(local.data(), count, MPI_BYTE, all.data(), counts.data(), offsets.data(), MPI_BYTE,
                         MPI_COMM_WORLD),
          "MPI_Allgatherv");
    std::vector<Bytes> blocks(static_cast<std::size_t>(ranks));
    for (std::size_t r = 0; r < blocks.size(); ++r) {
      blocks[r].assign(all.begin() + offsets[r], all.begin() + offsets[r] + counts[r]);
    }
    return blocks;
  }

 private:
  /// The receives of from[i] (counts[i] bytes from peers[i]) and the sends of to[i], with `tag`,
  /// appended to `requests`; with skip_empty, an empty block is neither sent nor awaited.
  template <class Count>
  void post_blocks(const std::vector<int>& peers, const std::vector<Bytes>& to, const std::vector<Count>& counts, int tag,
                   bool skip_empty, std::vector<Bytes>& from, std::vector<MPI_Request>& requests) const {
    const std::size_t n = peers.size();
    for (std::size_t i = 0; i < n; ++i) {
      from[i].resize(static_cast<std::size_t>(counts[i]));
      if (skip_empty && from[i].empty()) continue;
      requests.emplace_back();
      check(MPI_Irecv(from[i].data(), to_int_count(from[i].size()), MPI_BYTE, peers[i], tag, MPI_COMM_WORLD,
                      &requests.back()),
            "MPI_Irecv");
    }
    for (std::size_t i = 0; i < n; ++i) {
      if (skip_empty && to[i].empty()) continue;
      requests.emplace_back();
      check(MPI_Isend(to[i].data(), to_int_count(to[i].size()), MPI_BYTE, peers[i], tag, MPI_COMM_WORLD,
                      &requests.back()),
            "MPI_Isend");
      ++messages_sent_;
    }
  }

  mutable MPI_Op combine_op_ = MPI_OP_NULL;                ///< combine_over_ranks' operation
  mutable MPI_Datatype record_type_ = MPI_DATATYPE_NULL;  ///< its record type, of record_words_
  mutable std::size_t record_words_ = 0;

  double reduce(double value, MPI_Op op) const {
    double result = 0.0;
    ++collectives_;
    check(MPI_Allreduce(&value, &result, 1, MPI_DOUBLE, op, MPI_COMM_WORLD), "MPI_Allreduce");
    return result;
  }

  std::vector<double> reduce_each(std::vector<double> values, MPI_Op op) const {
    std::vector<double> result(values.size());
    ++collectives_;
    check(MPI_Allreduce(values.data(), result.data(), to_int_count(values.size()), MPI_DOUBLE, op, MPI_COMM_WORLD),
          "MPI_Allreduce");
    return result;
  }

  template <typename T>
  std::vector<T> gather(std::span<const T> local, MPI_Datatype type) const {
    const int ranks = size();
    const int me = rank();
    const int count = to_int_count(local.size());
    std::vector<int> counts(static_cast<std::size_t>(ranks), 0);
    collectives_ += 2;  // the counts' MPI_Gather and the values' MPI_Gatherv
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

namespace {

/// True when a process manager (mpirun/mpiexec of Open MPI or MPICH, srun) started this
/// process: they set these variables. A program started on its own is one rank, and MPI_Init
/// would only start Open MPI's singleton daemon (orted), which then polls on one of the cores
/// the computation uses (docs/performance.md "No MPI_Init without mpirun").
bool started_by_a_process_manager() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE", "MPI_LOCALNRANKS"}) {
    if (std::getenv(name) != nullptr) return true;
  }
  return false;
}

}  // namespace

CommEnvironment::CommEnvironment(int* argc, char*** argv) {
  int initialised = 0;
  check(MPI_Initialized(&initialised), "MPI_Initialized");
  if (!initialised && !started_by_a_process_manager()) {
    world_ = std::make_unique<SerialComm>();  // one rank, without MPI
    return;
  }
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
