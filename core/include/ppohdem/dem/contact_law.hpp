#pragma once
/// \file contact_law.hpp
/// The contact laws of ppohdem (linear, hooke, Hertz-Mindlin), in "observable" form (MercuryDPM habit): users give
/// restitution and a collision time or stiffness (linear) or the elastic constants (Hertz),
/// and the laws derive springs and dashpots once. Both laws offer the same member functions,
/// so force kernels are templates over the law (contact_force.hpp).
///
/// Sign conventions: delta > 0 is the overlap [m]; delta_dot = d(delta)/dt [m/s] is positive
/// while the bodies approach; normal forces are positive when repulsive [N].
///
/// LINEAR SPRING-DASHPOT (Cundall & Strack 1979; analytic solution e.g. Schwager & Poeschel,
/// "Computational Granular Dynamics", 2005, sec. 3.1):
///   F_n = k_n delta + gamma_n delta_dot                                    [N]
///   omega_0 = sqrt(k_n / m*),  omega_d = sqrt(omega_0^2 - (gamma_n / (2 m*))^2)   [rad/s]
///   contact duration t_c = pi / omega_d,  restitution e = exp(-gamma_n t_c / (2 m*))
///   => gamma_n = 2 sqrt(m* k_n) (-ln e) / sqrt(pi^2 + ln^2 e)              [kg/s]
///   from a collision time t_c (for the reference effective mass m_ref):
///      k_n = m_ref (pi^2 + ln^2 e) / t_c^2                                 [N/m]
///   The force is NOT clamped at zero: the textbook damped oscillator, whose restitution and
///   duration are exactly the formulas above (contact ends when delta returns to 0).
///   Tangential spring k_t = ratio * k_n (default 2/7: the tangential and normal oscillation
///   periods of a sphere then agree, Schaefer, Dippel & Wolf 1996), with history and the
///   Coulomb cap |F_t| <= mu |F_n|.
///
/// HOOKE (LIGGGHTS `model hooke`, its documentation "gran model hooke"): the same linear
/// spring-dashpot with k_n per contact, the secant stiffness of a Hertz contact at the
/// overlap that an elastic impact at the characteristic velocity v_c reaches (the linear
/// spring stores the Hertz energy (8/15) E* sqrt(R*) delta^{5/2} there):
///   k_n = (16/15) sqrt(R*) E* (15 m* v_c^2 / (16 sqrt(R*) E*))^{1/5}      [N/m]
///   gamma_n as above with this k_n (LIGGGHTS: sqrt(4 m* k_n / (1 + (pi / ln e)^2)), equal),
///   k_t = ratio * k_n with ratio 1 by default (LIGGGHTS' kt = kn; ktToKnUser: 2/7).
///   Against a wall or object R* = R and m* = m, so k_n is 2^{3/5} = 1.516 times that of a
///   pair of two equal spheres. No clamp at F_n >= 0 (LIGGGHTS' default, limitForce off).
///
/// TANGENTIAL DASHPOT (`tangential_damping`; LIGGGHTS' default for hooke, Cundall & Strack
/// 1979): F_t = -k_t xi - gamma_t v_t with gamma_t = gamma_n of the contact (LIGGGHTS'
/// gammat = gamman; Hertz: the Tsuji coefficient eta delta^{1/4}) [kg/s] and v_t the
/// tangential relative velocity at the contact point [m/s]; Coulomb caps the TOTAL force
/// (contact_force.hpp).
///
/// HERTZ-MINDLIN (Hertz 1882; Mindlin 1949 no-slip; Johnson 1985 ch. 4 and 7):
///   F_n = K delta^{3/2} + eta delta^{1/4} delta_dot,   K = (4/3) E* sqrt(R*)   [N]
///   clamped at F_n >= 0 (no attraction), as YADE/LIGGGHTS/LAMMPS do;
///   elastic energy U_n = (2/5) K delta^{5/2}                               [J]
///   tangential stiffness k_t = 8 G* sqrt(R* delta)  (Mindlin no-slip)      [N/m]
///   Damping: the form of Tsuji, Tanaka & Ishida (1992, Powder Technol. 71:239), damping
///   force proportional to delta^{1/4} so that e does not depend on the impact velocity:
///      eta = alpha(e) sqrt(m* K)                                           [kg/(s m^{1/4})]
///   Tsuji read alpha(e) off a chart; here alpha(e) is found once per scene by solving the
///   dimensionless equation x'' = -x^{3/2} - alpha x^{1/4} x' (with the same clamp) for the
///   alpha whose MEASURED rebound velocity ratio is e (hertz_damping.hpp). So the scene's e is
///   the measured restitution of a binary collision (DESIGN.md), unlike LAMMPS `damping tsuji`
///   (0.616 measured for input 0.5). For e = 0.5 the contact lasts 1.1051 times the elastic
///   Hertz duration 2.87 (m*^2 / (R* E*^2 v))^{1/5} (peer codes: 1.7854e-4 s for two 1 mm
///   diameter spheres, 2500 kg/m^3, E = 1e7 Pa, nu = 0.3, at 0.1 m/s).
#include <cmath>

#include "ppohdem/dem/material.hpp"
#include "ppohdem/dem/rolling_resistance.hpp"

namespace ppohdem::dem {

enum class ContactModel { kLinear, kHertzMindlin };  // (hooke: LinearSpringDashpot::hooke)

/// Effective inertia and curvature of one contact (material.hpp).
struct PairProperties {
  double m_eff = 0.0;  ///< m* [kg]
  double r_eff = 0.0;  ///< R* [m]
};

class LinearSpringDashpot {
 public:
  /// Given k_n [N/m] and restitution e in (0, 1].
  static LinearSpringDashpot from_stiffness(double k_n, double restitution, double friction,
                                            double tangential_ratio = 2.0 / 7.0);
  /// Given the collision duration t_c [s] of a pair with effective mass m_ref [kg].
  static LinearSpringDashpot from_collision_time(double t_c, double m_ref, double restitution,
                                                 double friction,
                                                 double tangential_ratio = 2.0 / 7.0);
  /// LIGGGHTS' hooke: k_n per contact from E* [Pa] and the characteristic velocity v_c [m/s]
  /// (header comment); k_t = tangential_ratio * k_n.
  static LinearSpringDashpot hooke(double e_star, double characteristic_velocity, double restitution,
                                   double friction, double tangential_ratio = 1.0);
  /// The law of materials a and b (pair_laws.hpp): this law's stiffness rule (its constant
  /// k_n, or hooke with E* of a and b), tangential ratio and dashpot switch, with the pair's e
  /// and mu.
  LinearSpringDashpot for_pair(const Material& a, const Material& b, double restitution,
                               double friction) const;

  /// k_n per contact (hooke) rather than one constant k_n.
  bool per_contact_stiffness() const { return hooke_e_star_ > 0.0; }
  double normal_stiffness() const { return k_n_; }  ///< the constant k_n [N/m]; 0 for hooke
  double characteristic_velocity() const { return hooke_velocity_; }  ///< v_c [m/s] (hooke)
  double effective_young() const { return hooke_e_star_; }  ///< E* [Pa] (hooke; else 0)
  double restitution() const { return e_; }
  double friction() const { return mu_; }
  /// k_n of a contact [N/m]: the constant, or hooke's formula.
  double stiffness(const PairProperties& pair) const {
    return per_contact_stiffness() ? hooke_stiffness(pair) : k_n_;
  }
  /// gamma_n [kg/s] giving restitution e for a pair of effective mass m* (constant k_n).
  double damping_coefficient(double m_eff) const;
  /// gamma_n [kg/s] of a contact (either stiffness rule).
  double damping_coefficient(const PairProperties& pair) const {
    return 2.0 * std::sqrt(pair.m_eff * stiffness(pair)) * log_factor_;
  }
  /// t_c = pi / omega_d [s] (constant k_n).
  double collision_time(double m_eff) const;
  /// t_c = pi / omega_d [s] of a contact (either stiffness rule).
  double collision_time(const PairProperties& pair) const;

  double elastic_force(double delta, const PairProperties& pair) const { return stiffness(pair) * delta; }
  double normal_force(double delta, double delta_dot, const PairProperties& pair) const {
    if (!per_contact_stiffness()) return k_n_ * delta + damping_coefficient(pair.m_eff) * delta_dot;
    const double k = hooke_stiffness(pair);
    return k * delta + 2.0 * std::sqrt(pair.m_eff * k) * log_factor_ * delta_dot;
  }
  double elastic_energy(double delta, const PairProperties& pair) const {
    return 0.5 * stiffness(pair) * delta * delta;  // U_n = k_n delta^2 / 2 [J]
  }
  double tangential_stiffness(double, const PairProperties& pair) const {
    return per_contact_stiffness() ? k_t_ratio_ * hooke_stiffness(pair) : k_t_;
  }
  /// Tangential dashpot on (contact_force.hpp), and its gamma_t = gamma_n [kg/s].
  bool tangential_damping() const { return tangential_damping_; }
  void set_tangential_damping(bool on) { tangential_damping_ = on; }
  double tangential_damping_coefficient(double, const PairProperties& pair) const {
    return damping_coefficient(pair);
  }
  /// Rolling resistance of the pair (rolling_resistance.hpp); none unless set.
  const RollingParameters& rolling() const { return rolling_; }
  void set_rolling(const RollingParameters& rolling) { rolling_ = rolling; }

 private:
  /// (16/15) sqrt(R*) E* (15 m* v_c^2 / (16 sqrt(R*) E*))^{1/5} [N/m]
  double hooke_stiffness(const PairProperties& pair) const {
    const double sqrt_r = std::sqrt(pair.r_eff);
    return 16.0 / 15.0 * sqrt_r * hooke_e_star_ *
           std::pow(15.0 * pair.m_eff * hooke_velocity_sq_ / (16.0 * sqrt_r * hooke_e_star_), 0.2);
  }

  double k_n_ = 0.0;  ///< [N/m]; 0 for hooke
  double k_t_ = 0.0;  ///< [N/m]; 0 for hooke
  double k_t_ratio_ = 2.0 / 7.0;  ///< k_t / k_n [-]
  double e_ = 1.0;
  double mu_ = 0.0;
  double log_factor_ = 0.0;  ///< -ln e / sqrt(pi^2 + ln^2 e) [-]
  double hooke_e_star_ = 0.0;  ///< E* [Pa]; > 0 selects hooke
  double hooke_velocity_ = 0.0;  ///< v_c [m/s]
  double hooke_velocity_sq_ = 0.0;  ///< v_c^2 [m^2/s^2]
  bool tangential_damping_ = false;
  RollingParameters rolling_;
};

class HertzMindlin {
 public:
  /// Uses E, nu, restitution and friction of `material`; alpha(e) from hertz_damping.hpp.
  static HertzMindlin from_material(const Material& material);
  /// Two materials a, b (pair_laws.hpp): E* and G* from pair_effective_young/_shear
  /// (material.hpp), the pair's restitution e and friction mu given. from_pair(m, m,
  /// m.restitution, m.friction) is bitwise from_material(m).
  static HertzMindlin from_pair(const Material& a, const Material& b, double restitution,
                                double friction);

  double restitution() const { return e_; }
  double friction() const { return mu_; }
  double damping_ratio() const { return alpha_; }  ///< Tsuji's alpha(e) [-]
  double effective_young() const { return e_star_; }  ///< E* [Pa]
  double effective_shear() const { return g_star_; }  ///< G* [Pa]

  /// K = (4/3) E* sqrt(R*) [N/m^{3/2}]
  double hertz_constant(const PairProperties& pair) const {
    return 4.0 / 3.0 * e_star_ * std::sqrt(pair.r_eff);
  }
  double elastic_force(double delta, const PairProperties& pair) const {
    return hertz_constant(pair) * delta * std::sqrt(delta);
  }
  double normal_force(double delta, double delta_dot, const PairProperties& pair) const {
    const double k = hertz_constant(pair);
    const double eta = alpha_ * std::sqrt(pair.m_eff * k);
    const double f = k * delta * std::sqrt(delta) + eta * std::sqrt(std::sqrt(delta)) * delta_dot;
    return f > 0.0 ? f : 0.0;  // no attraction
  }
  double elastic_energy(double delta, const PairProperties& pair) const {
    return 0.4 * hertz_constant(pair) * delta * delta * std::sqrt(delta);  // (2/5) K delta^{5/2}
  }
  double tangential_stiffness(double delta, const PairProperties& pair) const {
    return 8.0 * g_star_ * std::sqrt(pair.r_eff * delta);
  }
  /// Tangential dashpot on (contact_force.hpp), and its gamma_t [kg/s]: the normal dashpot's
  /// coefficient eta delta^{1/4} at this overlap (gamma_t = gamma_n, as LIGGGHTS' hooke).
  bool tangential_damping() const { return tangential_damping_; }
  void set_tangential_damping(bool on) { tangential_damping_ = on; }
  double tangential_damping_coefficient(double delta, const PairProperties& pair) const {
    return alpha_ * std::sqrt(pair.m_eff * hertz_constant(pair)) * std::sqrt(std::sqrt(delta));
  }
  /// Rolling resistance of the pair (rolling_resistance.hpp); none unless set.
  const RollingParameters& rolling() const { return rolling_; }
  void set_rolling(const RollingParameters& rolling) { rolling_ = rolling; }

 private:
  double e_star_ = 0.0;
  double g_star_ = 0.0;
  double e_ = 1.0;
  double mu_ = 0.0;
  double alpha_ = 0.0;
  bool tangential_damping_ = false;
  RollingParameters rolling_;
};

/// The elastic Hertz collision duration 2.87 (m*^2 / (R* E*^2 v))^{1/5} [s] (Johnson 1985,
/// eq. 11.24 with the exact coefficient 2.868); v [m/s] is the relative approach speed.
double hertz_elastic_duration(double m_eff, double r_eff, double e_star, double v);

}  // namespace ppohdem::dem
