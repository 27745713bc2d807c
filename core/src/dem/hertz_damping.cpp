#include "ppohdem/dem/hertz_damping.hpp"

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

}  // namespace

HertzDampedImpact hertz_damped_impact(double alpha, double scaled_step) {
  return integrate(alpha, scaled_step);
}

double hertz_damping_ratio_for_restitution(double restitution) {
  if (!(restitution > 0.0 && restitution <= 1.0)) {
    throw InputError("restitution must be in (0, 1], got " + std::to_string(restitution));
  }
  if (restitution == 1.0) return 0.0;
  // The bisection is slow next to a lookup, and scenes and tests ask for the same few values
  // repeatedly.
  static std::mutex mutex;
  static std::map<double, double> cache;
  const std::lock_guard<std::mutex> lock(mutex);
  if (auto it = cache.find(restitution); it != cache.end()) return it->second;
  double lo = 0.0;
  double hi = 10.0;
  if (integrate(hi, 1.0e-3).restitution > restitution) {
    throw InputError("restitution " + std::to_string(restitution) +
                     " is below what the damped Hertz law reaches (alpha <= 10)");
  }
  // e(alpha) decreases monotonically; 40 halvings of [0, 10] give alpha to 1e-11.
  for (int i = 0; i < 40; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (integrate(mid, 1.0e-4).restitution > restitution) lo = mid; else hi = mid;
  }
  const double alpha = 0.5 * (lo + hi);
  cache[restitution] = alpha;
  return alpha;
}

}  // namespace ppohdem::dem
