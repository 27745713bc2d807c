#include "ppohdem/grid/trilinear.hpp"

#include <cmath>
#include <stdexcept>

namespace ppohdem {
namespace {

/// Where p lies along one axis: the lower node of its cell and the local coordinate t in [0,1].
struct AxisPosition {
  int lower = 0;     ///< node index of the cell's lower face
  double t = 0.0;    ///< (p - x_lower) / h, in [0, 1]
  bool degenerate = false;  ///< the axis has a single node (no cell)
};

/// Locate coordinate x on an axis with n nodes at origin + i h; nullopt outside [x_0, x_{n-1}].
std::optional<AxisPosition> locate(double x, double origin, double h, int n) {
  if (!std::isfinite(x)) return std::nullopt;
  if (n == 1) {
    // A single node: the node box is the one coordinate; the field is constant along the axis.
    if (x != origin) return std::nullopt;
    return AxisPosition{0, 0.0, true};
  }
  const double upper = origin + (n - 1) * h;  // same expression as GridSpec::position
  if (x < origin || x > upper) return std::nullopt;
  const double s = (x - origin) / h;  // node-index coordinate, >= 0
  int lower = static_cast<int>(std::floor(s));
  if (lower > n - 2) lower = n - 2;  // points on the upper face use the last cell
  double t = s - lower;
  // Rounding in s may put t a few ulps outside [0,1] at the box faces; clamp.
  if (t < 0.0) t = 0.0;
  if (t > 1.0) t = 1.0;
  return AxisPosition{lower, t, false};
}

}  // namespace

std::optional<FieldSample> sample_trilinear(const ScalarField& field, const Vec3& p) {
  const GridSpec& g = field.grid;
  if (field.values.size() != g.node_count()) {
    throw std::invalid_argument("sample_trilinear: field has " + std::to_string(field.values.size()) +
                                " values for " + std::to_string(g.node_count()) + " grid nodes");
  }
  AxisPosition axis[3];
  for (int a = 0; a < 3; ++a) {
    const auto located = locate(p[a], g.origin[a], g.spacing[a], g.nodes[static_cast<std::size_t>(a)]);
    if (!located) return std::nullopt;
    axis[a] = *located;
  }

  // Corner values c[a][b][c] = f_{i+a, j+b, k+c}; a degenerate axis repeats its single node.
  double c[2][2][2];
  for (int dk = 0; dk < 2; ++dk) {
    for (int dj = 0; dj < 2; ++dj) {
      for (int di = 0; di < 2; ++di) {
        const int i = axis[0].lower + (axis[0].degenerate ? 0 : di);
        const int j = axis[1].lower + (axis[1].degenerate ? 0 : dj);
        const int k = axis[2].lower + (axis[2].degenerate ? 0 : dk);
        c[di][dj][dk] = field.at(i, j, k);
      }
    }
  }
  const double tx = axis[0].t, ty = axis[1].t, tz = axis[2].t;

  // Value by nested linear interpolation, w_0(t) = 1 - t, w_1(t) = t. std::lerp is exact at
  // t = 0 and t = 1 and never leaves [min(a,b), max(a,b)], so the result stays within the
  // corner values' range exactly.
  double along_x[2][2];  // [dj][dk]
  for (int dk = 0; dk < 2; ++dk)
    for (int dj = 0; dj < 2; ++dj) along_x[dj][dk] = std::lerp(c[0][dj][dk], c[1][dj][dk], tx);
  const double along_xy0 = std::lerp(along_x[0][0], along_x[1][0], ty);
  const double along_xy1 = std::lerp(along_x[0][1], along_x[1][1], ty);

  FieldSample s;
  s.value = std::lerp(along_xy0, along_xy1, tz);

  // Gradient of the interpolant: df/dx = (1/h_x) sum_{b,c} (f_{1bc} - f_{0bc}) w_b(t_y) w_c(t_z),
  // and likewise for y and z. A degenerate axis has no cell: derivative 0.
  auto bilerp = [](double v00, double v10, double v01, double v11, double u, double v) {
    return std::lerp(std::lerp(v00, v10, u), std::lerp(v01, v11, u), v);
  };
  if (!axis[0].degenerate) {
    double d[2][2];
    for (int dk = 0; dk < 2; ++dk)
      for (int dj = 0; dj < 2; ++dj) d[dj][dk] = c[1][dj][dk] - c[0][dj][dk];
    s.gradient.x() = bilerp(d[0][0], d[1][0], d[0][1], d[1][1], ty, tz) / g.spacing.x();
  }
  if (!axis[1].degenerate) {
    double d[2][2];
    for (int dk = 0; dk < 2; ++dk)
      for (int di = 0; di < 2; ++di) d[di][dk] = c[di][1][dk] - c[di][0][dk];
    s.gradient.y() = bilerp(d[0][0], d[1][0], d[0][1], d[1][1], tx, tz) / g.spacing.y();
  }
  if (!axis[2].degenerate) {
    double d[2][2];
    for (int dj = 0; dj < 2; ++dj)
      for (int di = 0; di < 2; ++di) d[di][dj] = c[di][dj][1] - c[di][dj][0];
    s.gradient.z() = bilerp(d[0][0], d[1][0], d[0][1], d[1][1], tx, ty) / g.spacing.z();
  }
  return s;
}

}  // namespace ppohdem
