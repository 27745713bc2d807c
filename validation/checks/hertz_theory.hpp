#pragma once
// Independent answers for the Chung & Ooi (2011) impact benchmarks.
//
// 1. Elastic Hertz impact, closed form (Johnson 1985, sec. 11.4):
//      delta_max = (15 m* v^2 / (16 E* sqrt(R*)))^{2/5}                    [m]
//      F_max     = (4/3) E* sqrt(R*) delta_max^{3/2}                         [N]
//      t_c       = 2 (delta_max / v) (2/5) B(2/5, 1/2) = 2.9432 delta_max/v  [s]
// 2. Linear spring-dashpot, closed form (Schwager & Poeschel 2005, sec. 3.1): see contact_law.hpp.
// 3. Oblique impacts: the reduced two-body problem of the Hertz-Mindlin spring model (normal
//    Hertz force, Mindlin no-slip tangential spring k_t = 8 G* sqrt(R* delta) on the total
//    tangential displacement xi, Coulomb cap |k_t xi| <= mu F_n), integrated here as scalar
//    ODEs by classical RK4 with 100,000 steps per contact and the cap applied after each step
//    (operator splitting). Tangential effective mass of two solid spheres at their contact point
//    1/m_t = sum (1/m_i + R_i^2/I_i) = (7/2)/m*  (both spheres, or one sphere on a plane).
//    The impact is fully described by m*, R*, E*, G*, mu, the normal approach speed v_n and the
//    initial slip velocity of the contact point v_c; the bodies' rebound velocities and spins
//    follow exactly from the impulses J_n, J_t (rigid-body momentum balance).
//    Analytic limits drawn with the curves (Maw, Barber & Fawcett 1976, Wear 38:101; the
//    normalisation of Thornton, Cummins & Cleary 2011, Powder Technol. 210:189):
//      Psi = 4 (G*/E*) v_c / (mu v_n)   (= 2(1-nu) v_c / ((2-nu) mu v_n) for one material)
//      chi = (1 + m R^2/I)(1 - nu)/(2 - nu) = 7 G*/E* (one material); gross sliding gives
//      Psi2 = Psi1 - 4 chi (e = 1), throughout the contact for Psi1 >= 4 chi (rigid-body limit);
//      the no-slip limit (mu -> infinity) gives Psi2 = r Psi1 with r from no_slip_ratio().
namespace ppohdem::validation {

struct HertzImpactTheory {
  double max_overlap = 0.0;  ///< [m]
  double max_force = 0.0;    ///< [N]
  double duration = 0.0;     ///< [s]
};
/// Elastic Hertz impact at approach speed v [m/s].
HertzImpactTheory hertz_impact(double m_eff, double r_eff, double e_star, double v);

struct ObliqueReference {
  double normal_impulse = 0.0;      ///< J_n [N s] (= 2 m* v_n for e = 1)
  double tangential_impulse = 0.0;  ///< J_t [N s], signed along the initial slip direction
  double slip_velocity_after = 0.0; ///< v_c' [m/s]
  double normal_velocity_after = 0.0;  ///< separation speed [m/s]
  double duration = 0.0;            ///< [s]
};
/// Elastic (e = 1) Hertz-Mindlin oblique impact, reduced scalar problem (see above).
ObliqueReference oblique_reference(double m_eff, double r_eff, double e_star, double g_star,
                                   double mu, double v_n, double v_c);

/// v_c'/v_c in the no-slip limit (mu -> infinity) for a given G*/E* (RK4, dimensionless).
double no_slip_ratio(double g_over_e);

}  // namespace ppohdem::validation
