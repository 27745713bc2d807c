#pragma once
// The neighbour search's distance test (fast_engine.cpp, search_neighbours): which particles of
// a few runs of cell-ordered members lie within reach of one particle. One member at a time, and
// four at a time with AVX: the same operations in the same order (IEEE subtraction, addition and
// multiplication are correctly rounded in every lane, and the "avx" target has no FMA), so both
// keep the same members (tested: near_members_test.cpp).
//
// Why by hand: the test is a few flops per candidate followed by a compaction of the kept ones,
// which GCC does not vectorize by itself (its share of a run: docs/performance.md "Cheaper
// list builds, second pass").
#include <cstddef>
#include <cstdint>
#include <vector>

namespace ppohdem::dem::fast {

/// Centres [m] and radii [m] of the search's members, one column each, in member order, and
/// kPadding members more (zeros, never kept) so that four lanes may read past a run's end.
struct ProbeColumns {
  static constexpr std::size_t kPadding = 3;
  std::vector<double> x, y, z, r;
  /// Room for `members` members and the padding (the padding zeroed).
  void resize(std::size_t members);
};

/// Members [begin, end) of ProbeColumns: a row of neighbouring cells.
struct MemberRun {
  std::uint32_t begin = 0, end = 0;
};

/// The particle whose neighbours are sought.
struct NearQuery {
  double x = 0.0, y = 0.0, z = 0.0;  ///< centre [m]
  double radius = 0.0;               ///< [m]
  double skin = 0.0;                 ///< Verlet skin [m]
  std::uint32_t self = 0;            ///< its own member index (never kept)
};

/// Writes to kept[0], kept[1], ... every member m of the runs, in run order, with
/// |c - p_m|^2 < (R + r_m + skin)^2 and m != self, where |d|^2 = (dx dx + dy dy) + dz dz and
/// R + r_m + skin = (R + r_m) + skin (Eigen's squaredNorm and the engine's order); returns how
/// many. `kept` must have room for the runs' total length plus 3.
std::size_t near_members(const ProbeColumns& probes, const MemberRun* runs, std::size_t run_count, const NearQuery& q,
                         std::uint32_t* kept);

/// The same, four members at a time (AVX); the same members in the same order. Requires
/// x4_contacts_available() (hertz_mindlin_x4.hpp).
std::size_t near_members_x4(const ProbeColumns& probes, const MemberRun* runs, std::size_t run_count,
                            const NearQuery& q, std::uint32_t* kept);

}  // namespace ppohdem::dem::fast
