// The fast engine: integration, cell sort, Verlet neighbour lists and the domain
// decomposition over MPI ranks (fast_engine.hpp; docs/dem.md "Domain decomposition").
#include "ppohdem/dem/fast/fast_engine.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <tuple>
#include <type_traits>
#include <unordered_map>

#include "decomposition.hpp"
#include "fast_state.hpp"
#include "hertz_mindlin_x4.hpp"
#include "near_members.hpp"
#include "pack.hpp"
#include "ppohdem/dem/cell_grid.hpp"
#include "ppohdem/dem/ordered_sum.hpp"
#include "ppohdem/dem/pair_laws.hpp"
#include "ppohdem/error.hpp"

namespace ppohdem::dem::fast {

namespace {

using Grid = CellGrid;  // ppohdem/dem/cell_grid.hpp (shared with the reference's cell list)

/// The cells of the sort and the search: the longest axis varies slowest, so the threads'
/// ranges of the cell order are cut across it (cell_grid.hpp, with_longest_axis_slowest).
Grid grid_for(const std::vector<Vec3>& x, double min_cell) { return with_longest_axis_slowest(cell_grid_for(x, min_cell)); }

/// a := (a[order[0]], a[order[1]], ...); order may be shorter than a (a selection).
template <class T>
void permute(std::vector<T>& a, const std::vector<std::uint32_t>& order) {
  std::vector<T> b(order.size());
  PPOHDEM_OMP(omp parallel for schedule(static) if (order.size() >= kParallelMin))
  for (std::size_t k = 0; k < order.size(); ++k) b[k] = a[order[k]];
  a.swap(b);
}

/// ordered_sum.hpp's sum of term(0) .. term(n-1) with its blocks summed on the OpenMP threads:
/// the same bits as the serial ordered_sum for any thread count.
template <std::size_t K, class Term>
std::array<double, K> parallel_ordered_sum(std::size_t n, const Term& term) {
  std::vector<std::array<double, K>> blocks(sum_blocks(n));
  const std::size_t count = blocks.size();
  PPOHDEM_OMP(omp parallel for schedule(static) if (n >= kParallelMin))
  for (std::size_t b = 0; b < count; ++b) {
    blocks[b] = sum_range<K>(b * kSumBlock, std::min(n, (b + 1) * kSumBlock), term);
  }
  return add_blocks(blocks);
}

/// A spring that is not the empty history (the kernel resets ended contacts to TangentialSpring{}).
bool keeps_history(const TangentialSpring& s) { return s.stiffness != 0.0 || s.branch_i != Vec3::Zero() || s.displacement != Vec3::Zero(); }

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
      p.put(records[a].spring);
      p.put(records[a].force);
      p.put(records[a].point);
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
      u.get(r.spring);
      u.get(r.force);
      u.get(r.point);
      records.push_back(r);
    }
    record_first.push_back(static_cast<std::uint32_t>(records.size()));
  }
};

void pack_particle(Packer& p, FastState& s, std::size_t k) {
  for_each_particle_array(s, [&](auto& a) { p.put(a[k]); });
}
void unpack_particle(Unpacker& u, FastState& s) {
  for_each_particle_array(s, [&](auto& a) {
    a.emplace_back();
    u.get(a.back());
  });
}

}  // namespace

struct FastEngine::Impl {
  FastState s;
  std::unique_ptr<ForceKernel> kernel;
  std::vector<Material> materials;  ///< material k of the scene (SimulationSetup::material_at), for restore_state
  SerialComm serial;
  const Comm* comm = &serial;
  Decomposition decomposition;
  std::size_t total = 0;  ///< particles of the whole system
  double skin = 0.0;      ///< [m]
  double r_max = 0.0;     ///< [m], over the whole system
  long steps = 0;
  long builds = 0;
  double elastic = 0.0;
  double dissipated = 0.0;
  double boundary_work = 0.0;
  double power = 0.0;  ///< P(n) of the last evaluation [W]
  /// SimulationSetup::energy_balance; false: the four accumulators above stay zero (the kernel
  /// computes no energy terms) and energies() reports the contact terms as NaN.
  bool energy_balance = true;
  mutable std::vector<BoundaryLoad> loads;
  /// `loads` is not yet the last evaluation's (lazy_sums(), or several ranks with the
  /// energies untracked): boundary_loads() sums them.
  mutable bool loads_stale = false;
  std::size_t escaped = 0;  ///< whole system (not kept up to date when lazy_sums())
  /// Several ranks: every rank's close_kick screen was finite at the last evaluation.
  bool screens_finite = true;
  mutable Particles out;  ///< particles() in construction order (whole system)
  mutable bool out_valid = false;
  // Halo plan (built at every list build, applied after every drift): send[r] = storage indices
  // of the owned particles that rank r holds as ghosts, in the order they are packed; recv[r] =
  // how many ghosts came from rank r (stored contiguously after the owned ones, by rank).
  std::vector<std::vector<std::uint32_t>> halo_send;
  std::vector<std::uint32_t> halo_recv;
  /// Histories dropped at the last list build: (construction index, partner id, energy) [J].
  std::vector<std::tuple<std::uint32_t, std::int64_t, double>> lost_terms;

  bool distributed() const { return comm->size() > 1; }
  /// One rank without energy tracking: no sum over the particles runs every step. The
  /// kinetic, rotational and gravitational energies, the boundary loads and the escaped count
  /// are summed when asked (the same terms in the same order, so the same bits), and the run
  /// checks screen the motion with close_kick's screen (motion_finite). Measured: 0.923-0.926
  /// of the time of a step of the settling bed (docs/performance.md).
  bool lazy_sums() const { return !energy_balance && !distributed(); }
  /// pv, pw hold the closing half kick of the last step (see step()); false after a (re)load.
  bool kick_cached = false;
  /// One rank: (kinetic, rotational, gravitational) energy of the state after the last step,
  /// summed in the evaluation's pass (reduce_one_rank); invalid after a (re)load.
  std::array<double, 3> motion_sums{};
  bool motion_valid = false;
  std::vector<std::array<double, 7>> block_sums;  ///< reduce_one_rank's per-block partial sums
  mutable std::vector<BoundaryLoad> block_loads;  ///< blocks x boundaries
  std::vector<std::vector<std::uint32_t>> search_buffers;  ///< search_neighbours' per-block lists (reused)
  ProbeColumns search_probes;  ///< search_neighbours' centres and radii in member order (reused)
  /// A list build's histories (build_lists): kept between builds so that their storage is
  /// reused, not allocated and zeroed afresh (about 0.5M cycles of a 10,000-particle build:
  /// docs/performance.md "Cheaper list builds, second pass"). They stay in the order before the
  /// cell sort: install_history reads them through the sort's order.
  History history;
  std::vector<std::array<double, 7>> all_terms;  ///< several ranks: every particle's energy terms by construction index

  /// Keeps the particles this rank owns (all of them on one rank).
  void load_particles(const Particles& particles) {
    auto& q = s;
    kick_cached = false;
    motion_valid = false;
    for_each_particle_array(q, [](auto& a) { a.clear(); });
    total = particles.size();
    r_max = 0.0;
    const int me = comm->rank();
    for (std::size_t i = 0; i < particles.size(); ++i) {
      const Particle& p = particles[i];
      r_max = std::max(r_max, p.radius);
      if (distributed() && decomposition.owner(p.position) != me) continue;
      q.id.push_back(p.id);
      q.original.push_back(static_cast<std::uint32_t>(i));
      q.x.push_back(p.position);
      q.v.push_back(p.velocity);
      q.w.push_back(p.angular_velocity);
      q.f.push_back(p.force);
      q.t.push_back(p.torque);
      q.pv.push_back(p.velocity);
      q.pw.push_back(p.angular_velocity);
      q.x_build.push_back(p.position);
      q.radius.push_back(p.radius);
      const Material& mat = materials[p.material];
      q.material.push_back(p.material);
      q.mass.push_back(mat.mass(p.radius));
      q.inertia.push_back(mat.moment_of_inertia(p.radius));
      q.escaped_via.push_back(0);
      q.terms.emplace_back();
    }
    const std::size_t n = q.id.size();
    q.owned = n;
    q.first.assign(n + 1, 0);
    q.partner.clear();
    q.mirror.clear();
    q.upper_first.clear();
    q.spring_of.clear();
    q.lower_codes_valid = false;
    q.spring_pools.clear();
    q.result_pools.clear();
    q.records.clear();
    q.record_first.assign(n + 1, 0);
    q.split_stale = true;
    halo_send.assign(static_cast<std::size_t>(comm->size()), {});
    halo_recv.assign(static_cast<std::size_t>(comm->size()), 0);
    out_valid = false;
  }

  /// h := what the owned particles carry across the build (History); h's storage is reused.
  void take_history(History& h) const {
    const std::size_t n = s.owned;
    const bool pairs = s.friction && s.first.size() == n + 1;
    const bool boundaries = s.record_first.size() == n + 1;
    // The code of the history slot `slot` of particle k carries, or kNoSpring: a pair of
    // owned particles keeps its history on the lower-id side only (the kernel evaluates it
    // there), and this side's is its mirror. With one rank the mirror is not carried:
    // install_history keeps only the lower-id side's (the pair stays owned by this rank, so
    // its lower-id side stays the one that evaluates it), and only that side books a lost
    // history. With several ranks it travels with its particle, which may leave the partner.
    const bool mirrors = distributed();
    auto carried = [&](std::size_t k, std::uint32_t slot, bool& other_side) {
      const std::uint32_t j = s.partner[slot];
      other_side = j < n && s.id[j] < s.id[k];
      if (other_side && !mirrors) return kNoSpring;
      const std::uint32_t code = other_side ? s.spring_of[s.mirror[slot]] : s.spring_of[slot];
      return code == kNoSpring || !keeps_history(s.spring_at(code)) ? kNoSpring : code;
    };
    // Counts, offsets, then each particle's block filled on the threads.
    h.first.assign(n + 1, 0);
    h.record_first.assign(n + 1, 0);
    PPOHDEM_OMP(omp parallel for schedule(static) if (n >= kParallelMin))
    for (std::size_t k = 0; k < n; ++k) {
      std::uint32_t count = 0;
      bool other_side = false;
      if (pairs) {
        for (std::uint32_t slot = s.first[k]; slot < s.first[k + 1]; ++slot) count += carried(k, slot, other_side) != kNoSpring;
      }
      h.first[k + 1] = count;
      h.record_first[k + 1] = boundaries ? s.record_first[k + 1] - s.record_first[k] : 0;
    }
    for (std::size_t k = 0; k < n; ++k) {
      h.first[k + 1] += h.first[k];
      h.record_first[k + 1] += h.record_first[k];
    }
    h.partner_id.resize(h.first[n]);
    h.spring.resize(h.first[n]);
    h.records.resize(h.record_first[n]);
    PPOHDEM_OMP(omp parallel for schedule(static) if (n >= kParallelMin))
    for (std::size_t k = 0; k < n; ++k) {
      std::uint32_t a = h.first[k];
      if (pairs) {
        for (std::uint32_t slot = s.first[k]; slot < s.first[k + 1]; ++slot) {
          bool other_side = false;
          const std::uint32_t code = carried(k, slot, other_side);
          if (code == kNoSpring) continue;
          h.partner_id[a] = s.id[s.partner[slot]];
          h.spring[a++] = other_side ? mirrored(s.spring_at(code)) : s.spring_at(code);
        }
      }
      if (boundaries) {
        std::copy(s.records.begin() + s.record_first[k], s.records.begin() + s.record_first[k + 1],
                  h.records.begin() + h.record_first[k]);
      }
    }
  }

  /// Migration (the migrate plan: each owned particle's new owner from its centre) with its
  /// history; arrivals are appended in rank order.
  void migrate(History& h) {
    const int me = comm->rank();
    std::vector<Bytes> to(static_cast<std::size_t>(comm->size()));
    std::vector<std::uint32_t> keep;
    History kept;
    for (std::size_t k = 0; k < s.owned; ++k) {
      const int dest = decomposition.owner(s.x[k]);
      if (dest == me) {
        keep.push_back(static_cast<std::uint32_t>(k));
        kept.append_from(h, k);
        continue;
      }
      Packer p(to[static_cast<std::size_t>(dest)]);
      pack_particle(p, s, k);
      h.pack(p, k);
    }
    const std::vector<Bytes> from = comm->exchange(to);
    for_each_particle_array(s, [&](auto& a) { permute(a, keep); });
    for (const Bytes& block : from) {
      Unpacker u(block);
      while (!u.done()) {
        unpack_particle(u, s);
        kept.unpack_append(u);
      }
    }
    s.owned = s.id.size();
    h = std::move(kept);
  }

  /// Ghosts (the halo plan): every owned particle whose centre is within the interaction
  /// range 2 R_max + skin of rank r's brick goes to rank r with all its fields.
  void make_ghosts() {
    const std::size_t ranks = static_cast<std::size_t>(comm->size());
    halo_send.assign(ranks, {});
    halo_recv.assign(ranks, 0);
    if (!distributed()) return;
    const int me = comm->rank();
    const double reach = 2.0 * r_max + skin;
    // Slack: bricks one part in 1e6 of the reach larger, so that the rounding of a brick face
    // (relative 1e-16 of the coordinates) never hides a partner; extra ghosts cost nothing but
    // memory (the list keeps only pairs within R_i + R_j + skin).
    const double slack = 1e-6 * reach;
    std::vector<Bytes> to(ranks);
    for (std::size_t k = 0; k < s.owned; ++k) {
      for (int r = 0; r < static_cast<int>(ranks); ++r) {
        if (r == me || decomposition.distance2(r, s.x[k], slack) >= reach * reach) continue;
        halo_send[static_cast<std::size_t>(r)].push_back(static_cast<std::uint32_t>(k));
        Packer p(to[static_cast<std::size_t>(r)]);
        pack_particle(p, s, k);
      }
    }
    const std::vector<Bytes> from = comm->exchange(to);
    for (std::size_t r = 0; r < ranks; ++r) {
      Unpacker u(from[r]);
      while (!u.done()) {
        unpack_particle(u, s);
        ++halo_recv[r];
      }
    }
  }

  /// The halo plan applied: the moving fields of the ghosts from their owners. A message holds
  /// the moving arrays one after the other (all the x, then all the v, ...), sized once and
  /// copied value by value without a Packer (appending value by value, this took 0.83 of 11.4
  /// Gcycles per rank of a 2-rank run of the settling bed: docs/performance.md "Threads cut
  /// across the longest axis").
  void refresh_ghosts() {
    if (!distributed()) return;
    static_assert(sizeof(Vec3) == 3 * sizeof(double), "a Vec3 array is a plain array of doubles");
    constexpr std::size_t kMovingArrays = 5;  // for_each_moving_array
    const std::size_t ranks = halo_send.size();
    std::vector<Bytes> to(ranks);
    for (std::size_t r = 0; r < ranks; ++r) {
      const std::vector<std::uint32_t>& send = halo_send[r];
      to[r].resize(send.size() * kMovingArrays * sizeof(Vec3));
      unsigned char* write = to[r].data();
      for_each_moving_array(s, [&](const std::vector<Vec3>& a) {
        for (const std::uint32_t k : send) {
          std::memcpy(write, a[k].data(), sizeof(Vec3));
          write += sizeof(Vec3);
        }
      });
    }
    const std::vector<Bytes> from = comm->exchange(to);
    std::size_t g = s.owned;
    for (std::size_t r = 0; r < ranks; ++r) {
      const std::size_t count = halo_recv[r];
      if (from[r].size() != count * kMovingArrays * sizeof(Vec3)) {
        throw std::logic_error("fast engine: a halo message of the wrong size");
      }
      const unsigned char* read = from[r].data();
      for_each_moving_array(s, [&](std::vector<Vec3>& a) {
        for (std::size_t c = 0; c < count; ++c) {
          std::memcpy(a[g + c].data(), read, sizeof(Vec3));
          read += sizeof(Vec3);
        }
      });
      g += count;
    }
  }

  /// A list build: migration (several ranks), sort of the owned particles by cell, ghosts,
  /// then the full neighbour list of the owned particles (pairs closer than R_i + R_j + skin,
  /// each particle's partners in ascending id) and the histories carried over by partner id.
  /// Collective: every rank builds at the same step (the decision is global).
  void build_lists() {
    ++builds;
    out_valid = false;
    History& h = history;
    take_history(h);
    for_each_particle_array(s, [&](auto& a) { a.resize(s.owned); });  // drop the ghosts
    if (distributed()) migrate(h);
    const CellOrder sorted = sort_owned_by_cell();
    make_ghosts();
    // With one rank there are no ghosts: the search's cells are the sort's (the same grid,
    // which depends only on the positions' values, and the particles now in its cell order).
    search_neighbours(distributed() ? nullptr : &sorted);
    install_history(h, sorted.order);
    mark_near_boundaries();
    s.split_stale = true;  // the kernel's ranges are cut afresh for the new order
    add_lost_energy();
  }

  /// FastState::near_boundaries at a list build. Until the next build every owned particle
  /// stays within skin / 2 of x_build (the rebuild rule), so its distance to a fixed plane
  /// wall changes by at most skin / 2: a wall farther than R + skin now stays farther than
  /// R + skin / 2 > R (no contact) and > 0 (not crossed). The margin skin / 2 covers the
  /// rounding of the distance many times over.
  void mark_near_boundaries() {
    const std::size_t n = s.owned;
    const std::size_t nb = s.boundaries.size();
    std::uint32_t always = 0;  // boundaries evaluated for every particle
    for (std::size_t b = 0; b < std::min<std::size_t>(nb, 32); ++b) {
      if (!s.is_wall[b] || s.walls[b].velocity != Vec3::Zero()) always |= 1u << b;
    }
    s.near_boundaries.assign(n, always);
    PPOHDEM_OMP(omp parallel for schedule(static) if (n >= kParallelMin))
    for (std::size_t k = 0; k < n; ++k) {
      std::uint32_t near = always;
      for (std::size_t b = 0; b < std::min<std::size_t>(nb, 32); ++b) {
        if ((always >> b) & 1u) continue;
        const double distance = (s.x[k] - s.walls[b].point0).dot(s.walls[b].normal);
        if (distance < s.radius[k] + skin) near |= 1u << b;
      }
      s.near_boundaries[k] = near;
    }
  }

  /// The cells of a cell sort: its grid, start[c] the first (sorted) index in cell c
  /// (start[c + 1] the end), and order[k] the index before the sort of the particle now at k.
  struct CellOrder {
    Grid grid;
    std::vector<std::uint32_t> start;
    std::vector<std::uint32_t> order;
  };

  /// Sorts the owned particles by cell (stable); returns the grid, the cells' starts and the
  /// order (empty if there are no owned particles).
  CellOrder sort_owned_by_cell() {
    const std::size_t n = s.owned;
    s.where.assign(total, kNotHere);
    if (n == 0) return {};
    const Grid grid = grid_for(s.x, 2.0 * r_max + skin);
    // Counting sort by cell (stable): order[new] = old.
    std::vector<std::uint32_t> cell(n);
    PPOHDEM_OMP(omp parallel for schedule(static) if (n >= kParallelMin))
    for (std::size_t i = 0; i < n; ++i) cell[i] = static_cast<std::uint32_t>(grid.linear(grid.index(s.x[i])));
    std::vector<std::uint32_t> start(grid.size() + 1, 0);
    for (std::size_t i = 0; i < n; ++i) ++start[cell[i] + 1];
    for (std::size_t c = 0; c < grid.size(); ++c) start[c + 1] += start[c];
    std::vector<std::uint32_t> order(n);
    {
      std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
      for (std::size_t i = 0; i < n; ++i) order[fill[cell[i]]++] = static_cast<std::uint32_t>(i);
    }
    // Every array follows its particle except two that the sort need not carry: x_build is
    // set from x below, and the energy terms are the last evaluation's outputs, which this
    // step's evaluation (after the build) writes afresh for every owned particle before any
    // sum reads them (force_kernel.cpp, close_kick). They are zeroed (what untracked terms
    // hold) rather than moved: moving their 64-byte records, through a new vector zero-filled
    // on one thread, was about a third of the sort's time on 2 threads (docs/performance.md
    // "The cell sort carries less").
    for_each_particle_array(s, [&](auto& a) {
      using Array = std::decay_t<decltype(a)>;
      if constexpr (std::is_same_v<Array, std::vector<FastState::ParticleTerms>>) {
        PPOHDEM_OMP(omp parallel for schedule(static) if (n >= kParallelMin))
        for (std::size_t k = 0; k < n; ++k) a[k] = FastState::ParticleTerms{};
      } else if constexpr (std::is_same_v<Array, std::vector<Vec3>>) {
        if (&a != &s.x_build) permute(a, order);
      } else {
        permute(a, order);
      }
    });
    s.x_build.resize(s.x.size());  // (= n: the ghosts are dropped before the sort)
    PPOHDEM_OMP(omp parallel for schedule(static) if (n >= kParallelMin))
    for (std::size_t k = 0; k < s.x.size(); ++k) {
      s.x_build[k] = s.x[k];
      if (k < n) s.where[s.original[k]] = static_cast<std::uint32_t>(k);  // `original` holds distinct indices: one writer per entry
    }
    return {grid, std::move(start), std::move(order)};
  }

  /// Neighbour search over owned + ghost particles for the owned ones, each particle
  /// independently. `sorted`: the cell order all of them are in already, if they are (one
  /// rank, after the cell sort), else made here.
  void search_neighbours(const CellOrder* sorted) {
    const std::size_t n = s.owned;
    const std::size_t all = s.size();
    std::vector<std::uint32_t> first(n + 1, 0);
    if (n == 0) {
      s.first.swap(first);
      s.partner.clear();
      s.mirror.clear();
      s.upper_first.clear();
      return;
    }
    std::vector<std::uint32_t> upper_first(n);
    // Members of each cell: members[start[c]] .. members[start[c + 1] - 1] are the particles in
    // cell c, and member_of[i] is owned particle i's index in members. Already in cell order
    // (`sorted`): members[k] = k. Else a counting sort of owned then ghosts.
    CellOrder made;
    std::vector<std::uint32_t> members(all);
    std::vector<std::uint32_t> member_of(n);
    if (sorted != nullptr) {
      std::iota(members.begin(), members.end(), 0u);
      std::iota(member_of.begin(), member_of.end(), 0u);
    } else {
      made.grid = grid_for(s.x, 2.0 * r_max + skin);
      std::vector<std::uint32_t> cell(all);
      made.start.assign(made.grid.size() + 1, 0);
      for (std::size_t i = 0; i < all; ++i) {
        cell[i] = static_cast<std::uint32_t>(made.grid.linear(made.grid.index(s.x[i])));
        ++made.start[cell[i] + 1];
      }
      for (std::size_t c = 0; c < made.grid.size(); ++c) made.start[c + 1] += made.start[c];
      std::vector<std::uint32_t> fill(made.start.begin(), made.start.end() - 1);
      for (std::size_t i = 0; i < all; ++i) {
        const std::uint32_t m = fill[cell[i]]++;
        members[m] = static_cast<std::uint32_t>(i);
        if (i < n) member_of[i] = m;
      }
    }
    const Grid& grid = sorted != nullptr ? sorted->grid : made.grid;
    const std::vector<std::uint32_t>& start = sorted != nullptr ? sorted->start : made.start;
    // The centres and radii in member order (one column each): a row of three cells along the
    // grid's fastest axis is one contiguous run of members, read in one sweep.
    search_probes.resize(all);
    PPOHDEM_OMP(omp parallel for schedule(static) if (all >= kParallelMin))
    for (std::size_t m = 0; m < all; ++m) {
      const std::uint32_t j = members[m];
      search_probes.x[m] = s.x[j].x();
      search_probes.y[m] = s.x[j].y();
      search_probes.z[m] = s.x[j].z();
      search_probes.r[m] = s.radius[j];
    }
    const bool x4 = x4_contacts_available();
    // The partners j != i with |x_i - x_j| < R_i + R_j + skin, as (id, storage index) into
    // `near` (unsorted): the 3 x 3 rows of three cells around i's cell along the grid's fastest
    // axis (contiguous in the cell order), tested by near_members (four at a time with AVX);
    // `candidates` has room for every member and the 3 more that near_members may write.
    // Named one by one, not a structured binding: Clang 14 cannot capture those in the lambda.
    const std::size_t along = grid.order[0], across1 = grid.order[1], across2 = grid.order[2];
    auto visit = [&](std::size_t i, std::vector<std::uint32_t>& candidates, std::vector<std::pair<std::int64_t, std::uint32_t>>& near) {
      const Vec3 xi = s.x[i];
      const Index3 c = grid.index(xi);
      Index3 corner = c;
      corner[along] = std::max(c[along] - 1, 0);
      const int row_end = std::min(c[along] + 1, grid.dims[along] - 1) + 1;
      const auto row_cells = static_cast<std::size_t>(row_end - corner[along]);
      MemberRun rows[9];
      std::size_t row_count = 0;
      for (int d2 = -1; d2 <= 1; ++d2) {
        corner[across2] = c[across2] + d2;
        if (corner[across2] < 0 || corner[across2] >= grid.dims[across2]) continue;
        for (int d1 = -1; d1 <= 1; ++d1) {
          corner[across1] = c[across1] + d1;
          if (corner[across1] < 0 || corner[across1] >= grid.dims[across1]) continue;
          const std::size_t row = grid.linear(corner);
          rows[row_count++] = {start[row], start[row + row_cells]};
        }
      }
      const NearQuery q{xi.x(), xi.y(), xi.z(), s.radius[i], skin, member_of[i]};
      const std::size_t count = x4 ? near_members_x4(search_probes, rows, row_count, q, candidates.data())
                                   : near_members(search_probes, rows, row_count, q, candidates.data());
      for (std::size_t k = 0; k < count; ++k) near.emplace_back(s.id[members[candidates[k]]], members[candidates[k]]);
    };
    // One pass: each of `blocks` contiguous blocks of particles lists its partners (each
    // particle's sorted by id) into its own buffer, and the buffers are joined in block order
    // (the list of a count pass and a fill pass, with half the distance tests: measured,
    // docs/performance.md).
    const int blocks = n >= kParallelMin ? max_threads() : 1;
    search_buffers.resize(static_cast<std::size_t>(std::max(blocks, 1)));
    PPOHDEM_OMP(omp parallel for schedule(static, 1) num_threads(blocks))
    for (int b = 0; b < blocks; ++b) {
      const std::size_t lo = n * static_cast<std::size_t>(b) / static_cast<std::size_t>(blocks);
      const std::size_t hi = n * static_cast<std::size_t>(b + 1) / static_cast<std::size_t>(blocks);
      // The block's list in a vector object of this thread's own (its storage the reused
      // buffer's): the vector objects of search_buffers share a cache line, and every push_back
      // writes the vector's end, so appending through them bounced that line between the
      // threads (the search's parallel part took 0.92 of its 1-thread time on 2 threads:
      // docs/performance.md "Cheaper list builds, second pass").
      std::vector<std::uint32_t> found;
      found.swap(search_buffers[static_cast<std::size_t>(b)]);
      found.clear();
      std::vector<std::pair<std::int64_t, std::uint32_t>> near;
      std::vector<std::uint32_t> candidates(all + ProbeColumns::kPadding);
      for (std::size_t i = lo; i < hi; ++i) {
        near.clear();
        visit(i, candidates, near);
        std::sort(near.begin(), near.end());  // by id (ids are unique)
        const std::int64_t id_i = s.id[i];
        std::uint32_t lower = 0;  // partners with a lower id: they come first
        for (const auto& [id, j] : near) {
          found.push_back(j);
          lower += static_cast<std::uint32_t>(id < id_i);
        }
        first[i + 1] = static_cast<std::uint32_t>(near.size());
        upper_first[i] = lower;  // made a slot index below
      }
      found.swap(search_buffers[static_cast<std::size_t>(b)]);
    }
    for (std::size_t i = 0; i < n; ++i) {
      first[i + 1] += first[i];
      upper_first[i] += first[i];
    }
    std::vector<std::uint32_t> partner(first[n]);
    for (int b = 0; b < blocks; ++b) {
      const std::size_t lo = n * static_cast<std::size_t>(b) / static_cast<std::size_t>(blocks);
      const std::vector<std::uint32_t>& found = search_buffers[static_cast<std::size_t>(b)];
      std::copy(found.begin(), found.end(), partner.begin() + first[lo]);
    }
    s.first.swap(first);
    s.partner.swap(partner);
    s.upper_first.swap(upper_first);
    link_mirrors();
  }

  /// FastState::mirror (frictional scenes; without history every contact is evaluated from
  /// both sides): for each slot of an owned partner j, the slot of this particle in j's list.
  /// The lists are symmetric between owned particles (the same reach and distance decide
  /// both), and each is sorted by id, so one binary search per pair, from its lower-id side i
  /// in the lower-id part of j's list, links both slots (half the searches of one per slot:
  /// docs/performance.md "Cheaper list builds, second pass"). Symmetry check: every upper slot
  /// finds its pair, and as many lower slots are linked as there are lower slots of owned
  /// partners (distinct pairs link distinct slots, so all of them).
  void link_mirrors() {
    const std::size_t n = s.owned;
    if (!s.friction) {
      s.mirror.clear();
      return;
    }
    s.mirror.assign(s.partner.size(), kNoMirror);
    s.lower_codes_valid = false;
    std::size_t lower_slots = 0, linked = 0, unmatched = 0;
    PPOHDEM_OMP(omp parallel for schedule(static) reduction(+ : lower_slots, linked, unmatched) if (n >= kParallelMin))
    for (std::size_t i = 0; i < n; ++i) {
      for (std::uint32_t slot = s.first[i]; slot < s.upper_first[i]; ++slot) lower_slots += s.partner[slot] < n;
      for (std::uint32_t slot = s.upper_first[i]; slot < s.first[i + 1]; ++slot) {
        const std::uint32_t j = s.partner[slot];
        if (j >= n) continue;
        // i's slot among j's lower-id partners (each slot is written by one pair only).
        const auto begin = s.partner.begin() + s.first[j];
        const auto end = s.partner.begin() + s.upper_first[j];
        const auto it = std::lower_bound(begin, end, s.id[i], [&](std::uint32_t k, std::int64_t id) { return s.id[k] < id; });
        if (it == end || *it != i) {
          ++unmatched;
          continue;
        }
        const auto other = static_cast<std::uint32_t>(it - s.partner.begin());
        s.mirror[slot] = other;
        s.mirror[other] = slot;
        ++linked;
      }
    }
    if (unmatched != 0 || linked != lower_slots) throw std::logic_error("fast engine: neighbour lists are not symmetric");
  }

  /// Pair histories by partner id (both ranges ascending in id: a merge); boundary records
  /// follow their particle. A pair history whose partner is no longer in the list is lost.
  /// h is in the order before the cell sort: particle k's history is h's entry before[k]
  /// (read in place: copying h into the new order first took 0.33-0.55M cycles of a
  /// 10,000-particle build, docs/performance.md "The cell sort carries less").
  void install_history(const History& h, const std::vector<std::uint32_t>& before) {
    const std::size_t n = s.owned;
    const int blocks = n >= kParallelMin ? max_threads() : 1;
    if (s.friction) {
      // Each slot's history (index into h) by a merge per particle, on the threads (the lost
      // ones into per-block lists: add_lost_energy sorts them); then pool 0 in slot order.
      constexpr std::uint32_t kNone = 0xffffffffu;
      std::vector<std::uint32_t> source(s.partner.size(), kNone);
      std::vector<std::vector<std::tuple<std::uint32_t, std::int64_t, double>>> lost_in(static_cast<std::size_t>(blocks));
      PPOHDEM_OMP(omp parallel for schedule(static, 1) num_threads(blocks))
      for (int block = 0; block < blocks; ++block) {
        auto& lost_here = lost_in[static_cast<std::size_t>(block)];
        for (std::size_t k = n * static_cast<std::size_t>(block) / static_cast<std::size_t>(blocks);
             k < n * static_cast<std::size_t>(block + 1) / static_cast<std::size_t>(blocks); ++k) {
          std::uint32_t a = h.first[before[k]];
          const std::uint32_t a_end = h.first[before[k] + 1];
          for (std::uint32_t b = s.first[k]; b < s.first[k + 1]; ++b) {
            const std::int64_t want = s.id[s.partner[b]];
            for (; a < a_end && h.partner_id[a] < want; ++a) lost(lost_here, h.spring[a], k, h.partner_id[a]);
            if (a < a_end && h.partner_id[a] == want) {
              // An owned lower-id partner keeps the pair's history (its mirror is this one).
              if (!(s.partner[b] < n && want < s.id[k])) source[b] = a;
              ++a;
            }
          }
          for (; a < a_end; ++a) lost(lost_here, h.spring[a], k, h.partner_id[a]);
        }
      }
      for (const auto& lost_here : lost_in) lost_terms.insert(lost_terms.end(), lost_here.begin(), lost_here.end());
      // Codes 1, 2, ... in slot order (entry 0: kNoSpring's): each block of slots counts its
      // histories, then numbers them from the sum of the counts before it.
      s.spring_of.resize(s.partner.size());
      std::vector<std::uint32_t> block_first(static_cast<std::size_t>(blocks) + 1, 0);
      const std::size_t slots = source.size();
      auto block_slots = [&](int block) {
        return std::pair{slots * static_cast<std::size_t>(block) / static_cast<std::size_t>(blocks),
                         slots * static_cast<std::size_t>(block + 1) / static_cast<std::size_t>(blocks)};
      };
      PPOHDEM_OMP(omp parallel num_threads(blocks))
      {
        PPOHDEM_OMP(omp for schedule(static, 1))
        for (int block = 0; block < blocks; ++block) {
          const auto [from, to] = block_slots(block);
          std::uint32_t count = 0;
          for (std::size_t b = from; b < to; ++b) count += source[b] != kNone;
          block_first[static_cast<std::size_t>(block) + 1] = count;
        }
        PPOHDEM_OMP(omp single)
        {
          block_first[0] = 1;
          for (int block = 0; block < blocks; ++block) block_first[static_cast<std::size_t>(block) + 1] += block_first[static_cast<std::size_t>(block)];
        }
        PPOHDEM_OMP(omp for schedule(static, 1))
        for (int block = 0; block < blocks; ++block) {
          const auto [from, to] = block_slots(block);
          std::uint32_t code = block_first[static_cast<std::size_t>(block)];
          for (std::size_t b = from; b < to; ++b) s.spring_of[b] = source[b] != kNone ? code++ : kNoSpring;
        }
      }
      const std::uint32_t next = block_first[static_cast<std::size_t>(blocks)];
      // Pool 0 reuses the last layout's storage (the ranges' pools go: lay_out_springs adds them
      // empty): entries 1 to next - 1 are all written below, entry 0 is kNoSpring's empty one.
      // A fresh zeroed pool, copied in, cost about as much as the rest of this function
      // (docs/performance.md "Cheaper list builds, second pass").
      s.spring_pools.resize(1);
      s.pool_shift = 31;
      std::vector<TangentialSpring>& pool = s.spring_pools[0];
      pool.resize(next);
      pool[0] = TangentialSpring{};
      PPOHDEM_OMP(omp parallel for schedule(static) if (n >= kParallelMin))
      for (std::size_t b = 0; b < source.size(); ++b) {
        if (source[b] != kNone) pool[s.spring_of[b]] = h.spring[source[b]];
      }
      lay_out_springs(s, kernel_threads(n), /*in_slot_order=*/true);  // checks the code range, adds the ranges' pools
    }
    // The boundary records: counts in the new order (reads at random: on the threads), their
    // running sums, then each particle's block copied.
    s.record_first.assign(n + 1, 0);
    PPOHDEM_OMP(omp parallel for schedule(static) if (n >= kParallelMin))
    for (std::size_t k = 0; k < n; ++k) s.record_first[k + 1] = h.record_first[before[k] + 1] - h.record_first[before[k]];
    for (std::size_t k = 0; k < n; ++k) s.record_first[k + 1] += s.record_first[k];
    s.records.resize(s.record_first[n]);
    PPOHDEM_OMP(omp parallel for schedule(static) if (n >= kParallelMin))
    for (std::size_t k = 0; k < n; ++k) {
      std::uint32_t r = s.record_first[k];
      for (std::uint32_t from = h.record_first[before[k]]; from < h.record_first[before[k] + 1]; ++from, ++r) {
        s.records[r] = h.records[from];
        s.records[r].particle = static_cast<std::uint32_t>(k);
      }
    }
  }

  /// A history dropped from the list (the pair moved apart by more than the skin within one
  /// step): its stored energy is dissipated, booked once (lower id side).
  void lost(std::vector<std::tuple<std::uint32_t, std::int64_t, double>>& to, const TangentialSpring& spring,
            std::size_t k, std::int64_t other) const {
    if (s.id[k] < other) to.emplace_back(s.original[k], other, spring.stored_energy());
  }

  /// The lost energies of this build, added in construction order (then partner id) on every
  /// rank: independent of the decomposition and of the cell order.
  void add_lost_energy() {
    if (distributed()) {
      Bytes mine;
      Packer p(mine);
      for (const auto& [o, other, e] : lost_terms) {
        p.put(o);
        p.put(other);
        p.put(e);
      }
      lost_terms.clear();
      for (const Bytes& block : comm->allgather(mine)) {
        Unpacker u(block);
        while (!u.done()) {
          const auto o = u.get<std::uint32_t>();
          const auto other = u.get<std::int64_t>();
          lost_terms.emplace_back(o, other, u.get<double>());
        }
      }
    }
    std::sort(lost_terms.begin(), lost_terms.end());
    if (energy_balance) {
      for (const auto& term : lost_terms) dissipated += std::get<2>(term);
    }
    lost_terms.clear();
  }

  /// Per-particle terms of the WHOLE system in construction order, on every rank:
  /// out[o * columns + c] = column c of particle o, filled by term(k, row) for owned k.
  template <class Term>
  std::vector<double> global_columns(std::size_t columns, Term term) const {
    std::vector<double> all(total * columns, 0.0);
    if (!distributed()) {
      for (std::size_t k = 0; k < s.owned; ++k) term(k, &all[s.original[k] * columns]);
      return all;
    }
    Bytes mine;
    Packer p(mine);
    std::vector<double> row(columns);
    for (std::size_t k = 0; k < s.owned; ++k) {
      term(k, row.data());
      p.put(s.original[k]);
      for (const double v : row) p.put(v);
    }
    for (const Bytes& block : comm->allgather(mine)) {
      Unpacker u(block);
      while (!u.done()) {
        const auto o = u.get<std::uint32_t>();
        for (std::size_t c = 0; c < columns; ++c) u.get(all[o * columns + c]);
      }
    }
    return all;
  }

  /// A force evaluation and the sums over particles. `closing_kick` (a step): the second half
  /// kick runs between the kernel and the sums, and with one rank the kinetic, rotational and
  /// gravitational sums of the new state come out of the same pass (cached for energies()).
  void evaluate_forces(double history_dt, bool closing_kick = false) {
    s.closing_kick = closing_kick;
    s.kick_closed = false;
    s.motion_terms = !lazy_sums();
    kernel->evaluate(s, static_cast<double>(steps) * s.dt, history_dt);
    motion_valid = false;
    if (closing_kick) close_step();
    if (lazy_sums()) {  // energies(), boundary_loads() and escaped_count() sum when asked
      loads_stale = true;
      out_valid = false;
      return;
    }
    if (!distributed()) {
      reduce_one_rank(history_dt, closing_kick);
      return;
    }
    // What the sums need from every rank, in ONE allgather per evaluation (with several
    // ranks): counts, the deepest contact and, with the energies tracked, the per-particle
    // energy terms (after a step's closing kick with the motion terms, so energies() needs no
    // gather of its own) and the boundary records, the tables as rows of bytes. Sums in
    // construction order: independent of the cell sort (so of restarts), of the decomposition
    // and of the thread count. Untracked, the energies and the loads are gathered and summed
    // when asked (the same rows in the same order, so the same bits): with every particle's
    // 64-byte row gathered and summed at every step, a 2-rank step of the settling bed took
    // 1.4x its cycles without (docs/performance.md "Threads cut across the longest axis").
    struct TermRow {  // 64 bytes: construction index and the 7 terms
      std::uint32_t original, unused;
      double values[7];  // elastic, dissipated, work, power, kinetic, rotational, gravitational
    };
    const bool gather_sums = energy_balance;
    std::vector<Load> all_records;
    std::vector<TermRow> term_rows;
    const std::size_t owned = s.owned;
    const std::size_t escaped_here = count_escaped();
    std::array<double, 7> sums{};  // (elastic, dissipated, work, power [J, J, J, W]; motion terms [J])
    {
      if (gather_sums) {
        term_rows.resize(owned);
        for (std::size_t k = 0; k < owned; ++k) {
          const FastState::ParticleTerms& c = s.terms[k];
          term_rows[k] = {s.original[k], 0, {c.elastic, c.dissipated, c.work, c.power, c.kinetic, c.rotational, c.gravitational}};
        }
      }
      const std::vector<Load> my_records = gather_sums ? own_loads() : std::vector<Load>{};
      Bytes mine;
      Packer pk(mine);
      pk.put(static_cast<std::uint64_t>(s.pair_contacts));
      pk.put(static_cast<std::uint64_t>(s.boundary_contacts));
      pk.put(static_cast<std::uint64_t>(escaped_here));
      pk.put(static_cast<std::uint8_t>(std::isfinite(s.screen) ? 1 : 0));
      pk.put(static_cast<std::uint8_t>(s.deepest ? 1 : 0));
      if (s.deepest) {
        pk.put(s.deepest->ratio);
        pk.put(s.deepest->overlap);
        pk.put(s.deepest->id_a);
        pk.put(s.deepest->id_b);
        pk.put(s.deepest->boundary);
      }
      pk.put(static_cast<std::uint64_t>(term_rows.size()));
      pk.put_rows(term_rows.data(), term_rows.size());
      pk.put(static_cast<std::uint64_t>(my_records.size()));
      pk.put_rows(my_records.data(), my_records.size());
      s.pair_contacts = 0;
      s.boundary_contacts = 0;
      escaped = 0;
      screens_finite = true;
      s.deepest.reset();
      if (gather_sums) all_terms.resize(total);  // every construction index is owned by one rank: all written
      for (const Bytes& block : comm->allgather(mine)) {
        Unpacker u(block);
        s.pair_contacts += u.get<std::uint64_t>();
        s.boundary_contacts += u.get<std::uint64_t>();
        escaped += u.get<std::uint64_t>();
        const bool screen_finite_there = u.get<std::uint8_t>() != 0;  // read whatever the flags so far
        screens_finite = screens_finite && screen_finite_there;
        if (u.get<std::uint8_t>() != 0) {
          // keep_deeper is a total order, so the rank order does not matter.
          LargestOverlap c;
          u.get(c.ratio);
          u.get(c.overlap);
          u.get(c.id_a);
          u.get(c.id_b);
          u.get(c.boundary);
          keep_deeper(s.deepest, c);
        }
        term_rows.clear();
        u.get_rows(term_rows, u.get<std::uint64_t>());
        for (const TermRow& row : term_rows) std::copy(row.values, row.values + 7, all_terms[row.original].begin());
        u.get_rows(all_records, u.get<std::uint64_t>());
      }
    }
    out_valid = false;
    if (!gather_sums) {  // energies() and boundary_loads() gather and sum when asked
      loads_stale = true;
      return;
    }
    sums = parallel_ordered_sum<7>(total, [&](std::size_t o) { return all_terms[o]; });
    if (closing_kick) {
      motion_sums = {sums[4], sums[5], sums[6]};
      motion_valid = true;
    }
    add_contact_sums({sums[0], sums[1], sums[2], sums[3]}, history_dt);
    add_gathered_loads(all_records);
  }

  /// A boundary record as sent between ranks (plain arrays: sent as bytes).
  struct Load {
    std::uint32_t original, boundary;
    double force[3], point[3];
  };

  /// This rank's boundary records of the last evaluation, by construction index.
  std::vector<Load> own_loads() const {
    std::vector<Load> mine(s.records.size());
    for (std::size_t r = 0; r < s.records.size(); ++r) {
      const BoundaryRecord& record = s.records[r];
      mine[r] = {s.original[record.particle], record.boundary, {record.force.x(), record.force.y(), record.force.z()},
                 {record.point.x(), record.point.y(), record.point.z()}};
    }
    return mine;
  }

  /// Boundary loads from every rank's records: minus the records' forces, in (construction
  /// index, boundary) order grouped in the blocks of construction indices of ordered_sum.hpp
  /// (each block from zero, then the blocks in order): the same bits for one rank (blocks on
  /// the threads, sum_loads) and several (the gathered records sorted).
  void add_gathered_loads(std::vector<Load>& all_records) const {
    const std::size_t nb = s.boundaries.size();
    block_loads.assign(sum_blocks(total) * nb, BoundaryLoad{});
    std::sort(all_records.begin(), all_records.end(), [](const Load& a, const Load& b) {
      return std::pair(a.original, a.boundary) < std::pair(b.original, b.boundary);
    });
    for (const Load& r : all_records) {
      add_load(block_loads.data() + r.original / kSumBlock * nb, r.boundary, Vec3(r.force[0], r.force[1], r.force[2]),
               Vec3(r.point[0], r.point[1], r.point[2]));
    }
    add_block_loads();
    loads_stale = false;
  }

  /// A record's load on its boundary: minus the contact force on the particle, its moment
  /// about the origin [N, N m].
  static void add_load(BoundaryLoad* block, std::uint32_t boundary, const Vec3& force, const Vec3& point) {
    block[boundary].force -= force;
    block[boundary].moment_about_origin += point.cross(-force);
  }

  /// Adds minus the forces of particle k's boundary records to the loads `block` (one per
  /// boundary), in boundary order.
  void add_records(BoundaryLoad* block, std::size_t k) const {
    for (std::uint32_t r = s.record_first[k]; r < s.record_first[k + 1]; ++r) {
      add_load(block, s.records[r].boundary, s.records[r].force, s.records[r].point);
    }
  }

  /// Owned particles that have crossed a boundary (one rank: all of them).
  std::size_t count_escaped() const {
    return static_cast<std::size_t>(std::count_if(s.escaped_via.begin(), s.escaped_via.begin() + static_cast<std::ptrdiff_t>(s.owned),
                                                  [](std::int32_t via) { return via != 0; }));
  }

  /// The loads of the last evaluation when they were not summed with it: one rank
  /// (lazy_sums()) as reduce_one_rank sums them; several ranks with the energies untracked
  /// gathered as evaluate_forces gathers them when tracked (collective).
  void sum_loads() const {
    if (distributed()) {  // collective: every rank's records (made on every rank, run.cpp)
      const std::vector<Load> mine = own_loads();
      Bytes packed;
      Packer pk(packed);
      pk.put(static_cast<std::uint64_t>(mine.size()));
      pk.put_rows(mine.data(), mine.size());
      std::vector<Load> all_records;
      for (const Bytes& block : comm->allgather(packed)) {
        Unpacker u(block);
        u.get_rows(all_records, u.get<std::uint64_t>());
      }
      add_gathered_loads(all_records);
      return;
    }
    const std::size_t nb = s.boundaries.size();
    const std::size_t count = sum_blocks(total);
    block_loads.assign(count * nb, BoundaryLoad{});
    PPOHDEM_OMP(omp parallel for schedule(static) if (total >= kParallelMin))
    for (std::size_t b = 0; b < count; ++b) {
      for (std::size_t o = b * kSumBlock; o < std::min(total, (b + 1) * kSumBlock); ++o) {
        add_records(block_loads.data() + b * nb, s.where[o]);
      }
    }
    add_block_loads();
    loads_stale = false;
  }

  /// loads = the blocks' loads (block_loads, blocks x boundaries) added in block order from zero.
  void add_block_loads() const {
    const std::size_t nb = s.boundaries.size();
    loads.assign(nb, BoundaryLoad{});
    for (std::size_t first = 0; first < block_loads.size(); first += nb) {
      for (std::size_t j = 0; j < nb; ++j) {
        loads[j].force += block_loads[first + j].force;
        loads[j].moment_about_origin += block_loads[first + j].moment_about_origin;
      }
    }
  }

  /// The contact energy terms of one evaluation added to the accumulators.
  void add_contact_sums(const std::array<double, 4>& sums, double history_dt) {
    if (!energy_balance) return;  // not tracked: the accumulators stay zero
    const auto [e, d, w, p] = sums;
    elastic = e;
    dissipated += d;
    boundary_work += w;
    // W = (P(n) + P(n+1)) dt / 2 (contact_force.hpp "Moving boundaries"); the start-up
    // evaluation (dt = 0) records P(0).
    boundary_work += 0.5 * (power + p) * history_dt;
    power = p;
  }

  /// One rank: every sum over particles in ONE pass over the blocks of construction indices of
  /// ordered_sum.hpp (the blocks on the threads): the four contact energy terms, the escaped
  /// count, the boundary loads (minus the records' forces, in (construction index, boundary)
  /// order within a block) and, after a closing kick, the kinetic, rotational and
  /// gravitational energies. Each sum is the one the separate ordered sums would give, bit for
  /// bit (the same terms in the same order); one pass reads each particle once instead of
  /// three or four times.
  void reduce_one_rank(double history_dt, bool motion) {
    const std::size_t nb = s.boundaries.size();
    const std::size_t count = sum_blocks(total);
    block_sums.assign(count, {});
    block_loads.assign(count * nb, BoundaryLoad{});
    PPOHDEM_OMP(omp parallel for schedule(static) if (total >= kParallelMin))
    for (std::size_t b = 0; b < count; ++b) {
      std::array<double, 7> sum{};
      BoundaryLoad* to = block_loads.data() + b * nb;
      for (std::size_t o = b * kSumBlock; o < std::min(total, (b + 1) * kSumBlock); ++o) {
        const std::size_t k = s.where[o];
        const FastState::ParticleTerms& c = s.terms[k];
        sum[0] += c.elastic;
        sum[1] += c.dissipated;
        sum[2] += c.work;
        sum[3] += c.power;
        if (motion) {  // written by close_step
          sum[4] += c.kinetic;
          sum[5] += c.rotational;
          sum[6] += c.gravitational;
        }
        add_records(to, k);
      }
      block_sums[b] = sum;
    }
    const std::array<double, 7> sums = add_blocks(block_sums);
    add_contact_sums({sums[0], sums[1], sums[2], sums[3]}, history_dt);
    if (motion) {
      motion_sums = {sums[4], sums[5], sums[6]};
      motion_valid = true;
    }
    // A count (in storage order: the sums above visit the particles in construction order,
    // a random order in memory).
    escaped = count_escaped();
    add_block_loads();
    out_valid = false;
  }

  /// The second half kick of every owned particle (close_kick, fast_state.hpp) unless the
  /// kernel's sum pass applied it; the next step's first half kick reuses it.
  void close_step() {
    if (!s.kick_closed) {  // else the kernel's sum pass applied it (fast_state.hpp)
      const std::size_t owned = s.owned;  // changed if the build migrated particles
      double screen = 0.0;
      PPOHDEM_OMP(omp parallel for schedule(static) reduction(+ : screen) if (owned >= kParallelMin))
      for (std::size_t i = 0; i < owned; ++i) screen += close_kick(s, i);
      s.screen = screen;
    }
    kick_cached = true;
  }

  void step() {
    const double dt = s.dt;
    const double half = 0.5 * dt;
    const Vec3 g = s.gravity;
    const std::size_t n = s.owned;
    double largest = 0.0;  // max |x - x_build|^2 [m^2]
    // Half kick and drift (the reference's expressions, so the same bits). The kick of
    // f(n) / m is the one the closing kick of the previous step computed from the same f(n):
    // that step left it in pv, pw (free between steps), which saves 6 of the 12 divisions of
    // a particle-step; after a (re)start the kick is computed afresh.
    const bool cached = kick_cached;
    PPOHDEM_OMP(omp parallel for schedule(static) reduction(max : largest) if (n >= kParallelMin))
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 kick = cached ? s.pv[i] : Vec3(half * (s.f[i] / s.mass[i] + g));
      const Vec3 spin_kick = cached ? s.pw[i] : Vec3(half * s.t[i] / s.inertia[i]);
      s.v[i] += kick;
      s.w[i] += spin_kick;
      s.x[i] += dt * s.v[i];
      s.pv[i] = s.v[i] + kick;
      s.pw[i] = s.w[i] + spin_kick;
      largest = std::max(largest, (s.x[i] - s.x_build[i]).squaredNorm());
    }
    ++steps;
    if (distributed()) largest = comm->max_over_ranks(largest);  // the same decision on every rank
    if (largest > 0.25 * skin * skin) {  // largest displacement > skin / 2
      build_lists();
    } else {
      refresh_ghosts();
    }
    evaluate_forces(dt, /*closing_kick=*/true);
    out_valid = false;
  }
};

FastEngine::FastEngine(const SimulationSetup& setup, FastOptions options) : impl_(std::make_unique<Impl>()) {
  validate_setup(setup);
  Impl& m = *impl_;
  if (options.comm != nullptr) m.comm = options.comm;
  m.s.dt = setup.dt;
  m.energy_balance = setup.energy_balance;
  m.s.gravity = setup.gravity;
  m.s.boundaries = setup.boundaries;
  m.s.walls.resize(setup.boundaries.size());
  m.s.is_wall.assign(setup.boundaries.size(), false);
  for (std::size_t b = 0; b < setup.boundaries.size(); ++b) {
    if (const auto* wall = dynamic_cast<const PlaneWall*>(setup.boundaries[b].get())) {
      m.s.is_wall[b] = true;
      m.s.walls[b].point0 = wall->point_at(0.0);
      m.s.walls[b].normal = wall->normal();
      m.s.walls[b].velocity = wall->velocity();
    }
  }
  // Histories if any pair of materials has friction (pair_laws.hpp).
  m.s.friction = std::visit([&](const auto& law) { return PairLaws(setup, law).any_friction(); }, setup.law);
  m.kernel = make_force_kernel(setup, options.vector_contacts);
  for (auto& p : setup.particles) m.r_max = std::max(m.r_max, p.radius);
  m.skin = options.skin_fraction * m.r_max;
  std::vector<Vec3> centres;
  for (const Particle& p : setup.particles) centres.push_back(p.position);
  m.decomposition = Decomposition(m.comm->size(), centres);
  // Only the materials are kept (a copy of the setup would hold a second copy of the particles).
  for (std::size_t k = 0; k < setup.material_count(); ++k) m.materials.push_back(setup.material_at(k));
  m.load_particles(setup.particles);
  std::fill(m.s.f.begin(), m.s.f.end(), Vec3::Zero());  // the first evaluation sets them
  std::fill(m.s.t.begin(), m.s.t.end(), Vec3::Zero());
  m.build_lists();
  m.evaluate_forces(0.0);  // a(0); no history increment at start-up
}

FastEngine::~FastEngine() = default;

std::unique_ptr<DemEngine> FastEngine::make(const SimulationSetup& setup) {
  return std::make_unique<FastEngine>(setup);
}

void FastEngine::step() { impl_->step(); }
long FastEngine::step_count() const { return impl_->steps; }
double FastEngine::time() const { return static_cast<double>(impl_->steps) * impl_->s.dt; }
int FastEngine::ranks() const { return impl_->comm->size(); }
std::array<int, 3> FastEngine::rank_grid() const { return impl_->decomposition.dims(); }
std::size_t FastEngine::owned_count() const { return impl_->s.owned; }
std::size_t FastEngine::ghost_count() const { return impl_->s.size() - impl_->s.owned; }

const Particles& FastEngine::particles() const {
  Impl& m = *impl_;
  if (!m.out_valid) {
    const FastState& s = m.s;
    m.out.resize(m.total);
    auto fill = [&](std::uint32_t o, const Particle& p) { m.out[o] = p; };
    Bytes mine;
    Packer pk(mine);
    for (std::size_t k = 0; k < s.owned; ++k) {
      Particle p;
      p.id = s.id[k];
      p.position = s.x[k];
      p.velocity = s.v[k];
      p.angular_velocity = s.w[k];
      p.radius = s.radius[k];
      p.material = s.material[k];
      p.force = s.f[k];
      p.torque = s.t[k];
      if (!m.distributed()) {
        fill(s.original[k], p);
        continue;
      }
      pk.put(s.original[k]);
      pk.put(p.id);
      pk.put(p.position);
      pk.put(p.velocity);
      pk.put(p.angular_velocity);
      pk.put(p.radius);
      pk.put(p.material);
      pk.put(p.force);
      pk.put(p.torque);
    }
    if (m.distributed()) {
      for (const Bytes& block : m.comm->allgather(mine)) {
        Unpacker u(block);
        while (!u.done()) {
          const auto o = u.get<std::uint32_t>();
          Particle p;
          u.get(p.id);
          u.get(p.position);
          u.get(p.velocity);
          u.get(p.angular_velocity);
          u.get(p.radius);
          u.get(p.material);
          u.get(p.force);
          u.get(p.torque);
          fill(o, p);
        }
      }
    }
    m.out_valid = true;
  }
  return m.out;
}

Energies FastEngine::energies() const {
  const Impl& m = *impl_;
  const FastState& s = m.s;
  // The reference's expressions and its summation order (ordered_sum.hpp): the same bits.
  auto energy_terms = [&](std::size_t i) { return motion_terms(m.s, i); };
  std::array<double, 3> sums{};
  if (m.motion_valid) {  // summed by the last step's pass (and gathered with several ranks)
    sums = m.motion_sums;
  } else if (!m.distributed()) {  // every particle here: construction order through `where`
    sums = parallel_ordered_sum<3>(m.total, [&](std::size_t o) { return energy_terms(s.where[o]); });
  } else {
    const std::vector<double> terms = m.global_columns(3, [&](std::size_t i, double* t) {
      const auto e = energy_terms(i);
      std::copy(e.begin(), e.end(), t);
    });
    sums = parallel_ordered_sum<3>(m.total, [&](std::size_t o) {
      return std::array{terms[3 * o], terms[3 * o + 1], terms[3 * o + 2]};
    });
  }
  Energies e;
  e.kinetic = sums[0];
  e.rotational = sums[1];
  e.gravitational = sums[2];
  e.elastic = m.elastic;
  e.dissipated = m.dissipated;
  e.boundary_work = m.boundary_work;
  if (!m.energy_balance) e.elastic = e.dissipated = e.boundary_work = std::numeric_limits<double>::quiet_NaN();
  return e;
}

ContactCounts FastEngine::contact_counts() const {
  return {impl_->s.pair_contacts, impl_->s.boundary_contacts};
}

std::size_t FastEngine::escaped_count() const {
  const Impl& m = *impl_;
  return m.lazy_sums() ? m.count_escaped() : m.escaped;
}

std::vector<BoundaryLoad> FastEngine::boundary_loads() const {
  if (impl_->loads_stale) impl_->sum_loads();
  return impl_->loads;
}

bool FastEngine::motion_finite() const {
  const Impl& m = *impl_;
  // The screen of the last closing kick (after a (re)load there is none yet: the energies'),
  // with several ranks every rank's, gathered with the evaluation's counts.
  if (!m.energy_balance && m.kick_cached) return m.distributed() ? m.screens_finite : std::isfinite(m.s.screen);
  return DemEngine::motion_finite();
}

std::optional<LargestOverlap> FastEngine::largest_overlap() const {
  // The reference reports ratio 0 (no contact) as an empty record; so do we.
  return impl_->s.deepest.value_or(LargestOverlap{});
}

long FastEngine::neighbour_list_builds() const { return impl_->builds; }
double FastEngine::skin() const { return impl_->skin; }
std::size_t FastEngine::neighbour_slots() const { return impl_->s.partner.size(); }
const ThreadSpeeds& FastEngine::thread_speeds() const { return impl_->s.thread_speeds; }

std::size_t FastEngine::memory_bytes() const {
  const FastState& s = impl_->s;
  std::size_t pool_bytes = bytes(s.spring_pools) + bytes(s.result_pools) + bytes(s.mirror) + bytes(s.upper_first);
  for (const auto& pool : s.spring_pools) pool_bytes += bytes(pool);
  for (const auto& pool : s.result_pools) pool_bytes += bytes(pool);
  pool_bytes += bytes(impl_->search_buffers) + bytes(impl_->search_probes.x) + bytes(impl_->search_probes.y) + bytes(impl_->search_probes.z) +
                bytes(impl_->search_probes.r) + bytes(impl_->all_terms);  // the engine's reused work buffers
  for (const auto& buffer : impl_->search_buffers) pool_bytes += bytes(buffer);
  const History& h = impl_->history;  // kept between list builds
  pool_bytes += bytes(h.first) + bytes(h.partner_id) + bytes(h.spring) + bytes(h.record_first) + bytes(h.records);
  return bytes(s.id) + bytes(s.original) + bytes(s.where) + bytes(s.x) + bytes(s.v) + bytes(s.w) + bytes(s.f) + bytes(s.t) +
         bytes(s.pv) + bytes(s.pw) + bytes(s.x_build) + bytes(s.radius) + bytes(s.mass) + bytes(s.inertia) + bytes(s.material) +
         bytes(s.escaped_via) + bytes(s.terms) + bytes(s.first) +
         bytes(s.partner) + bytes(s.spring_of) + bytes(s.lower_code) + pool_bytes + bytes(s.records) + bytes(s.record_first) +
         bytes(s.next_records) + bytes(s.next_record_first) + bytes(s.near_boundaries);
}

EngineState FastEngine::save_state() const {
  const Impl& m = *impl_;
  const FastState& s = m.s;
  EngineState state;
  state.engine = name();
  state.step = m.steps;
  state.dt = s.dt;
  state.particles = particles();  // whole system (gathered)
  if (s.friction) {
    // This rank's records (pairs from the lower-id side, which is owned here), then all ranks'.
    Bytes mine;
    Packer pk(mine);
    auto put = [&](ContactHistoryRecord::Kind kind, std::int64_t a, std::int64_t b, const TangentialSpring& sp) {
      pk.put(kind);
      pk.put(a);
      pk.put(b);
      pk.put(sp);
    };
    for (std::size_t k = 0; k < s.owned; ++k) {
      for (std::uint32_t slot = s.first[k]; slot < s.first[k + 1]; ++slot) {
        const std::uint32_t j = s.partner[slot];
        if (s.spring_of[slot] == kNoSpring || s.id[k] > s.id[j]) continue;
        // A slot keeps a spring only while its pair touched at the last evaluation, whose
        // positions these still are; the branch vectors are the ones it computed (the same
        // expressions, pair_geometry), which the kernel stores only when the energies are
        // tracked (their only other use): the checkpoint is the same either way.
        TangentialSpring sp = s.spring_at(s.spring_of[slot]);
        const PairGeometry g = pair_geometry(s, k, j, s.x[k] - s.x[j]);
        sp.branch_i = g.r_i;
        sp.branch_j = g.r_j;
        if (sp.stiffness != 0.0 || sp.branch_i != Vec3::Zero()) {
          put(ContactHistoryRecord::Kind::kParticlePair, s.id[k], s.id[j], sp);
        }
      }
    }
    for (const BoundaryRecord& r : s.records) {
      put(ContactHistoryRecord::Kind::kParticleBoundary, s.id[r.particle], static_cast<std::int64_t>(r.boundary), r.spring);
    }
    for (const Bytes& block : m.comm->allgather(mine)) {
      Unpacker u(block);
      while (!u.done()) {
        ContactHistoryRecord c;
        u.get(c.kind);
        u.get(c.id_a);
        u.get(c.id_b);
        u.get(c.spring);
        state.contacts.push_back(c);
      }
    }
    std::sort(state.contacts.begin(), state.contacts.end(), [](const auto& a, const auto& b) {
      return std::tuple(a.kind, a.id_a, a.id_b) < std::tuple(b.kind, b.id_a, b.id_b);
    });
  }
  state.accumulators = energies();
  {
    Bytes mine;
    Packer pk(mine);
    for (std::size_t k = 0; k < s.owned; ++k) {
      if (s.escaped_via[k] != 0) pk.put(s.id[k]);
    }
    for (const Bytes& block : m.comm->allgather(mine)) {
      Unpacker u(block);
      while (!u.done()) state.escaped_ids.push_back(u.get<std::int64_t>());
    }
  }
  std::sort(state.escaped_ids.begin(), state.escaped_ids.end());
  if (m.loads_stale) m.sum_loads();
  state.boundary_loads = m.loads;
  state.contact_counts = contact_counts();
  state.boundary_power = m.power;  // P(n), for the next trapezoid step of boundary_work
  return state;
}

void FastEngine::restore_state(const EngineState& state) {
  Impl& m = *impl_;
  FastState& s = m.s;
  const Particles& current = particles();  // whole system (collective)
  if (state.dt != s.dt) throw InputError("restore_state: the checkpoint's dt differs from the scene's");
  if (state.particles.size() != current.size()) {
    throw InputError("restore_state: the checkpoint has " + std::to_string(state.particles.size()) +
                     " particles, the scene " + std::to_string(current.size()));
  }
  for (std::size_t i = 0; i < current.size(); ++i) {
    if (state.particles[i].id != current[i].id || state.particles[i].radius != current[i].radius ||
        state.particles[i].material != current[i].material) {
      throw InputError("restore_state: particle " + std::to_string(i) + " (id " +
                       std::to_string(state.particles[i].id) + ") does not match the scene");
    }
  }
  if (state.boundary_loads.size() != s.boundaries.size()) {
    throw InputError("restore_state: the checkpoint's boundary count differs from the scene's");
  }
  // Validate the records against the whole system on every rank (so that every rank throws
  // or none does), then install each on the rank owning its particle.
  std::unordered_map<std::int64_t, std::uint32_t> index_of;  // id -> construction index
  for (std::size_t i = 0; i < state.particles.size(); ++i) index_of[state.particles[i].id] = static_cast<std::uint32_t>(i);
  auto known = [&](std::int64_t id) {
    if (!index_of.count(id)) throw InputError("restore_state: contact names unknown particle id " + std::to_string(id));
  };
  for (const std::int64_t id : state.escaped_ids) known(id);
  for (const ContactHistoryRecord& c : state.contacts) {
    known(c.id_a);
    if (c.kind == ContactHistoryRecord::Kind::kParticleBoundary) {
      if (c.id_b < 0 || static_cast<std::size_t>(c.id_b) >= s.boundaries.size()) {
        throw InputError("restore_state: boundary index " + std::to_string(c.id_b) + " out of range");
      }
    } else {
      known(c.id_b);
    }
  }
  m.load_particles(state.particles);
  m.steps = state.step;
  m.elastic = state.accumulators.elastic;
  m.dissipated = state.accumulators.dissipated;
  m.boundary_work = state.accumulators.boundary_work;
  m.loads = state.boundary_loads;
  m.loads_stale = false;
  m.power = state.boundary_power;
  m.escaped = state.escaped_ids.size();
  s.deepest.reset();  // of the evaluation before the checkpoint: not saved (as the reference)
  m.build_lists();
  s.pair_contacts = state.contact_counts.particle_pairs;
  s.boundary_contacts = state.contact_counts.particle_boundary;
  std::unordered_map<std::int64_t, std::uint32_t> where;  // id -> storage index (owned and ghosts)
  for (std::size_t k = 0; k < s.size(); ++k) where[s.id[k]] = static_cast<std::uint32_t>(k);
  auto owned_index = [&](std::int64_t id) -> std::optional<std::size_t> {
    const auto it = where.find(id);
    if (it == where.end() || it->second >= s.owned) return std::nullopt;
    return it->second;
  };
  for (const std::int64_t id : state.escaped_ids) {
    if (const auto k = owned_index(id)) s.escaped_via[*k] = 1;  // the boundary is only used in the warning
  }
  std::vector<BoundaryRecord> records;
  bool misplaced = false;  // a pair record between particles that are not neighbours
  for (const ContactHistoryRecord& c : state.contacts) {
    if (c.kind == ContactHistoryRecord::Kind::kParticleBoundary) {
      if (const auto a = owned_index(c.id_a)) {
        BoundaryRecord r;
        r.particle = static_cast<std::uint32_t>(*a);
        r.boundary = static_cast<std::uint32_t>(c.id_b);
        r.spring = c.spring;
        records.push_back(r);
      }
      continue;
    }
    if (!s.friction) continue;
    auto install = [&](std::int64_t self_id, std::int64_t other_id, const TangentialSpring& spring) {
      const auto self = owned_index(self_id);
      if (!self) return;
      const auto begin = s.partner.begin() + s.first[*self];
      const auto end = s.partner.begin() + s.first[*self + 1];
      const auto it = std::lower_bound(begin, end, other_id, [&](std::uint32_t j, std::int64_t id) { return s.id[j] < id; });
      if (it == end || s.id[*it] != other_id) {
        misplaced = true;
        return;
      }
      if (*it < s.owned && other_id < self_id) return;  // kept by the owned lower-id side
      std::uint32_t& code = s.spring_of[static_cast<std::size_t>(it - s.partner.begin())];
      if (code == kNoSpring) code = s.new_spring(0);
      s.spring_at(code) = spring;
      s.lower_codes_valid = false;
    };
    install(c.id_a, c.id_b, c.spring);
    install(c.id_b, c.id_a, mirrored(c.spring));
  }
  if (m.distributed()) misplaced = m.comm->max_over_ranks(misplaced ? 1.0 : 0.0) > 0.0;
  if (misplaced) throw InputError("restore_state: a contact history joins particles that are not neighbours");
  std::sort(records.begin(), records.end(), [](const BoundaryRecord& x, const BoundaryRecord& y) {
    return std::pair(x.particle, x.boundary) < std::pair(y.particle, y.boundary);
  });
  s.records = std::move(records);
  s.record_first.assign(s.owned + 1, 0);
  for (const BoundaryRecord& r : s.records) ++s.record_first[r.particle + 1];
  for (std::size_t i = 0; i < s.owned; ++i) s.record_first[i + 1] += s.record_first[i];
  m.out_valid = false;
}

}  // namespace ppohdem::dem::fast
