// Field comparison metrics against fields whose answer is known by construction.
// Most fields use dyadic values (multiples of powers of two) so that every difference and
// quotient below is exact in binary floating point and can be compared with ==.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <limits>

#include "ppohdem/error.hpp"
#include "ppohdem/sdf/field_metrics.hpp"

namespace ppohdem {
namespace {

GridSpec make_grid(const Vec3& origin, const Vec3& spacing, const Index3& nodes) {
  GridSpec g;
  g.origin = origin;
  g.spacing = spacing;
  g.nodes = nodes;
  return g;
}

// f(node) = a . x(node) + b at every node.
ScalarField linear_field(const GridSpec& g, const Vec3& a, double b) {
  ScalarField f(g);
  for (int k = 0; k < g.nodes[2]; ++k)
    for (int j = 0; j < g.nodes[1]; ++j)
      for (int i = 0; i < g.nodes[0]; ++i) f.at(i, j, k) = a.dot(g.position(i, j, k)) + b;
  return f;
}

// 4 x 3 x 2 nodes, h = 0.5, origin (-1, 0, 0): x = -1, -0.5, 0, 0.5 (all dyadic).
GridSpec small_grid() { return make_grid(Vec3(-1.0, 0.0, 0.0), Vec3::Constant(0.5), {4, 3, 2}); }

TEST(CompareFields, IdenticalFieldsHaveZeroError) {
  const ScalarField oracle = linear_field(small_grid(), Vec3(1.0, 0.0, 0.0), 0.0);  // phi = x
  const FieldComparison c = compare_fields(oracle, oracle);
  EXPECT_EQ(c.all.nodes, 24u);
  EXPECT_EQ(c.all.max_error_h, 0.0);
  EXPECT_EQ(c.all.rms_error_h, 0.0);
  EXPECT_EQ(c.band.max_error_h, 0.0);
  EXPECT_EQ(c.sign_mismatches, 0u);
  EXPECT_EQ(c.max_relative_error, 0.0);
  EXPECT_EQ(c.h, 0.5);
}

TEST(CompareFields, OnePerturbedNodeGivesPerturbationOverH) {
  const ScalarField oracle = linear_field(small_grid(), Vec3(1.0, 0.0, 0.0), 0.0);
  ScalarField candidate = oracle;
  candidate.at(2, 1, 1) += 0.125;  // oracle there is x = 0, so the sign flips too
  const FieldComparison c = compare_fields(candidate, oracle);
  EXPECT_EQ(c.all.max_error_h, 0.25);  // 0.125 / h, h = 0.5
  EXPECT_EQ(c.all.worst_node, (Index3{2, 1, 1}));
  // RMS over 24 nodes with one error of 0.25 h: sqrt(0.25^2 / 24). Computed the same way
  // (one multiply, one divide, one sqrt), so equal to within one rounding.
  EXPECT_DOUBLE_EQ(c.all.rms_error_h, std::sqrt(0.0625 / 24.0));
  // Node (2,1,1) has oracle 0: inside the band (|0| < 2h) but below the sign tolerance.
  EXPECT_EQ(c.band.max_error_h, 0.25);
  EXPECT_EQ(c.sign_mismatches, 0u);
}

TEST(CompareFields, BandHoldsOnlyNodesNearTheOracleSurface) {
  const ScalarField oracle = linear_field(small_grid(), Vec3(1.0, 0.0, 0.0), 0.0);  // phi = x
  ScalarField candidate = oracle;
  candidate.at(0, 0, 0) += 1.0;   // x = -1 = -2h: outside the 1h band
  candidate.at(1, 2, 1) += 0.25;  // x = -0.5 = -h: also outside the strict band |o| < 1h
  candidate.at(2, 2, 1) += 0.5;   // x = 0: inside
  const FieldComparison c = compare_fields(candidate, oracle, /*band_in_h=*/1.0);
  EXPECT_EQ(c.band.nodes, 6u);           // the x = 0 plane: 3 x 2 nodes
  EXPECT_EQ(c.band.max_error_h, 1.0);    // 0.5 / 0.5
  EXPECT_EQ(c.band.worst_node, (Index3{2, 2, 1}));
  EXPECT_EQ(c.all.max_error_h, 2.0);     // 1.0 / 0.5
  EXPECT_EQ(c.all.worst_node, (Index3{0, 0, 0}));
}

TEST(CompareFields, ErrorsAreInUnitsOfTheSmallestSpacing) {
  const GridSpec g = make_grid(Vec3::Zero(), Vec3(1.0, 0.25, 2.0), {2, 2, 2});
  ScalarField oracle(g, 1.0);
  ScalarField candidate = oracle;
  candidate.at(1, 1, 1) = 1.5;
  EXPECT_EQ(compare_fields(candidate, oracle).all.max_error_h, 2.0);  // 0.5 / 0.25
}

TEST(CompareFields, CountsSignMismatchesAboveTheTolerance) {
  const ScalarField oracle = linear_field(small_grid(), Vec3(1.0, 0.0, 0.0), 0.0);  // phi = x
  ScalarField candidate = oracle;
  candidate.at(0, 0, 0) = 0.25;   // oracle -1: flipped
  candidate.at(3, 0, 0) = 0.0;    // oracle 0.5: zero is not positive, mismatch
  candidate.at(1, 1, 0) = -0.0;   // oracle -0.5: -0 is not negative, mismatch
  candidate.at(2, 0, 0) = -1.0;   // oracle exactly 0: not checked
  const FieldComparison c = compare_fields(candidate, oracle);
  EXPECT_EQ(c.sign_checked_nodes, 18u);  // 24 nodes minus the 6 on x = 0
  EXPECT_EQ(c.sign_mismatches, 3u);
  // With a tolerance of 1.5 h = 0.75 only the x = -1 nodes are checked.
  const FieldComparison wide = compare_fields(candidate, oracle, 2.0, 1.5);
  EXPECT_EQ(wide.sign_checked_nodes, 6u);
  EXPECT_EQ(wide.sign_mismatches, 1u);
}

TEST(CompareFields, MaxRelativeErrorIsExact) {
  ScalarField oracle(small_grid(), 2.0);
  ScalarField candidate = oracle;
  candidate.at(1, 1, 1) = 2.0 + std::ldexp(1.0, -40);
  EXPECT_EQ(compare_fields(candidate, oracle).max_relative_error, std::ldexp(1.0, -41));
  // A zero oracle with a non-zero candidate is an enormous relative error, on purpose.
  oracle.at(0, 0, 0) = 0.0;
  candidate.at(0, 0, 0) = 1e-300;
  EXPECT_GT(compare_fields(candidate, oracle).max_relative_error, 1e7);
}

TEST(CompareFields, NonFiniteCandidateIsInfiniteError) {
  const ScalarField oracle(small_grid(), 1.0);
  ScalarField candidate = oracle;
  candidate.at(3, 2, 1) = std::numeric_limits<double>::quiet_NaN();
  const FieldComparison c = compare_fields(candidate, oracle);
  EXPECT_EQ(c.non_finite_candidate, 1u);
  EXPECT_TRUE(std::isinf(c.all.max_error_h));
  EXPECT_EQ(c.all.worst_node, (Index3{3, 2, 1}));
  EXPECT_EQ(c.sign_mismatches, 1u);
}

TEST(CompareFields, RejectsMismatchedGrids) {
  const ScalarField oracle(small_grid(), 1.0);
  GridSpec other_count = small_grid();
  other_count.nodes[2] = 3;
  GridSpec other_origin = small_grid();
  other_origin.origin.y() = 1e-12;
  GridSpec other_spacing = small_grid();
  other_spacing.spacing.z() = 0.5000001;
  EXPECT_THROW(compare_fields(ScalarField(other_count, 1.0), oracle), InputError);
  EXPECT_THROW(compare_fields(ScalarField(other_origin, 1.0), oracle), InputError);
  EXPECT_THROW(compare_fields(ScalarField(other_spacing, 1.0), oracle), InputError);
  ScalarField short_values = oracle;
  short_values.values.pop_back();
  EXPECT_THROW(compare_fields(short_values, oracle), InputError);
  EXPECT_THROW(compare_fields(oracle, oracle, -1.0), InputError);
}

TEST(CompareFields, FormatNamesEveryQuantity) {
  const ScalarField oracle(small_grid(), 1.0);
  const std::string table = format_comparison(compare_fields(oracle, oracle));
  for (const char* label : {"band max |error| [h]", "all RMS error [h]", "sign mismatches",
                            "max relative error"}) {
    EXPECT_NE(table.find(label), std::string::npos) << label;
  }
}

TEST(LipschitzRatio, LinearFieldAlongAnAxisGivesItsGradientNorm) {
  // phi = 0.5 x on h = 0.25: neighbour differences 0.125 over 0.25 (and 0.125 over longer
  // diagonals), all exact.
  const GridSpec g = make_grid(Vec3(-1.0, -1.0, -1.0), Vec3::Constant(0.25), {5, 4, 3});
  EXPECT_EQ(lipschitz_ratio(linear_field(g, Vec3(0.5, 0.0, 0.0), 0.25)), 0.5);
}

TEST(LipschitzRatio, IncludesFaceDiagonalNeighbours) {
  // Gradient (0.3, 0.4, 0), norm 0.5, on spacing (3, 4, 1): axis neighbours see 0.3 and 0.4,
  // only the (1,1,0) diagonal, length 5, sees (0.9 + 1.6) / 5 = 0.5.
  const GridSpec g = make_grid(Vec3::Zero(), Vec3(3.0, 4.0, 1.0), {3, 3, 2});
  // 0.3, 0.4 are not dyadic: a few roundings of values ~2 give ~4e-16 relative.
  EXPECT_NEAR(lipschitz_ratio(linear_field(g, Vec3(0.3, 0.4, 0.0), 0.0)), 0.5, 2e-15);
}

TEST(LipschitzRatio, IncludesBodyDiagonalNeighbours) {
  // Gradient along (1,1,1) with norm 0.5 on a unit grid: axis 0.289, face diagonal 0.408,
  // body diagonal exactly the norm.
  const GridSpec g = make_grid(Vec3::Zero(), Vec3::Ones(), {2, 2, 2});
  const Vec3 gradient = Vec3::Ones().normalized() * 0.5;
  EXPECT_NEAR(lipschitz_ratio(linear_field(g, gradient, 0.0)), 0.5, 2e-15);  // a few roundings
}

TEST(LipschitzRatio, SingleNodeGridIsZeroAndNaNIsInfinite) {
  const GridSpec one = make_grid(Vec3::Zero(), Vec3::Ones(), {1, 1, 1});
  EXPECT_EQ(lipschitz_ratio(ScalarField(one, 3.0)), 0.0);
  ScalarField f(small_grid(), 0.0);
  f.at(1, 1, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(std::isinf(lipschitz_ratio(f)));
}

// Property: for phi = g . x the ratio lies between the largest axis component |g_a| (an axis
// neighbour sees exactly that) and |g| (Cauchy-Schwarz). Relative slack 1e-12 covers the
// rounding of values of magnitude <= ~100 differenced and divided (a few ulps).
RC_GTEST_PROP(LipschitzRatio, LinearFieldIsBetweenAxisComponentAndNorm, ()) {
  const auto coord = [] { return *rc::gen::inRange(-1000, 1000) / 100.0; };
  const Vec3 gradient(coord(), coord(), coord());
  const Vec3 spacing(*rc::gen::inRange(1, 100) / 50.0, *rc::gen::inRange(1, 100) / 50.0,
                     *rc::gen::inRange(1, 100) / 50.0);
  const GridSpec g = make_grid(Vec3(coord(), coord(), coord()), spacing, {3, 4, 3});
  const double ratio = lipschitz_ratio(linear_field(g, gradient, coord()));
  RC_ASSERT(ratio <= gradient.norm() * (1.0 + 1e-12) + 1e-12);
  RC_ASSERT(ratio >= gradient.cwiseAbs().maxCoeff() * (1.0 - 1e-12) - 1e-12);
}

// Property: a sampled exact sphere SDF |x - c| - R is 1-Lipschitz (triangle inequality).
RC_GTEST_PROP(LipschitzRatio, SampledSphereDistanceIsAtMostOne, ()) {
  const double h = *rc::gen::inRange(1, 100) / 100.0;
  const Vec3 centre(*rc::gen::inRange(0, 100) / 25.0, *rc::gen::inRange(0, 100) / 25.0,
                    *rc::gen::inRange(0, 100) / 25.0);
  const double radius = *rc::gen::inRange(1, 300) / 100.0;
  const GridSpec g = make_grid(Vec3::Zero(), Vec3::Constant(h), {8, 8, 8});
  ScalarField f(g);
  for (int k = 0; k < 8; ++k)
    for (int j = 0; j < 8; ++j)
      for (int i = 0; i < 8; ++i) f.at(i, j, k) = (g.position(i, j, k) - centre).norm() - radius;
  RC_ASSERT(lipschitz_ratio(f) <= 1.0 + 1e-12);  // rounding of norms of size <= ~10, h >= 0.01
}

// Property: perturbing one node of any field by delta gives max error |delta| / h at that
// node. (o + delta) - o differs from delta by at most ulp(o) ~ 2e-15 for |o| <= 10, and
// |delta| >= 1e-3, so 1e-11 relative covers it.
RC_GTEST_PROP(CompareFields, OnePerturbationIsTheMaxError, ()) {
  const GridSpec g = small_grid();
  ScalarField oracle(g);
  for (double& v : oracle.values) v = *rc::gen::inRange(-10000, 10000) / 1000.0;
  const int i = *rc::gen::inRange(0, 4);
  const int j = *rc::gen::inRange(0, 3);
  const int k = *rc::gen::inRange(0, 2);
  const double delta = *rc::gen::nonZero<int>() % 1000 / 1000.0;
  RC_PRE(delta != 0.0);
  ScalarField candidate = oracle;
  candidate.at(i, j, k) += delta;
  const FieldComparison c = compare_fields(candidate, oracle);
  RC_ASSERT(std::abs(c.all.max_error_h - std::abs(delta) / g.min_spacing()) <=
            1e-11 * std::abs(delta) / g.min_spacing());
  RC_ASSERT(c.all.worst_node == (Index3{i, j, k}));
}

}  // namespace
}  // namespace ppohdem
