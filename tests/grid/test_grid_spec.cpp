// GridSpec: validation, the two constructors, equality.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "ppohdem/error.hpp"
#include "ppohdem/grid/grid_spec.hpp"

namespace ppohdem {
namespace {

using ::testing::HasSubstr;

TEST(GridSpec, IndexIsXFastest) {
  GridSpec g;
  g.nodes = {3, 4, 5};
  EXPECT_EQ(g.index(0, 0, 0), 0u);
  EXPECT_EQ(g.index(1, 0, 0), 1u);
  EXPECT_EQ(g.index(0, 1, 0), 3u);
  EXPECT_EQ(g.index(0, 0, 1), 12u);
  EXPECT_EQ(g.index(2, 3, 4), g.node_count() - 1);
}

TEST(GridSpec, ValidateAcceptsPositiveCountsAndSpacing) {
  GridSpec g;
  g.nodes = {1, 2, 3};
  g.spacing = Vec3(0.5, 1e-9, 3.0);
  EXPECT_NO_THROW(g.validate("ctx"));
}

TEST(GridSpec, ValidateRejectsZeroNodeCountNamingAxis) {
  GridSpec g;
  g.nodes = {4, 0, 4};
  try {
    g.validate("my.vtk");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("my.vtk"));
    EXPECT_THAT(e.what(), HasSubstr("node count >= 1 along y"));
  }
}

TEST(GridSpec, ValidateRejectsNonPositiveOrNonFiniteSpacing) {
  for (double bad : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(),
                     std::numeric_limits<double>::infinity()}) {
    GridSpec g;
    g.spacing = Vec3(1.0, 1.0, bad);
    EXPECT_THROW(g.validate(), InputError) << "spacing z = " << bad;
  }
}

TEST(GridSpec, SpanningPutsFirstAndLastNodeOnTheBox) {
  const Vec3 lo(-1.5, 0.25, 10.0);
  const Vec3 hi(2.5, 1.0, 10.7);
  const GridSpec g = GridSpec::spanning(lo, hi, {5, 4, 8});
  EXPECT_EQ(g.origin, lo);
  // Hand values: h = (hi - lo) / (n - 1).
  EXPECT_DOUBLE_EQ(g.spacing.x(), 1.0);
  EXPECT_DOUBLE_EQ(g.spacing.y(), 0.25);
  // 10.7 - 10.0 rounds at the scale of 10.7 (~2e-15), then is divided by 7.
  EXPECT_NEAR(g.spacing.z(), 0.1, 4 * std::numeric_limits<double>::epsilon() * 10.7 / 7);
  // upper = lo + (n-1) * ((hi-lo)/(n-1)): two roundings, so within 2 ulps of hi (4 ulps margin).
  const Vec3 upper = g.upper_corner();
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(upper[a], hi[a], 4 * std::numeric_limits<double>::epsilon() * std::abs(hi[a])) << a;
  }
}

TEST(GridSpec, SpanningRejectsSingleNodeOrEmptyBox) {
  EXPECT_THROW(GridSpec::spanning(Vec3::Zero(), Vec3::Ones(), {1, 2, 2}), InputError);
  EXPECT_THROW(GridSpec::spanning(Vec3::Zero(), Vec3(1, 0, 1), {2, 2, 2}), InputError);
  EXPECT_THROW(GridSpec::spanning(Vec3::Ones(), Vec3::Zero(), {2, 2, 2}), InputError);
}

TEST(GridSpec, LegacyGridIsLOverNFromZero) {
  // The original: x_i = (L / n) (i - 1), i = 1..n; 44 / 76 for the seed sample.
  const GridSpec g = GridSpec::ppohdem_legacy(Vec3(44, 44, 11), {76, 76, 40});
  EXPECT_EQ(g.origin, Vec3::Zero());
  EXPECT_EQ(g.spacing.x(), 44.0 / 76.0);
  EXPECT_EQ(g.spacing.z(), 11.0 / 40.0);
  EXPECT_EQ(g.nodes, (Index3{76, 76, 40}));
  // The last node is at L - h, not L (tolerance: one rounding of 75 * h).
  EXPECT_NEAR(g.upper_corner().x(), 44.0 - 44.0 / 76.0, 1e-13);
}

TEST(GridSpec, LegacyGridRejectsBadLengthOrCount) {
  EXPECT_THROW(GridSpec::ppohdem_legacy(Vec3(44, 0, 44), {76, 76, 76}), InputError);
  EXPECT_THROW(GridSpec::ppohdem_legacy(Vec3(44, 44, 44), {76, 0, 76}), InputError);
}

TEST(GridSpec, EqualityComparesEveryMember) {
  GridSpec a;
  a.origin = Vec3(1, 2, 3);
  a.spacing = Vec3(0.5, 0.5, 0.25);
  a.nodes = {2, 3, 4};
  GridSpec b = a;
  EXPECT_TRUE(a == b);
  b.origin.z() = 3.0000000001;
  EXPECT_FALSE(a == b);
  b = a;
  b.spacing.y() = 0.75;
  EXPECT_FALSE(a == b);
  b = a;
  b.nodes[2] = 5;
  EXPECT_FALSE(a == b);
}

}  // namespace
}  // namespace ppohdem
