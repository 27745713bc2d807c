#pragma once
// Analytic distance fields sampled on grids, for the object tests.
#include <cmath>
#include <functional>

#include "ppohdem/grid/scalar_field.hpp"

namespace ppohdem::dem::test {

/// phi(x) sampled at every node of `grid`.
inline ScalarField sampled_field(const GridSpec& grid, const std::function<double(const Vec3&)>& phi) {
  ScalarField f(grid);
  for (int k = 0; k < grid.nodes[2]; ++k) {
    for (int j = 0; j < grid.nodes[1]; ++j) {
      for (int i = 0; i < grid.nodes[0]; ++i) f.at(i, j, k) = phi(grid.position(i, j, k));
    }
  }
  return f;
}

/// Half-space object {(x - p) . n < 0}: phi(x) = (x - p) . n, n unit (linear, so trilinear
/// interpolation reproduces it exactly).
inline ScalarField half_space_field(const GridSpec& grid, const Vec3& point, const Vec3& unit_normal) {
  return sampled_field(grid, [&](const Vec3& x) { return (x - point).dot(unit_normal); });
}

/// Ball of radius r centred at c: phi(x) = |x - c| - r.
inline ScalarField ball_field(const GridSpec& grid, const Vec3& c, double r) {
  return sampled_field(grid, [&](const Vec3& x) { return (x - c).norm() - r; });
}

}  // namespace ppohdem::dem::test
