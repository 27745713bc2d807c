#pragma once
// The state of the fast engine (structure of arrays, cell-sorted) and its force kernel
// interface. Private to core/src/dem/fast. Formulas: ppohdem/dem/contact_force.hpp; the
// divergences from the reference engine are listed in ppohdem/dem/fast/fast_engine.hpp.
#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "ppohdem/dem/boundary.hpp"
#include "ppohdem/dem/contact_force.hpp"
#include "ppohdem/dem/engine.hpp"
#include "ppohdem/dem/exact_sum.hpp"
#include "ppohdem/dem/fast/fast_engine.hpp"
#include "spring_pool.hpp"

#ifdef PPOHDEM_WITH_OPENMP
#include <omp.h>
#define PPOHDEM_OMP(x) _Pragma(#x)
#else
#define PPOHDEM_OMP(x)
#endif

namespace ppohdem::dem::fast {

/// Below this many particles the loops run on one thread: a parallel region costs more than
/// the work (results are the same either way).
constexpr std::size_t kParallelMin = 1024;

inline int max_threads() {
#ifdef PPOHDEM_WITH_OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}
inline int thread_id() {
#ifdef PPOHDEM_WITH_OPENMP
  return omp_get_thread_num();
#else
  return 0;
#endif
}

/// One particle-boundary contact of the last evaluation (sorted by (particle, boundary, feature)).
struct BoundaryRecord {
  std::uint32_t particle = 0;  ///< storage (cell-sorted) index
  std::uint32_t boundary = 0;  ///< index in SimulationSetup::boundaries
  std::uint32_t feature = 0;   ///< the boundary's feature (boundary.hpp FeatureContact; 0: its only contact)
  TangentialSpring spring;     ///< friction only
  Vec3 force = Vec3::Zero();   ///< contact force on the particle [N]
  Vec3 point = Vec3::Zero();   ///< contact point [m]
  Vec3 rolling = Vec3::Zero(); ///< rolling torque on the particle (FastState::rolling) [N m]
};

/// A particle's records are in this order: by boundary, then by feature.
inline std::uint64_t record_key(std::size_t boundary, std::uint32_t feature) {
  return (static_cast<std::uint64_t>(boundary) << 32) | feature;
}
inline std::uint64_t record_key(const BoundaryRecord& r) { return record_key(r.boundary, r.feature); }

/// One entry of a chunk's pair list (frictional kernels, force_pairs.hpp): a touching
/// pair that the chunk's particle evaluates, or a contact that ended (its stored energy is lost).
/// Entries are in the order in which the particle books them (its slot order).
struct PairEntry {
  enum Kind : std::uint32_t { kContact, kContactUpper };
  std::uint32_t i = 0;     ///< storage index of the evaluating particle
  std::uint32_t j = 0;     ///< storage index of the partner
  std::uint32_t code = 0;  ///< spring code of a contact
  Kind kind = kContact;    ///< kContactUpper: the partner's id is above i's (energy and count here)
  double elastic = 0.0;     ///< contact: energy stored in it now [J]
  double dissipated = 0.0;  ///< contact: dissipated this step [J]
  double overlap = 0.0;     ///< contact: delta [m]
};

/// Storage for a chunk's contacts (the entries the contact law evaluates); the kernel sizes it
/// for the chunk's slots and counts the valid entries itself.
struct PairBatch {
  std::vector<PairEntry> entries;
};

/// What one range of particles produced in a force evaluation (concatenated in range order,
/// which is storage order: the ranges are contiguous and ascending).
/// One cache line or more of its own (alignas(64)): each thread appends to its records and
/// spring lists, whose sizes live here, while the neighbouring thread reads its own members.
struct alignas(64) ThreadOutput {
  std::vector<BoundaryRecord> records;
  std::vector<std::uint32_t> newly_escaped;  ///< storage indices
  std::optional<LargestOverlap> deepest;     ///< of this thread's contacts
  std::size_t base = 0;                      ///< offset of `records` in the merged records
  double screen = 0.0;  ///< the sum of close_kick's screens over this range's particles
  double drift = 0.0;   ///< the largest next_drift of this range's particles (predict_drift)
  /// Spring codes of this range's contacts that ended since the pools were laid out: reused
  /// for its next new contacts, so a bed whose contacts open and close between list builds
  /// does not grow its pools (friction only; emptied by lay_out_springs).
  std::vector<std::uint32_t> free_springs;
  PairBatch batch;  ///< the current chunk's pairs (frictional kernels; reused storage)
  std::vector<FeatureContact> touching;  ///< one boundary's contacts (force_boundaries.hpp; reused)
  std::size_t skipped_screens = 0;  ///< particles whose slots this range did not screen (screen_gap)
  /// The exact sums of this range's particles' energy rates in this evaluation (kEnergy):
  /// dissipated [J], boundary work [J], boundary power [W] (docs/dem.md "Energy book-keeping").
  std::array<ExactSum, 3> rates;
  /// This range's nonzero dissipation rates not yet in rates[0], one a particle: added in
  /// lanes when the buffer is full and at the end of each pair pass (add_dissipation_buffer),
  /// the same words as one exact add each at a fraction of the cost (docs/performance.md
  /// "Energy book-keeping").
  std::array<double, 1024> dissipation_buffer;
  std::size_t buffered = 0;
  void add_dissipation_buffer() {
    add_terms_overwriting(rates[0], std::span<double>(dissipation_buffer.data(), buffered));
    buffered = 0;
  }
};

/// Deterministic choice of the deeper contact: larger ratio, ties to the smaller
/// (boundary, id_a, id_b), so the answer does not depend on the thread count.
inline void keep_deeper(std::optional<LargestOverlap>& deepest, const LargestOverlap& c) {
  if (!deepest || c.ratio > deepest->ratio ||
      (c.ratio == deepest->ratio &&
       std::tuple(c.boundary, c.id_a, c.id_b) < std::tuple(deepest->boundary, deepest->id_a, deepest->id_b))) {
    deepest = c;
  }
}

/// One particle pair's contact as evaluated by its lower-id side in a frictional force pass
/// (force_kernel.cpp, "Each pair once"): what the sum pass adds. The evaluating particle's
/// own sums take its force and torque where the pair is evaluated, so only the other side's
/// torque is kept: 48 bytes a contact instead of 72 (docs/performance.md "Smaller pair results").
struct PairResult {
  Vec3 force = Vec3::Zero();  ///< on the evaluating particle i [N]; j receives -force
  /// r_j x force (+ M_roll), of which j receives the negation (= its r x (-force) - M_roll);
  /// for a pair with a lower-id ghost j, which the sum pass adds to i itself, r_i x force
  /// (+ M_roll) [N m]
  Vec3 torque_summed = Vec3::Zero();
};


/// A planar wall, evaluated inline with PlaneWall's formulas (core/src/dem/plane_wall.cpp).
struct WallData {
  Vec3 point0 = Vec3::Zero();    ///< point at t = 0 [m]
  Vec3 normal = Vec3::UnitZ();   ///< unit, into the domain
  Vec3 velocity = Vec3::Zero();  ///< [m/s]
  Vec3 point = Vec3::Zero();     ///< point at the current evaluation time [m]
};

/// spring_of of a slot without history: the code of pool 0's first entry, a spring never used
/// whose result stays zero, so the force kernel's sums read a zero result for a slot without
/// contact without testing for one (force_kernel.cpp, "Each pair once").
inline constexpr std::uint32_t kNoSpring = 0u;

struct FastState {
  // --- per particle, storage order: [0, owned) this rank's particles in cell order (permuted
  // at every list build), then [owned, size()) the ghosts (copies of other ranks' particles
  // within the interaction range, in the order of the halo plan; none on one rank) ---
  std::size_t owned = 0;
  /// The owned particles [0, n_interior) have no ghost partner: a list build puts the halo
  /// layer (the owned particles within the halo reach of another rank's brick) last, so the
  /// pair pass can run the interior while the halo refresh is in flight (cell_sort.cpp,
  /// docs/dem.md "Domain decomposition (MPI)"). One rank: n_interior = owned.
  std::size_t n_interior = 0;
  std::vector<std::int64_t> id;
  std::vector<std::uint32_t> original;  ///< construction index (the seed's newtoorig)
  std::vector<std::uint32_t> where;     ///< inverse: storage index of construction index o
                                        ///< (kNotHere if another rank owns it); not per particle
  std::vector<Vec3> x, v, w;            ///< position [m], v(n) or v(n+1/2) [m/s], omega [rad/s]
  std::vector<Vec3> f, t;               ///< contact force [N], torque [N m] (last evaluation)
  std::vector<Vec3> pv, pw;             ///< predicted v(n+1), omega(n+1) for the dashpots
  std::vector<Vec3> x_build;            ///< position at the last list build [m]
  std::vector<double> radius, mass, inertia;  ///< R [m], m [kg], I [kg m^2]
  /// Material index (Particle::material; pair_laws.hpp). Per particle like radius and mass:
  /// permuted with them, and to be packed with them for ghosts and migration.
  std::vector<std::uint16_t> material;
  std::vector<std::int32_t> escaped_via;      ///< 0, or 1 + index of the boundary crossed first
  /// Bit b set: boundary b must be evaluated for this particle until the next list build (it
  /// moves, it is not a plane wall, or it is a fixed wall within R + skin at the build); bits
  /// exist for the first 32 boundaries, the others are always evaluated. Owned particles only.
  std::vector<std::uint32_t> near_boundaries;
  /// One rank, frictional lists: the smallest gap |x_i - x_j| - (R_i + R_j) [m] over particle i's
  /// upper slots at the last list build; -inf if one of them held a spring then, +inf if it
  /// has none. Not carried by the sort: made afresh after every build (mark_screen_gaps).
  std::vector<double> screen_gap;
  /// The pair pass lists none of particle i's upper slots while screen_gap[i] exceeds this
  /// [m]: twice the largest displacement since the build, plus a margin (step.cpp); +inf, no
  /// skipping, outside a step's evaluation (docs/performance.md "Dilute lists").
  double screen_skip_bound = std::numeric_limits<double>::infinity();
  /// Per-particle energy term of the last evaluation that outlives it (energies tracked; zero
  /// otherwise): the elastic energy, summed only when the energies are asked. The step's
  /// rates (dissipated, work, power) go straight into the exact sums and are not kept
  /// (docs/dem.md "Energy book-keeping").
  struct ParticleTerms {
    double elastic = 0.0;  ///< energy stored in its contacts [J]
    using packed_as_bytes = void;  ///< pack.hpp: copied as its bytes (no padding)
  };
  std::vector<ParticleTerms> terms;
  // --- full neighbour list (CSR) of the owned particles, each range sorted by the partner's id;
  // partners may be ghosts ---
  std::vector<std::uint32_t> first;    ///< n + 1 offsets
  std::vector<std::uint32_t> partner;  ///< storage index of the partner
  /// Per slot of an owned partner j: the slot of this particle in j's list (kNoMirror for a
  /// ghost partner). Frictional kernels evaluate a pair of owned particles once, on its
  /// lower-id side, which also keeps the other side's history through this link.
  std::vector<std::uint32_t> mirror;
  /// Per owned particle i: the first slot of i's list whose partner has a higher id than i
  /// (the list is sorted by id: [upper_first[i], first[i + 1]) are the pairs i evaluates and
  /// books the energy of; the slots before it hold the lower-id partners, whose owned ones
  /// evaluate the pair, while a lower-id ghost's pair is evaluated here too, force only).
  /// The kernels loop over the two parts separately instead of testing each slot's
  /// side: the test is a coin toss for the branch predictor (docs/performance.md "Fewer
  /// mispredicted branches").
  std::vector<std::uint32_t> upper_first;
  /// Per owned particle: 1 if a lower-id partner is a ghost (its pair is evaluated here too).
  /// The kernels scan the lower-id slots for ghosts only then: most particles of a rank have
  /// none (docs/performance.md "Projection to many nodes").
  std::vector<std::uint8_t> lower_ghost;
  // --- friction only: the tangential history of each slot that has one; for a partner that is
  // owned too, only the lower-id side's slot has it (the other side's code stays kNoSpring).
  // A slot holds a 4-byte code (kNoSpring, or pool and index), the springs themselves live in
  // pools: pool 0 is laid out at each list build, pool 1 + r receives the contacts that the
  // force loop's range r (FastState::split) sees begin between builds (only the thread running
  // range r appends to it or reads the slots of its particles, so the loop needs no lock; the
  // ranges move only when the pools are laid out afresh). Most slots of a Verlet list are not touching (about
  // 4 of 7 in a settled bed), so this keeps 4 bytes instead of a spring per idle slot. ---
  std::vector<std::uint32_t> spring_of;  ///< per slot: kNoSpring or (pool << pool_shift) | index
  std::vector<SpringPool> spring_pools;  ///< each in three arrays (spring_pool.hpp)
  unsigned pool_shift = 31;  ///< bits of the index part of a code
  /// Per slot of an owned LOWER-id partner j: j's code for the pair (spring_of at j's slot of
  /// this particle, mirror), copied here so that the kernel's sum pass reads it in slot order
  /// instead of through mirror and a scattered spring_of (one dependent load less per slot).
  /// Other slots: unused. Written only by the evaluating side: link_lower_codes after the
  /// codes are laid out (lower_codes_valid false), then by the kernel's listing when that
  /// side's contact begins or ends (a slot of another particle, but written by one thread only).
  std::vector<std::uint32_t> lower_code;
  bool lower_codes_valid = false;  ///< cleared wherever spring_of or mirror is set afresh

  std::size_t pool_index(std::uint32_t code) const { return code & ((std::uint32_t{1} << pool_shift) - 1); }
  TangentialSpring spring_at(std::uint32_t code) const { return spring_pools[code >> pool_shift].get(pool_index(code)); }
  void put_spring(std::uint32_t code, const TangentialSpring& spring) {
    spring_pools[code >> pool_shift].set(pool_index(code), spring);
  }
  /// The parts of spring `code` that the lane law reads and writes (spring_pool.hpp).
  SpringCore& spring_core(std::uint32_t code) { return spring_pools[code >> pool_shift].core(pool_index(code)); }
  SpringArms& spring_arms(std::uint32_t code) { return spring_pools[code >> pool_shift].arms(pool_index(code)); }
  /// A new empty spring in `pool`; its code.
  std::uint32_t new_spring(std::size_t pool) {
    SpringPool& springs = spring_pools[pool];
    springs.push_back(TangentialSpring{});
    return static_cast<std::uint32_t>((pool << pool_shift) | (springs.size() - 1));
  }
  /// The slot of owned particle k's list whose partner has id `partner_id` (the list is in
  /// partner id order), or none: a restore's lookup (fast_checkpoint.cpp, restore_from_shares.cpp).
  std::optional<std::uint32_t> slot_of_partner(std::size_t k, std::int64_t partner_id) const {
    const auto begin = partner.begin() + first[k], end = partner.begin() + first[k + 1];
    const auto it = std::lower_bound(begin, end, partner_id, [&](std::uint32_t j, std::int64_t other) { return id[j] < other; });
    if (it == end || id[*it] != partner_id) return std::nullopt;
    return static_cast<std::uint32_t>(it - partner.begin());
  }
  /// Sets slot's spring to `spring`, giving the slot a new one if it has none.
  void set_spring(std::uint32_t slot, const TangentialSpring& spring) {
    std::uint32_t& code = spring_of[slot];
    if (code == kNoSpring) code = new_spring(0);
    put_spring(code, spring);
    lower_codes_valid = false;
  }
  /// The last evaluation's result of the pair whose evaluating side holds spring `code`: laid
  /// out like spring_pools (result_pools[p][k] belongs to spring_pools[p][k]), kept as long
  /// as the pools by the kernel, valid only for the slots it evaluated in its last pass.
  std::vector<std::vector<PairResult>> result_pools;
  PairResult& result_at(std::uint32_t code) { return result_pools[code >> pool_shift][pool_index(code)]; }
  const PairResult& result_at(std::uint32_t code) const { return result_pools[code >> pool_shift][pool_index(code)]; }
  // --- boundary contacts of the last evaluation, sorted by (particle, boundary, feature) ---
  std::vector<BoundaryRecord> records;
  std::vector<std::uint32_t> record_first;  ///< n + 1 offsets into records
  std::vector<BoundaryRecord> next_records;        ///< the kernel's output buffers (swapped in)
  std::vector<std::uint32_t> next_record_first;
  std::vector<ThreadOutput> threads;  ///< per kernel range
  /// The force kernel's ranges: range r computes the owned particles [split[r], split[r + 1]),
  /// one range per thread, cut by estimated work and measured times (balance_split) after every
  /// list build.
  std::vector<std::size_t> split;
  bool split_stale = true;  ///< set by a list build or a (re)load
  /// Per range: the share of the estimated work it got at the last cut (sums to 1), and the
  /// seconds its thread has spent in the force kernel since (balance_split corrects the next
  /// cut with them). Only the speed depends on them, never a result.
  std::vector<double> range_share;
  std::vector<double> range_seconds;
  ThreadSpeeds thread_speeds;  ///< the intervals of range_share and range_seconds (a diagnostic)
  /// The frictional kernels' second (sum) pass has its own ranges: range r sums the particles
  /// whose neighbour slots begin in the r-th part of the slots, the parts' shares corrected by
  /// the pass's measured times every kSumRecut evaluations (force_sums.hpp). It reads only
  /// finished results, so its cut may move at any evaluation. Only the speed depends on them.
  std::vector<double> sum_share;
  std::vector<double> sum_seconds;
  unsigned sum_evaluations = 0;  ///< since the last recut
  // --- scene ---
  std::vector<WallData> walls;        ///< per boundary index (unused entries for others)
  std::vector<bool> is_wall;          ///< per boundary index
  BoundaryList boundaries;
  /// Per boundary index: where it can touch a particle at this evaluation (Boundary::reach,
  /// set by the engine before each evaluation); the boundary pass skips the particles outside
  /// (force_boundaries.hpp). The whole space for walls, and for every boundary when
  /// FastOptions::skip_far_objects is off.
  std::vector<ReachBox> reach;
  double dt = 0.0;
  Vec3 gravity = Vec3::Zero();
  bool friction = false;
  /// Set by the engine for an evaluation that closes a step: a kernel whose sums end in a pass
  /// over the particles may apply the closing kick there (close_kick below), right after each
  /// particle's sums, and then sets kick_closed; otherwise the engine applies it afterwards.
  bool closing_kick = false;
  /// [contact] rolling is on: contacts add a rolling torque besides r x F (rolling_resistance.hpp)
  bool rolling = false;
  bool kick_closed = false;
  /// Set by the engine with several ranks: the closing kick also finds the largest next_drift,
  /// so that the next step's rebuild decision travels in this step's one allreduce.
  bool predict_drift = false;
  /// The sum of close_kick's screens over the owned particles at the last closing kick.
  double screen = 0.0;
  /// The largest next_drift over the owned particles at the last closing kick (predict_drift).
  double next_drift = 0.0;
  // --- results of the last evaluation ---
  std::size_t pair_contacts = 0;
  std::size_t boundary_contacts = 0;
  std::optional<LargestOverlap> deepest;  ///< deepest contact of the last evaluation
  /// The energy rates of the last evaluation over the owned particles (kEnergy; the ranges'
  /// ThreadOutput::rates merged): dissipated [J], boundary work [J], boundary power [W].
  std::array<ExactSum, 3> rates;
  std::size_t size() const { return id.size(); }
};

/// The contact geometry of touching particles i and j (storage indices) with d = x_i - x_j:
/// the reference's expressions (reference/src/dem/force_passes.hpp), so the same bits. The
/// force kernel evaluates every pair with it (force_pairs.hpp; hertz_mindlin_x4.cpp lane by
/// lane), and save_state writes a pair history's branch vectors with it (fast_engine.cpp).
using PairGeometry = SpherePairGeometry;
inline PairGeometry pair_geometry(const FastState& s, std::size_t i, std::size_t j, const Vec3& d) {
  return sphere_pair_geometry(d, s.radius[i], s.radius[j]);
}

inline constexpr std::uint32_t kNotHere = 0xffffffffu;  ///< `where` of a particle owned elsewhere
inline constexpr std::uint32_t kNoMirror = 0xffffffffu;  ///< mirror of a slot whose partner is a ghost

/// Threads of the force kernel for `owned` particles (one below kParallelMin).
inline int kernel_threads(std::size_t owned) { return owned >= kParallelMin ? max_threads() : 1; }

/// The shares of `ranges` ranges that would have taken equal times, from each range's share
/// of the work at the last cut and the seconds it has taken since: each range's speed in
/// shares per second gives the balanced shares; the result moves half-way there (damping: one
/// interval's timing is noisy) and stays within [1/2, 3/2] of an even share. Even shares if
/// there is no timing for `ranges` ranges yet (other sizes, or a range without time). Only
/// the kernel's speed depends on the shares, never a result.
inline std::vector<double> timed_shares(std::size_t ranges, const std::vector<double>& share,
                                        const std::vector<double>& seconds) {
  const double even = 1.0 / static_cast<double>(ranges);
  std::vector<double> next(ranges, even);
  if (share.size() != ranges || seconds.size() != ranges) return next;
  for (const double t : seconds) {
    if (!(t > 0.0)) return next;
  }
  double speeds = 0.0;  // [shares / s]
  for (std::size_t r = 0; r < ranges; ++r) speeds += share[r] / seconds[r];
  double total = 0.0;
  for (std::size_t r = 0; r < ranges; ++r) {
    const double balanced = share[r] / seconds[r] / speeds;
    next[r] = std::clamp(0.5 * (share[r] + balanced), 0.5 * even, 1.5 * even);
    total += next[r];
  }
  for (double& x : next) x /= total;
  return next;
}

/// Cuts the owned particles into `threads` contiguous ranges of about equal estimated work,
/// in units of one idle neighbour slot: 8 per particle (integration, walls, stores), 1 per slot,
/// 15 more per touching slot (a contact law evaluation; instruction ratios from callgrind of
/// the bench scene, docs/performance.md). Only the speed depends on the cut: every particle's
/// result is computed
/// by one thread from its own data. The estimate uses the positions at the cut.
inline void balance_split(FastState& s, int threads) {
  const std::size_t n = s.owned;
  const auto ranges = static_cast<std::size_t>(threads);
  // Corrected by the measured times: the estimate misjudges parts of a scene (in the settling
  // bed the range holding the floor is slower during the fall).
  const std::vector<double> share = timed_shares(ranges, s.range_share, s.range_seconds);
  s.thread_speeds.record(s.range_share, s.range_seconds);
  s.range_share = share;
  s.range_seconds.assign(ranges, 0.0);
  std::vector<std::uint64_t> cumulative(n + 1, 0);
  PPOHDEM_OMP(omp parallel for schedule(static) if (n >= kParallelMin))
  for (std::size_t i = 0; i < n; ++i) {
    std::uint64_t work = 8;
    if (s.first.size() == n + 1) {
      for (std::uint32_t slot = s.first[i]; slot < s.first[i + 1]; ++slot) {
        const std::uint32_t j = s.partner[slot];
        // With friction a pair of owned particles is evaluated on its lower-id side only; the
        // other side skips the slot and later adds the result (about the cost of a slot).
        if (s.friction && j < n && s.id[j] < s.id[i]) {
          work += 1;
          continue;
        }
        const double reach = s.radius[i] + s.radius[j];
        work += (s.x[i] - s.x[j]).squaredNorm() < reach * reach ? 16 : 1;
      }
    }
    cumulative[i + 1] = work;
  }
  for (std::size_t i = 0; i < n; ++i) cumulative[i + 1] += cumulative[i];
  s.split.assign(static_cast<std::size_t>(threads) + 1, n);
  s.split[0] = 0;
  double before = 0.0;  // shares of the ranges before r
  for (int r = 1; r < threads; ++r) {
    before += share[static_cast<std::size_t>(r - 1)];
    const auto target = static_cast<std::uint64_t>(static_cast<double>(cumulative[n]) * std::min(before, 1.0));
    s.split[static_cast<std::size_t>(r)] =
        static_cast<std::size_t>(std::lower_bound(cumulative.begin(), cumulative.end(), target) - cumulative.begin());
  }
  s.split_stale = false;
}

/// Lays the springs of every slot out afresh in pool 0, in slot order, with pools for `threads`
/// OpenMP threads after it (at a list build, and if the thread count changed). Throws if the
/// codes cannot address as many slots (2^(32 - bits for 1 + threads pools), e.g. 2^30 with 2
/// threads: then this rank holds too many particles for one process). `in_slot_order`: the
/// caller has just laid pool 0 out alone in slot order (install_history), so the check of
/// that below is skipped (a serial pass over the slots).
inline void lay_out_springs(FastState& s, int threads, bool in_slot_order = false) {
  s.lower_codes_valid = false;
  unsigned pool_bits = 1;
  while ((std::size_t{1} << pool_bits) < static_cast<std::size_t>(threads) + 1) ++pool_bits;
  const unsigned shift = 32 - pool_bits;
  if (s.partner.size() >= (std::size_t{1} << shift) - 1) {
    throw std::length_error("fast engine: " + std::to_string(s.partner.size()) +
                            " neighbour slots on one rank exceed the spring index range (2^" + std::to_string(shift) +
                            "); run with more MPI ranks");
  }
  // Already laid out (pool 0 alone, its codes 1, 2, ... in slot order, as install_history
  // makes them): a copy would change nothing, so only the ranges' empty pools are added.
  if (s.spring_pools.size() == 1 && s.spring_of.size() == s.partner.size()) {
    std::uint32_t next = 1;
    bool in_order = true;
    if (in_slot_order) {
      next = static_cast<std::uint32_t>(s.spring_pools[0].size());
    } else {
      for (const std::uint32_t code : s.spring_of) {
        if (code == kNoSpring) continue;
        in_order = in_order && code == next;
        ++next;
      }
    }
    if (in_order && next == s.spring_pools[0].size()) {
      s.spring_pools.resize(static_cast<std::size_t>(threads) + 1);
      for (ThreadOutput& range : s.threads) range.free_springs.clear();
      s.pool_shift = shift;
      return;
    }
  }
  SpringPool packed;
  packed.resize(1);  // the entry of kNoSpring
  std::vector<std::uint32_t> codes(s.partner.size(), kNoSpring);
  if (s.spring_of.size() == s.partner.size()) {
    for (std::size_t slot = 0; slot < codes.size(); ++slot) {
      if (s.spring_of[slot] == kNoSpring) continue;
      codes[slot] = static_cast<std::uint32_t>(packed.size());
      packed.push_back(s.spring_at(s.spring_of[slot]));
    }
  }
  s.spring_pools.assign(static_cast<std::size_t>(threads) + 1, {});
  for (ThreadOutput& range : s.threads) range.free_springs.clear();
  s.spring_pools[0] = std::move(packed);
  s.spring_of = std::move(codes);
  s.pool_shift = shift;
}

/// FastState::lower_code from spring_of and mirror (friction): for each owned pair, the
/// evaluating (lower-id) side's code copied to the other side's slot (each slot has one
/// writer, so the particles may be split among threads).
inline void link_lower_codes(FastState& s) {
  s.lower_code.assign(s.partner.size(), kNoSpring);
  const std::size_t n = s.owned;
  PPOHDEM_OMP(omp parallel for schedule(static) if (n >= kParallelMin))
  for (std::size_t i = 0; i < n; ++i) {
    for (std::uint32_t slot = s.upper_first[i]; slot < s.first[i + 1]; ++slot) {
      if (s.mirror[slot] != kNoMirror) s.lower_code[s.mirror[slot]] = s.spring_of[slot];
    }
  }
  s.lower_codes_valid = true;
}

/// Calls f(array) for EVERY per-particle array of the state (storage order): the cell sort,
/// migration and ghost creation move particles through this one list, so a new per-particle
/// field is one line here (and nothing else to change in the decomposition).
template <class State, class F>
void for_each_particle_array(State& s, F&& f) {
  f(s.id);
  f(s.original);
  f(s.x);
  f(s.v);
  f(s.w);
  f(s.f);
  f(s.t);
  f(s.pv);
  f(s.pw);
  f(s.x_build);
  f(s.radius);
  f(s.mass);
  f(s.inertia);
  f(s.material);
  f(s.escaped_via);
  f(s.terms);
}

/// The arrays that change every step and that a partner's force reads: refreshed on the ghosts
/// after every drift (the halo plan's gather). Fixed per particle (radius, mass, ...) travel
/// only when a ghost is created.
template <class State, class F>
void for_each_moving_array(State& s, F&& f) {
  f(s.x);
  f(s.v);
  f(s.w);
  f(s.pv);
  f(s.pw);
}

/// Kinetic, rotational and gravitational energy of particle k (the reference's expressions)
/// [J]: m |v|^2 / 2, I |w|^2 / 2, -m g . x.
inline std::array<double, 3> motion_terms(const FastState& s, std::size_t k) {
  return {0.5 * s.mass[k] * s.v[k].squaredNorm(), 0.5 * s.inertia[k] * s.w[k].squaredNorm(),
          -(s.mass[k] * s.gravity.dot(s.x[k]))};
}

/// The second half kick of particle i, v(n+1) = v(n+1/2) + a(n+1) dt/2 with a from f, t: the
/// kick is kept in pv, pw for the next step's first half kick (FastEngine::Impl::step).
/// Returns |v|^2 + |w|^2 of the new state [m^2/s^2, 1/s^2]: summed over the particles, a
/// screen that is not finite as soon as one component is not (the run checks' screen between
/// the energy rows).
inline double close_kick(FastState& s, std::size_t i) {
  const double half = 0.5 * s.dt;
  s.pv[i] = half * (s.f[i] / s.mass[i] + s.gravity);
  s.pw[i] = half * s.t[i] / s.inertia[i];
  s.v[i] += s.pv[i];
  s.w[i] += s.pw[i];
  return s.v[i].squaredNorm() + s.w[i].squaredNorm();
}

/// The first half kick of particle i in a step, dt/2 (a, alpha): the one the closing kick of
/// the previous step left in pv, pw when `cached`, else from f, t (after a (re)load).
struct HalfKick {
  Vec3 v;  ///< [m/s]
  Vec3 w;  ///< [1/s]
};
inline HalfKick first_half_kick(const FastState& s, std::size_t i, bool cached) {
  if (cached) return {s.pv[i], s.pw[i]};
  const double half = 0.5 * s.dt;
  return {Vec3(half * (s.f[i] / s.mass[i] + s.gravity)), Vec3(half * s.t[i] / s.inertia[i])};
}

/// The half kick and drift of particle i (the reference's expressions, so the same bits),
/// with pv, pw the predicted velocities the force pass reads. The owner applies it to its
/// particles and each rank to its ghosts, from the same kick (halo.cpp), so a ghost keeps
/// its owner's bits.
inline void kick_and_drift(FastState& s, std::size_t i, const HalfKick& k) {
  s.v[i] += k.v;
  s.w[i] += k.w;
  s.x[i] += s.dt * s.v[i];
  s.pv[i] = s.v[i] + k.v;
  s.pw[i] = s.w[i] + k.w;
}

/// |x - x_build|^2 of particle i after the next step's drift, right after its closing kick:
/// that drift is v += pv, x += dt v (FastEngine::Impl::step), here with the same expressions,
/// so the same bits (docs/dem.md "One collective a step").
inline double next_drift(const FastState& s, std::size_t i) {
  const Vec3 v = s.v[i] + s.pv[i];
  const Vec3 x = s.x[i] + s.dt * v;
  return (x - s.x_build[i]).squaredNorm();
}

/// kick_and_drift of particles [begin, end) with first_half_kick(s, i, cached), eight at a time
/// where the CPU has AVX-512F and `cached` (the same bits; kicks_and_drifts.cpp). Returns the
/// largest |x - x_build|^2 [m^2] (0 for none).
double kicks_and_drifts(FastState& s, std::size_t begin, std::size_t end, bool cached);

/// close_kick of particles [begin, end), eight at a time where the CPU has AVX-512F (the same
/// bits; close_kicks.cpp). Returns a screen that is finite if and only if every close_kick's is.
double close_kicks(FastState& s, std::size_t begin, std::size_t end);

/// The halo refresh in flight during an evaluation (step.cpp): the ghosts' moving fields are
/// not yet this step's. The pair pass polls it now and then from the master thread during the
/// interior particles (MPI makes progress on large messages only inside MPI calls), and the
/// master thread completes it (wait, then the ghosts' kicks and drifts) before any thread
/// evaluates the halo layer.
class HaloInFlight {
 public:
  virtual ~HaloInFlight() = default;
  virtual void poll() = 0;
  virtual void complete() = 0;
};

/// A force evaluation: contact forces and torques of every OWNED particle at time `time` with
/// history increment interval `dt` (0 at start-up); fills f, t, the energy terms, the new
/// boundary records and the counts.
/// `halo`: the halo refresh in flight (or null): the interior particles [0, s.n_interior)
/// are evaluated first, the halo layer after halo->complete().
class ForceKernel {
 public:
  virtual ~ForceKernel() = default;
  virtual void evaluate(FastState& s, double time, double dt, HaloInFlight* halo) const = 0;
};

/// The kernel for the scene's law, friction and boundary kinds. `vector_contacts`: evaluate the
/// contacts of a one-material Hertz-Mindlin scene with friction four at a time where the CPU
/// has AVX (hertz_mindlin_x4.hpp; the same bits); false: always one at a time.
std::unique_ptr<ForceKernel> make_force_kernel(const SimulationSetup& setup, bool vector_contacts = true);

}  // namespace ppohdem::dem::fast
