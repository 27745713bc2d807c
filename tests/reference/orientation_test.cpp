// orient2d: the filtered sign equals the rational-arithmetic sign; simulation of simplicity.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>

#include "ppohdem/sdf/reference/orientation.hpp"

using namespace ppohdem::sdf::reference;

TEST(Orient2d, HandComputedSigns) {
  EXPECT_EQ(orient2d_sign({0, 0}, {1, 0}, {0, 1}), +1);   // left of the x axis
  EXPECT_EQ(orient2d_sign({0, 0}, {1, 0}, {0, -1}), -1);  // right
  EXPECT_EQ(orient2d_sign({0, 0}, {1, 1}, {3, 3}), 0);    // collinear, exactly
  // Not collinear in double: 0.1, 0.2, 0.3 are not exactly 1:2:3; the exact sign decides.
  EXPECT_EQ(orient2d_sign({0.1, 0.1}, {0.2, 0.2}, {0.3, 0.3}), orient2d_sign_exact({0.1, 0.1}, {0.2, 0.2}, {0.3, 0.3}));
}

RC_GTEST_PROP(Orient2d, FilteredSignEqualsExactSignNearLines, ()) {
  // Points on (or one rounding off) a line: the filter's hard cases (Shewchuk's examples).
  const Vec2 a(*rc::gen::inRange(-1000, 1000) / 997.0, *rc::gen::inRange(-1000, 1000) / 991.0);
  const Vec2 b(*rc::gen::inRange(-1000, 1000) / 983.0, *rc::gen::inRange(-1000, 1000) / 977.0);
  const double t = *rc::gen::inRange(-3000, 3000) / 1000.0;
  Vec2 p = a + t * (b - a);
  const int nudge = *rc::gen::inRange(-1, 2);  // move p.x by one ulp left, not at all, or right
  if (nudge != 0) p.x() = std::nextafter(p.x(), nudge * 10.0);
  RC_ASSERT(orient2d_sign(a, b, p) == orient2d_sign_exact(a, b, p));
}

TEST(Orient2dPerturbed, HandComputedTieBreaks) {
  // p on the x axis: p' = p + (e, e^2) is above it, i.e. left of (0,0) -> (1,0).
  EXPECT_EQ(orient2d_sign_perturbed({0, 0}, {1, 0}, {0.5, 0}), +1);
  // p on the upward y axis: p' is to its right.
  EXPECT_EQ(orient2d_sign_perturbed({0, 0}, {0, 1}, {0, 0.5}), -1);
  // p at a vertex still gets a side.
  EXPECT_NE(orient2d_sign_perturbed({0, 0}, {1, 1}, {0, 0}), 0);
  // Degenerate edge.
  EXPECT_EQ(orient2d_sign_perturbed({1, 1}, {1, 1}, {0, 0}), 0);
}

RC_GTEST_PROP(Orient2dPerturbed, AntisymmetricAndNeverZero, ()) {
  const Vec2 a(*rc::gen::inRange(-4, 5), *rc::gen::inRange(-4, 5));  // small integers: many exact ties
  const Vec2 b(*rc::gen::inRange(-4, 5), *rc::gen::inRange(-4, 5));
  const Vec2 p(*rc::gen::inRange(-4, 5), *rc::gen::inRange(-4, 5));
  RC_PRE(a != b);
  const int s = orient2d_sign_perturbed(a, b, p);
  RC_ASSERT(s != 0);
  RC_ASSERT(orient2d_sign_perturbed(b, a, p) == -s);
  // Agrees with the unperturbed sign whenever that is not zero.
  const int exact = orient2d_sign_exact(a, b, p);
  if (exact != 0) RC_ASSERT(s == exact);
}
