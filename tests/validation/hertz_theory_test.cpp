// The Hertz oracle's closed forms against each other (validation/checks/hertz_theory.hpp): the
// work of the elastic force up to the largest overlap must equal the kinetic energy of approach.
#include <gtest/gtest.h>

#include <cmath>

#include "hertz_theory.hpp"

namespace ppohdem::validation {
namespace {

TEST(HertzTheory, ForceWorkToMaxOverlapEqualsApproachEnergy) {
  const double m_eff = 6.545e-7, r_eff = 2.5e-4, e_star = 5.4945e6, v = 0.1;  // two 1 mm spheres
  const HertzImpactTheory h = hertz_impact(m_eff, r_eff, e_star, v);
  // Simpson's rule on F(delta) = K delta^1.5 over 20000 panels: error ~1e-9 relative (the
  // integrand's derivative is singular only mildly at 0), well under the 1e-7 asked.
  const int n = 20000;
  const double step = h.max_overlap / n;
  double work = 0.0;
  for (int k = 0; k <= n; ++k) {
    const double w = (k == 0 || k == n) ? 1.0 : (k % 2 == 1 ? 4.0 : 2.0);
    work += w * hertz_elastic_force(k * step, r_eff, e_star);
  }
  work *= step / 3.0;
  EXPECT_NEAR(work / (0.5 * m_eff * v * v), 1.0, 1e-7);
  EXPECT_DOUBLE_EQ(h.max_force, hertz_elastic_force(h.max_overlap, r_eff, e_star));
}

TEST(HertzTheory, NoForceWithoutOverlap) {
  EXPECT_EQ(hertz_elastic_force(0.0, 1e-3, 1e7), 0.0);
  EXPECT_EQ(hertz_elastic_force(-1e-6, 1e-3, 1e7), 0.0);
}

}  // namespace
}  // namespace ppohdem::validation
