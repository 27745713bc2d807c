#include "ppohdem/dem/contact_law.hpp"

#include <cmath>

#include "ppohdem/dem/hertz_damping.hpp"
#include "ppohdem/error.hpp"
#include "ppohdem/units.hpp"

namespace ppohdem::dem {

LinearSpringDashpot LinearSpringDashpot::from_stiffness(double k_n, double restitution,
                                                        double friction, double tangential_ratio) {
  if (!(k_n > 0.0) || !std::isfinite(k_n)) {
    throw InputError("linear contact: stiffness must be > 0 N/m, got " + std::to_string(k_n));
  }
  if (!(restitution > 0.0 && restitution <= 1.0)) {
    throw InputError("linear contact: restitution must be in (0, 1], got " +
                     std::to_string(restitution));
  }
  if (!(tangential_ratio >= 0.0)) {
    throw InputError("linear contact: tangential_stiffness_ratio must be >= 0");
  }
  LinearSpringDashpot law;
  law.k_n_ = k_n;
  law.k_t_ = tangential_ratio * k_n;
  law.e_ = restitution;
  law.mu_ = friction;
  const double ln_e = std::log(restitution);
  law.log_factor_ = -ln_e / std::sqrt(units::kPi * units::kPi + ln_e * ln_e);
  return law;
}

LinearSpringDashpot LinearSpringDashpot::from_collision_time(double t_c, double m_ref,
                                                             double restitution, double friction,
                                                             double tangential_ratio) {
  if (!(t_c > 0.0) || !(m_ref > 0.0)) {
    throw InputError("linear contact: collision_time and reference mass must be > 0");
  }
  const double ln_e = std::log(restitution);
  // k_n = m_ref (pi^2 + ln^2 e) / t_c^2  [N/m]
  const double k_n = m_ref * (units::kPi * units::kPi + ln_e * ln_e) / (t_c * t_c);
  return from_stiffness(k_n, restitution, friction, tangential_ratio);
}

double LinearSpringDashpot::damping_coefficient(double m_eff) const {
  // gamma_n = 2 sqrt(m* k_n) (-ln e) / sqrt(pi^2 + ln^2 e)  [kg/s]
  return 2.0 * std::sqrt(m_eff * k_n_) * log_factor_;
}

double LinearSpringDashpot::collision_time(double m_eff) const {
  const double omega0_sq = k_n_ / m_eff;
  const double g = damping_coefficient(m_eff) / (2.0 * m_eff);
  return units::kPi / std::sqrt(omega0_sq - g * g);  // pi / omega_d [s]
}

HertzMindlin HertzMindlin::from_material(const Material& material) {
  return from_pair(material, material, material.restitution, material.friction);
}

HertzMindlin HertzMindlin::from_pair(const Material& a, const Material& b, double restitution,
                                     double friction) {
  HertzMindlin law;
  law.e_star_ = pair_effective_young(a, b);
  law.g_star_ = pair_effective_shear(a, b);
  law.e_ = restitution;
  law.mu_ = friction;
  law.alpha_ = hertz_damping_ratio_for_restitution(restitution);
  return law;
}

double hertz_elastic_duration(double m_eff, double r_eff, double e_star, double v) {
  return 2.87 * std::pow(m_eff * m_eff / (r_eff * e_star * e_star * v), 0.2);
}

}  // namespace ppohdem::dem
