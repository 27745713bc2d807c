#pragma once
// The force kernel's passes after the pair pass (force_kernel.cpp): the frictional kernels'
// sum pass, the table of new boundary records, and the ranges' outputs gathered into the
// state (counts, deepest contact, escapes, the sum pass's recut).
//
// Sum pass (each pair once, frictional kernels). After the pair pass's barrier every pair's
// result and history is in place. Each particle adds to its first part (its own higher-id
// contacts) the negated results of its lower-id partners in descending id (-f and -(r_j x f)
// are bitwise the partner side's f' and r' x f'), then its new boundary records; at the end
// of a step it also applies the closing kicks (close_kicks, fast_state.hpp) of every kChunk
// particles it has summed, while their f and t are in L1, instead of a separate pass of the engine. It reads only finished results and
// writes only its particles' f and t, so it has its own cut: shares of the neighbour slots
// (its work is about the same per slot), corrected by the pass's own measured times every
// kSumRecut evaluations (FastState::sum_share), while the pair pass's ranges are balanced by
// that pass's measured times alone, so that each barrier waits less (docs/performance.md
// "Each pass its own cut"; docs/machine.md "Two threads: where the time goes").
#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdio>

#include "force_pass.hpp"

namespace ppohdem::dem::fast {

/// Evaluations between two cuts of the sum pass by its measured times: a few milliseconds of
/// that pass in a bench-sized bed, long enough for the clock (steady_clock, two reads per range
/// and evaluation) and short next to how fast the bed's work moves.
constexpr unsigned kSumRecut = 20;

/// The result of the pair whose code is `code`; for kNoSpring the never-written zero result of
/// pool 0's first entry (fast_state.hpp), so a slot without contact needs no test (GCC turns a
/// test into a branch, which mispredicts: callgrind --branch-sim).
inline const PairResult& result_or_zero(const FastState& s, std::uint32_t code) { return s.result_at(code); }

/// The first particle of the sum pass's range `range` of `ranges` over the n owned particles:
/// where the slots of the ranges before it reach their shares' sum (s.sum_share).
inline std::size_t sum_cut(const FastState& s, std::size_t range, std::size_t ranges, std::size_t n) {
  if (range == 0) return 0;
  if (range == ranges) return n;
  const std::size_t slots = s.first[n];
  double before = 0.0;  // shares of the ranges before `range`
  for (std::size_t r = 0; r < range; ++r) before += s.sum_share[r];
  const auto want = static_cast<std::uint32_t>(static_cast<double>(slots) * std::min(before, 1.0));
  return static_cast<std::size_t>(std::lower_bound(s.first.begin(), s.first.begin() + static_cast<std::ptrdiff_t>(n), want) -
                                  s.first.begin());
}

/// The end of particle i's lower-id slots to add in the sum pass: the first slot (none) if no
/// lower-id partner touches it (the OR of their codes is kNoSpring, 0), else all of them. One
/// load and OR a slot instead of a result's loads and adds, for a particle in flight; in a bed
/// nearly every particle has a lower-id contact, so the sum pass scans only in a dilute
/// evaluation (kScanLower; docs/performance.md "Energy book-keeping").
inline std::uint32_t touched_lower_end(const FastState& s, std::size_t i) {
  static_assert(kNoSpring == 0u, "the codes OR to kNoSpring only if each is kNoSpring");
  std::uint32_t touching = 0;
  for (std::uint32_t slot = s.first[i]; slot < s.upper_first[i]; ++slot) touching |= s.lower_code[slot];
  return touching == kNoSpring ? s.first[i] : s.upper_first[i];
}

/// The sum pass (see the top); inside the kernel's parallel region, one range per thread.
/// kScanLower: skip the lower-id results of the particles no lower-id partner touches.
template <class K, bool kScanLower>
inline void sum_pass(FastState& s, std::size_t ranges, std::size_t n, bool has_ghosts) {
  PPOHDEM_OMP(omp for schedule(static, 1))
  for (std::size_t range = 0; range < ranges; ++range) {
    const auto sums_started = std::chrono::steady_clock::now();
    const std::size_t begin = sum_cut(s, range, ranges, n);
    const std::size_t last = sum_cut(s, range + 1, ranges, n);
    double screen = 0.0;  // close_kick's
    double drift = 0.0;   // the largest next_drift (predict_drift)
    // The particles in pieces, one per pair-pass range they fall in: that range's block holds
    // their new boundary records, particle i's from the previous particle's end to
    // next_record_first[i + 1] (from the block's start for the range's first particle, whose
    // next_record_first entry is the previous range's end).
    for (std::size_t block = 0; block < ranges; ++block) {
      const std::size_t from = std::max(begin, s.split[block]);
      const std::size_t to = std::min(last, s.split[block + 1]);
      if (from >= to) continue;
      [[maybe_unused]] const BoundaryRecord* const records = s.threads[block].records.data();
      [[maybe_unused]] std::uint32_t record = K::kRecords && from != s.split[block] ? s.next_record_first[from] : 0u;
      // By pieces of kChunk particles: the closing kicks of a piece follow its sums, while its
      // f and t are in L1.
      for (std::size_t piece = from; piece < to; piece += kChunk) {
        const std::size_t piece_end = std::min(piece + kChunk, to);
        for (std::size_t i = piece; i < piece_end; ++i) {
          // The pair pass's sum of the higher-id partners' contacts, then the lower-id partners'
          // in descending id. A slot without contact adds a zero result instead of being
          // skipped (no branch, which mispredicted about 2.9 times per particle): the sum
          // started at +0 and a sum of doubles is -0 only if both terms are, so it is never -0
          // and adding +0 (or -0) leaves every bit of it unchanged.
          Vec3 force = s.f[i];
          Vec3 torque = s.t[i];
          const std::uint32_t first = s.first[i];
          const bool ghost_partners = has_ghosts && s.lower_ghost[i] != 0;
          const std::uint32_t lower_end = kScanLower && !ghost_partners ? touched_lower_end(s, i) : s.upper_first[i];
          for (std::uint32_t slot = lower_end; slot-- > first;) {
            if (ghost_partners && s.partner[slot] >= n) {  // a lower-id ghost: evaluated here
              const PairResult& r = result_or_zero(s, s.spring_of[slot]);
              force += r.force;
              torque += r.torque_summed;
              continue;
            }
            const PairResult& r = result_or_zero(s, s.lower_code[slot]);  // the lower-id side's
            force += -r.force;
            torque += -r.torque_summed;
          }
          if constexpr (K::kRecords) {
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
        }
        if (s.closing_kick) {
          screen += close_kicks(s, piece, piece_end);
          if (s.predict_drift) {
            for (std::size_t i = piece; i < piece_end; ++i) drift = std::max(drift, next_drift(s, i));
          }
        }
      }
    }
    s.threads[range].screen = screen;
    s.threads[range].drift = drift;
    s.sum_seconds[range] += std::chrono::duration<double>(std::chrono::steady_clock::now() - sums_started).count();
  }
}

/// The new boundary records' table, sized (inside the parallel region, after the pair pass):
/// the ranges' blocks in range order are in storage order, so the table is their
/// concatenation. Each range's block starts at the sum of the blocks before it (`base`); one
/// thread sizes the table (nowait: the sum pass reads the blocks, not the table, and its
/// closing barrier orders this before the copies). Why: each barrier costs a synchronisation
/// of the threads every step (docs/performance.md "Fewer synchronisations a step").
template <class K>
inline void size_record_table(FastState& s, std::size_t ranges) {
  if constexpr (K::kRecords) {
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
    if constexpr (!K::kHalf) {
      PPOHDEM_OMP(omp barrier)  // no sum pass: the copies below need the table's size
    }
  }
}

/// The new boundary records' table, filled (inside the parallel region, after every read of
/// the blocks): one range's block is the table itself, swapped in (no copy of 160 bytes per
/// boundary contact; the buffers rotate, keeping their capacity); else each range copies its
/// block and offsets its particles' ends, in parallel.
template <class K>
inline void fill_record_table(FastState& s, std::size_t ranges) {
  if constexpr (K::kRecords) {
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

/// After the parallel region: the closing kick's screen and the sum pass's recut (kHalf), the
/// counts, the deepest contact over the ranges, the new records swapped in, and a warning for
/// each particle that left the domain in this evaluation.
template <class K>
inline void gather_ranges(FastState& s, std::size_t ranges, std::size_t n, std::size_t pairs,
                          std::size_t touching_boundaries, double time) {
  if constexpr (K::kHalf) {
    s.kick_closed = s.closing_kick;
    if (s.closing_kick) {
      s.screen = 0.0;
      s.next_drift = 0.0;
      for (std::size_t range = 0; range < ranges; ++range) {
        s.screen += s.threads[range].screen;
        s.next_drift = std::max(s.next_drift, s.threads[range].drift);
      }
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
  for (std::size_t range = 0; range < ranges; ++range) {
    if (const auto& d = s.threads[range].deepest) keep_deeper(s.deepest, *d);
  }
  if constexpr (K::kEnergy) {  // exact: the same bits in any order of the ranges
    for (std::size_t c = 0; c < s.rates.size(); ++c) {
      s.rates[c].reset();
      for (std::size_t range = 0; range < ranges; ++range) s.rates[c].merge(s.threads[range].rates[c]);
    }
  }
  if constexpr (K::kRecords) {
    s.records.swap(s.next_records);
    s.record_first.swap(s.next_record_first);
  } else {
    s.records.clear();
    s.record_first.assign(n + 1, 0);
  }
  for (std::size_t range = 0; range < ranges; ++range) {
    for (const std::uint32_t i : s.threads[range].newly_escaped) {
      const std::size_t b = static_cast<std::size_t>(s.escaped_via[i] - 1);
      std::fprintf(stderr, "warning: particle id %lld left the domain through %s at t = %g s\n",
                   static_cast<long long>(s.id[i]), s.boundaries[b]->describe().c_str(), time);
    }
  }
}

}  // namespace ppohdem::dem::fast
