#pragma once
// The fast engine's state and its concepts, one file each (docs/dem.md "Optimized engine"):
//   migrate.cpp             particles to the ranks that own them (the migrate plan)
//   halo.cpp                ghosts: the halo plan built at a list build, applied every step
//   cell_sort.cpp           the owned particles sorted by cell
//   neighbour_list.cpp      Verlet lists, mirror links, boundaries near each particle
//   history_carry_over.cpp  contact histories carried across a list build (and ranks)
//   global_sums.cpp         exact sums over particles (energies, loads): any order, same bits
//   step.cpp                one time step: kicks, drift, list builds, force evaluation
//   fast_checkpoint.cpp     save_state / restore_state
//   fast_engine.cpp         the DemEngine interface
// The force kernel is force_kernel.cpp, its passes force_pairs.hpp, force_boundaries.hpp and
// force_sums.hpp (with hertz_mindlin_x4.cpp), the per-particle arrays fast_state.hpp. Shared by those files only: not installed.
#include "ppohdem/dem/fast/fast_engine.hpp"
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <optional>
#include <tuple>
#include <type_traits>
#include <unordered_map>
#include "decomposition.hpp"
#include "fast_state.hpp"
#include "hertz_mindlin_x4.hpp"
#include "near_members.hpp"
#include "pack.hpp"
#include "ppohdem/dem/cell_grid.hpp"
#include "ppohdem/dem/exact_sum.hpp"
#include "ppohdem/dem/pair_laws.hpp"
#include "ppohdem/error.hpp"

namespace ppohdem::dem::fast {

using Grid = CellGrid;  // ppohdem/dem/cell_grid.hpp (shared with the reference's cell list)

/// The cells of the sort and the search: the longest axis varies slowest, so the threads'
/// ranges of the cell order are cut across it (cell_grid.hpp, with_longest_axis_slowest).
inline Grid grid_for(const std::vector<Vec3>& x, double min_cell) { return with_longest_axis_slowest(cell_grid_for(x, min_cell)); }

/// a := (a[order[0]], a[order[1]], ...); order may be shorter than a (a selection).
template <class T>
void permute(std::vector<T>& a, const std::vector<std::uint32_t>& order) {
  std::vector<T> b(order.size());
  PPOHDEM_OMP(omp parallel for schedule(static) if (order.size() >= kParallelMin))
  for (std::size_t k = 0; k < order.size(); ++k) b[k] = a[order[k]];
  a.swap(b);
}

/// The sums of one evaluation over the particles, exact until rounded (exact_sum.hpp), so
/// that the threads' and the ranks' partial sums merge in any order to the same bits: the
/// seven energy terms, then per boundary its load's force and moment about the origin (x, y, z).
struct EvaluationSums {
  static constexpr std::size_t kEnergies = 7;  ///< elastic, dissipated, work, power, kinetic, rotational, gravitational
  std::vector<ExactSum> sums;
  explicit EvaluationSums(std::size_t boundaries) : sums(kEnergies + 6 * boundaries) {}
  ExactSum* energy() { return sums.data(); }
  ExactSum* load(std::size_t boundary) { return sums.data() + kEnergies + 6 * boundary; }
  void merge(const EvaluationSums& other) {
    for (std::size_t c = 0; c < sums.size(); ++c) sums[c].merge(other.sums[c]);
  }
  void reset() {
    for (ExactSum& sum : sums) sum.reset();
  }
  /// Every rank's sums merged, on every rank: ONE allreduce of the sums' integer words
  /// (Comm::sum_over_ranks), whatever the particle count. Collective.
  void merge_over_ranks(const Comm& comm) {
    std::vector<std::int64_t> words(sums.size() * ExactSum::kWords);
    for (std::size_t c = 0; c < sums.size(); ++c) {
      const auto w = sums[c].words();
      std::copy(w.begin(), w.end(), words.begin() + static_cast<std::ptrdiff_t>(c * ExactSum::kWords));
    }
    comm.sum_over_ranks(words);
    for (std::size_t c = 0; c < sums.size(); ++c) {
      sums[c] = ExactSum::from_words(std::span<const std::int64_t, ExactSum::kWords>(words.data() + c * ExactSum::kWords, ExactSum::kWords));
    }
  }
  /// The rounded loads (one per boundary).
  std::vector<BoundaryLoad> loads(std::size_t boundaries) {
    std::vector<BoundaryLoad> out(boundaries);
    for (std::size_t b = 0; b < boundaries; ++b) {
      const ExactSum* l = load(b);
      out[b].force = Vec3(l[0].value(), l[1].value(), l[2].value());
      out[b].moment_about_origin = Vec3(l[3].value(), l[4].value(), l[5].value());
    }
    return out;
  }
};

/// A spring that is not the empty history (the kernel resets ended contacts to TangentialSpring{}).

template <class T>
std::size_t bytes(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}

/// The contact history an owned particle carries across a list build (and to another rank):
/// its side of every pair history keyed by the partner's global id (ascending), and its
/// boundary records (ascending boundary). CSR over the owned particles in storage order.
struct History {
  std::vector<std::uint32_t> first{0};
  std::vector<std::int64_t> partner_id;
  std::vector<TangentialSpring> spring;
  std::vector<std::uint32_t> record_first{0};
  std::vector<BoundaryRecord> records;  ///< .particle is not used here

  void append_from(const History& h, std::size_t k) {
    for (std::uint32_t a = h.first[k]; a < h.first[k + 1]; ++a) {
      partner_id.push_back(h.partner_id[a]);
      spring.push_back(h.spring[a]);
    }
    first.push_back(static_cast<std::uint32_t>(partner_id.size()));
    for (std::uint32_t a = h.record_first[k]; a < h.record_first[k + 1]; ++a) records.push_back(h.records[a]);
    record_first.push_back(static_cast<std::uint32_t>(records.size()));
  }
  void pack(Packer& p, std::size_t k) const {
    p.put(first[k + 1] - first[k]);
    for (std::uint32_t a = first[k]; a < first[k + 1]; ++a) {
      p.put(partner_id[a]);
      p.put(spring[a]);
    }
    p.put(record_first[k + 1] - record_first[k]);
    for (std::uint32_t a = record_first[k]; a < record_first[k + 1]; ++a) {
      p.put(records[a].boundary);
      p.put(records[a].feature);
      p.put(records[a].spring);
      p.put(records[a].force);
      p.put(records[a].point);
      p.put(records[a].rolling);
    }
  }
  void unpack_append(Unpacker& u) {
    const auto springs = u.get<std::uint32_t>();
    for (std::uint32_t a = 0; a < springs; ++a) {
      partner_id.push_back(u.get<std::int64_t>());
      spring.push_back(u.get<TangentialSpring>());
    }
    first.push_back(static_cast<std::uint32_t>(partner_id.size()));
    const auto count = u.get<std::uint32_t>();
    for (std::uint32_t a = 0; a < count; ++a) {
      BoundaryRecord r;
      u.get(r.boundary);
      u.get(r.feature);
      u.get(r.spring);
      u.get(r.force);
      u.get(r.point);
      u.get(r.rolling);
      records.push_back(r);
    }
    record_first.push_back(static_cast<std::uint32_t>(records.size()));
  }
};

inline void pack_particle(Packer& p, FastState& s, std::size_t k) {
  for_each_particle_array(s, [&](auto& a) { p.put(a[k]); });
}
inline void unpack_particle(Unpacker& u, FastState& s) {
  for_each_particle_array(s, [&](auto& a) {
    a.emplace_back();
    u.get(a.back());
  });
}

struct FastEngine::Impl {
  FastState s;
  std::unique_ptr<ForceKernel> kernel;
  std::vector<Material> materials;  ///< material k of the scene (SimulationSetup::material_at), for restore_state
  SerialComm serial;
  const Comm* comm = &serial;
  Decomposition decomposition;
  FastOptions::Balance balance = FastOptions::Balance::kOff;
  double balance_threshold = 1.05;
  /// The equal bricks of the box of the scene's initial particles (also after a restore): the
  /// bricks with the balance off and the load report's "before".
  Decomposition equal_bricks;
  bool equal_bricks_made = false;
  /// The ranks whose bricks lie within the halo reach of this rank's (Decomposition::peers):
  /// halo and migrate exchange with them only.
  std::vector<int> peers;
  long recuts = 0;
  long global_exchanges = 0;
  long exchanges = 0;  ///< LoadReport::exchanges
  long overlapped_refreshes = 0;  ///< LoadReport::overlapped_refreshes
  std::size_t total = 0;  ///< particles of the whole system
  double skin = 0.0;      ///< [m]
  double skin_fraction = 0.2;  ///< FastOptions::skin_fraction (insertion may raise R_max)
  double r_max = 0.0;     ///< [m], over the whole system
  bool skip_far_objects = true;  ///< FastOptions::skip_far_objects
  bool skip_apart_slots = true;  ///< FastOptions::skip_apart_slots
  long steps = 0;
  long builds = 0;
  /// The cumulative energy terms, summed at every evaluation (add_rates) [J].
  double dissipated = 0.0;
  double boundary_work = 0.0;
  double power = 0.0;  ///< P(n) of the last evaluation [W]
  /// After a restore, the checkpoint's elastic energy until the next evaluation (the particles'
  /// records were not saved) [J].
  std::optional<double> restored_elastic;
  /// SimulationSetup::energy_balance; false: the kernel computes no energy terms, the totals
  /// stay zero and energies() reports the contact terms as NaN.
  bool energy_balance = true;
  /// energies() of the current state (collective with several ranks: every rank asks).
  mutable std::optional<Energies> energies_cache;
  mutable std::vector<BoundaryLoad> loads;
  /// `loads` is not yet the last evaluation's: boundary_loads() sums them.
  mutable bool loads_stale = false;
  std::size_t escaped = 0;  ///< whole system (not kept up to date when lazy_sums())
  /// Several ranks: every rank's close_kick screen was finite at the last evaluation.
  bool screens_finite = true;
  /// Several ranks: the next drift's largest |x - x_build|^2 over every rank, from the last
  /// closing evaluation's allreduce (next_drift, fast_state.hpp); empty when not known (after a
  /// (re)load or a non-closing evaluation): step() then asks the ranks after its drift.
  std::optional<double> drift_over_ranks;
  mutable Particles out;  ///< particles() in construction order (whole system)
  mutable bool out_valid = false;
  // Halo plan (built at every list build, applied after every drift): send[i] = storage indices
  // of the owned particles that peers[i] holds as ghosts, in the order they are packed; recv[i] =
  // how many ghosts came from peers[i] (stored contiguously after the owned ones, by peer).
  std::vector<std::vector<std::uint32_t>> halo_send;
  std::vector<std::uint32_t> halo_recv;
  std::vector<Bytes> halo_kicks;  ///< pack_ghost_kicks' messages, one per peer (reused)
  /// Histories dropped at the last list build: (construction index, partner id, energy) [J].
  std::vector<std::tuple<std::uint32_t, std::int64_t, double>> lost_terms;

  bool distributed() const { return comm->size() > 1; }
  /// One rank: the escaped count is counted when asked (several ranks reduce it with every
  /// evaluation's counts). On any rank count the energies and the boundary loads are summed
  /// when asked, never in a step, and the run checks screen the motion with close_kick's screen
  /// (motion_finite). Why: a per-step sum is a pass over every particle that nothing reads
  /// (docs/performance.md "Energy book-keeping").
  bool lazy_sums() const { return !distributed(); }
  /// pv, pw hold the closing half kick of the last step (see step()); false after a (re)load.
  bool kick_cached = false;
  mutable std::vector<EvaluationSums> thread_sums;  ///< sum_owned's partial sums, one per thread (reused)
  std::vector<std::vector<std::uint32_t>> search_buffers;  ///< search_neighbours' per-block lists (reused)
  ProbeColumns search_probes;  ///< search_neighbours' centres and radii in member order (reused)
  /// A list build's histories (build_lists): kept between builds so that their storage is
  /// reused, not allocated and zeroed afresh (docs/performance.md "Cheaper list builds, second
  /// pass"). They stay in the order before the
  /// cell sort: install_history reads them through the sort's order.
  History history;

  /// Keeps the particles this rank owns (all of them on one rank).
  void load_particles(const Particles& particles);
  /// The same from this rank's share of the file (SimulationSetup::share; collective): the
  /// bricks from all the shares, then the shares migrate to their owners.
  void load_share(const Particles& particles, const ParticleShare& share);
  /// load_share's placing, with `carried` (what share's particles carry, in their order; or
  /// empty: nothing) and `escaped_flags` (nonzero: escaped; or null: none) migrating with them: on
  /// return `carried` is the owned particles'. The lists are left as they were (reset_lists,
  /// then build_from, make them).
  void place_share(const Particles& particles, const ParticleShare& share, History& carried,
                   const std::vector<std::uint8_t>* escaped_flags = nullptr);
  /// Empties every per-particle array and what was built from them (load_particles, load_share).
  void clear_particles();
  /// Appends a particle as owned, with its construction index.
  void append_owned(const Particle& p, std::size_t original);
  /// FastEngine::insert_particles (collective): `added` appended to the owned particles (each
  /// rank every P-th), then a list build that carries every history over (fast_insert.cpp).
  void insert_in_place(const Particles& added);
  /// After the owned particles are in place: the empty lists and exchanges they start from.
  void reset_lists();

  /// A restore's counters and accumulators from `state` (restore_state, restore_state_share);
  /// `escaped_total`: the escaped particles over all the ranks.
  void restore_counters(const EngineState& state, std::size_t escaped_total);
  /// A restore's last fields, once the histories are installed: the contact counts, the caches.
  void finish_restore(const EngineState& state);

  /// The lists of the owned particles as placed (a list build after its migration): the cell
  /// sort, the ghosts, the search, h's histories installed (those whose pair is no longer
  /// listed go to lost_terms; build_lists books them).
  void build_from(const History& h);

  /// h := what the owned particles carry across the build (History); h's storage is reused.
  void take_history(History& h) const;

  /// Migration (the migrate plan: each owned particle's new owner from its centre) with its
  /// history; arrivals are appended in rank order. With the peers only, unless a particle
  /// goes to a rank that is not a peer (farther than the halo reach) on any rank, or `global`:
  /// then with every rank (counted in global_exchanges unless `global`).
  void migrate(History& h, bool global = false);

  /// The bricks of the particles given (the whole system, on every rank): equal bricks and,
  /// with balance on, the bisection; and the peers.
  void decompose_whole(const Particles& particles);
  /// The same from the owned particles of every rank (collective): the equal bricks over the
  /// box of every centre unless made, the bisection with balance on; and the peers.
  void decompose_owned();

  /// Initial overlaps above 1 % of the smaller radius among the owned particles and their
  /// ghosts (a shared setup's check, after the first list build; collective): every rank
  /// throws validate_setup's error (initial_overlaps.cpp).
  void check_initial_overlaps(const std::string& source) const;

  /// Load balance at a list build, after the migration: if the most loaded rank owns more
  /// than balance_threshold times the mean, re-cut by bisection of the owned particles
  /// (collective) and migrate to the new bricks.
  void rebalance(History& h);

  /// FastEngine::load_report (collective).
  LoadReport load_report() const;

  /// peers := the ranks within the halo reach (2 R_max + skin) of this rank's brick.
  void update_peers();

  /// The owned particles within the halo reach of a peer's brick (the halo layer: those that
  /// can have a ghost partner until the next build, a superset of those that do) moved after
  /// the others in `order` (the cell sort's order[new] = old, a stable partition: the cell
  /// order holds within each part); s.n_interior := the others' count.
  void put_halo_layer_last(std::vector<std::uint32_t>& order);

  /// Ghosts (the halo plan): every owned particle whose centre is within the interaction
  /// range 2 R_max + skin of rank r's brick goes to rank r with all its fields.
  void make_ghosts();

  /// The halo plan's messages of this step, before the drift: for each peer the first half
  /// kicks (first_half_kick) of the particles it holds as ghosts, in the plan's order.
  void pack_ghost_kicks(bool cached);

  /// The halo plan applied after the drift: each ghost gets its owner's half kick and repeats
  /// its owner's arithmetic (kick_and_drift, after the closing kick's v += kick when `cached`),
  /// so its moving fields are its owner's bits: 48 bytes a ghost instead of the 120 of x, v,
  /// omega, pv, pw (docs/dem.md "Domain decomposition").
  void refresh_ghosts(bool cached);
  /// The bytes of each peer's half kicks to receive (the plan's ghost counts x 48).
  std::vector<std::size_t> ghost_kick_sizes() const;

  /// refresh_ghosts split in two, for a step that will not build: the messages are posted
  /// now (after pack_ghost_kicks, before the drift), and the force kernel completes them
  /// between the interior particles and the halo layer (HaloInFlight: wait, then the ghosts'
  /// kicks and drifts); the same messages and bits as refresh_ghosts.
  struct GhostKicksInFlight;
  std::unique_ptr<HaloInFlight> post_ghost_kicks(bool cached);

  /// The ghosts' half kicks received from the peers (`from`, in the plan's order) applied:
  /// each ghost repeats its owner's arithmetic (refresh_ghosts).
  void apply_ghost_kicks(const std::vector<Bytes>& from, bool cached);

  /// A list build: migration (several ranks), sort of the owned particles by cell, ghosts,
  /// then the full neighbour list of the owned particles (pairs closer than R_i + R_j + skin,
  /// each particle's partners in ascending id) and the histories carried over by partner id.
  /// Collective: every rank builds at the same step (the decision is global).
  void build_lists();

  /// FastState::near_boundaries at a list build. Until the next build every owned particle
  /// stays within skin / 2 of x_build (the rebuild rule), so its distance to a fixed plane
  /// wall changes by at most skin / 2: a wall farther than R + skin now stays farther than
  /// R + skin / 2 > R (no contact) and > 0 (not crossed). The margin skin / 2 covers the
  /// rounding of the distance many times over.
  void mark_near_boundaries();

  /// FastState::screen_gap at a list build (one rank; else left empty), and the largest
  /// displacement since the build back to 0. A pair whose gap at the build exceeds twice the
  /// largest displacement of any particle since cannot touch now, nor at any evaluation since
  /// (that largest one is a running maximum), so it holds no spring: its slot needs no
  /// screening. The margin (1e-9 of a list's reach) covers the rounding of the gaps, the
  /// displacement and the screen's own test many times over.
  void mark_screen_gaps();
  double drift_since_build = 0.0;  ///< max over the steps since the build of max |x - x_build|^2 [m^2]

  /// The cells of a cell sort: its grid, start[c] the first (sorted) index in cell c
  /// (start[c + 1] the end), and order[k] the index before the sort of the particle now at k.
  struct CellOrder {
    Grid grid;
    std::vector<std::uint32_t> start;
    std::vector<std::uint32_t> order;
  };

  /// Sorts the owned particles by cell (stable); returns the grid, the cells' starts and the
  /// order (empty if there are no owned particles). Several ranks: the halo layer then goes
  /// last (put_halo_layer_last), and the starts are not those of the new order.
  CellOrder sort_owned_by_cell();

  /// Neighbour search over owned + ghost particles for the owned ones, each particle
  /// independently. `sorted`: the cell order all of them are in already, if they are (one
  /// rank, after the cell sort), else made here.
  void search_neighbours(const CellOrder* sorted);

  /// FastState::mirror (frictional scenes; without history every contact is evaluated from
  /// both sides): for each slot of an owned partner j, the slot of this particle in j's list.
  /// The lists are symmetric between owned particles (the same reach and distance decide
  /// both), and each is sorted by id, so one binary search per pair, from its lower-id side i
  /// in the lower-id part of j's list, links both slots (half the searches of one per slot:
  /// docs/performance.md "Cheaper list builds, second pass"). Symmetry check: every upper slot
  /// finds its pair, and as many lower slots are linked as there are lower slots of owned
  /// partners (distinct pairs link distinct slots, so all of them).
  void link_mirrors();

  /// Pair histories by partner id (both ranges ascending in id: a merge); boundary records
  /// follow their particle. A pair history whose partner is no longer in the list is lost.
  /// h is in the order before the cell sort: particle k's history is h's entry before[k]
  /// (read in place: copying h into the new order first cost a pass over every history,
  /// docs/performance.md "The cell sort carries less").
  void install_history(const History& h, const std::vector<std::uint32_t>& before);

  /// A history dropped from the list (the pair moved apart by more than the skin within one
  /// step): its stored energy is dissipated, booked once (lower id side).
  void lost(std::vector<std::tuple<std::uint32_t, std::int64_t, double>>& to, const TangentialSpring& spring,
            std::size_t k, std::int64_t other) const {
    if (s.id[k] < other) to.emplace_back(s.original[k], other, spring.stored_energy());
  }

  /// The lost energies of this build, added in construction order (then partner id) on every
  /// rank: independent of the decomposition and of the cell order.
  void add_lost_energy();

  /// A force evaluation. `closing_kick` (a step): the second half kick follows the kernel (or
  /// runs in its sum pass). One rank: sums the rates only (energies tracked); several ranks:
  /// one allreduce of a StepRecord (step_record.hpp) and nothing else.
  /// `halo`: the halo refresh in flight (a step), completed here at the latest.
  void evaluate_forces(double history_dt, bool closing_kick = false, HaloInFlight* halo = nullptr);
  /// s.reach for the evaluation at `time` [s] (step.cpp).
  void update_reach(double time);

  /// A record's load on its boundary: minus the contact force on the particle, its moment
  /// about the origin, minus the rolling torque on the particle [N, N m]: the terms the
  /// reference adds (force_passes.hpp), each exactly.
  void add_load(EvaluationSums& to, std::uint32_t boundary, const Vec3& force, const Vec3& point,
                const Vec3& rolling) const {  // inline: once per boundary record in the loads' sums
    ExactSum* load = to.load(boundary);
    const Vec3 moment = point.cross(-force);
    for (int c = 0; c < 3; ++c) {
      load[c].add(-force[c]);
      load[3 + c].add(moment[c]);
      if (s.rolling) load[3 + c].add(-rolling[c]);
    }
  }

  /// Adds the loads of owned particle k's boundary records.
  void add_records(EvaluationSums& to, std::size_t k) const {
    for (std::uint32_t r = s.record_first[k]; r < s.record_first[k + 1]; ++r) {
      add_load(to, s.records[r].boundary, s.records[r].force, s.records[r].point, s.records[r].rolling);
    }
  }

  /// This rank's sums over its owned particles (the threads' partial sums merged): the energies
  /// of the state if `state` (elastic from the records when tracked; kinetic, rotational,
  /// gravitational from the particles), the boundary loads if `with_loads`. (The rates are
  /// summed by the kernel itself: FastState::rates.)
  EvaluationSums sum_owned(bool state, bool with_loads) const;

  /// Owned particles that have crossed a boundary (one rank: all of them).
  std::size_t count_escaped() const;

  /// The loads of the last evaluation when they were not summed with it (lazy_sums(), or
  /// several ranks with the energies untracked): sum_owned's loads, merged over the ranks
  /// (collective).
  void sum_loads() const;

  /// The energies of the current state: the kinetic, rotational and gravitational energy from
  /// the state and (tracked) the elastic energy from the particles' records, each an exact
  /// sum rounded once, with the cumulative terms (collective with several ranks: one
  /// allreduce).
  Energies sum_energies() const;

  /// Energies tracked: the rates of one evaluation (rates[0..3): dissipated, boundary work and
  /// power, exact sums over the particles of every rank) added to the cumulative terms.
  void add_rates(const ExactSum* rates, double history_dt);

  /// The second half kick of every owned particle (close_kick, fast_state.hpp) unless the
  /// kernel's sum pass applied it; the next step's first half kick reuses it.
  void close_step();

  void step();
};

}  // namespace ppohdem::dem::fast
