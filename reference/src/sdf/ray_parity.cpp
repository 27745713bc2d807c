/// \file ray_parity.cpp
/// Column ray parity with simulation of simplicity. See ray_parity.hpp for the method; the
/// original counterparts are ppohDEM_v_makecrosslist and ppohDEM_v_makegridout.
#include "ppohdem/sdf/reference/ray_parity.hpp"

#include <algorithm>
#include <cmath>

namespace ppohdem::sdf::reference {

namespace {

Vec2 xy(const Vec3& v) { return Vec2(v.x(), v.y()); }

double cross2(const Vec2& u, const Vec2& v) { return u.x() * v.y() - u.y() * v.x(); }

/// Column indices n with origin + n h in [lo, hi], widened by one column on each side to absorb
/// the rounding of the division (the exact predicate then decides), clamped to [0, count - 1].
std::pair<int, int> column_range(double lo, double hi, double origin, double h, int count) {
  const double first = std::ceil((lo - origin) / h) - 1.0;
  const double last = std::floor((hi - origin) / h) + 1.0;
  // Clamp in double before converting: a triangle far outside the grid must not overflow int.
  const double max_index = static_cast<double>(count - 1);
  return {static_cast<int>(std::clamp(first, 0.0, max_index + 1.0)),
          static_cast<int>(std::clamp(last, -1.0, max_index))};
}

}  // namespace

bool projection_contains(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& p) {
  const int orientation = orient2d_sign(a, b, c);
  if (orientation == 0) return false;  // zero-area projection: a face parallel to the ray
  return orient2d_sign_perturbed(a, b, p) == orientation &&
         orient2d_sign_perturbed(b, c, p) == orientation &&
         orient2d_sign_perturbed(c, a, p) == orientation;
}

double crossing_height(const Vec3& a, const Vec3& b, const Vec3& c, const Vec2& p) {
  // p - a = beta (b - a) + gamma (c - a) in the xy-plane; z = a.z + beta (b.z - a.z) + gamma (c.z - a.z).
  // Written relative to a so that a horizontal face (all z equal) gives exactly that z.
  const Vec2 ab = xy(b) - xy(a);
  const Vec2 ac = xy(c) - xy(a);
  const Vec2 ap = p - xy(a);
  const double twice_area = cross2(ab, ac);
  double beta = 1.0 / 3.0;  // used only if the double area rounds to 0 (the exact one is not 0)
  double gamma = 1.0 / 3.0;
  if (twice_area != 0.0) {
    beta = std::clamp(cross2(ap, ac) / twice_area, 0.0, 1.0);
    gamma = std::clamp(cross2(ab, ap) / twice_area, 0.0, 1.0);
    if (beta + gamma > 1.0) {
      const double sum = beta + gamma;
      beta /= sum;
      gamma /= sum;
    }
  }
  return a.z() + beta * (b.z() - a.z()) + gamma * (c.z() - a.z());
}

CrossList make_cross_list(const TriangleMesh& mesh, const GridSpec& grid) {
  CrossList list;
  list.nx = grid.nodes[0];
  list.ny = grid.nodes[1];
  list.columns.resize(static_cast<std::size_t>(list.nx) * static_cast<std::size_t>(list.ny));

  for (std::size_t t = 0; t < mesh.size(); ++t) {
    const auto& v = mesh.triangles[t].v;
    const Vec2 a = xy(v[0]), b = xy(v[1]), c = xy(v[2]);
    const Vec2 lo = a.cwiseMin(b).cwiseMin(c);
    const Vec2 hi = a.cwiseMax(b).cwiseMax(c);
    const auto [i_first, i_last] = column_range(lo.x(), hi.x(), grid.origin.x(), grid.spacing.x(), list.nx);
    const auto [j_first, j_last] = column_range(lo.y(), hi.y(), grid.origin.y(), grid.spacing.y(), list.ny);
    for (int j = j_first; j <= j_last; ++j) {
      for (int i = i_first; i <= i_last; ++i) {
        const Vec2 column = xy(grid.position(i, j, 0));  // the same x, y as every node of the column
        if (!projection_contains(a, b, c, column)) continue;
        const std::size_t index = static_cast<std::size_t>(i) + static_cast<std::size_t>(list.nx) * static_cast<std::size_t>(j);
        list.columns[index].push_back({t, crossing_height(v[0], v[1], v[2], column)});
      }
    }
  }
  for (auto& column : list.columns) {
    std::sort(column.begin(), column.end(),
              [](const ColumnCrossing& s, const ColumnCrossing& t) { return s.z < t.z; });
  }
  return list;
}

std::vector<bool> inside_by_column_parity(const CrossList& crossings, const GridSpec& grid) {
  std::vector<bool> inside(grid.node_count(), false);
  for (int j = 0; j < grid.nodes[1]; ++j) {
    for (int i = 0; i < grid.nodes[0]; ++i) {
      const auto& column = crossings.column(i, j);
      for (int k = 0; k < grid.nodes[2]; ++k) {
        const double z = grid.position(i, j, k).z();
        // Crossings strictly above z: the column is sorted, so they are the tail after upper_bound.
        const auto first_above = std::upper_bound(column.begin(), column.end(), z,
                                                  [](double value, const ColumnCrossing& c) { return value < c.z; });
        const auto above = std::distance(first_above, column.end());
        inside[grid.index(i, j, k)] = (above % 2) == 1;
      }
    }
  }
  return inside;
}

std::vector<bool> inside_by_column_parity(const TriangleMesh& mesh, const GridSpec& grid) {
  return inside_by_column_parity(make_cross_list(mesh, grid), grid);
}

}  // namespace ppohdem::sdf::reference
