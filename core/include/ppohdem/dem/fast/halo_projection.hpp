#pragma once
/// \file halo_projection.hpp
/// The fast engine's decomposition and halo for P ranks, computed in one process without
/// running them (`ppohdem project`, docs/performance.md "Projection to many nodes"): the
/// bricks of the engine's own decomposition (the bisection of `[parallel] balance = "rcb"`,
/// or the equal bricks), the owner of every particle, each rank's peers, and the ghosts each
/// rank sends to and receives from each peer under the engine's own halo rule
/// (core/src/dem/fast/decomposition.hpp, in_halo), as at a list build on these positions.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "ppohdem/dem/fast/fast_engine.hpp"
#include "ppohdem/dem/particle.hpp"

namespace ppohdem::dem::fast {

/// One rank's share at a list build and its halo traffic per step.
struct RankTraffic {
  std::size_t owned = 0;       ///< particles it owns
  /// Of those, the interior ones: within the halo reach of no other rank's brick (no ghost
  /// partner; their pairs hide the halo refresh, docs/dem.md "Domain decomposition (MPI)").
  std::size_t interior = 0;
  std::size_t ghosts_in = 0;   ///< ghosts it holds (received from its peers)
  std::size_t ghosts_out = 0;  ///< ghost copies of its particles it sends (one per peer that needs one)
  int peers = 0;               ///< ranks within the halo reach of its brick
  int messages_out = 0;        ///< halo-refresh messages it sends per step (peers it sends ghosts to)
  int messages_in = 0;         ///< halo-refresh messages it receives per step
};

struct HaloProjection {
  int ranks = 1;
  std::size_t particles = 0;
  double reach = 0.0;                 ///< 2 R_max + skin [m]
  std::size_t refresh_bytes = 0;      ///< bytes per ghost of the per-step refresh
  std::size_t creation_bytes = 0;     ///< bytes per ghost when it is created at a list build
  std::vector<RankTraffic> rank;      ///< per rank
};

/// The decomposition of `ranks` ranks over the particles centred at x with ids `id` (the whole
/// system), with the engine's options (skin_fraction, balance), and every rank's traffic.
/// r_max [m] is the largest radius.
HaloProjection project_halo(int ranks, const std::vector<Vec3>& x, const std::vector<std::int64_t>& id, double r_max,
                            const FastOptions& options);

}  // namespace ppohdem::dem::fast
