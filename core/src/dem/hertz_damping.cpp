#include "ppohdem/dem/hertz_damping.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>

#include "ppohdem/error.hpp"

namespace ppohdem::dem {
namespace {

// Scaled acceleration x'' = -x^{3/2} - alpha x^{1/4} x', clamped at >= 0 (no attraction).
double scaled_acceleration(double x, double v, double alpha) {
  if (x <= 0.0) return 0.0;
  const double a = -x * std::sqrt(x) - alpha * std::sqrt(std::sqrt(x)) * v;
  return a < 0.0 ? a : 0.0;
}

HertzDampedImpact integrate(double alpha, double h) {
  double x = 0.0;
  double v = 1.0;
  double t = 0.0;
  for (long n = 0; n < 100000000; ++n) {
    // Classical RK4 for (x, v).
    const double k1x = v, k1v = scaled_acceleration(x, v, alpha);
    const double k2x = v + 0.5 * h * k1v, k2v = scaled_acceleration(x + 0.5 * h * k1x, k2x, alpha);
    const double k3x = v + 0.5 * h * k2v, k3v = scaled_acceleration(x + 0.5 * h * k2x, k3x, alpha);
    const double k4x = v + h * k3v, k4v = scaled_acceleration(x + h * k3x, k4x, alpha);
    const double x_next = x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
    const double v_next = v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
    if (n > 0 && x_next <= 0.0) {
      const double f = x / (x - x_next);  // linear interpolation of the zero crossing
      return {-(v + f * (v_next - v)), t + f * h};
    }
    x = x_next;
    v = v_next;
    t += h;
  }
  return {0.0, t};
}

/// e(alpha) of the scaled impact at the bisection's step.
double restitution_at(double alpha) { return integrate(alpha, 1.0e-4).restitution; }

/// The alpha of 40 halvings of [0, 10] on "e(mid) > e" (hertz_damping.hpp), with a quarter of
/// the integrations. e(alpha) decreases, so a mid at or below a point integrated to more than
/// e goes up, and one at or above a point integrated to at most e goes down, without being
/// integrated. Regula falsi (Illinois) on ln e(alpha) first narrows that bracket [up, down] to
/// about the halvings' last width; then the halvings are replayed, integrating only the mids
/// inside it: about 10 integrations instead of 40 (docs/dem.md "Model and formulas"). Only
/// integrated points decide; the ends 0 and 10 (e(10) from the coarse step of the range check)
/// only steer the interpolation, as no mid reaches them.
double bisection_by_bracket(double restitution, double coarse_e_at_ten) {
  const double target = std::log(restitution);
  double up = 0.0;  // e(0) = 1 > e
  double f_up = -target;
  double down = 10.0;
  double f_down = std::min(std::log(coarse_e_at_ten) - target, 0.0);
  int kept = 0;  // Illinois: the side kept twice in a row halves its f
  for (int i = 0; i < 24 && down - up > 5.0e-12; ++i) {
    double c = down - f_down * (down - up) / (f_down - f_up);
    if (!(c > up && c < down)) c = 0.5 * (up + down);
    const double e = restitution_at(c);
    const double f = std::log(e) - target;  // steers the interpolation; the side is the halvings' test
    if (e > restitution) {
      up = c;
      f_up = std::max(f, 1e-300);
      if (kept == -1) f_down *= 0.5;
      kept = -1;
    } else {
      down = c;
      f_down = std::min(f, 0.0);
      if (kept == 1) f_up *= 0.5;
      kept = 1;
    }
  }
  double lo = 0.0;
  double hi = 10.0;
  for (int i = 0; i < 40; ++i) {
    const double mid = 0.5 * (lo + hi);
    bool goes_up;  // e(mid) > e
    if (mid <= up) {
      goes_up = true;
    } else if (mid >= down) {
      goes_up = false;
    } else {
      goes_up = restitution_at(mid) > restitution;
      if (goes_up) up = std::max(up, mid); else down = std::min(down, mid);
    }
    if (goes_up) lo = mid; else hi = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

HertzDampedImpact hertz_damped_impact(double alpha, double scaled_step) {
  return integrate(alpha, scaled_step);
}

double hertz_damping_ratio_for_restitution(double restitution) {
  if (!(restitution > 0.0 && restitution <= 1.0)) {
    throw InputError("restitution must be in (0, 1], got " + std::to_string(restitution));
  }
  if (restitution == 1.0) return 0.0;
  // Scenes and tests ask for the same few values repeatedly.
  static std::mutex mutex;
  static std::map<double, double> cache;
  const std::lock_guard<std::mutex> lock(mutex);
  if (auto it = cache.find(restitution); it != cache.end()) return it->second;
  const double coarse_e_at_ten = integrate(10.0, 1.0e-3).restitution;
  if (coarse_e_at_ten > restitution) {
    throw InputError("restitution " + std::to_string(restitution) +
                     " is below what the damped Hertz law reaches (alpha <= 10)");
  }
  const double alpha = bisection_by_bracket(restitution, coarse_e_at_ten);
  cache[restitution] = alpha;
  return alpha;
}

}  // namespace ppohdem::dem
