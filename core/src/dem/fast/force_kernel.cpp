// The fast engine's force kernel: one template per (law, friction, walls, other boundaries,
// several materials), chosen once at construction (make_force_kernel). A one-material scene
// runs the kernel without the pair-law lookup (kMulti = false: the one law is a member). Each
// particle adds all of ITS contacts (full neighbour list): those with higher-id partners in
// ascending id, then those with lower-id partners in descending id, then its boundary
// contacts in boundary order. That is the order in which the reference engine adds them to
// that particle (its pair pass visits the pairs by lower id descending, reference/src/dem/
// force_passes.hpp), with each contact bitwise the negation of the reference's (i, j)
// evaluation when this particle is j. No thread writes another particle's data, so the loop
// needs no atomics; per-particle results are independent of the number of threads.
//
// Each pair once (frictional kernels, kHalf). A pair of two owned particles is evaluated only
// by its lower-id side, as the reference does; the evaluation stores its force and both
// torques (PairResult, next to the spring, found through the spring's code), and only that
// side keeps the history (the other side's is its exact mirror: fast_engine.cpp derives it
// when the list is rebuilt). The first pass sums each particle's own (higher-id) contacts
// right after their evaluation, into f and t. A second pass, after a barrier, adds the
// negated results of its lower-id partners (-f and -(r_j x f) are bitwise the partner side's
// f' and r' x f') and then its boundary records; at the end of a step it also applies the
// particle's closing kick (close_kick, fast_state.hpp) while f and t are in registers,
// instead of a separate pass of the engine. Each pass writes only its own particles' data, so
// neither needs atomics. A ghost partner's pair is evaluated from this side as before (the
// ghost's own rank evaluates its side). Why each pair once, and why the other side's history
// is derived rather than written at every evaluation (a scattered write per contact):
// docs/performance.md, "Kept optimisations".
//
// Chunks (frictional kernels). The first pass takes 64 particles at a time: it lists their
// slots' touching pairs (and the contacts that ended, whose stored energy is lost) in slot
// order, evaluates the listed contacts (four at a time with AVX for one Hertz-Mindlin law:
// hertz_mindlin_x4.hpp, the same bits), then books each particle's entries in slot order and
// adds its boundaries, so every sum keeps the order of one particle at a time. Measured on the
// settled bed: docs/performance.md "Four contacts at a time". With the energies untracked the
// four-lane law adds each particle's own contacts itself, in the same order (OwnSums), and
// the booking has nothing left to do: docs/performance.md "The law adds its own sums".
#include <algorithm>
#include <bit>
#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <type_traits>
#include <variant>

#include "fast_state.hpp"
#include "hertz_mindlin_x4.hpp"
#include "ppohdem/dem/material.hpp"
#include "ppohdem/dem/pair_laws.hpp"

namespace ppohdem::dem::fast {
namespace {

/// The result of the pair whose code is `code`; for kNoSpring the never-written zero result of
/// pool 0's first entry (fast_state.hpp), so a slot without contact needs no test (GCC turns a
/// test into a branch, which mispredicts: callgrind --branch-sim).
inline const PairResult& result_or_zero(const FastState& s, std::uint32_t code) { return s.result_at(code); }

/// harmonic_pair (material.cpp) for finite values, inline: a b / (a + b), symmetric in a, b.
inline double pair_value(double a, double b) { return a * b / (a + b); }

/// The kinematics of touching particles i and j with d = x_i - x_j (the reference's
/// expressions, force_passes.hpp): normal, overlap, the contact's branch vectors r_i, r_j and
/// the relative velocity at the evaluation time (not the step's displacement).
struct PairKinematics {
  ContactKinematics k;
  Vec3 r_i, r_j;  ///< centre of i (of j) to the contact point [m]
};
inline PairKinematics pair_kinematics(const FastState& s, std::size_t i, std::size_t j, const Vec3& d) {
  const PairGeometry g = pair_geometry(s, i, j, d);
  const double ri = s.radius[i];
  PairKinematics p;
  ContactKinematics& k = p.k;
  k.normal = g.normal;
  k.overlap = g.overlap;
  p.r_i = g.r_i;
  p.r_j = g.r_j;
  k.relative_velocity = (s.pv[i] + s.pw[i].cross(p.r_i)) - (s.pv[j] + s.pw[j].cross(p.r_j));
  k.pair.m_eff = pair_value(s.mass[i], s.mass[j]);
  k.pair.r_eff = pair_value(ri, s.radius[j]);
  return p;
}

// kEnergy false ([simulation] energy_balance = false): no contact energy terms at all (the
// previous-arms displacement, elastic energy, the dissipation and boundary-work terms); the
// forces, torques and histories are the same bit for bit (docs/performance.md).
/// Particles per chunk of the frictional kernels' first pass (their pair lists stay in L1).
constexpr std::size_t kChunk = 64;
/// Evaluations between two cuts of the sum pass by its measured times: a few milliseconds of
/// that pass in a bench-sized bed, long enough for the clock (steady_clock, two reads per range
/// and evaluation) and short next to how fast the bed's work moves.
constexpr unsigned kSumRecut = 20;

template <class Law, bool kFriction, bool kWalls, bool kOthers, bool kMulti, bool kEnergy>
class Kernel final : public ForceKernel {
 public:
  /// The contact law runs four contacts at a time for one Hertz-Mindlin law with friction.
  static constexpr bool kX4 = std::is_same_v<Law, HertzMindlin> && kFriction && !kMulti;

  Kernel(const PairLaws<Law>& laws, bool vector_contacts)
      : laws_(laws), law_(laws.pair(0, 0)),
        x4_(kX4 && vector_contacts && x4_contacts_available() && !laws.any_rolling()) {}

  /// The contacts entries[contacts[k]], k < count, of a chunk (friction; `contacts` null: the
  /// entries 0 to count - 1): springs, pair results and the entries' energies and overlaps.
  /// Four at a time (hertz_mindlin_x4) or one at a time, the same bits.
  /// With AVX and the energies untracked, the law also adds the upper contacts to s.f, s.t,
  /// counts them and offers them as the deepest (`sums`, OwnSums), so the booking has nothing
  /// left to do; returns whether it did. With the energies tracked the booking still walks the
  /// entries for their energy terms, and the law adding the forces as well was slower
  /// (docs/performance.md "The law adds its own sums").
  bool evaluate_contacts(FastState& s, PairEntry* entries, const std::uint32_t* contacts, std::size_t count,
                         double dt, [[maybe_unused]] OwnSums& sums) const {
    if constexpr (kX4) {
      if (x4_) {
        hertz_mindlin_x4<kEnergy>(law_, s, entries, contacts, count, dt, kEnergy ? nullptr : &sums);
        return !kEnergy;
      }
    }
    for (std::size_t c = 0; c < count; ++c) {
      PairEntry& entry = entries[contacts != nullptr ? contacts[c] : c];
      const std::size_t i = entry.i;
      const std::uint32_t j = entry.j;
      PairKinematics p = pair_kinematics(s, i, j, s.x[i] - s.x[j]);
      ContactKinematics& k = p.k;
      const Vec3& r_i = p.r_i;
      const Vec3& r_j = p.r_j;
      k.relative_displacement = dt * ((s.v[i] + s.w[i].cross(r_i)) - (s.v[j] + s.w[j].cross(r_j)));
      TangentialSpring& sp = s.spring_at(entry.code);
      if constexpr (kEnergy) {  // the energy terms' only use
        k.relative_displacement_previous_arms =
            dt * ((s.v[i] + s.w[i].cross(sp.branch_i)) - (s.v[j] + s.w[j].cross(sp.branch_j)));
      }
      if (s.rolling) {  // rolling_resistance.hpp
        k.relative_spin = s.pw[i] - s.pw[j];
        k.relative_rotation = dt * (s.w[i] - s.w[j]);
      }
      const ContactForce f = frictional_contact_force(pair_law(s, i, j), k, sp, dt);
      if constexpr (kEnergy) {  // their only use (save_state writes them from the positions)
        sp.branch_i = r_i;
        sp.branch_j = r_j;
      }
      PairResult& result = s.result_at(entry.code);
      result.force = f.on_i;
      if (s.rolling) {  // the reference's sums (force_passes.hpp)
        result.torque_i = r_i.cross(f.on_i) + f.rolling_torque;
        result.torque_j = r_j.cross(f.on_i) + f.rolling_torque;
      } else {
        result.torque_i = r_i.cross(f.on_i);
        result.torque_j = r_j.cross(f.on_i);
      }
      entry.elastic = f.elastic_energy;
      entry.dissipated = f.dissipated;
      entry.overlap = k.overlap;
    }
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

  // flatten: inline the contact law and contact_force.hpp into the loop (no change in the
  // arithmetic: GCC does not reassociate or contract without -ffast-math / FMA targets).
  [[gnu::flatten]] void evaluate(FastState& s, double time, double dt) const override {
    const std::size_t n = s.owned;  // ghosts ([owned, size())) are partners only
    const std::size_t nb = s.boundaries.size();
    const std::uint32_t near_mask = nb < 32 ? (std::uint32_t{1} << nb) - 1u : ~std::uint32_t{0};  // near_boundaries' bits
    if constexpr (kWalls) {
      for (std::size_t b = 0; b < nb; ++b) {
        if (s.is_wall[b]) s.walls[b].point = s.walls[b].point0 + s.walls[b].velocity * time;  // PlaneWall::point_at
      }
    }
    // One range of particles per thread, balanced by estimated work corrected by the ranges'
    // measured times (balance_split), so a bed whose contacts sit in one part of the cell
    // order does not idle a thread. Range r
    // appends its new springs to pool 1 + r only; ranges move only when the pools are laid
    // out afresh, so no two threads ever touch the same pool.
    const int threads = kernel_threads(n);
    const auto ranges = static_cast<std::size_t>(threads);
    if (s.threads.size() < ranges) s.threads.resize(ranges);
    if constexpr (kFriction) {
      if (s.spring_pools.size() != ranges + 1) lay_out_springs(s, threads);
    }
    if (s.split_stale || s.split.size() != ranges + 1) {
      if constexpr (kFriction) {
        bool pools_empty = true;
        for (std::size_t pool = 1; pool < s.spring_pools.size(); ++pool) pools_empty = pools_empty && s.spring_pools[pool].empty();
        if (!pools_empty) lay_out_springs(s, threads);
      }
      balance_split(s, threads);
    }
    [[maybe_unused]] const bool has_ghosts = s.size() > n;
    std::size_t pairs = 0;
    std::size_t touching_boundaries = 0;
    constexpr bool kRecords = kWalls || kOthers;
    constexpr bool kHalf = kFriction;  // each pair of owned particles evaluated once
    if (kRecords && s.next_record_first.size() != n + 1) s.next_record_first.assign(n + 1, 0);
    if constexpr (kHalf) {
      if (s.mirror.size() != s.partner.size() || s.upper_first.size() != n) {
        throw std::logic_error("fast engine: neighbour mirrors not linked");
      }
      // The sum pass's ranges (below), even at first.
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
    // A new empty spring for range `range`: one its ended contacts freed, else a new one in its
    // pool (with its result slot).
    [[maybe_unused]] auto new_spring_with_result = [&s](std::size_t range) {
      std::vector<std::uint32_t>& free = s.threads[range].free_springs;
      if (!free.empty()) {
        const std::uint32_t code = free.back();
        free.pop_back();
        s.spring_at(code) = TangentialSpring{};
        return code;
      }
      const std::size_t pool = 1 + range;
      const std::uint32_t code = s.new_spring(pool);
      if (s.result_pools[pool].size() < s.spring_pools[pool].size()) s.result_pools[pool].resize(s.spring_pools[pool].capacity());
      return code;
    };
    PPOHDEM_OMP(omp parallel num_threads(threads) reduction(+ : pairs, touching_boundaries))
    {
    PPOHDEM_OMP(omp for schedule(static, 1))
    for (std::size_t range = 0; range < ranges; ++range) {
      [[maybe_unused]] const std::size_t my_pool = 1 + range;  // new springs of this range
      ThreadOutput& out = s.threads[range];
      out.records.clear();
      out.newly_escaped.clear();
      out.deepest.reset();
      const auto started = std::chrono::steady_clock::now();  // for balance_split
      [[maybe_unused]] std::vector<FeatureContact> touching_list;  // one boundary's contacts (kOthers)
      // The boundaries of particle i in boundary order, then its stores (both kinds of kernel).
      auto boundaries_and_stores = [&](std::size_t i, Vec3& force, Vec3& torque, double& elastic, double& dissipated) {
        const Vec3 xi = s.x[i];
        const double ri = s.radius[i];
        const std::int64_t idi = s.id[i];
        double work = 0.0, power = 0.0;
          // --- boundaries, in boundary order ---
          if constexpr (kWalls || kOthers) {
            std::uint32_t old = s.record_first[i];
            const std::uint32_t old_end = s.record_first[i + 1];
            // A fixed wall farther than R + skin at the list build is neither touched nor crossed
            // before the next build (near_boundaries): nothing to evaluate, so only the set bits
            // of the first 32 boundaries are visited (most particles of a bed have none: no
            // loop over the boundaries, whose exits mispredicted once per particle). A record of
            // a skipped boundary (impossible then) would still end at the next one, as untouched.
            // One contact (c, feature) with boundary b; a mesh object may give several per boundary,
            // in feature order, each with its own record (boundary.hpp FeatureContact).
            auto book_contact = [&](std::size_t b, const BoundaryContact& c, std::uint32_t feature) {
              if constexpr (kFriction) {
                for (; old < old_end && record_key(s.records[old]) < record_key(b, feature); ++old) {
                  if constexpr (kEnergy) dissipated += s.records[old].spring.stored_energy();  // ended
                }
              }
              ++touching_boundaries;
              if (!out.deepest || c.overlap / ri >= out.deepest->ratio) {
                keep_deeper(out.deepest, LargestOverlap{c.overlap / ri, c.overlap, idi, static_cast<std::int64_t>(b), true});
              }
              ContactKinematics k;
              k.normal = c.normal;
              k.overlap = c.overlap;
              const Vec3 r_a = c.point - xi;
              k.relative_velocity = s.pv[i] + s.pw[i].cross(r_a) - c.surface_velocity;
              k.pair.m_eff = s.mass[i];
              k.pair.r_eff = ri;
              BoundaryRecord record;
              record.particle = static_cast<std::uint32_t>(i);
              record.boundary = static_cast<std::uint32_t>(b);
              record.feature = feature;
              ContactForce f;
              if constexpr (kFriction) {
                const bool continuing = old < old_end && record_key(s.records[old]) == record_key(b, feature);
                if (continuing) record.spring = s.records[old++].spring;
                TangentialSpring& sp = record.spring;
                // Trapezoid surface displacement (contact_force.hpp "Moving boundaries").
                const Vec3 v_s = boundary_step_velocity(sp, continuing, c.surface_velocity);
                k.relative_displacement = dt * (s.v[i] + s.w[i].cross(r_a) - v_s);
                if constexpr (kEnergy) k.relative_displacement_previous_arms = dt * (s.v[i] + s.w[i].cross(sp.branch_i) - v_s);
                if (s.rolling) {  // the boundary's spin is that of its material
                  k.relative_spin = s.pw[i] - c.surface_spin;
                  k.relative_rotation = dt * (s.w[i] - c.surface_spin);
                }
                f = frictional_contact_force(boundary_law(s, i, b), k, sp, dt);
                sp.branch_i = r_a;
                record.rolling = f.rolling_torque;
              } else {
                f = normal_contact_force(boundary_law(s, i, b), k, dt);
              }
              if constexpr (!kHalf) {  // else added after the pairs by the second pass
                force += f.on_i;
                torque += r_a.cross(f.on_i);
              }
              if constexpr (kEnergy) {
                elastic += f.elastic_energy;
                dissipated += f.dissipated;
                // Boundary work: the dashpot's share now, the rest by the trapezoid rule of the
                // power P = (F - F_d) . v_s (reduced in the engine) [J], [W].
                work += f.dashpot.dot(c.surface_velocity) * dt;
                power += (f.on_i - f.dashpot).dot(c.surface_velocity);
              }
              record.force = f.on_i;
              record.point = c.point;
              out.records.push_back(record);
            };
            auto visit_boundary = [&](std::size_t b) {
              const auto escape = [&] {
                if (s.escaped_via[i] == 0) {
                  s.escaped_via[i] = static_cast<std::int32_t>(b + 1);
                  out.newly_escaped.push_back(static_cast<std::uint32_t>(i));
                }
              };
              if (kWalls && s.is_wall[b]) {
                const WallData& wall = s.walls[b];
                const double distance = PlaneWall::signed_distance(wall.point, wall.normal, xi);
                if (distance <= 0.0) {
                  escape();
                } else if (distance < ri) {
                  book_contact(b, PlaneWall::touching(wall.normal, wall.velocity, xi, ri, distance), 0u);
                }
              } else if constexpr (kOthers) {
                const Boundary& boundary = *s.boundaries[b];
                if (boundary.has_escaped(xi, time)) {
                  escape();
                } else {
                  boundary.contacts(xi, ri, time, touching_list);
                  for (const FeatureContact& t : touching_list) book_contact(b, t.contact, t.feature);
                }
              }
            };
            std::uint32_t near = s.near_boundaries[i] & near_mask;
            for (; near != 0; near &= near - 1u) visit_boundary(static_cast<std::size_t>(std::countr_zero(near)));
            for (std::size_t b = 32; b < nb; ++b) visit_boundary(b);
            if constexpr (kFriction) {
              for (; old < old_end; ++old) {
                if constexpr (kEnergy) dissipated += s.records[old].spring.stored_energy();
              }
            }
          }
        if constexpr (!kHalf) {
          s.f[i] = force;
          s.t[i] = torque;
        }
        if constexpr (kEnergy) {  // else nothing sums them (they keep their zeros)
          FastState::ParticleTerms& terms = s.terms[i];
          terms.elastic = elastic;
          terms.dissipated = dissipated;
          terms.work = work;
          terms.power = power;
        }
        if constexpr (kRecords) s.next_record_first[i + 1] = static_cast<std::uint32_t>(out.records.size());
      };
      if constexpr (kHalf) {
        // Chunks: the pairs of kChunk particles are first listed (contact test, ended and new
        // contacts), then their contacts evaluated (four at a time where the AVX path runs),
        // then each particle books its entries in slot order and adds its boundaries. The
        // order of every sum is the one-particle-at-a-time order.
        PairBatch& batch = out.batch;
        for (std::size_t chunk = s.split[range]; chunk < s.split[range + 1]; chunk += kChunk) {
          const std::size_t chunk_end = std::min(chunk + kChunk, s.split[range + 1]);
          // At most one entry per slot (plus the scratch entry written past the last): sized
          // once, then written without a branch per slot (whether a slot touches is a coin toss
          // for the branch predictor).
          const std::size_t most = s.first[chunk_end] - s.first[chunk] + 1;
          if (batch.entries.size() < most) batch.entries.resize(most);
          if (batch.contacts.size() < most) batch.contacts.resize(most);
          PairEntry* const entries = batch.entries.data();
          std::uint32_t* const contacts = batch.contacts.data();
          std::uint32_t count = 0;           // entries listed
          std::uint32_t contact_count = 0;   // of which contacts
          std::uint32_t entries_of[kChunk + 1];
          for (std::size_t i = chunk; i < chunk_end; ++i) {
            entries_of[i - chunk] = count;
            const Vec3 xi = s.x[i];
            const double ri = s.radius[i];
            auto list = [&](std::uint32_t slot, bool upper) {
              const std::uint32_t j = s.partner[slot];
              const Vec3 d = xi - s.x[j];  // from j to i
              const double reach = ri + s.radius[j];
              const bool touching = d.squaredNorm() < reach * reach;
              std::uint32_t& code = s.spring_of[slot];
              if (touching == (code == kNoSpring)) [[unlikely]] {  // a contact begins or ends
                if (touching) {
                  code = new_spring_with_result(range);  // a new contact: empty history
                } else {  // ended: its stored energy is lost
                  const TangentialSpring& sp = s.spring_at(code);
                  if (kEnergy && upper && sp.holds_history()) {
                    PairEntry& ended = entries[count++];
                    ended.kind = PairEntry::kEnded;
                    ended.dissipated = sp.stored_energy();
                  }
                  out.free_springs.push_back(code);
                  code = kNoSpring;
                }
                // The other side's copy (its sum pass reads it; only this range writes it).
                if (const std::uint32_t other = s.mirror[slot]; other != kNoMirror) s.lower_code[other] = code;
              }
              // Written always, kept (counted) only for a contact.
              PairEntry& contact = entries[count];
              contact.i = static_cast<std::uint32_t>(i);
              contact.j = j;
              contact.code = code;
              contact.kind = upper ? PairEntry::kContactUpper : PairEntry::kContact;
              if constexpr (kEnergy) contacts[contact_count] = count;  // else every entry is a contact
              count += touching;
              contact_count += touching;
            };
            // The lower-id owned partners evaluate their pairs (and keep this side's history);
            // a lower-id ghost's pair is evaluated here as well (its rank evaluates the other side).
            const std::uint32_t upper_first = s.upper_first[i];
            if (has_ghosts) {
              for (std::uint32_t slot = s.first[i]; slot < upper_first; ++slot) {
                if (s.partner[slot] >= n) list(slot, false);
              }
            }
            for (std::uint32_t slot = upper_first; slot < s.first[i + 1]; ++slot) list(slot, true);
          }
          entries_of[chunk_end - chunk] = count;
          for (std::size_t i = chunk; i < chunk_end; ++i) {  // the law may add to them (OwnSums)
            s.f[i] = Vec3::Zero();
            s.t[i] = Vec3::Zero();
          }
          OwnSums sums{&out.deepest};
          // Untracked, no entry is an ended contact: the law reads the entries in order, without
          // the index (docs/performance.md "Fewer loads and stores per contact and per
          // particle").
          const bool summed = evaluate_contacts(s, entries, kEnergy ? contacts : nullptr, contact_count, dt, sums);
          pairs += sums.pairs;
          if (summed) {  // nothing left to book; the boundaries' forces are added in the sum pass
            for (std::size_t i = chunk; i < chunk_end; ++i) {
              // Near no boundary (most of a bed): nothing to visit, only its empty block of
              // records to close (docs/performance.md "Fewer loads and stores per contact and
              // per particle"). Without energies an old record needs no
              // visit.
              if (nb <= 32 && (s.near_boundaries[i] & near_mask) == 0) {
                if constexpr (kRecords) s.next_record_first[i + 1] = static_cast<std::uint32_t>(out.records.size());
                continue;
              }
              Vec3 unused_force, unused_torque;
              double elastic = 0.0, dissipated = 0.0;
              boundaries_and_stores(i, unused_force, unused_torque, elastic, dissipated);
            }
            continue;
          }
          for (std::size_t i = chunk; i < chunk_end; ++i) {
            // The sum's first part: the contacts with higher-id partners (this side's results,
            // in slot order = ascending partner id); the sum pass adds the rest to it. The
            // law has added them already where it could (`summed`: the same sums in the same
            // order, OwnSums), else they are added here.
            Vec3 force = s.f[i];
            Vec3 torque = s.t[i];
            double elastic = 0.0, dissipated = 0.0;
            for (std::uint32_t e = entries_of[i - chunk]; e < entries_of[i + 1 - chunk]; ++e) {
              const PairEntry& entry = entries[e];
              if (entry.kind == PairEntry::kEnded) {
                dissipated += entry.dissipated;
                continue;
              }
              if (entry.kind != PairEntry::kContactUpper) continue;  // each pair's energy once, on its lower-id side
              const PairResult& result = s.result_at(entry.code);
              force += result.force;
              torque += result.torque_i;
              if constexpr (kEnergy) {
                elastic += entry.elastic;
                dissipated += entry.dissipated;
              }
              ++pairs;
              const double ratio = entry.overlap / std::min(s.radius[i], s.radius[entry.j]);
              if (!out.deepest || ratio >= out.deepest->ratio) {
                keep_deeper(out.deepest, LargestOverlap{ratio, entry.overlap, s.id[i], s.id[entry.j], false});
              }
            }
            boundaries_and_stores(i, force, torque, elastic, dissipated);
            s.f[i] = force;  // the part from higher-id partners (the sum pass reads it)
            s.t[i] = torque;
          }
        }
      } else {
        for (std::size_t i = s.split[range]; i < s.split[range + 1]; ++i) {
          Vec3 force = Vec3::Zero();
          Vec3 torque = Vec3::Zero();
          double elastic = 0.0, dissipated = 0.0;
          const Vec3 xi = s.x[i];
          const double ri = s.radius[i];
          const std::int64_t idi = s.id[i];
          // Frictionless: every pair from both sides, the higher-id partners in ascending id,
          // then the lower-id ones in descending id (the slots are in ascending id); `upper`:
          // the partner's id is above idi (each pair's energy and count once, on that side).
          const std::uint32_t first = s.first[i];
          const std::uint32_t end = s.first[i + 1];
          const std::uint32_t upper_first = s.upper_first[i];
          auto add_contact = [&](std::uint32_t slot, bool upper) {
            const std::uint32_t j = s.partner[slot];
            const Vec3 d = xi - s.x[j];  // from j to i
            const double reach = ri + s.radius[j];
            if (!(d.squaredNorm() < reach * reach)) return;
            const PairKinematics p = pair_kinematics(s, i, j, d);
            const ContactKinematics& k = p.k;
            const ContactForce f = normal_contact_force(pair_law(s, i, j), k, dt);
            force += f.on_i;
            torque += p.r_i.cross(f.on_i);
            if (upper) {
              if constexpr (kEnergy) {
                elastic += f.elastic_energy;
                dissipated += f.dissipated;
              }
              ++pairs;
              const double ratio = k.overlap / std::min(ri, s.radius[j]);
              if (!out.deepest || ratio >= out.deepest->ratio) {
                keep_deeper(out.deepest, LargestOverlap{ratio, k.overlap, idi, s.id[j], false});
              }
            }
          };
          for (std::uint32_t slot = upper_first; slot < end; ++slot) add_contact(slot, true);
          for (std::uint32_t slot = upper_first; slot-- > first;) add_contact(slot, false);
          boundaries_and_stores(i, force, torque, elastic, dissipated);
        }
      }
      s.range_seconds[range] += std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    }
    // The new boundary records: the ranges' blocks in range order are in storage order, so the
    // table is their concatenation. Each range's block starts at the sum of the blocks before
    // it (`base`); one thread sizes the table (nowait: the sum pass reads the blocks, not the
    // table, and its closing barrier orders this before the copies). Why: each barrier costs
    // a synchronisation of the threads every step (docs/performance.md "Fewer synchronisations
    // a step").
    if constexpr (kRecords) {
      if (ranges > 1) {
        PPOHDEM_OMP(omp single nowait)
        {
          std::size_t count = 0;
          for (std::size_t range = 0; range < ranges; ++range) {
            s.threads[range].base = count;
            count += s.threads[range].records.size();
          }
          s.next_records.resize(count);
        }
      }
      if constexpr (!kHalf) {
        PPOHDEM_OMP(omp barrier)  // no sum pass: the copies below need the table's size
      }
    }
    // Each pair once: the sums, in the order of the comment at the top (after the barrier
    // of the loop above, every pair's result and history is in place). This pass reads only
    // finished results and writes only its particles' f and t, so it has its own cut: shares
    // of the neighbour slots (its work is about the same per slot), corrected by the pass's
    // own measured times every kSumRecut evaluations (FastState::sum_share), while the first
    // pass's ranges are balanced by that pass's measured times alone, so that each barrier
    // waits less (docs/performance.md "Each pass its own cut" and "Two threads:
    // where the time goes").
    if constexpr (kHalf) {
      const std::size_t slots = s.first[n];
      auto cut = [&](std::size_t range) -> std::size_t {
        if (range == 0) return 0;
        if (range == ranges) return n;
        double before = 0.0;  // shares of the ranges before `range`
        for (std::size_t r = 0; r < range; ++r) before += s.sum_share[r];
        const auto want = static_cast<std::uint32_t>(static_cast<double>(slots) * std::min(before, 1.0));
        return static_cast<std::size_t>(std::lower_bound(s.first.begin(), s.first.begin() + static_cast<std::ptrdiff_t>(n), want) -
                                        s.first.begin());
      };
      PPOHDEM_OMP(omp for schedule(static, 1))
      for (std::size_t range = 0; range < ranges; ++range) {
        const auto sums_started = std::chrono::steady_clock::now();
        const std::size_t begin = cut(range);
        const std::size_t last = cut(range + 1);
        double screen = 0.0;  // close_kick's
        // The particles in pieces, one per first-pass range they fall in: that range's block
        // holds their new boundary records, particle i's from the previous particle's end to
        // next_record_first[i + 1] (from the block's start for the range's first particle, whose
        // next_record_first entry is the previous range's end).
        for (std::size_t block = 0; block < ranges; ++block) {
          const std::size_t from = std::max(begin, s.split[block]);
          const std::size_t to = std::min(last, s.split[block + 1]);
          if (from >= to) continue;
          [[maybe_unused]] const BoundaryRecord* const records = s.threads[block].records.data();
          [[maybe_unused]] std::uint32_t record = kRecords && from != s.split[block] ? s.next_record_first[from] : 0u;
          for (std::size_t i = from; i < to; ++i) {
            // The first pass's sum of the higher-id partners' contacts, then the lower-id
            // partners' in descending id. A slot without contact adds a zero result instead of
            // being skipped (no branch, which mispredicted about 2.9 times per particle): the
            // sum started at +0 and a sum of doubles is -0 only if both terms are, so it is
            // never -0 and adding +0 (or -0) leaves every bit of it unchanged.
            Vec3 force = s.f[i];
            Vec3 torque = s.t[i];
            const std::uint32_t first = s.first[i];
            for (std::uint32_t slot = s.upper_first[i]; slot-- > first;) {
              if (has_ghosts && s.partner[slot] >= n) {  // a lower-id ghost: evaluated here
                const PairResult& r = result_or_zero(s, s.spring_of[slot]);
                force += r.force;
                torque += r.torque_i;
                continue;
              }
              const PairResult& r = result_or_zero(s, s.lower_code[slot]);  // the lower-id side's
              force += -r.force;
              torque += -r.torque_j;
            }
            if constexpr (kRecords) {
              for (const std::uint32_t end = s.next_record_first[i + 1]; record < end; ++record) {
                force += records[record].force;
                if (s.rolling) {
                  torque += (records[record].point - s.x[i]).cross(records[record].force) + records[record].rolling;
                } else {
                  torque += (records[record].point - s.x[i]).cross(records[record].force);
                }
              }
            }
            s.f[i] = force;
            s.t[i] = torque;
            if (s.closing_kick) screen += close_kick(s, i);  // while f and t are in registers
          }
        }
        s.threads[range].screen = screen;
        s.sum_seconds[range] += std::chrono::duration<double>(std::chrono::steady_clock::now() - sums_started).count();
      }
    }
    // The table: one range's block is the table itself, swapped in (no copy of 160 bytes per
    // boundary contact; the buffers rotate, keeping their capacity); else each range copies its
    // block and offsets its particles' ends, in parallel, after every read of the blocks.
    if constexpr (kRecords) {
      if (ranges == 1) {
        PPOHDEM_OMP(omp single nowait)
        s.next_records.swap(s.threads[0].records);
      } else {
        PPOHDEM_OMP(omp for schedule(static, 1) nowait)
        for (std::size_t range = 0; range < ranges; ++range) {
          const ThreadOutput& out = s.threads[range];
          std::copy(out.records.begin(), out.records.end(), s.next_records.begin() + static_cast<std::ptrdiff_t>(out.base));
          const auto base = static_cast<std::uint32_t>(out.base);
          for (std::size_t i = s.split[range]; i < s.split[range + 1]; ++i) s.next_record_first[i + 1] += base;
        }
      }
    }
    }
    if constexpr (kHalf) {
      s.kick_closed = s.closing_kick;
      if (s.closing_kick) {
        s.screen = 0.0;
        for (std::size_t range = 0; range < ranges; ++range) s.screen += s.threads[range].screen;
      }
      if (++s.sum_evaluations >= kSumRecut) {
        s.sum_share = timed_shares(ranges, s.sum_share, s.sum_seconds);
        s.sum_seconds.assign(ranges, 0.0);
        s.sum_evaluations = 0;
      }
    }
    s.pair_contacts = pairs;
    s.boundary_contacts = touching_boundaries;
    s.deepest.reset();
    for (int th = 0; th < threads; ++th) {
      if (const auto& d = s.threads[static_cast<std::size_t>(th)].deepest) keep_deeper(s.deepest, *d);
    }
    if constexpr (kRecords) {
      s.records.swap(s.next_records);
      s.record_first.swap(s.next_record_first);
    } else {
      s.records.clear();
      s.record_first.assign(n + 1, 0);
    }
    for (int th = 0; th < threads; ++th) {
      for (const std::uint32_t i : s.threads[static_cast<std::size_t>(th)].newly_escaped) {
        const std::size_t b = static_cast<std::size_t>(s.escaped_via[i] - 1);
        std::fprintf(stderr, "warning: particle id %lld left the domain through %s at t = %g s\n",
                     static_cast<long long>(s.id[i]), s.boundaries[b]->describe().c_str(), time);
      }
    }
  }

 private:
  PairLaws<Law> laws_;  ///< kMulti only
  Law law_;             ///< the one law (= laws_.pair(0, 0))
  bool x4_ = false;     ///< kX4 and the CPU has AVX and the engine allows it
};

template <class Law, bool kFriction, bool kWalls, bool kOthers, bool kEnergy>
std::unique_ptr<ForceKernel> with_materials(const PairLaws<Law>& laws, bool vector_contacts) {
  // The linear law has one material (pair_laws.hpp): no multi-material instance of it.
  if constexpr (std::is_same_v<Law, HertzMindlin>) {
    if (laws.materials() > 1) return std::make_unique<Kernel<Law, kFriction, kWalls, kOthers, true, kEnergy>>(laws, vector_contacts);
  }
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
