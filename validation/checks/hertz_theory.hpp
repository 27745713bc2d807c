#pragma once
// Independent answers for the Chung & Ooi (2011) impact benchmarks.
//
// 1. Elastic Hertz impact, closed form (Johnson 1985, sec. 11.4):
//      delta_max = (15 m* v^2 / (16 E* sqrt(R*)))^{2/5}                    [m]
//      F_max     = (4/3) E* sqrt(R*) delta_max^{3/2}                         [N]
//      t_c       = 2 (delta_max / v) (2/5) B(2/5, 1/2) = 2.9432 delta_max/v  [s]
// 2. Linear spring-dashpot, closed form (Schwager & Poeschel 2005, sec. 3.1): see contact_law.hpp.
// 3. Oblique impacts: the two-body problem of the Hertz-Mindlin spring model with the same
//    definitions as contact_law.hpp, written here for motion in one plane and integrated as
//    ODEs by classical RK4 with 100,000 steps per contact, the Coulomb cap applied to the
//    force in every stage and to the spring after each step:
//      normal       m* delta'' = -F_n,  F_n = max(0, K delta^{3/2} + alpha sqrt(m* K) delta^{1/4} delta')
//                   K = (4/3) E* sqrt(R*)   (Hertz; Tsuji, Tanaka & Ishida 1992 damping)
//      tangential   F_t = -k_t xi,  k_t = 8 G* sqrt(R* delta) (Mindlin),  |k_t xi| <= mu F_n
//                   xi' = u = V - a_A w_A - a_B w_B   (slip of the contact point)
//                   V' = F_t (1/m_A + 1/m_B),  w_A' = -a_A F_t / I_A,  w_B' = -a_B F_t / I_B
//    where V is the tangential velocity of A's centre relative to B's, w the spins about the
//    axis normal to the plane of motion, and a the lever arms from the centres to the contact
//    point: a = R - delta for a sphere on a plane (contact point on the plane), a_i = R_i -
//    delta/2 between two spheres (middle of the overlap). The line of centres is held fixed
//    (exact against a plane; between spheres it turns by ~|V| t_c / (R_A + R_B), which the
//    checks bound). The rebound follows from the state at the end of contact (delta = 0).
//    Analytic limits drawn with the curves (Maw, Barber & Fawcett 1976, Wear 38:101; the
//    normalisation of Thornton, Cummins & Cleary 2011, Powder Technol. 210:189):
//      Psi = 4 (G*/E*) v_c / (mu v_n),  chi = 7 G*/E* for one material of solid spheres;
//      gross sliding throughout the contact (rigid-body limit, Psi1 >= 2 chi (1 + e)):
//      J_t = mu J_n, J_n = m* (1 + e) v_n, so Psi2 = Psi1 - 2 chi (1 + e);
//      the no-slip elastic limit (mu -> infinity) gives Psi2 = r Psi1 with r from no_slip_ratio().
namespace ppohdem::validation {

struct HertzImpactTheory {
  double max_overlap = 0.0;  ///< [m]
  double max_force = 0.0;    ///< [N]
  double duration = 0.0;     ///< [s]
};
/// The Hertz normal force F = (4/3) E* sqrt(R*) delta^{3/2} at overlap delta >= 0 [N]
/// (Johnson 1985, eq. 4.23); 0 for delta <= 0.
double hertz_elastic_force(double overlap, double r_eff, double e_star);
/// Elastic Hertz impact at approach speed v [m/s].
HertzImpactTheory hertz_impact(double m_eff, double r_eff, double e_star, double v);

/// One body of an oblique impact (plane of motion x-z, normal z, spin about y).
struct ImpactBody {
  double mass = 0.0;     ///< [kg]
  double inertia = 0.0;  ///< [kg m^2]
  double radius = 0.0;   ///< [m]
};
struct ObliqueProblem {
  ImpactBody a;
  ImpactBody b;                 ///< ignored when `plane` (B is a rigid plane at rest)
  bool plane = false;
  double e_star = 0.0, g_star = 0.0;  ///< [Pa]
  double mu = 0.0;              ///< Coulomb friction [-]
  double alpha = 0.0;           ///< Tsuji damping ratio alpha(e) (0: elastic) [-]
  double v_n = 0.0;             ///< approach speed [m/s] (> 0)
  double v_t = 0.0;             ///< tangential velocity of A's centre relative to B's [m/s]
  double spin_a = 0.0, spin_b = 0.0;  ///< [rad/s]
};
struct ObliqueReference {
  double normal_velocity_after = 0.0;  ///< separation speed [m/s]
  double tangential_velocity_after = 0.0;  ///< V' [m/s]
  double spin_a_after = 0.0, spin_b_after = 0.0;  ///< [rad/s]
  double slip_velocity_after = 0.0;    ///< u' = V' - a_A w_A' - a_B w_B' at separation [m/s]
  double normal_impulse = 0.0;         ///< J_n = m* (v_n + v_n') [N s]
  double tangential_impulse = 0.0;     ///< J_t on A along x [N s]
  double duration = 0.0;               ///< [s]
};
ObliqueReference oblique_reference(const ObliqueProblem& p);

/// v_c'/v_c in the no-slip elastic limit (mu -> infinity, lever arm R) for a given G*/E*
/// (RK4, dimensionless).
double no_slip_ratio(double g_over_e);

}  // namespace ppohdem::validation
