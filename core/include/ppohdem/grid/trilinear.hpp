#pragma once
/// \file trilinear.hpp
/// Trilinear interpolation of a node field and the exact gradient of that interpolant.
///
/// In the cell [x_i, x_i + h] x ... with local coordinates t = (p - x_ijk) ./ h in [0,1]^3:
///   f(p) = sum_{a,b,c in {0,1}} f_{i+a,j+b,k+c} w_a(t_x) w_b(t_y) w_c(t_z),
///   w_0(t) = 1 - t, w_1(t) = t;
///   df/dx = (1/h_x) sum f_{...} (2a - 1) w_b(t_y) w_c(t_z)   (and likewise for y, z).
/// It reproduces every field linear in x, y, z exactly and never leaves the cell's min/max.
/// Ref: e.g. Press et al., Numerical Recipes 3rd ed., section 3.6.
#include <optional>

#include "ppohdem/grid/scalar_field.hpp"

namespace ppohdem {

struct FieldSample {
  double value = 0.0;             ///< interpolated f (units of the field)
  Vec3 gradient = Vec3::Zero();   ///< grad f (field units per metre)
};

/// Sample at world position p. Returns nullopt when p is outside the node box
/// [origin, upper_corner] (or not finite); points on the upper faces use the last cell.
/// A grid with a single node on an axis is constant along that axis (zero derivative).
std::optional<FieldSample> sample_trilinear(const ScalarField& field, const Vec3& p);

}  // namespace ppohdem
