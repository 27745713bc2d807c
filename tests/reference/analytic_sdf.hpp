#pragma once
/// \file analytic_sdf.hpp
/// Signed distances computed without any triangle: the independent oracles of the SDF tests.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "ppohdem/grid/grid_spec.hpp"

namespace ppohdem::test {

/// |p - c| - r.
inline double sphere_sdf(const Vec3& p, const Vec3& centre, double radius) { return (p - centre).norm() - radius; }

/// Box [lo, hi]: with q = |p - centre| - half extent, phi = |max(q, 0)| + min(max_a q_a, 0)
/// (Quilez's box formula): outside the distance to the box, inside -(distance to the nearest face).
inline double box_sdf(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  const Vec3 q = (p - 0.5 * (lo + hi)).cwiseAbs() - 0.5 * (hi - lo);
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

/// An axis-aligned rectangle (or any box, possibly flat): distance = |p - clamp(p, lo, hi)|.
struct AxisBox {
  Vec3 lo, hi;
  double distance(const Vec3& p) const { return (p - p.cwiseMax(lo).cwiseMin(hi)).norm(); }
  bool contains(const Vec3& p) const { return (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all(); }
};

/// The L solid of test_meshes.hpp, l_shape(s, offset): inside test and boundary faces as flat boxes.
struct LShapeOracle {
  double s;
  Vec3 offset;

  std::vector<AxisBox> solids() const {
    return {{offset + Vec3(0, 0, 0), offset + Vec3(2 * s, s, s)}, {offset + Vec3(0, 0, 0), offset + Vec3(s, 2 * s, s)}};
  }
  std::vector<AxisBox> faces() const {
    auto at = [&](double x, double y, double z) -> Vec3 { return offset + Vec3(x * s, y * s, z * s); };
    return {
        {at(0, 0, 0), at(2, 1, 0)}, {at(0, 1, 0), at(1, 2, 0)},  // bottom z = 0 (two rectangles)
        {at(0, 0, 1), at(2, 1, 1)}, {at(0, 1, 1), at(1, 2, 1)},  // top z = 1
        {at(0, 0, 0), at(0, 2, 1)},                              // x = 0
        {at(0, 0, 0), at(2, 0, 1)},                              // y = 0
        {at(2, 0, 0), at(2, 1, 1)},                              // x = 2
        {at(1, 1, 0), at(2, 1, 1)},                              // y = 1 (concave side)
        {at(1, 1, 0), at(1, 2, 1)},                              // x = 1 (concave side)
        {at(0, 2, 0), at(1, 2, 1)},                              // y = 2
    };
  }
  /// Signed distance = -+ min over the boundary faces, negative inside the union of the solids.
  double sdf(const Vec3& p) const {
    double d = std::numeric_limits<double>::infinity();
    for (const AxisBox& f : faces()) d = std::min(d, f.distance(p));
    bool inside = false;
    for (const AxisBox& b : solids()) inside = inside || b.contains(p);
    return inside ? -d : d;
  }
};

/// A cubic grid of n^3 nodes spanning [lo, hi] (h = (hi - lo) / (n - 1)), built field by field.
inline GridSpec cube_grid(double lo, double hi, int n) {
  GridSpec g;
  g.origin = Vec3::Constant(lo);
  g.spacing = Vec3::Constant((hi - lo) / (n - 1));
  g.nodes = {n, n, n};
  return g;
}

}  // namespace ppohdem::test
