#include "hertz_theory.hpp"

#include <algorithm>
#include <cmath>

namespace ppohdem::validation {

double hertz_elastic_force(double overlap, double r_eff, double e_star) {
  return overlap > 0.0 ? 4.0 / 3.0 * e_star * std::sqrt(r_eff) * std::pow(overlap, 1.5) : 0.0;
}

HertzImpactTheory hertz_impact(double m_eff, double r_eff, double e_star, double v) {
  HertzImpactTheory h;
  h.max_overlap = std::pow(15.0 * m_eff * v * v / (16.0 * e_star * std::sqrt(r_eff)), 0.4);
  h.max_force = hertz_elastic_force(h.max_overlap, r_eff, e_star);
  const double beta = std::tgamma(0.4) * std::tgamma(0.5) / std::tgamma(0.9);  // B(2/5, 1/2)
  h.duration = 2.0 * h.max_overlap / v * 0.4 * beta;
  return h;
}

ObliqueReference oblique_reference(const ObliqueProblem& p) {
  const double m_a = p.a.mass, m_b = p.plane ? 0.0 : p.b.mass;
  const double m_eff = p.plane ? m_a : m_a * m_b / (m_a + m_b);  // m* [kg]
  const double r_eff = p.plane ? p.a.radius : p.a.radius * p.b.radius / (p.a.radius + p.b.radius);
  const double inv_m = 1.0 / m_a + (p.plane ? 0.0 : 1.0 / m_b);  // [1/kg]
  const double k_hertz = 4.0 / 3.0 * p.e_star * std::sqrt(r_eff);  // K [N/m^{3/2}]
  const double eta = p.alpha * std::sqrt(m_eff * k_hertz);         // [kg/(s m^{1/4})]
  const double h = hertz_impact(m_eff, r_eff, p.e_star, p.v_n).duration / 100000.0;  // [s]
  // state: overlap d, its rate dd (> 0 approaching), V, spins w_a, w_b, spring xi.
  struct State {
    double d, dd, v, wa, wb, xi;
  };
  auto normal_force = [&](double d, double dd) {
    if (d <= 0.0) return 0.0;
    const double f = k_hertz * d * std::sqrt(d) + eta * std::sqrt(std::sqrt(d)) * dd;
    return f > 0.0 ? f : 0.0;  // no attraction
  };
  auto arms = [&](double d, double& arm_a, double& arm_b) {
    const double dd = d > 0.0 ? d : 0.0;
    arm_a = p.plane ? p.a.radius - dd : p.a.radius - 0.5 * dd;
    arm_b = p.plane ? 0.0 : p.b.radius - 0.5 * dd;
  };
  auto rhs = [&](const State& s) {
    const double d = s.d > 0.0 ? s.d : 0.0;
    // Spring force, capped at mu F_n inside the step as well (the engines cap every force
    // they apply; capping only the state after a step would let RK4's stages exceed it).
    const double spring = 8.0 * p.g_star * std::sqrt(r_eff * d) * std::abs(s.xi);
    const double f_t = -std::copysign(std::min(spring, p.mu * normal_force(s.d, s.dd)), s.xi);
    double arm_a, arm_b;
    arms(s.d, arm_a, arm_b);
    return State{s.dd,
                 -normal_force(s.d, s.dd) / m_eff,
                 f_t * inv_m,
                 -arm_a * f_t / p.a.inertia,
                 p.plane ? 0.0 : -arm_b * f_t / p.b.inertia,
                 s.v - arm_a * s.wa - arm_b * s.wb};
  };
  auto axpy = [](const State& a, const State& k, double c) {
    return State{a.d + c * k.d, a.dd + c * k.dd, a.v + c * k.v, a.wa + c * k.wa, a.wb + c * k.wb, a.xi + c * k.xi};
  };
  State s{0.0, p.v_n, p.v_t, p.spin_a, p.spin_b, 0.0};
  ObliqueReference r;
  for (long n = 0; n < 20000000; ++n) {
    const State k1 = rhs(s), k2 = rhs(axpy(s, k1, h / 2)), k3 = rhs(axpy(s, k2, h / 2)),
                k4 = rhs(axpy(s, k3, h));
    State next = axpy(s, k1, h / 6);
    next = axpy(next, k2, h / 3);
    next = axpy(next, k3, h / 3);
    next = axpy(next, k4, h / 6);
    // Coulomb cap on the spring (contact_force.hpp step 3: |k_t xi| <= mu F_n).
    if (next.d > 0.0) {
      const double cap = p.mu * normal_force(next.d, next.dd);
      const double k_t = 8.0 * p.g_star * std::sqrt(r_eff * next.d);
      if (k_t * std::abs(next.xi) > cap) next.xi = std::copysign(cap / k_t, next.xi);
    }
    if (n > 0 && next.d <= 0.0) {
      const double w = s.d / (s.d - next.d);  // interpolate the end of contact
      auto lerp = [w](double x0, double x1) { return x0 + w * (x1 - x0); };
      r.duration = (static_cast<double>(n) + w) * h;
      r.normal_velocity_after = -lerp(s.dd, next.dd);
      r.tangential_velocity_after = lerp(s.v, next.v);
      r.spin_a_after = lerp(s.wa, next.wa);
      r.spin_b_after = lerp(s.wb, next.wb);
      const double arm_b = p.plane ? 0.0 : p.b.radius;  // levers at separation (delta = 0)
      r.slip_velocity_after = r.tangential_velocity_after - p.a.radius * r.spin_a_after - arm_b * r.spin_b_after;
      r.normal_impulse = m_eff * (p.v_n + r.normal_velocity_after);
      r.tangential_impulse = (r.tangential_velocity_after - p.v_t) / inv_m;
      return r;
    }
    s = next;
  }
  return r;
}

double no_slip_ratio(double g_over_e) {
  // Dimensionless no-slip equations (tests/dem/chung_ooi_test.cpp derives them):
  //   x'' = -x^{3/2},  y'' = -21 (G*/E*) x^{1/2} y,  x(0) = y(0) = 0, x'(0) = y'(0) = 1.
  auto f = [&](const double* q, double* out) {
    const double sx = q[0] > 0.0 ? std::sqrt(q[0]) : 0.0;
    out[0] = q[1];
    out[1] = -q[0] * sx;
    out[2] = q[3];
    out[3] = -21.0 * g_over_e * sx * q[2];
  };
  double u[4] = {0.0, 1.0, 0.0, 1.0};
  const double h = 1e-5;
  for (long n = 0; n < 10000000; ++n) {
    double k1[4], k2[4], k3[4], k4[4], t[4], next[4];
    f(u, k1);
    for (int i = 0; i < 4; ++i) t[i] = u[i] + h / 2 * k1[i];
    f(t, k2);
    for (int i = 0; i < 4; ++i) t[i] = u[i] + h / 2 * k2[i];
    f(t, k3);
    for (int i = 0; i < 4; ++i) t[i] = u[i] + h * k3[i];
    f(t, k4);
    for (int i = 0; i < 4; ++i) next[i] = u[i] + h / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
    if (n > 0 && next[0] <= 0.0) {
      const double w = u[0] / (u[0] - next[0]);
      return u[3] + w * (next[3] - u[3]);
    }
    for (int i = 0; i < 4; ++i) u[i] = next[i];
  }
  return 0.0;
}

}  // namespace ppohdem::validation
