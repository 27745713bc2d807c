#pragma once
/// \file fast_engine.hpp
/// The optimized DEM engine ("fast"; alias "optimized" in `ppohdem simulate --engine`): same
/// interface and same step contract as the reference engine (ppohdem/dem/engine.hpp), and the
/// same trajectories BIT FOR BIT on one node for any number of OpenMP threads (docs/dem.md,
/// "Optimized engine"). Divergences from the reference (STYLE habit 8), each for speed:
///   - structure of arrays: one array per field (x, v, omega, F, T, ...), particles stored in
///     the order of their cell (counting sort, the seed's cellindex/newtoorig), re-sorted
///     whenever the neighbour list is rebuilt, the cells with the longest axis varying slowest
///     (the reference: x, y, z; cell_grid.hpp); particles() is assembled on demand;
///   - Verlet neighbour list with a skin (default 0.2 R_max): a FULL list (each pair appears
///     for both particles), no Newton-3, so OpenMP threads never write the same particle and
///     need no atomics; rebuilt when the largest displacement since the last build exceeds
///     half the skin (the seed's pos_accum); cells of side >= 2 R_max + skin;
///   - each particle sums its contact forces with higher-id partners in ascending id, then
///     those with lower-id partners in descending id, which is the order in which the
///     reference (pairs visited by lower id descending, Newton 3) adds them.
///     Without friction each particle computes each contact from its own side, which is
///     bitwise the negation of the other side (IEEE negation is exact; tests/dem invariants
///     ContactForce.IsEqualAndOpposite). With friction a pair of particles owned by the same
///     rank is evaluated once, by its lower-id side (as the reference), which stores the
///     force and both torques and sums its own contacts at once; a second pass after a
///     barrier adds the lower-id partners' results in that order (the exact negations).
///     Either way forces, torques
///     and trajectories equal the reference's bit for bit;
///   - the contact history of a pair is kept by its lower-id side (a ghost's pair by both
///     ranks, mirrored), keyed by the partner's global id and carried over by id when the list
///     is rebuilt (the higher-id side's is the exact mirror, derived when needed);
///   - energies and boundary loads are summed per particle (loads: per boundary record) and
///     then over particles exactly, rounded once to the nearest double (ppohdem/dem/exact_sum.hpp):
///     the threads' and ranks' partial sums merge in any order to the same bits, so the sums
///     are the same for any thread count, storage order and rank count (histories dropped at
///     a list build: by construction index, then partner id). Kinetic, rotational and
///     gravitational energy and the boundary loads are the reference's sums bit for bit (it
///     sums the same terms exactly); the contact energy terms differ from the reference's
///     exact sum over contacts by the round-off of the per-particle sums (relative ~1e-15);
///   - the force loop gives each thread one contiguous range of particles cut by estimated
///     work (neighbour slots, touching slots) at every list build, so a bed whose contacts lie
///     in one part of the cell order keeps both threads busy;
///   - kernels are templates over (law, friction, walls, other boundaries) chosen once at
///     construction: a frictionless scene has no history code, a scene without walls no wall
///     loop; planar walls are evaluated inline (PlaneWall's formulas), other boundaries
///     (distance-field objects) through Boundary::contact.
/// Domain decomposition over MPI ranks (FastOptions::comm; docs/dem.md "Domain decomposition"):
/// bricks (by default a recursive coordinate bisection of the particle count, re-cut at a list
/// build when the load drifts: FastOptions::balance, docs/dem.md "Load balance"), each rank
/// owning the particles whose centre lies in its brick, ghosts within 2 R_max + skin of it,
/// exchanged with the ranks whose bricks lie within that reach only; halo and migrate plans
/// built at every list build (the rebuild
/// decision is the maximum over ranks), the halo refreshed after every drift; contact
/// histories migrate with their particle. Per-particle forces are summed in an order of the partners'
/// global ids and global sums exact (one allreduce of fixed size), so the trajectories, energies and outputs are BIT
/// FOR BIT those of one rank. With more than one rank, particles(), energies(), save_state()
/// and restore_state() are collective (every rank calls them, in the same order) and return
/// the whole system on every rank; the other queries are global values cached at each step.
#include <algorithm>
#include <array>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ppohdem/comm/comm.hpp"
#include "ppohdem/dem/engine.hpp"

namespace ppohdem::dem::fast {

struct FastOptions {
  double skin_fraction = 0.2;  ///< Verlet skin as a fraction of R_max [-]
  /// Ranks to decompose the domain over (every rank constructs the engine from the same
  /// setup); nullptr: one rank. Must outlive the engine.
  const Comm* comm = nullptr;
  /// Evaluate the contacts of a one-material Hertz-Mindlin scene with friction four at a time
  /// where the CPU has AVX (the same bits as one at a time; false: always one at a time, the
  /// tests' way to check both).
  bool vector_contacts = true;
  /// Skip the particles outside an object's reach at each evaluation (Boundary::reach; the
  /// same bits as evaluating them all, which false does: the tests' way to check it).
  bool skip_far_objects = true;
  /// One rank: list none of a particle's pair slots while none of them can touch (its
  /// smallest gap at the list build exceeds twice the largest displacement since; the same
  /// bits as screening them all, which false does: the tests' way to check it; docs/performance.md
  /// "Dilute lists").
  bool skip_apart_slots = true;
  /// Load balance over the ranks (docs/dem.md "Load balance"; scene `[parallel] balance`):
  /// kBisection cuts the domain by recursive coordinate bisection of the particle count at the
  /// start and re-cuts it at a list build when the most loaded rank owns more than
  /// balance_threshold times the mean; kOff keeps the equal bricks of the initial box.
  enum class Balance { kOff, kBisection };
  Balance balance = Balance::kBisection;
  double balance_threshold = 1.05;  ///< max/mean particles per rank that triggers a re-cut (>= 1)
};

/// Particles per rank (max/mean) and the exchanges so far (FastEngine::load_report).
struct LoadReport {
  double max_over_mean = 1.0;         ///< owned particles per rank, at the last list build
  double equal_bricks_max_over_mean = 1.0;  ///< the same positions in the equal bricks of the initial box
  long recuts = 0;                    ///< re-cuts during the run (not the one at the start)
  long global_exchanges = 0;          ///< migrations that fell back to an all-rank exchange
  std::size_t peers = 0;              ///< ranks this rank exchanges with (at the last list build)
  long exchanges = 0;                 ///< halo refreshes, ghost creations and migrations so far
  double ghosts_mean = 0.0;           ///< ghosts per rank (mean over the ranks, at the last list build)
  double ghosts_max = 0.0;            ///< ghosts on the rank with the most
  double interior_mean = 0.0;         ///< interior particles per rank (no ghost partner; at the last list build)
  double interior_min = 0.0;          ///< interior particles on the rank with the fewest
  long overlapped_refreshes = 0;      ///< of `exchanges`: halo refreshes overlapped with the interior pairs
};

/// How fast the force kernel's threads ran against each other (a diagnostic: no result depends
/// on it). The kernel's first pass gives each thread one range of particles and re-cuts the
/// ranges at every list build from their measured times; record() takes one such interval:
/// each range's share of the work and the seconds it took. A range's speed is share / seconds;
/// the interval's ratio is the slowest range's speed over the fastest's, 1 for equal cores.
/// Cores that are not equal (a virtual CPU sharing its physical core with another guest, a
/// lower clock) give ratios below 1, and then t threads cannot run t times as fast as one:
/// with 2 threads at a ratio q, at most 1 + q.
struct ThreadSpeeds {
  std::size_t intervals = 0;
  double seconds = 0.0;            ///< the intervals' lengths (each its longest range time), summed [s]
  double ratio_seconds = 0.0;      ///< ratio x length, summed [s]
  double seconds_below_0_9 = 0.0;  ///< length of the intervals whose ratio is below 0.9 [s]

  /// One interval of two or more ranges; ignored if a share or a time is not positive or the
  /// sizes differ (the first interval after a change of the thread count).
  void record(const std::vector<double>& share, const std::vector<double>& range_seconds) {
    if (share.size() < 2 || share.size() != range_seconds.size()) return;
    double slowest = 0.0, fastest = 0.0, length = 0.0;  // speeds [shares / s], length [s]
    for (std::size_t r = 0; r < share.size(); ++r) {
      if (!(share[r] > 0.0) || !(range_seconds[r] > 0.0)) return;
      const double speed = share[r] / range_seconds[r];
      slowest = r == 0 ? speed : std::min(slowest, speed);
      fastest = std::max(fastest, speed);
      length = std::max(length, range_seconds[r]);
    }
    const double ratio = slowest / fastest;
    ++intervals;
    seconds += length;
    ratio_seconds += ratio * length;
    if (ratio < 0.9) seconds_below_0_9 += length;
  }
  /// The ratio averaged over the intervals' lengths (1 without intervals).
  double mean_ratio() const { return seconds > 0.0 ? ratio_seconds / seconds : 1.0; }
  /// The share of the time in intervals whose ratio is below 0.9.
  double fraction_below_0_9() const { return seconds > 0.0 ? seconds_below_0_9 / seconds : 0.0; }
};

class FastEngine final : public DemEngine {
 public:
  /// Validates the setup (validate_setup; throws InputError), builds the cells and lists and
  /// evaluates the forces of the initial state.
  explicit FastEngine(const SimulationSetup& setup, FastOptions options = {});
  ~FastEngine() override;

  static std::unique_ptr<DemEngine> make(const SimulationSetup& setup);

  std::string name() const override { return "fast"; }
  void step() override;
  long step_count() const override;
  double time() const override;
  const Particles& particles() const override;
  /// This rank's particles in construction order (not collective).
  Particles owned_particles() const override;
  /// Several ranks: one personalised exchange moves each owned particle to the rank of its
  /// construction index (docs/dem.md "Reading on every rank").
  OrderedPart ordered_part() const override;
  Energies energies() const override;
  ContactCounts contact_counts() const override;
  std::size_t escaped_count() const override;
  /// From the last closing kick's sum of |v|^2 + |w|^2 over the particles (with several
  /// ranks every rank's), so that no energy is summed for the screen; after a (re)load, before
  /// any step, the default.
  bool motion_finite() const override;
  /// Each rank scans its owned particles (no gather), then one allreduce.
  bool state_finite() const override;
  std::vector<BoundaryLoad> boundary_loads() const override;
  EngineState save_state() const override;
  EngineStateShare save_state_share() const override;
  void restore_state(const EngineState& state) override;
  void restore_state_share(const EngineStateShare& share, std::size_t inserted = 0) override;
  std::size_t particle_count() const override;
  /// Each rank's owned particles, then one reduction of the two maxima.
  Extent particle_extent() const override;
  /// Each rank's owned particles in the boxes, then one allgather of those only.
  Particles particles_in(const std::vector<CentreBox>& boxes) const override;
  /// Particle insertion (DemEngine::insert_particles, fast_insert.cpp): the new particles
  /// appended (each rank takes every P-th), then one list build that carries every history
  /// over (collective with several ranks; no gather, no reload).
  void insert_particles(const Particles& added) override;
  /// Deepest contact of the last evaluation (ties: smaller (boundary, id_a, id_b)).
  std::optional<LargestOverlap> largest_overlap() const override;

  int ranks() const;                    ///< ranks the domain is decomposed over
  std::array<int, 3> rank_grid() const;  ///< bricks per axis (product = ranks()); {0, 0, 0}: bisection
  /// Particles per rank and exchange counts (collective with several ranks).
  LoadReport load_report() const;
  std::size_t owned_count() const;       ///< particles owned by this rank
  std::size_t ghost_count() const;       ///< ghosts held by this rank (since the last build)
  /// Owned particles without a ghost partner, first in storage order (since the last build;
  /// owned_count() on one rank): the pairs evaluated while the halo refresh travels.
  std::size_t interior_count() const;
  /// Of the interior_count() particles, those with a ghost in their neighbour list or within
  /// R_i + R_j + skin of a ghost j at the last build, by brute force over every such pair: 0
  /// unless the halo layer is wrong (a test's check; O(owned x ghosts)).
  std::size_t interior_near_ghosts() const;
  long neighbour_list_builds() const;  ///< number of list builds so far (diagnostics)
  /// Particle evaluations whose pair slots were not screened (skip_apart_slots; diagnostics,
  /// summed over the kernel's thread ranges since they were last made).
  std::size_t skipped_screens() const;
  double skin() const;                 ///< [m]
  std::size_t neighbour_slots() const; ///< entries of the full list (diagnostics)
  /// This rank's force-kernel threads' speeds against each other since construction (no
  /// intervals with one thread).
  const ThreadSpeeds& thread_speeds() const;
  /// Bytes held by the engine's arrays (capacity), for the memory-per-particle figure.
  std::size_t memory_bytes() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace ppohdem::dem::fast
