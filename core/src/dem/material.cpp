#include "ppohdem/dem/material.hpp"

#include <cmath>
#include <limits>

#include "ppohdem/error.hpp"
#include "ppohdem/units.hpp"

namespace ppohdem::dem {

double Material::mass(double radius) const {
  return density * 4.0 / 3.0 * units::kPi * radius * radius * radius;
}

double Material::moment_of_inertia(double radius) const {
  return 0.4 * mass(radius) * radius * radius;
}

double pair_effective_young(const Material& a, const Material& b) {
  if (a.young == b.young && a.poisson == b.poisson) return a.effective_young();
  // 1/E* = (1-nu_a^2)/E_a + (1-nu_b^2)/E_b [1/Pa]; the sum is commutative in floating point,
  // so (a, b) and (b, a) give the same bits.
  return 1.0 / ((1.0 - a.poisson * a.poisson) / a.young + (1.0 - b.poisson * b.poisson) / b.young);
}

double pair_effective_shear(const Material& a, const Material& b) {
  if (a.young == b.young && a.poisson == b.poisson) return a.effective_shear();
  // 1/G* = (2-nu_a)/G_a + (2-nu_b)/G_b [1/Pa]
  return 1.0 / ((2.0 - a.poisson) / a.shear_modulus() + (2.0 - b.poisson) / b.shear_modulus());
}

double harmonic_pair(double a, double b) {
  if (std::isinf(b)) return a;
  if (std::isinf(a)) return b;
  return a * b / (a + b);
}

void validate(const Material& m, bool needs_elastic, const std::string& where) {
  auto fail = [&](const std::string& what) { throw InputError(where, 0, "[material] " + what); };
  if (!(m.density > 0.0) || !std::isfinite(m.density)) {
    fail("density must be > 0 kg/m^3, got " + std::to_string(m.density));
  }
  if (!(m.restitution > 0.0 && m.restitution <= 1.0)) {
    fail("restitution must be in (0, 1], got " + std::to_string(m.restitution));
  }
  if (!(m.friction >= 0.0) || !std::isfinite(m.friction)) {
    fail("friction must be >= 0, got " + std::to_string(m.friction));
  }
  if (!(m.rolling_friction >= 0.0) || !std::isfinite(m.rolling_friction)) {
    fail("rolling_friction must be >= 0, got " + std::to_string(m.rolling_friction));
  }
  if (needs_elastic) {
    if (!(m.young > 0.0) || !std::isfinite(m.young)) {
      fail("young must be > 0 Pa, got " + std::to_string(m.young));
    }
    if (!(m.poisson > -1.0 && m.poisson < 0.5)) {
      fail("poisson must be in (-1, 0.5), got " + std::to_string(m.poisson));
    }
  }
}

}  // namespace ppohdem::dem
