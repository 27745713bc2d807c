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
  law.k_t_ratio_ = tangential_ratio;
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

LinearSpringDashpot LinearSpringDashpot::hooke(double e_star, double characteristic_velocity,
                                               double restitution, double friction,
                                               double tangential_ratio) {
  if (!(e_star > 0.0) || !std::isfinite(e_star)) {
    throw InputError("hooke contact: E* must be > 0 Pa (young > 0, -1 < poisson < 0.5), got " +
                     std::to_string(e_star));
  }
  if (!(characteristic_velocity > 0.0) || !std::isfinite(characteristic_velocity)) {
    throw InputError("hooke contact: characteristic_velocity must be > 0 m/s, got " +
                     std::to_string(characteristic_velocity));
  }
  // The constant-stiffness factory checks e, mu and the ratio; k_n = 1 is a placeholder.
  LinearSpringDashpot law = from_stiffness(1.0, restitution, friction, tangential_ratio);
  law.k_n_ = 0.0;
  law.k_t_ = 0.0;
  law.hooke_e_star_ = e_star;
  law.hooke_velocity_ = characteristic_velocity;
  law.hooke_velocity_sq_ = characteristic_velocity * characteristic_velocity;
  return law;
}

LinearSpringDashpot LinearSpringDashpot::for_pair(const Material& a, const Material& b,
                                                  double restitution, double friction) const {
  LinearSpringDashpot law =
      per_contact_stiffness()
          ? hooke(pair_effective_young(a, b), hooke_velocity_, restitution, friction, k_t_ratio_)
          : from_stiffness(k_n_, restitution, friction, k_t_ratio_);
  if (!per_contact_stiffness()) law.k_t_ = k_t_;  // the same bits as this law's k_t
  law.tangential_damping_ = tangential_damping_;
  law.rolling_ = rolling_;
  return law;
}

double LinearSpringDashpot::collision_time(const PairProperties& pair) const {
  const double omega0_sq = stiffness(pair) / pair.m_eff;
  const double g = damping_coefficient(pair) / (2.0 * pair.m_eff);
  return units::kPi / std::sqrt(omega0_sq - g * g);  // pi / omega_d [s]
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
