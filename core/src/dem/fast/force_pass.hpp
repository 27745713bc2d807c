#pragma once
// What the force kernel's passes share (force_kernel.cpp): the view of one range of the first
// pass, one particle's sums, and the kernel type they are written for. Private to
// core/src/dem/fast; included by force_kernel.cpp only (every pass is inlined into its one
// evaluate(), so each kernel instance compiles to the loops it had as one function).
//
// The passes are function templates over K, the kernel instance (force_kernel.cpp), which
// names the contact law and the kernel's flags:
//   K::kFriction  the law keeps a tangential spring (each pair evaluated once, kHalf)
//   K::kWalls     the scene has planar walls (evaluated inline), K::kOthers other boundaries
//   K::kEnergy    [simulation] energy_balance: the contact energy terms are computed
//   K::kRecords   kWalls || kOthers: boundary records are written
//   K::kHalf      kFriction: the sums come from a second (sum) pass
// and offers kernel.pair_law(s, i, j), kernel.boundary_law(s, i, b) and
// kernel.evaluate_contacts(...) (the contact law on a chunk's listed contacts).
#include <cstddef>
#include <cstdint>

#include "fast_state.hpp"

namespace ppohdem::dem::fast {

/// Particles per chunk of the frictional kernels' first pass (their pair lists stay in L1).
constexpr std::size_t kChunk = 64;

/// One range of the first pass (one thread's contiguous share of the owned particles): the
/// step, this range's output, and the thread's counters (the parallel region's reduction
/// variables). The pass writes only this range's particles, records, free springs and pool.
struct RangePass {
  FastState& s;
  double time;        ///< evaluation time [s]
  double dt;          ///< history increment interval [s] (0 at start-up)
  std::size_t range;  ///< index into s.split and s.threads; new springs go to pool 1 + range
  ThreadOutput& out;  ///< s.threads[range]
  std::size_t& pairs;                ///< pair contacts counted (each pair once)
  std::size_t& touching_boundaries;  ///< boundary contacts counted
  std::size_t n;            ///< s.owned (ghosts, [n, s.size()), are partners only)
  std::size_t boundaries;   ///< s.boundaries.size()
  std::uint32_t near_mask;  ///< the bits of s.near_boundaries in use (the first 32 boundaries)
  bool has_ghosts;          ///< s.size() > n
  /// The particles of this part of the range: [split[range], split[range + 1]), or its part
  /// below or at and above s.n_interior while the halo refresh is in flight.
  std::size_t begin, end;
  /// Polled every kPollChunks chunks (the master thread's interior part only; else null).
  HaloInFlight* poll = nullptr;
};

/// Chunks between two polls of the halo refresh in flight.
constexpr std::size_t kPollChunks = 4;

/// One particle's sums in the first pass: force [N] and torque [N m] of its contacts (the
/// frictional kernels' first part only: the sum pass adds the rest), and with kEnergy its
/// contact energy terms: stored [J], dissipated this step [J], boundary work (dashpot share)
/// [J] and boundary power [W] (store_terms keeps the first and adds the rates).
struct ParticleSums {
  Vec3 force = Vec3::Zero();
  Vec3 torque = Vec3::Zero();
  double elastic = 0.0;
  double dissipated = 0.0;
  double work = 0.0;
  double power = 0.0;
};

}  // namespace ppohdem::dem::fast
