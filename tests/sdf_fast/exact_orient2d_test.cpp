// The expansion-arithmetic orient2d against an independent exact oracle: the reference's
// rational-arithmetic determinant (boost::multiprecision::cpp_rational).
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>

#include "ppohdem/sdf/reference/orientation.hpp"
#include "ppohdem/sdf/fast/exact_orient2d.hpp"

namespace ppohdem::sdf {
namespace {

int rational_sign(double ax, double ay, double bx, double by, double px, double py) {
  return reference::orient2d_sign_exact({ax, ay}, {bx, by}, {px, py});
}

TEST(FastOrient2d, CollinearPointsGiveZero) {
  EXPECT_EQ(fast::orient2d_sign(0, 0, 1, 1, 0.5, 0.5), 0);
  EXPECT_EQ(fast::orient2d_sign_expansion(0.1, 0.1, 0.3, 0.3, 0.2, 0.2),
            rational_sign(0.1, 0.1, 0.3, 0.3, 0.2, 0.2));  // 0.1, 0.2, 0.3 are not exactly collinear
}

TEST(FastOrient2d, PerturbationBreaksTiesLikeTheReference) {
  // p on the segment's line: the sign comes from the e and e^2 coefficients.
  for (double y : {0.0, 1.0}) {
    EXPECT_EQ(fast::orient2d_sign_perturbed(0, 0, 2, 2 * y, 1, y),
              reference::orient2d_sign_perturbed({0, 0}, {2, 2 * y}, {1, y}));
  }
}

// Near-degenerate triples: p on the line a->b up to a few ulps, coordinates offset by up to 1e6.
RC_GTEST_PROP(FastOrient2d, ExpansionSignEqualsRationalSign, ()) {
  const double offset = std::ldexp(1.0, *rc::gen::inRange(0, 20));
  const auto coord = [&] { return offset + *rc::gen::inRange(-1000, 1000) / 64.0; };
  const double ax = coord(), ay = coord(), bx = coord(), by = coord();
  const double t = *rc::gen::inRange(-100, 100) / 37.0;
  double px = ax + t * (bx - ax), py = ay + t * (by - ay);
  const int nudge = *rc::gen::inRange(-3, 4);
  for (int s = 0; s < std::abs(nudge); ++s) py = std::nextafter(py, nudge > 0 ? INFINITY : -INFINITY);
  RC_ASSERT(fast::orient2d_sign_expansion(ax, ay, bx, by, px, py) == rational_sign(ax, ay, bx, by, px, py));
  RC_ASSERT(fast::orient2d_sign(ax, ay, bx, by, px, py) == rational_sign(ax, ay, bx, by, px, py));
}

}  // namespace
}  // namespace ppohdem::sdf
