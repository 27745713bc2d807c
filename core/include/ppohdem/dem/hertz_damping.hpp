#pragma once
/// \file hertz_damping.hpp
/// Restitution <-> damping ratio for the damped Hertz law of Tsuji et al. (1992).
///
/// With delta = L x, t = T tau, L = (m* v0^2 / K)^{2/5}, T = L / v0, the equation
///   m* delta'' = -K delta^{3/2} - eta delta^{1/4} delta'   (force clamped at >= 0)
/// becomes   x'' = -x^{3/2} - alpha x^{1/4} x',  x(0) = 0, x'(0) = 1,  alpha = eta / sqrt(m* K),
/// so the restitution e = -x'(tau_end) and the scaled duration tau_end depend on alpha only.
/// They are computed here by classical RK4 with step 1e-4 in tau (about 35,000 steps;
/// the end point is found by linear interpolation of the zero crossing of x). The force is
/// not smooth (x^{1/4}, the clamp), so convergence is slower than h^4: halving the step
/// changes e by < 1e-6 (tests/dem checks), far below the 1% the scenes promise.
namespace ppohdem::dem {

struct HertzDampedImpact {
  double restitution = 1.0;     ///< e = -x'(tau_end) [-]
  double scaled_duration = 0.0; ///< tau_end; duration [s] = tau_end * T
};

/// Integrates the dimensionless impact for damping ratio alpha >= 0.
/// `scaled_step` is the RK4 step in tau.
HertzDampedImpact hertz_damped_impact(double alpha, double scaled_step = 1.0e-4);
/// The alpha in [0, 10] whose impact has restitution e (bisection to 1e-10 in alpha);
/// throws InputError unless 0 < e <= 1 (e <= ~0.0 is not reachable: the law is
/// never critically damped for the clamped force, but alpha is capped at 10).
double hertz_damping_ratio_for_restitution(double restitution);

}  // namespace ppohdem::dem
