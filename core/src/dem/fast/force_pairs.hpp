#pragma once
// The force kernel's pair pass (force_kernel.cpp, the first pass over a range's particles):
// the contacts of each particle with its neighbour-list partners, then its boundaries
// (force_boundaries.hpp).
//
// Frictional kernels (each pair once, from its lower-id side; the sum pass, force_sums.hpp,
// adds the other side) go by chunks of kChunk particles: list the chunk's touching pairs and
// the contacts that ended, in slot order (list_chunk_pairs); evaluate the listed contacts
// (the kernel's evaluate_contacts: four or eight at a time for one Hertz-Mindlin law,
// hertz_mindlin_x4.hpp, or one at a time here, the same bits); then book each particle's
// entries in slot order and add its boundaries (book_chunk), so every sum keeps the order of
// one particle at a time. The lane law adds each particle's own contacts itself, in the same
// order (OwnSums: forces, torques and, tracked, the energy terms), and only the ended
// contacts' energy and the boundaries are left (chunk_boundaries). A particle's energy terms
// are its upper contacts' in slot order, then its ended contacts', then its boundaries'
// (docs/dem.md "Energy book-keeping"). Frictionless kernels evaluate every pair from both sides, the
// higher-id partners in ascending id, then the lower-id ones in descending id
// (frictionless_pair_pass).
#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "force_boundaries.hpp"
#include "force_pass.hpp"
#include "hertz_mindlin_x4.hpp"

namespace ppohdem::dem::fast {

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

/// The contacts entries[0, count), one at a time (frictional kernels): springs, pair results,
/// the upper contacts' force and torque added to s.f, s.t (zeroed for the chunk), and the
/// entries' energies and overlaps for the booking.
template <class K>
inline void evaluate_contacts_one_by_one(const K& kernel, FastState& s, PairEntry* entries, std::size_t count, double dt) {
  for (std::size_t c = 0; c < count; ++c) {
    PairEntry& entry = entries[c];
    const std::size_t i = entry.i;
    const std::uint32_t j = entry.j;
    PairKinematics p = pair_kinematics(s, i, j, s.x[i] - s.x[j]);
    ContactKinematics& k = p.k;
    const Vec3& r_i = p.r_i;
    const Vec3& r_j = p.r_j;
    k.relative_displacement = dt * ((s.v[i] + s.w[i].cross(r_i)) - (s.v[j] + s.w[j].cross(r_j)));
    TangentialSpring sp = s.spring_at(entry.code);
    if constexpr (K::kEnergy) {  // the energy terms' only use
      k.relative_displacement_previous_arms =
          dt * ((s.v[i] + s.w[i].cross(sp.branch_i)) - (s.v[j] + s.w[j].cross(sp.branch_j)));
    }
    if (s.rolling) {  // rolling_resistance.hpp
      k.relative_spin = s.pw[i] - s.pw[j];
      k.relative_rotation = dt * (s.w[i] - s.w[j]);
    }
    const ContactForce f = frictional_contact_force(kernel.pair_law(s, i, j), k, sp, dt);
    if constexpr (K::kEnergy) {  // their only use (save_state writes them from the positions)
      sp.branch_i = r_i;
      sp.branch_j = r_j;
    }
    s.put_spring(entry.code, sp);
    // The reference's sums (force_passes.hpp).
    const Vec3 torque_i = s.rolling ? Vec3(r_i.cross(f.on_i) + f.rolling_torque) : Vec3(r_i.cross(f.on_i));
    PairResult& result = s.result_at(entry.code);
    result.force = f.on_i;
    if (entry.kind == PairEntry::kContactUpper) {
      // i's own sums, in its entries' order as the lane law adds them (OwnSums): the booking
      // starts from them.
      s.f[i] += f.on_i;
      s.t[i] += torque_i;
      result.torque_summed = s.rolling ? Vec3(r_j.cross(f.on_i) + f.rolling_torque) : Vec3(r_j.cross(f.on_i));
    } else {  // a lower-id ghost's: the sum pass adds it to i
      result.torque_summed = torque_i;
    }
    entry.elastic = f.elastic_energy;
    entry.dissipated = f.dissipated;
    entry.overlap = k.overlap;
  }
}

/// A new empty spring for range `range`: one its ended contacts freed, else a new one in its
/// pool (with its result slot).
inline std::uint32_t new_spring_with_result(FastState& s, std::size_t range) {
  std::vector<std::uint32_t>& free = s.threads[range].free_springs;
  if (!free.empty()) {
    const std::uint32_t code = free.back();
    free.pop_back();
    s.put_spring(code, TangentialSpring{});
    return code;
  }
  const std::size_t pool = 1 + range;
  const std::uint32_t code = s.new_spring(pool);
  if (s.result_pools[pool].size() < s.spring_pools[pool].size()) s.result_pools[pool].resize(s.spring_pools[pool].capacity());
  return code;
}

/// The pair list of particles [chunk, chunk_end): for each particle in order, its slots'
/// touching pairs it evaluates, in slot order; a contact that begins gets a new spring, one
/// that ends frees its spring and (kEnergy) adds its lost stored energy to
/// ended[i - chunk], in slot order. Particle i's entries are [entries_of[i - chunk],
/// entries_of[i + 1 - chunk]); returns the number of entries (all contacts).
template <class K>
inline std::uint32_t list_chunk_pairs(RangePass& pass, std::size_t chunk, std::size_t chunk_end, PairEntry* entries,
                                      std::uint32_t* entries_of, [[maybe_unused]] double* ended) {
  FastState& s = pass.s;
  // A particle whose upper slots cannot touch (screen_gap, one rank) lists none of them.
  const double* const gap = s.screen_gap.size() == s.owned ? s.screen_gap.data() : nullptr;
  const double skip_bound = s.screen_skip_bound;
  std::uint32_t count = 0;  // entries listed
  for (std::size_t i = chunk; i < chunk_end; ++i) {
    entries_of[i - chunk] = count;
    if constexpr (K::kEnergy) ended[i - chunk] = 0.0;
    if (gap != nullptr && gap[i] > skip_bound) {
      ++pass.out.skipped_screens;
      continue;
    }
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
          code = new_spring_with_result(s, pass.range);  // a new contact: empty history
        } else {  // ended: its stored energy is lost
          if constexpr (K::kEnergy) {
            const TangentialSpring sp = s.spring_at(code);
            if (upper && sp.holds_history()) ended[i - chunk] += sp.stored_energy();
          }
          pass.out.free_springs.push_back(code);
          code = kNoSpring;
        }
        // The other side's copy (its sum pass reads it; only this range writes it).
        if (const std::uint32_t other = s.mirror[slot]; other != kNoMirror) s.lower_code[other] = code;
      }
      // Written always, kept (counted) only for a contact: no branch per slot (whether a slot
      // touches is a coin toss for the branch predictor).
      PairEntry& contact = entries[count];
      contact.i = static_cast<std::uint32_t>(i);
      contact.j = j;
      contact.code = code;
      contact.kind = upper ? PairEntry::kContactUpper : PairEntry::kContact;
      count += touching;
    };
    // The lower-id owned partners evaluate their pairs (and keep this side's history); a
    // lower-id ghost's pair is evaluated here as well (its rank evaluates the other side).
    const std::uint32_t upper_first = s.upper_first[i];
    if (pass.has_ghosts && s.lower_ghost[i] != 0) {
      for (std::uint32_t slot = s.first[i]; slot < upper_first; ++slot) {
        if (s.partner[slot] >= pass.n) list(slot, false);
      }
    }
    for (std::uint32_t slot = upper_first; slot < s.first[i + 1]; ++slot) list(slot, true);
  }
  entries_of[chunk_end - chunk] = count;
  return count;
}

/// Each particle of [chunk, chunk_end) books its listed entries in slot order: of the contacts
/// with higher-id partners (whose force and torque the evaluation added to s.f, s.t: the sum's
/// first part; the sum pass adds the rest) its energy terms, count and deepest contact, then
/// the energy of its contacts that ended (`ended`); then its boundaries.
template <class K>
inline void book_chunk(const K& kernel, RangePass& pass, std::size_t chunk, std::size_t chunk_end,
                       const PairEntry* entries, const std::uint32_t* entries_of, [[maybe_unused]] const double* ended) {
  FastState& s = pass.s;
  for (std::size_t i = chunk; i < chunk_end; ++i) {
    if (entries_of[i - chunk] == entries_of[i + 1 - chunk] && (!K::kEnergy || ended[i - chunk] == 0.0) &&
        pass.boundaries <= 32 && (s.near_boundaries[i] & pass.near_mask) == 0) {
      // Nothing touches it (a particle in flight): zero sums, only its energy record to close
      // (the same bits as the full path; docs/performance.md "Energy book-keeping").
      if constexpr (K::kEnergy) s.terms[i] = FastState::ParticleTerms{};
      if constexpr (K::kRecords) s.next_record_first[i + 1] = static_cast<std::uint32_t>(pass.out.records.size());
      continue;
    }
    ParticleSums sums;
    sums.force = s.f[i];
    sums.torque = s.t[i];
    for (std::uint32_t e = entries_of[i - chunk]; e < entries_of[i + 1 - chunk]; ++e) {
      const PairEntry& entry = entries[e];
      if (entry.kind != PairEntry::kContactUpper) continue;  // each pair's energy once, on its lower-id side
      if constexpr (K::kEnergy) {
        sums.elastic += entry.elastic;
        sums.dissipated += entry.dissipated;
      }
      ++pass.pairs;
      const double ratio = entry.overlap / std::min(s.radius[i], s.radius[entry.j]);
      if (!pass.out.deepest || ratio >= pass.out.deepest->ratio) {
        keep_deeper(pass.out.deepest, LargestOverlap{ratio, entry.overlap, s.id[i], s.id[entry.j], false});
      }
    }
    if constexpr (K::kEnergy) sums.dissipated += ended[i - chunk];
    boundaries_and_stores(kernel, pass, i, sums);
    s.f[i] = sums.force;  // the part from higher-id partners (the sum pass reads it)
    s.t[i] = sums.torque;
  }
}

/// The rest of particles [chunk, chunk_end) whose pair contacts the law has booked itself
/// (OwnSums, with their energy terms in `own`): the energy of their ended contacts and their
/// boundaries. A particle near no boundary (most of a bed) has nothing to visit, only its
/// empty block of records to close and its energy terms to finish (docs/performance.md
/// "Fewer loads and stores per contact and per particle").
template <class K>
inline void chunk_boundaries(const K& kernel, RangePass& pass, std::size_t chunk, std::size_t chunk_end,
                             [[maybe_unused]] const OwnSums& own, [[maybe_unused]] const double* ended) {
  FastState& s = pass.s;
  for (std::size_t i = chunk; i < chunk_end; ++i) {
    ParticleSums sums;  // the boundaries' forces are added in the sum pass
    if constexpr (K::kEnergy) {
      sums.elastic = own.elastic[i - chunk];
      sums.dissipated = own.dissipated[i - chunk] + ended[i - chunk];
    }
    if (pass.boundaries <= 32 && (s.near_boundaries[i] & pass.near_mask) == 0) {
      if constexpr (K::kRecords) s.next_record_first[i + 1] = static_cast<std::uint32_t>(pass.out.records.size());
      if constexpr (K::kEnergy) store_terms(pass, i, sums);
      continue;
    }
    boundaries_and_stores(kernel, pass, i, sums);
  }
}

/// The frictional kernels' first pass over one range, chunk by chunk (see the top).
template <class K>
inline void frictional_pair_pass(const K& kernel, RangePass& pass) {
  FastState& s = pass.s;
  PairBatch& batch = pass.out.batch;
  std::size_t chunks = 0;
  for (std::size_t chunk = pass.begin; chunk < pass.end; chunk += kChunk) {
    if (pass.poll != nullptr && ++chunks % kPollChunks == 0) pass.poll->poll();
    const std::size_t chunk_end = std::min(chunk + kChunk, pass.end);
    // At most one entry per slot (plus the scratch entry written past the last): sized once,
    // then written without a branch per slot.
    const std::size_t most = s.first[chunk_end] - s.first[chunk] + 1;
    if (batch.entries.size() < most) batch.entries.resize(most);
    PairEntry* const entries = batch.entries.data();
    std::uint32_t entries_of[kChunk + 1];
    double ended[kChunk];  // kEnergy: the chunk's particles' ended contacts' energy [J]
    double elastic[kChunk], dissipated[kChunk];  // kEnergy: their pair contacts' (OwnSums) [J]
    const std::uint32_t contact_count = list_chunk_pairs<K>(pass, chunk, chunk_end, entries, entries_of, ended);
    for (std::size_t i = chunk; i < chunk_end; ++i) {  // the law may add to them (OwnSums)
      s.f[i] = Vec3::Zero();
      s.t[i] = Vec3::Zero();
      if constexpr (K::kEnergy) elastic[i - chunk] = dissipated[i - chunk] = 0.0;
    }
    OwnSums own{&pass.out.deepest, 0, chunk, elastic, dissipated};
    const bool summed = kernel.evaluate_contacts(s, entries, contact_count, pass.dt, own);
    pass.pairs += own.pairs;
    if (summed) {
      chunk_boundaries(kernel, pass, chunk, chunk_end, own, ended);
    } else {
      book_chunk(kernel, pass, chunk, chunk_end, entries, entries_of, ended);
    }
  }
}

/// The frictionless kernels' first pass over one range: every pair from both sides, the
/// higher-id partners in ascending id, then the lower-id ones in descending id (the slots are
/// in ascending id); each pair's energy, count and deepest offer once, on the side whose
/// partner has the higher id. Then the particle's boundaries and stores.
template <class K>
inline void frictionless_pair_pass(const K& kernel, RangePass& pass) {
  FastState& s = pass.s;
  const double dt = pass.dt;
  for (std::size_t i = pass.begin; i < pass.end; ++i) {
    if (pass.poll != nullptr && (i - pass.begin) % (kPollChunks * kChunk) == kPollChunks * kChunk - 1) pass.poll->poll();
    ParticleSums sums;
    const Vec3 xi = s.x[i];
    const double ri = s.radius[i];
    const std::int64_t idi = s.id[i];
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
      const ContactForce f = normal_contact_force(kernel.pair_law(s, i, j), k, dt);
      sums.force += f.on_i;
      sums.torque += p.r_i.cross(f.on_i);
      if (upper) {
        if constexpr (K::kEnergy) {
          sums.elastic += f.elastic_energy;
          sums.dissipated += f.dissipated;
        }
        ++pass.pairs;
        const double ratio = k.overlap / std::min(ri, s.radius[j]);
        if (!pass.out.deepest || ratio >= pass.out.deepest->ratio) {
          keep_deeper(pass.out.deepest, LargestOverlap{ratio, k.overlap, idi, s.id[j], false});
        }
      }
    };
    for (std::uint32_t slot = upper_first; slot < end; ++slot) add_contact(slot, true);
    for (std::uint32_t slot = upper_first; slot-- > first;) add_contact(slot, false);
    boundaries_and_stores(kernel, pass, i, sums);
  }
}

}  // namespace ppohdem::dem::fast
