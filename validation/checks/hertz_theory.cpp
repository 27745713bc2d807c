#include "hertz_theory.hpp"

#include <cmath>

namespace ppohdem::validation {

HertzImpactTheory hertz_impact(double m_eff, double r_eff, double e_star, double v) {
  HertzImpactTheory h;
  h.max_overlap = std::pow(15.0 * m_eff * v * v / (16.0 * e_star * std::sqrt(r_eff)), 0.4);
  h.max_force = 4.0 / 3.0 * e_star * std::sqrt(r_eff) * std::pow(h.max_overlap, 1.5);
  const double beta = std::tgamma(0.4) * std::tgamma(0.5) / std::tgamma(0.9);  // B(2/5, 1/2)
  h.duration = 2.0 * h.max_overlap / v * 0.4 * beta;
  return h;
}

ObliqueReference oblique_reference(double m_eff, double r_eff, double e_star, double g_star,
                                   double mu, double v_n, double v_c) {
  const double m_t = m_eff * 2.0 / 7.0;  // tangential effective mass of solid spheres [kg]
  const double k_hertz = 4.0 / 3.0 * e_star * std::sqrt(r_eff);  // [N/m^{3/2}]
  const double t_c = hertz_impact(m_eff, r_eff, e_star, v_n).duration;
  const double h = t_c / 100000.0;
  // state: delta, delta_dot, slip velocity u, spring xi; F_t = -k_t xi acts on the slip.
  struct State {
    double d, dd, u, xi;
  };
  auto rhs = [&](const State& s) {
    const double d = s.d > 0.0 ? s.d : 0.0;
    const double f_n = k_hertz * d * std::sqrt(d);
    const double k_t = 8.0 * g_star * std::sqrt(r_eff * d);
    return State{s.dd, -f_n / m_eff, -k_t * s.xi / m_t, s.u};
  };
  auto axpy = [](const State& a, const State& k, double c) {
    return State{a.d + c * k.d, a.dd + c * k.dd, a.u + c * k.u, a.xi + c * k.xi};
  };
  State s{0.0, v_n, v_c, 0.0};
  ObliqueReference r;
  for (long n = 0; n < 10000000; ++n) {
    const State k1 = rhs(s), k2 = rhs(axpy(s, k1, h / 2)), k3 = rhs(axpy(s, k2, h / 2)),
                k4 = rhs(axpy(s, k3, h));
    State next{s.d + h / 6 * (k1.d + 2 * k2.d + 2 * k3.d + k4.d),
               s.dd + h / 6 * (k1.dd + 2 * k2.dd + 2 * k3.dd + k4.dd),
               s.u + h / 6 * (k1.u + 2 * k2.u + 2 * k3.u + k4.u),
               s.xi + h / 6 * (k1.xi + 2 * k2.xi + 2 * k3.xi + k4.xi)};
    // Coulomb cap on the spring (the engines' rule, contact_force.hpp step 3).
    if (next.d > 0.0) {
      const double f_n = k_hertz * next.d * std::sqrt(next.d);
      const double k_t = 8.0 * g_star * std::sqrt(r_eff * next.d);
      if (k_t * std::abs(next.xi) > mu * f_n) next.xi = std::copysign(mu * f_n / k_t, next.xi);
    }
    if (n > 0 && next.d <= 0.0) {
      const double w = s.d / (s.d - next.d);  // interpolate the end of contact
      r.duration = (static_cast<double>(n) + w) * h;
      r.slip_velocity_after = s.u + w * (next.u - s.u);
      r.normal_velocity_after = -(s.dd + w * (next.dd - s.dd));
      r.normal_impulse = m_eff * (v_n + r.normal_velocity_after);
      r.tangential_impulse = m_t * (r.slip_velocity_after - v_c);
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
