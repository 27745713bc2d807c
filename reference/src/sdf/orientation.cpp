/// \file orientation.cpp
/// Filtered exact orient2d (Shewchuk 1997) and its simulation-of-simplicity perturbation
/// (Edelsbrunner & Muecke 1990). See orientation.hpp for the formulas.
#include "ppohdem/sdf/reference/orientation.hpp"

#include <boost/multiprecision/cpp_int.hpp>
#include <cmath>
#include <limits>

namespace ppohdem::sdf::reference {

namespace {

template <typename T>
int sign_of(const T& value) {
  return (value > 0) - (value < 0);
}

}  // namespace

int orient2d_sign_exact(const Vec2& a, const Vec2& b, const Vec2& p) {
  using boost::multiprecision::cpp_rational;
  const cpp_rational ax(a.x()), ay(a.y()), bx(b.x()), by(b.y()), px(p.x()), py(p.y());
  const cpp_rational det = (ax - px) * (by - py) - (ay - py) * (bx - px);
  return sign_of(det);
}

int orient2d_sign(const Vec2& a, const Vec2& b, const Vec2& p) {
  const double left = (a.x() - p.x()) * (b.y() - p.y());
  const double right = (a.y() - p.y()) * (b.x() - p.x());
  const double det = left - right;
  constexpr double eps = std::numeric_limits<double>::epsilon() / 2.0;  // 2^-53, Shewchuk's epsilon
  constexpr double ccw_error_bound = (3.0 + 16.0 * eps) * eps;
  const double error_bound = ccw_error_bound * (std::abs(left) + std::abs(right));
  if (std::abs(det) > error_bound) return sign_of(det);
  return orient2d_sign_exact(a, b, p);  // the filter cannot decide (includes det == 0)
}

int orient2d_sign_perturbed(const Vec2& a, const Vec2& b, const Vec2& p) {
  const int unperturbed = orient2d_sign(a, b, p);
  if (unperturbed != 0) return unperturbed;
  // Coefficient of e: -(b.y - a.y). The sign of a difference of doubles is exact (compare them).
  if (b.y() != a.y()) return b.y() > a.y() ? -1 : +1;
  // Coefficient of e^2: (b.x - a.x).
  if (b.x() != a.x()) return b.x() > a.x() ? +1 : -1;
  return 0;  // a == b: a degenerate edge, no line to be on either side of
}

}  // namespace ppohdem::sdf::reference
