#pragma once
/// \file comm.hpp
/// The communicator the optimized code talks to, and nothing else: a rank, a size, a barrier and
/// the few collectives the SDF slab decomposition and the DEM domain decomposition need. MPI lives behind it in exactly one file
/// (core/src/comm/mpi_comm.cpp, built only with PPOHDEM_ENABLE_MPI); the serial communicator is
/// real behaviour for one rank (its gather copies), not a no-op (CoMD's parallel.c habit).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <span>
#include <stdexcept>
#include <vector>

namespace ppohdem {

/// A message: raw bytes (packed and unpacked by the caller, e.g. core/src/dem/fast/pack.hpp).
using Bytes = std::vector<unsigned char>;

/// Combines the record `in` into `inout` (both `words` long), as a reduction over ranks does:
/// commutative and associative, so the ranks' records combine in any order to the same result.
using CombineWords = void (*)(const std::int64_t* in, std::int64_t* inout, std::size_t words);

class Comm {
 public:
  virtual ~Comm() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  virtual void barrier() const = 0;
  /// Every rank passes its `local` block; rank 0 receives the blocks concatenated in rank order
  /// (other ranks get an empty vector). Blocks may differ in length.
  virtual std::vector<double> gather_to_root(std::span<const double> local) const = 0;
  /// The same for float blocks.
  virtual std::vector<float> gather_to_root(std::span<const float> local) const = 0;
  /// Maximum of `value` over all ranks, returned on every rank.
  virtual double max_over_ranks(double value) const = 0;
  /// Sum of `value` over all ranks, returned on every rank.
  virtual double sum_over_ranks(double value) const = 0;
  /// Elementwise sum of `values` over all ranks, in place on every rank (exact: integers; the
  /// words of exact sums, ppohdem/dem/exact_sum.hpp). Collective.
  virtual void sum_over_ranks(std::span<std::int64_t> values) const = 0;
  /// Every rank's `record` combined by `combine`, in place on every rank: ONE allreduce of the
  /// record (a fixed size, the same on every rank) with `combine` as its operation: what a DEM
  /// step needs from every rank at once (docs/dem.md "One collective a step"). Collective.
  virtual void combine_over_ranks(std::span<std::int64_t> record, CombineWords combine) const = 0;
  /// Rank 0's `value` on every rank.
  virtual double broadcast_from_root(double value) const = 0;
  /// Personalised all-to-all: `to[r]` (to.size() == size()) goes to rank r; returns `from`
  /// with from[r] = what rank r sent to this rank (empty blocks allowed). Collective.
  virtual std::vector<Bytes> exchange(const std::vector<Bytes>& to) const = 0;
  /// Every rank's block on every rank, in rank order (blocks may differ in length). Collective.
  virtual std::vector<Bytes> allgather(const Bytes& local) const = 0;
  /// Element-wise sum / maximum of `values` over all ranks (the same length on every rank),
  /// returned on every rank. Collective.
  virtual std::vector<double> sum_each_over_ranks(std::vector<double> values) const = 0;
  virtual std::vector<double> max_each_over_ranks(std::vector<double> values) const = 0;
  /// Point-to-point exchange with `peers` only (ascending, without this rank): `to[i]` goes
  /// to peers[i], and the result's [i] is what peers[i] sent. Every peer must list this rank
  /// among its own peers and call this at the same point (the relation is symmetric).
  /// `sizes`: the byte counts to receive, if known (one message per peer each way, none for an
  /// empty block: the sender's block must then be empty too); else the counts are exchanged
  /// first (two, also for empty blocks). Not collective over the other ranks.
  virtual std::vector<Bytes> exchange_with(const std::vector<int>& peers, const std::vector<Bytes>& to,
                                           const std::vector<std::size_t>* sizes = nullptr) const = 0;
  /// exchange_with() with the sizes known, split in two so that the caller can compute while
  /// the messages travel: post_exchange_with() posts the receives and sends (MPI_Irecv,
  /// MPI_Isend) and returns; progress_exchange() lets them move (MPI_Testall: Open MPI moves a
  /// large, rendezvous, message only inside MPI calls); finish_exchange() waits for all of them
  /// (MPI_Waitall), after which the result's `from` holds what exchange_with() would return.
  /// `to` must stay alive and unchanged until finish_exchange(). The same messages as
  /// exchange_with() with `sizes`; not collective. This base does the blocking exchange_with()
  /// at the post (one rank: no peers, nothing to move).
  struct PostedExchange {
    virtual ~PostedExchange() = default;
    std::vector<Bytes> from;  ///< from[i]: what peers[i] sent (complete after finish_exchange)
  };
  virtual std::unique_ptr<PostedExchange> post_exchange_with(const std::vector<int>& peers, const std::vector<Bytes>& to,
                                                             const std::vector<std::size_t>& sizes) const {
    auto posted = std::make_unique<PostedExchange>();
    posted->from = exchange_with(peers, to, &sizes);
    return posted;
  }
  virtual void progress_exchange(PostedExchange& /*posted*/) const {}
  virtual void finish_exchange(PostedExchange& /*posted*/) const {}
  /// Point-to-point messages this rank has sent in exchange() and exchange_with() so far
  /// (exchange(): one count and one block to every other rank, 2 (P - 1); the collectives of
  /// the sums are not counted): the figure of docs/dem.md "Neighbour-only exchanges".
  std::uint64_t messages_sent() const { return messages_sent_; }
  /// Collective operations this rank has entered so far (every MPI collective call: barrier,
  /// reductions, gathers, broadcasts; exchange() counts its two): what a step costs in latency
  /// on many ranks (docs/performance.md "The cost model"). Zero on one rank (no collectives).
  std::uint64_t collectives() const { return collectives_; }
  /// Ends every rank of the program with exit status `code` (MPI_Abort): for an error met by
  /// some ranks only, which would otherwise leave the others waiting in a collective.
  [[noreturn]] virtual void abort(int code) const = 0;

 protected:
  mutable std::uint64_t messages_sent_ = 0;
  mutable std::uint64_t collectives_ = 0;
};

/// One rank: gather returns the block itself, reductions return their argument.
class SerialComm final : public Comm {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  void barrier() const override {}
  std::vector<double> gather_to_root(std::span<const double> local) const override {
    return {local.begin(), local.end()};
  }
  std::vector<float> gather_to_root(std::span<const float> local) const override {
    return {local.begin(), local.end()};
  }
  double max_over_ranks(double value) const override { return value; }
  double sum_over_ranks(double value) const override { return value; }
  void sum_over_ranks(std::span<std::int64_t>) const override {}
  void combine_over_ranks(std::span<std::int64_t>, CombineWords) const override {}
  double broadcast_from_root(double value) const override { return value; }
  /// One rank sends to itself: the block is copied (real behaviour, not a no-op).
  std::vector<Bytes> exchange(const std::vector<Bytes>& to) const override {
    if (to.size() != 1) throw std::invalid_argument("SerialComm::exchange: expected one block (one rank)");
    return {to[0]};
  }
  std::vector<Bytes> allgather(const Bytes& local) const override { return {local}; }
  std::vector<double> sum_each_over_ranks(std::vector<double> values) const override { return values; }
  std::vector<double> max_each_over_ranks(std::vector<double> values) const override { return values; }
  /// One rank has no peers.
  std::vector<Bytes> exchange_with(const std::vector<int>& peers, const std::vector<Bytes>& to,
                                   const std::vector<std::size_t>* /*sizes*/ = nullptr) const override {
    if (!peers.empty() || !to.empty()) throw std::invalid_argument("SerialComm::exchange_with: one rank has no peers");
    return {};
  }
  [[noreturn]] void abort(int code) const override { std::exit(code); }
};

/// True if this build has the MPI communicator (PPOHDEM_ENABLE_MPI).
bool mpi_available();

/// RAII owner of the MPI environment. Constructing it calls MPI_Init_thread (FUNNELED: only the
/// master thread calls MPI; OpenMP threads do not) unless MPI is already initialised; the
/// destructor calls MPI_Finalize if this object initialised it. Without MPI it does nothing and
/// world() is a SerialComm. Create one at the top of main(), before any other use of world().
class CommEnvironment {
 public:
  CommEnvironment(int* argc, char*** argv);
  ~CommEnvironment();
  CommEnvironment(const CommEnvironment&) = delete;
  CommEnvironment& operator=(const CommEnvironment&) = delete;

  /// MPI_COMM_WORLD behind the Comm interface (a SerialComm without MPI or when the program was
  /// not started by mpirun with more than one rank it still works: size() is then 1).
  const Comm& world() const { return *world_; }

 private:
  [[maybe_unused]] bool finalize_ = false;  // used by the MPI build only
  std::unique_ptr<Comm> world_;
};

}  // namespace ppohdem
