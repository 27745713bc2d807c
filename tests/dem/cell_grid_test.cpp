// The cell grid's linear order (core/include/ppohdem/dem/cell_grid.hpp): for any axis order a
// bijection of the cells onto [0, size) with cells adjacent along the fastest axis adjacent in
// it, and with_longest_axis_slowest's choice checked against brute force over all six orders:
// cutting its order in two contiguous halves crosses no more cell faces than cutting any other,
// up to the partial slab's step (below).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <vector>

#include "ppohdem/dem/cell_grid.hpp"

namespace ppohdem::dem::test {
namespace {

std::vector<Index3> all_cells(const CellGrid& g) {
  std::vector<Index3> cells;
  for (int z = 0; z < g.dims[2]; ++z)
    for (int y = 0; y < g.dims[1]; ++y)
      for (int x = 0; x < g.dims[0]; ++x) cells.push_back({x, y, z});
  return cells;
}

/// Faces between a cell whose linear index is below size/2 and one whose index is not: the
/// cut of a cell order into two contiguous ranges, as the fast engine's two threads cut it.
std::size_t faces_across_half(const CellGrid& g) {
  const std::size_t half = g.size() / 2;
  std::size_t faces = 0;
  for (const Index3& c : all_cells(g)) {
    for (std::size_t axis = 0; axis < 3; ++axis) {
      Index3 next = c;
      ++next[axis];
      if (next[axis] >= g.dims[axis]) continue;
      faces += (g.linear(c) < half) != (g.linear(next) < half) ? 1 : 0;
    }
  }
  return faces;
}

std::vector<std::array<std::size_t, 3>> all_orders() {
  std::array<std::size_t, 3> order = {0, 1, 2};
  std::vector<std::array<std::size_t, 3>> orders;
  do orders.push_back(order);
  while (std::next_permutation(order.begin(), order.end()));
  return orders;
}

TEST(CellGrid, EveryAxisOrderIsABijectionWithRowsAlongTheFastestAxis) {
  CellGrid g;
  g.dims = {4, 3, 5};
  for (const auto& order : all_orders()) {
    g.order = order;
    std::vector<int> hits(g.size(), 0);
    for (const Index3& c : all_cells(g)) {
      ASSERT_LT(g.linear(c), g.size());
      ++hits[g.linear(c)];
      Index3 next = c;
      if (++next[order[0]] < g.dims[order[0]]) {
        EXPECT_EQ(g.linear(next), g.linear(c) + 1);
      }
    }
    EXPECT_TRUE(std::all_of(hits.begin(), hits.end(), [](int h) { return h == 1; }));
  }
}

TEST(CellGrid, DefaultOrderIsXThenYThenZ) {
  CellGrid g;
  g.dims = {4, 3, 5};
  EXPECT_EQ(g.linear({1, 2, 3}), 1u + 4u * (2u + 3u * 3u));
}

TEST(CellGrid, LongestAxisSlowestCutsTheFewestFaces) {
  for (const Index3& dims : {Index3{25, 25, 16}, Index3{8, 30, 6}, Index3{40, 9, 9}, Index3{6, 6, 20}, Index3{7, 7, 7}}) {
    CellGrid g;
    g.dims = dims;
    const CellGrid chosen = with_longest_axis_slowest(g);
    // The slowest axis has the most cells (ties: z, then y); the others stay in x, y, z order.
    const std::size_t slowest = chosen.order[2];
    for (std::size_t axis = 0; axis < 3; ++axis) EXPECT_GE(dims[slowest], dims[axis]);
    EXPECT_LT(chosen.order[0], chosen.order[1]);
    std::size_t fewest = g.size() * 3;
    for (const auto& order : all_orders()) {
      g.order = order;
      fewest = std::min(fewest, faces_across_half(g));
    }
    // A cut inside a slab of the slowest axis crosses the slab's plane of dims[fast] x
    // dims[middle] faces plus a step between its full and its partial rows: at most 2 x
    // dims[fast] + 1 faces more, whose size depends on where size/2 falls in the slab, not on
    // the cut's plane (25 x 25 x 16: 425 for the chosen x, z, y order, 417 for z, x, y; z
    // slowest, the default order, crosses 625).
    const auto step = static_cast<std::size_t>(2 * dims[chosen.order[0]] + 1);
    EXPECT_LE(faces_across_half(chosen), fewest + step) << dims[0] << " x " << dims[1] << " x " << dims[2];
    g.order = {0, 1, 2};
    EXPECT_LE(faces_across_half(chosen), faces_across_half(g));
  }
  CellGrid bed;  // the 10,000-particle bed (cells of about one diameter)
  bed.dims = {25, 25, 16};
  EXPECT_EQ(faces_across_half(bed), 625u);
  EXPECT_EQ(faces_across_half(with_longest_axis_slowest(bed)), 425u);
  CellGrid cube;
  cube.dims = {7, 7, 7};
  EXPECT_EQ(with_longest_axis_slowest(cube).order, (std::array<std::size_t, 3>{0, 1, 2}));  // ties: z
  CellGrid wide;
  wide.dims = {25, 25, 16};
  EXPECT_EQ(with_longest_axis_slowest(wide).order, (std::array<std::size_t, 3>{0, 2, 1}));  // ties: y before x
}

}  // namespace
}  // namespace ppohdem::dem::test
