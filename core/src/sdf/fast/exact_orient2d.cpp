/// \file exact_orient2d.cpp
/// Filtered orient2d with an exact expansion-arithmetic fallback. See exact_orient2d.hpp.
#include "ppohdem/sdf/fast/exact_orient2d.hpp"

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

namespace ppohdem::sdf::fast {

namespace {

/// a - b = x + y exactly, x = fl(a - b) (Knuth's Two-Sum applied to a and -b).
inline void two_diff(double a, double b, double& x, double& y) {
  x = a - b;
  const double b_virtual = a - x;
  const double a_virtual = x + b_virtual;
  const double b_round = b_virtual - b;
  const double a_round = a - a_virtual;
  y = a_round + b_round;
}

/// a + b = x + y exactly, x = fl(a + b) (Knuth's Two-Sum).
inline void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double b_virtual = x - a;
  const double a_virtual = x - b_virtual;
  const double b_round = b - b_virtual;
  const double a_round = a - a_virtual;
  y = a_round + b_round;
}

/// a * b = x + y exactly (fma computes a*b - x with one rounding, which is exact here).
inline void two_product(double a, double b, double& x, double& y) {
  x = a * b;
  y = std::fma(a, b, -x);
}

int sign_of(double v) { return (v > 0.0) - (v < 0.0); }

}  // namespace

int orient2d_sign_expansion(double ax, double ay, double bx, double by, double px, double py) {
  // (a.x - p.x), (b.y - p.y), (a.y - p.y), (b.x - p.x) as exact pairs (s, e).
  std::array<double, 2> u{}, v{}, w{}, z{};
  two_diff(ax, px, u[0], u[1]);
  two_diff(by, py, v[0], v[1]);
  two_diff(ay, py, w[0], w[1]);
  two_diff(bx, px, z[0], z[1]);
  // 16 terms: u_i v_j (8 doubles) and -(w_i z_j) (8 doubles).
  std::array<double, 16> terms{};
  std::size_t n = 0;
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < 2; ++j) {
      double hi = 0.0, lo = 0.0;
      two_product(u[static_cast<std::size_t>(i)], v[static_cast<std::size_t>(j)], hi, lo);
      terms[n++] = hi;
      terms[n++] = lo;
      two_product(w[static_cast<std::size_t>(i)], z[static_cast<std::size_t>(j)], hi, lo);
      terms[n++] = -hi;
      terms[n++] = -lo;
    }
  }
  // Grow-Expansion (Shewchuk 1997, Theorem 10): adding a double to a non-overlapping expansion
  // sorted by increasing magnitude keeps it so; zeros may appear and are harmless.
  std::array<double, 17> expansion{};
  std::size_t length = 0;
  for (double b : terms) {
    double q = b;
    for (std::size_t k = 0; k < length; ++k) {
      double sum = 0.0, err = 0.0;
      two_sum(q, expansion[k], sum, err);
      expansion[k] = err;
      q = sum;
    }
    expansion[length++] = q;
  }
  // The largest non-zero component dominates the sum of the rest (non-overlapping).
  for (std::size_t k = length; k-- > 0;) {
    if (expansion[k] != 0.0) return sign_of(expansion[k]);
  }
  return 0;
}

int orient2d_sign(double ax, double ay, double bx, double by, double px, double py) {
  const double left = (ax - px) * (by - py);
  const double right = (ay - py) * (bx - px);
  const double det = left - right;
  constexpr double eps = std::numeric_limits<double>::epsilon() / 2.0;  // 2^-53
  constexpr double ccw_error_bound = (3.0 + 16.0 * eps) * eps;
  if (std::abs(det) > ccw_error_bound * (std::abs(left) + std::abs(right))) return sign_of(det);
  return orient2d_sign_expansion(ax, ay, bx, by, px, py);
}

int orient2d_sign_perturbed(double ax, double ay, double bx, double by, double px, double py) {
  const int unperturbed = orient2d_sign(ax, ay, bx, by, px, py);
  if (unperturbed != 0) return unperturbed;
  if (by != ay) return by > ay ? -1 : +1;  // coefficient of e: -(b.y - a.y)
  if (bx != ax) return bx > ax ? +1 : -1;  // coefficient of e^2: (b.x - a.x)
  return 0;
}

}  // namespace ppohdem::sdf::fast
