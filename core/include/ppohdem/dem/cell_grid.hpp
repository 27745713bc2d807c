#pragma once
/// \file cell_grid.hpp
/// The uniform cell grid both DEM engines use for contact search (Allen & Tildesley 1987,
/// sec. 5.3.2): cubic cells of side `cell` [m] starting at `origin`, `dims` cells per axis.
///
/// The grid covers the bulk of the particles: per axis from the 1st to the 99th percentile of
/// the centres, plus one cell on each side, at most ~8 N + 27 cells in all. Centres outside it
/// (e.g. escaped particles falling away) are CLAMPED into the border cells. Clamping is
/// correct: the cell indices of two centres closer than one cell differ by at most 1 per axis,
/// and the clamp (monotone, never increasing distances) keeps that true; outliers only crowd
/// the border cells. The layout decides which pairs are examined, never a force value.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

#include "ppohdem/geometry/vector.hpp"

namespace ppohdem::dem {

struct CellGrid {
  Vec3 origin = Vec3::Zero();  ///< [m]
  double cell = 1.0;           ///< cell side [m]
  Index3 dims = {1, 1, 1};
  /// The axes from the fastest to the slowest varying in `linear` (x, y, z unless set, e.g.
  /// by with_longest_axis_slowest). Cells adjacent along order[0] are adjacent in `linear`.
  std::array<std::size_t, 3> order = {0, 1, 2};

  int axis_index(double x, int axis) const {
    const double c = std::floor((x - origin[axis]) / cell);
    return static_cast<int>(std::clamp(c, 0.0, static_cast<double>(dims[axis] - 1)));
  }
  Index3 index(const Vec3& x) const { return {axis_index(x.x(), 0), axis_index(x.y(), 1), axis_index(x.z(), 2)}; }
  std::size_t linear(const Index3& c) const {
    const auto [fast, middle, slow] = order;
    return static_cast<std::size_t>(c[fast]) +
           static_cast<std::size_t>(dims[fast]) *
               (static_cast<std::size_t>(c[middle]) + static_cast<std::size_t>(dims[middle]) * static_cast<std::size_t>(c[slow]));
  }
  std::size_t size() const {
    return static_cast<std::size_t>(dims[0]) * static_cast<std::size_t>(dims[1]) * static_cast<std::size_t>(dims[2]);
  }
};

/// The grid of cells of side `cell` [m] for these centres (rules in the file comment).
inline CellGrid cell_grid_for(const std::vector<Vec3>& centres, double cell) {
  CellGrid g;
  g.cell = cell;
  const std::size_t n = centres.size();
  std::vector<double> c(n);
  Vec3 cells = Vec3::Ones();
  for (int axis = 0; axis < 3; ++axis) {
    for (std::size_t i = 0; i < n; ++i) c[i] = centres[i][axis];
    const auto lo = c.begin() + static_cast<std::ptrdiff_t>(n / 100);
    const auto hi = c.begin() + static_cast<std::ptrdiff_t>(n - 1 - n / 100);
    std::nth_element(c.begin(), lo, c.end());
    const double low = *lo;
    std::nth_element(c.begin(), hi, c.end());
    const double high = *hi;
    g.origin[axis] = low - g.cell;
    cells[axis] = std::ceil((high - low) / g.cell) + 2.0;
  }
  // At most ~8 N + 27 cells: a sparse bulk gets fewer, larger-in-effect border cells.
  const double budget = 8.0 * static_cast<double>(n) + 27.0;
  const double total = cells.prod();
  if (total > budget) cells *= std::cbrt(budget / total);
  for (int axis = 0; axis < 3; ++axis) g.dims[axis] = static_cast<int>(std::max(1.0, std::floor(cells[axis])));
  return g;
}

/// `grid` with the axis of the most cells varying slowest in `linear` (ties: z, then y, then
/// x), the others in x, y, z order. Particles sorted by cell and cut into contiguous ranges
/// are then cut across the longest extent of the bulk: each cut is a plane through the fewest
/// cells, so the fewest particles have partners on the other side of it. The fast engine's
/// threads cut its cell order so, and every particle near a cut costs transfers between the
/// cores every step (docs/performance.md "Threads cut across the longest axis"). The order
/// decides which particles sit next to each other in memory, never a force value.
inline CellGrid with_longest_axis_slowest(CellGrid grid) {
  std::size_t slowest = 2;
  for (std::size_t axis : {1, 0}) {
    if (grid.dims[axis] > grid.dims[slowest]) slowest = axis;
  }
  std::size_t k = 0;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    if (axis != slowest) grid.order[k++] = axis;
  }
  grid.order[2] = slowest;
  return grid;
}

}  // namespace ppohdem::dem
