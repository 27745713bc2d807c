// The fast engine's force kernel: one template per (law, friction, walls, other boundaries,
// several materials, energies tracked), chosen once at construction (make_force_kernel). A
// one-material scene runs the kernel without the pair-law lookup (kMulti = false: the one law
// is a member). Each particle adds all of ITS contacts (full neighbour list): those with
// higher-id partners in ascending id, then those with lower-id partners in descending id,
// then its boundary contacts in boundary order. That is the order in which the reference
// engine adds them to that particle (its pair pass visits the pairs by lower id descending,
// reference/src/dem/force_passes.hpp), with each contact bitwise the negation of the
// reference's (i, j) evaluation when this particle is j. No thread writes another particle's
// data, so the loops need no atomics; per-particle results are independent of the number of
// threads.
//
// An evaluation runs these passes (each in its own function, all inlined into evaluate()):
//   prepare_ranges      wall positions, the threads' ranges, spring pools and links
//   pair pass           per range: pair contacts, then each particle's boundaries
//                       (force_pairs.hpp, force_boundaries.hpp); with the halo refresh in
//                       flight, each range's interior part, the refresh completed, then its
//                       halo layer (docs/dem.md "The halo refresh behind the interior")
//   size_record_table   the new boundary records' table (force_sums.hpp)
//   sum pass            frictional kernels: each particle adds its lower-id partners' results
//                       and its boundary records, and closes the step's kick (force_sums.hpp)
//   fill_record_table   the ranges' record blocks into the table (force_sums.hpp)
//   gather_ranges       counts, deepest contact, escapes, records swapped in (force_sums.hpp)
//
// Each pair once (frictional kernels, kHalf). A pair of two owned particles is evaluated only
// by its lower-id side, as the reference does; the evaluation stores its force and both
// torques (PairResult, next to the spring, found through the spring's code), and only that
// side keeps the history (the other side's is its exact mirror: fast_engine.cpp derives it
// when the list is rebuilt). The pair pass sums each particle's own (higher-id) contacts right
// after their evaluation; the sum pass, after a barrier, adds the rest. A ghost partner's pair
// is evaluated from this side as before (the ghost's own rank evaluates its side). Why each
// pair once, and why the other side's history is derived rather than written at every
// evaluation (a scattered write per contact): docs/performance.md, "Kept optimisations".
// Why chunks and four contacts at a time: force_pairs.hpp, docs/performance.md "Four contacts
// at a time" and "The law adds its own sums".
//
// kEnergy false ([simulation] energy_balance = false): no contact energy terms at all (the
// previous-arms displacement, elastic energy, the dissipation and boundary-work terms); the
// forces, torques and histories are the same bit for bit (docs/performance.md).
#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <type_traits>
#include <variant>

#include "fast_state.hpp"
#include "force_boundaries.hpp"
#include "force_pairs.hpp"
#include "force_pass.hpp"
#include "force_sums.hpp"
#include "hertz_mindlin_x4.hpp"
#include "ppohdem/dem/material.hpp"
#include "ppohdem/dem/pair_laws.hpp"

namespace ppohdem::dem::fast {
namespace {

/// Before the passes: the walls' points at `time`, the threads' ranges (balance_split; the
/// spring pools laid out afresh if the ranges move with new springs in them), and for the
/// frictional kernels the sum pass's shares, the lower-id codes and the result pools. Returns
/// the number of threads (= ranges).
template <class K>
int prepare_ranges(FastState& s, double time) {
  const std::size_t n = s.owned;
  if constexpr (K::kWalls) {
    for (std::size_t b = 0; b < s.boundaries.size(); ++b) {
      if (s.is_wall[b]) s.walls[b].point = s.walls[b].point0 + s.walls[b].velocity * time;  // PlaneWall::point_at
    }
  }
  // One range of particles per thread, balanced by estimated work corrected by the ranges'
  // measured times (balance_split), so a bed whose contacts sit in one part of the cell order
  // does not idle a thread. Range r appends its new springs to pool 1 + r only; ranges move
  // only when the pools are laid out afresh, so no two threads ever touch the same pool.
  const int threads = kernel_threads(n);
  const auto ranges = static_cast<std::size_t>(threads);
  if (s.threads.size() < ranges) s.threads.resize(ranges);
  if constexpr (K::kFriction) {
    if (s.spring_pools.size() != ranges + 1) lay_out_springs(s, threads);
  }
  if (s.split_stale || s.split.size() != ranges + 1) {
    if constexpr (K::kFriction) {
      bool pools_empty = true;
      for (std::size_t pool = 1; pool < s.spring_pools.size(); ++pool) pools_empty = pools_empty && s.spring_pools[pool].empty();
      if (!pools_empty) lay_out_springs(s, threads);
    }
    balance_split(s, threads);
  }
  if (K::kRecords && s.next_record_first.size() != n + 1) s.next_record_first.assign(n + 1, 0);
  if constexpr (K::kHalf) {
    if (s.mirror.size() != s.partner.size() || s.upper_first.size() != n) {
      throw std::logic_error("fast engine: neighbour mirrors not linked");
    }
    // The sum pass's ranges, even at first.
    if (s.sum_share.size() != ranges || s.sum_seconds.size() != ranges) {
      s.sum_share.assign(ranges, 1.0 / static_cast<double>(ranges));
      s.sum_seconds.assign(ranges, 0.0);
      s.sum_evaluations = 0;
    }
    if (!s.lower_codes_valid || s.lower_code.size() != s.partner.size()) link_lower_codes(s);
    s.result_pools.resize(s.spring_pools.size());
    for (std::size_t pool = 0; pool < s.spring_pools.size(); ++pool) {
      if (s.result_pools[pool].size() < s.spring_pools[pool].size()) s.result_pools[pool].resize(s.spring_pools[pool].size());
    }
  }
  return threads;
}

template <class LawT, bool Friction, bool Walls, bool Others, bool Multi, bool Energy>
class Kernel final : public ForceKernel {
 public:
  using Law = LawT;
  static constexpr bool kFriction = Friction;
  static constexpr bool kWalls = Walls;
  static constexpr bool kOthers = Others;
  static constexpr bool kMulti = Multi;  ///< several materials: the law looked up per pair
  static constexpr bool kEnergy = Energy;
  static constexpr bool kRecords = kWalls || kOthers;
  static constexpr bool kHalf = kFriction;  ///< each pair of owned particles evaluated once
  /// The contact law runs four contacts at a time for one Hertz-Mindlin law with friction.
  static constexpr bool kX4 = std::is_same_v<Law, HertzMindlin> && kFriction && !kMulti;

  Kernel(const PairLaws<Law>& laws, bool vector_contacts)
      : laws_(laws), law_(laws.pair(0, 0)),
        x4_(kX4 && vector_contacts && x4_contacts_available() && !laws.any_rolling() &&
           !laws.any_tangential_damping()) {}

  /// The contacts entries[0, count) of a chunk (friction): springs and pair results, four or
  /// eight at a time (hertz_mindlin_x4) or one at a time, the same bits. In lanes the law also
  /// adds the upper contacts to s.f, s.t (and, tracked, their energy terms to the chunk's), counts
  /// them and offers them as the deepest (`sums`, OwnSums), so no booking walks the entries
  /// again; returns whether it did. One at a time, the entries keep their energies and
  /// overlaps for the booking (docs/performance.md "The law adds its own sums").
  bool evaluate_contacts(FastState& s, PairEntry* entries, std::size_t count, double dt,
                         [[maybe_unused]] OwnSums& sums) const {
    if constexpr (kX4) {
      if (x4_) {
        hertz_mindlin_x4<kEnergy>(law_, s, entries, count, dt, &sums);
        return true;
      }
    }
    evaluate_contacts_one_by_one(*this, s, entries, count, dt);
    return false;
  }

  /// The law of particles i and j (storage indices), and of particle i with boundary b.
  const Law& pair_law(const FastState& s, std::size_t i, std::size_t j) const {
    if constexpr (kMulti) return laws_.pair(s.material[i], s.material[j]);
    return law_;
  }
  const Law& boundary_law(const FastState& s, std::size_t i, std::size_t b) const {
    if constexpr (kMulti) return laws_.boundary(s.material[i], b);
    return law_;
  }

  // flatten: inline the passes, the contact law and contact_force.hpp into the loops (no
  // change in the arithmetic: GCC does not reassociate or contract without -ffast-math / FMA
  // targets).
  [[gnu::flatten]] void evaluate(FastState& s, double time, double dt, HaloInFlight* halo) const override {
    const std::size_t n = s.owned;  // ghosts ([owned, size())) are partners only
    const std::size_t nb = s.boundaries.size();
    const std::uint32_t near_mask = nb < 32 ? (std::uint32_t{1} << nb) - 1u : ~std::uint32_t{0};  // near_boundaries' bits
    const int threads = prepare_ranges<Kernel>(s, time);
    const auto ranges = static_cast<std::size_t>(threads);
    const bool has_ghosts = s.size() > n;
    // Fewer pair contacts than half the particles at the last evaluation: most particles
    // touch nothing, and the sum pass skips their lower-id results (the same bits either way).
    const bool dilute = 2 * s.pair_contacts < n;
    // With the halo refresh in flight each range runs its interior particles, then (after the
    // master thread has completed the refresh, and a barrier) its halo layer: the same
    // particles in the same order, cut at one more chunk boundary (the same bits).
    const std::size_t interior = halo != nullptr ? std::min(s.n_interior, n) : n;
    std::size_t pairs = 0;
    std::size_t touching_boundaries = 0;
    PPOHDEM_OMP(omp parallel num_threads(threads) reduction(+ : pairs, touching_boundaries))
    {
      // The pair pass over [begin, end) of range `range` (a part of it, or all of it).
      auto pair_pass = [&](std::size_t range, std::size_t begin, std::size_t end, HaloInFlight* poll) {
        const auto started = std::chrono::steady_clock::now();  // for balance_split
        RangePass pass{s, time, dt, range, s.threads[range], pairs, touching_boundaries, n, nb, near_mask, has_ghosts,
                       begin, end, poll};
        if constexpr (kFriction) {
          frictional_pair_pass(*this, pass);
        } else {
          frictionless_pair_pass(*this, pass);
        }
        if constexpr (kEnergy) pass.out.add_dissipation_buffer();
        s.range_seconds[range] += std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
      };
      PPOHDEM_OMP(omp for schedule(static, 1) nowait)
      for (std::size_t range = 0; range < ranges; ++range) {
        ThreadOutput& out = s.threads[range];
        out.records.clear();
        out.newly_escaped.clear();
        out.deepest.reset();
        if constexpr (kEnergy) {
          for (ExactSum& rate : out.rates) rate.reset();
          out.buffered = 0;
        }
        const std::size_t begin = s.split[range];
        const std::size_t end = std::max(begin, std::min(s.split[range + 1], interior));
        pair_pass(range, begin, end, halo != nullptr && thread_id() == 0 ? halo : nullptr);
      }
      if (halo != nullptr) {
        PPOHDEM_OMP(omp master)
        halo->complete();
      }
      PPOHDEM_OMP(omp barrier)
      if (interior < n) {
        PPOHDEM_OMP(omp for schedule(static, 1))
        for (std::size_t range = 0; range < ranges; ++range) {
          const std::size_t end = s.split[range + 1];
          pair_pass(range, std::min(end, std::max(s.split[range], interior)), end, nullptr);
        }
      }
      size_record_table<Kernel>(s, ranges);
      if constexpr (kHalf) {
        if (dilute) {
          sum_pass<Kernel, true>(s, ranges, n, has_ghosts);
        } else {
          sum_pass<Kernel, false>(s, ranges, n, has_ghosts);
        }
      }
      fill_record_table<Kernel>(s, ranges);
    }
    gather_ranges<Kernel>(s, ranges, n, pairs, touching_boundaries, time);
  }

 private:
  PairLaws<Law> laws_;  ///< kMulti only
  Law law_;             ///< the one law (= laws_.pair(0, 0))
  bool x4_ = false;     ///< kX4 and the CPU has AVX and the engine allows it
};

template <class Law, bool kFriction, bool kWalls, bool kOthers, bool kEnergy>
std::unique_ptr<ForceKernel> with_materials(const PairLaws<Law>& laws, bool vector_contacts) {
  if (laws.materials() > 1) return std::make_unique<Kernel<Law, kFriction, kWalls, kOthers, true, kEnergy>>(laws, vector_contacts);
  return std::make_unique<Kernel<Law, kFriction, kWalls, kOthers, false, kEnergy>>(laws, vector_contacts);
}

template <class Law, bool kFriction, bool kWalls, bool kEnergy>
std::unique_ptr<ForceKernel> with_others(const PairLaws<Law>& laws, bool others, bool vector_contacts) {
  if (others) return with_materials<Law, kFriction, kWalls, true, kEnergy>(laws, vector_contacts);
  return with_materials<Law, kFriction, kWalls, false, kEnergy>(laws, vector_contacts);
}

template <class Law, bool kFriction, bool kEnergy>
std::unique_ptr<ForceKernel> with_walls(const PairLaws<Law>& laws, bool walls, bool others, bool vector_contacts) {
  if (walls) return with_others<Law, kFriction, true, kEnergy>(laws, others, vector_contacts);
  return with_others<Law, kFriction, false, kEnergy>(laws, others, vector_contacts);
}

}  // namespace

std::unique_ptr<ForceKernel> make_force_kernel(const SimulationSetup& setup, bool vector_contacts) {
  bool walls = false;
  bool others = false;
  for (const auto& b : setup.boundaries) {
    if (dynamic_cast<const PlaneWall*>(b.get())) {
      walls = true;
    } else {
      others = true;
    }
  }
  return std::visit(
      [&](const auto& law) -> std::unique_ptr<ForceKernel> {
        using Law = std::decay_t<decltype(law)>;
        const PairLaws<Law> laws(setup, law);
        if (setup.energy_balance) {
          if (laws.any_friction()) return with_walls<Law, true, true>(laws, walls, others, vector_contacts);
          return with_walls<Law, false, true>(laws, walls, others, vector_contacts);
        }
        if (laws.any_friction()) return with_walls<Law, true, false>(laws, walls, others, vector_contacts);
        return with_walls<Law, false, false>(laws, walls, others, vector_contacts);
      },
      setup.law);
}

}  // namespace ppohdem::dem::fast
