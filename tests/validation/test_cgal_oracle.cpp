// The CGAL oracle against analytic signed distances (box: exact; sphere: bounded by the mesh's
// chord error), exact on-surface zeros, the open-mesh fallback and thread independence.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>

#include "analytic_meshes.hpp"
#include "ppohdem/error.hpp"
#include "ppohdem/sdf/field_metrics.hpp"
#include "ppohdem/validation/cgal_signed_distance.hpp"
#include "ppohdem/validation/exact_distance.hpp"

namespace ppohdem {
namespace {

using test::box_mesh;
using test::box_sdf;
using test::icosphere;
using validation::cgal_signed_distance;
using validation::OracleReport;

GridSpec make_grid(const Vec3& origin, const Vec3& spacing, const Index3& nodes) {
  GridSpec g;
  g.origin = origin;
  g.spacing = spacing;
  g.nodes = nodes;
  return g;
}

GridSpec single_node(const Vec3& p) { return make_grid(p, Vec3::Ones(), {1, 1, 1}); }

template <class Function>
ScalarField sample(const GridSpec& g, Function phi) {
  ScalarField f(g);
  for (int k = 0; k < g.nodes[2]; ++k)
    for (int j = 0; j < g.nodes[1]; ++j)
      for (int i = 0; i < g.nodes[0]; ++i) f.at(i, j, k) = phi(g.position(i, j, k));
  return f;
}

const Vec3 kBoxLo(-1.0, -0.5, -0.75);
const Vec3 kBoxHi(1.0, 0.5, 0.75);
// Spacing 1/8 from -1.5: every node coordinate is dyadic and whole node planes lie on the
// box faces, so the grid holds inside, outside, on-face, on-edge and on-corner nodes.
const GridSpec kBoxGrid = make_grid(Vec3(-1.5, -1.0, -1.25), Vec3::Constant(0.125), {25, 17, 21});

TEST(CgalOracle, AxisAlignedBoxMatchesAnalyticDistanceInsideAndOutside) {
  OracleReport report;
  const ScalarField oracle = cgal_signed_distance(box_mesh(kBoxLo, kBoxHi), kBoxGrid, 1, &report);
  const ScalarField exact =
      sample(kBoxGrid, [](const Vec3& p) { return box_sdf(kBoxLo, kBoxHi, p); });
  const FieldComparison c = compare_fields(oracle, exact, 2.0, 0.0);
  EXPECT_TRUE(report.sign_valid);
  EXPECT_TRUE(report.warnings.empty());
  EXPECT_EQ(report.welded_vertices, 8u);
  // Relative 1e-12: Epick rounds the closest-point construction (a few ulps, ~1e-16 of the
  // coordinates ~1) and every non-zero |phi| here is >= h = 0.125, so the true relative error
  // is ~1e-15; 1e-12 leaves three orders of margin and still catches any wrong face/edge.
  EXPECT_LE(c.max_relative_error, 1e-12);
  std::printf("box: max relative error vs analytic %.3g\n", c.max_relative_error);
  EXPECT_EQ(c.sign_mismatches, 0u);  // sign tolerance 0: every non-zero node is checked
  // The grid really probes all regions (counted from the analytic field):
  std::size_t inside = 0, on_surface = 0;
  for (double v : exact.values) {
    inside += v < 0.0 ? 1 : 0;
    on_surface += v == 0.0 ? 1 : 0;
  }
  EXPECT_EQ(inside, 15u * 7u * 11u);   // interior nodes strictly inside: (17-2) x (9-2) x (13-2)
  EXPECT_EQ(on_surface, 17u * 9u * 13u - inside);
  EXPECT_EQ(report.boundary_nodes, on_surface);
  EXPECT_EQ(report.inside_nodes, inside);
}

// The point-list form (pd.oracles.signed_distance) is the grid form at the nodes, bit for bit,
// and the analytic box distance off the grid.
TEST(CgalOracle, AtPointsEqualsTheGridFormAndTheAnalyticBox) {
  const TriangleMesh mesh = box_mesh(kBoxLo, kBoxHi);
  const ScalarField grid = cgal_signed_distance(mesh, kBoxGrid, 1);
  std::vector<Vec3> nodes;
  for (int k = 0; k < kBoxGrid.nodes[2]; ++k)
    for (int j = 0; j < kBoxGrid.nodes[1]; ++j)
      for (int i = 0; i < kBoxGrid.nodes[0]; ++i) nodes.push_back(kBoxGrid.position(i, j, k));
  const std::vector<double> at = validation::cgal_signed_distance_at(mesh, nodes, 2);
  ASSERT_EQ(at.size(), grid.values.size());
  for (std::size_t n = 0; n < at.size(); ++n) ASSERT_EQ(at[n], grid.values[n]) << n;
  const std::vector<Vec3> off = {Vec3(0.1, 0.2, 0.3), Vec3(1.3, -0.7, 0.05), Vec3(-0.9, 0.0, 0.0)};
  const std::vector<double> phi = validation::cgal_signed_distance_at(mesh, off, 1);
  // Same rounding argument as the box test above: a few ulps of coordinates ~1.
  for (std::size_t n = 0; n < off.size(); ++n) EXPECT_NEAR(phi[n], box_sdf(kBoxLo, kBoxHi, off[n]), 1e-14);
  EXPECT_THROW(validation::cgal_signed_distance_at(mesh, {Vec3(std::nan(""), 0, 0)}, 1), InputError);
}

TEST(CgalOracle, PointsOnTheSurfaceAreExactlyZero) {
  const TriangleMesh box = box_mesh(kBoxLo, kBoxHi);
  // face interior, the diagonal shared by the two +x triangles, a box edge, a corner
  for (const Vec3& p : {Vec3(1.0, 0.1, 0.2), Vec3(1.0, 0.0, 0.0), Vec3(1.0, 0.5, 0.3),
                        Vec3(1.0, 0.5, 0.75)}) {
    OracleReport report;
    EXPECT_EQ(cgal_signed_distance(box, single_node(p), 1, &report).values[0], 0.0)
        << p.transpose();
    EXPECT_EQ(report.boundary_nodes, 1u);
  }
  // A slanted face with full-mantissa vertices (found by a random search for a case where
  // Epick's closest-point construction rounds: its distance here is ~5e-16, not 0).
  // p = 1/4 v1 + 1/4 v2 + 1/2 v3 is exactly on the face when both additions are exact
  // (checked below with TwoSum); the exact side predicate says ON_BOUNDARY and the oracle must
  // return exactly 0.
  const Vec3 v0(0.0, 0.0, 0.0);
  const Vec3 v1(1.0302947109259111, 1.1249034823572064, 2.1263833263977703);
  const Vec3 v2(2.8050035636798687, 1.4892627291026104, 1.0174971315914765);
  const Vec3 v3(1.8570173020134142, 2.3205690824269056, 1.4356348873883698);
  TriangleMesh tetra;
  test::add_triangle(tetra, v1, v2, v3);
  test::add_triangle(tetra, v0, v2, v1);
  test::add_triangle(tetra, v0, v3, v2);
  test::add_triangle(tetra, v0, v1, v3);
  const Vec3 half_sum = (v1 + v2) * 0.5;
  const Vec3 on_slanted = (half_sum + v3) * 0.5;
  auto two_sum_error = [](double a, double b) {  // Knuth's TwoSum: a + b - fl(a + b), exactly
    const double s = a + b, bb = s - a;
    return (a - (s - bb)) + (b - bb);
  };
  for (int a = 0; a < 3; ++a) {
    ASSERT_EQ(two_sum_error(v1[a], v2[a]), 0.0);
    ASSERT_EQ(two_sum_error(half_sum[a], v3[a]), 0.0);
  }
  OracleReport report;
  EXPECT_EQ(cgal_signed_distance(tetra, single_node(on_slanted), 1, &report).values[0], 0.0);
  EXPECT_EQ(report.boundary_nodes, 1u);
}

TEST(CgalOracle, IcosphereIsWithinTheChordErrorOfTheSphere) {
  const Vec3 centre(0.1, -0.2, 0.05);
  const double radius = 1.0;
  const TriangleMesh mesh = icosphere(centre, radius, 3);  // 1280 triangles
  const double delta = test::inscribed_chord_error(mesh, centre, radius);
  ASSERT_GT(delta, 0.0);
  ASSERT_LT(delta, 0.01);  // the bound must be tight enough to mean something (~4e-3 here)

  const GridSpec g = GridSpec::spanning(centre - Vec3::Constant(1.6), centre + Vec3::Constant(1.6),
                                        {24, 24, 24});
  OracleReport report;
  const ScalarField oracle = cgal_signed_distance(mesh, g, 2, &report);
  const ScalarField sphere =
      sample(g, [&](const Vec3& p) { return (p - centre).norm() - radius; });
  EXPECT_TRUE(report.sign_valid);
  EXPECT_EQ(report.welded_vertices, 642u);  // 10 * 4^3 + 2: welding found every shared vertex
  // Sign compared only where the sphere is farther than delta from its surface.
  const FieldComparison c = compare_fields(oracle, sphere, 2.0, delta / g.min_spacing());
  // Bound delta (see inscribed_chord_error) plus 1e-12 for rounding of values ~1.
  EXPECT_LE(c.all.max_error_h * c.h, delta + 1e-12);
  EXPECT_EQ(c.sign_mismatches, 0u);
  EXPECT_GT(c.sign_checked_nodes, g.node_count() / 2);
  // A true distance field is 1-Lipschitz; rounding of values ~1 adds ~1e-15.
  EXPECT_LE(lipschitz_ratio(oracle), 1.0 + 1e-12);

  // The bound is attained at the centre: phi_mesh(centre) = -(nearest plane) = -(R - delta)
  // while the sphere gives -R. Rounding of the plane distances ~1: 1e-14.
  const double at_centre = cgal_signed_distance(mesh, single_node(centre)).values[0];
  EXPECT_NEAR(at_centre, -(radius - delta), 1e-14);
}

TEST(CgalOracle, OpenMeshGivesUnsignedDistanceAndSaysSo) {
  const TriangleMesh open_box = box_mesh(kBoxLo, kBoxHi, /*skip_plus_x=*/true);
  OracleReport report;
  const ScalarField field = cgal_signed_distance(open_box, kBoxGrid, 1, &report);
  EXPECT_FALSE(report.sign_valid);
  EXPECT_FALSE(report.warnings.empty());
  for (double v : field.values) ASSERT_GE(v, 0.0);
  // At nodes whose nearest box face is not the missing +x face the unsigned distance is
  // |box_sdf| (exact as in the closed-box test); the centre is 0.5 from the y faces.
  const double at_centre = cgal_signed_distance(open_box, single_node(Vec3::Zero())).values[0];
  EXPECT_EQ(at_centre, 0.5);
}

TEST(CgalOracle, ThreadCountDoesNotChangeTheFieldBitwise) {
  const TriangleMesh mesh = icosphere(Vec3(0.3, 0.1, -0.2), 0.9, 3);
  const GridSpec g = make_grid(Vec3::Constant(-1.3), Vec3::Constant(0.13), {21, 20, 19});
  OracleReport one_report, two_report;
  const ScalarField one = cgal_signed_distance(mesh, g, 1, &one_report);
  const ScalarField two = cgal_signed_distance(mesh, g, 2, &two_report);
  ASSERT_EQ(one.values.size(), two.values.size());
  EXPECT_EQ(std::memcmp(one.values.data(), two.values.data(), one.values.size() * sizeof(double)),
            0);
#if defined(PPOHDEM_WITH_OPENMP)
  EXPECT_EQ(two_report.threads, 2);
#endif
  EXPECT_GT(one_report.inside_nodes, 0u);
}

// Epick constructs the closest point in double; exact_unsigned_distance (Epeck, exact) gives
// the true distance. Their difference is an absolute error of a few ulps of the coordinates'
// magnitude L, independent of the distance itself. Measured 0.79 eps L on this mesh (CGAL
// 5.5, x86-64); the bound 8 eps L allows for a few more roundings in other configurations.
TEST(CgalOracle, DistanceRoundingIsAFewUlpsOfTheCoordinates) {
  const Vec3 centre(10.0, -20.0, 5.0);  // far from the origin so that L >> the distances
  const TriangleMesh mesh = icosphere(centre, 3.0, 1);
  const double magnitude = 26.0;  // L >= every |coordinate| of mesh and query points
  const double eps = std::numeric_limits<double>::epsilon();
  double worst = 0.0;  // max |d_epick - d_exact| / (eps L)
  std::uint32_t state = 12345;
  auto uniform = [&state] {  // LCG (Numerical Recipes ranqd1): fixed, platform-independent
    state = 1664525u * state + 1013904223u;
    return static_cast<double>(state) / 4294967296.0;
  };
  for (int n = 0; n < 200; ++n) {
    // Points in a 10-wide cube around the sphere, half of them within 0.01 of the surface.
    Vec3 p = centre + Vec3(uniform() - 0.5, uniform() - 0.5, uniform() - 0.5) * 10.0;
    if (n % 2 == 0) p = centre + (p - centre).normalized() * (2.99 + 0.02 * uniform());
    const double epick = std::abs(cgal_signed_distance(mesh, single_node(p)).values[0]);
    const double exact = validation::exact_unsigned_distance(mesh, p);
    worst = std::max(worst, std::abs(epick - exact) / (eps * magnitude));
  }
  std::printf("max |d_epick - d_exact| = %.3g eps L (L = %.0f)\n", worst, magnitude);
  EXPECT_LE(worst, 8.0);
}

// Property: any axis-aligned box, on any grid around it, matches the analytic box SDF.
// Both sides round: the oracle by a few ulps of the coordinates' magnitude L (measured above),
// the analytic formula by ~2 ulps of L; 16 eps L covers both. Signs must agree wherever the
// analytic value is farther than that from 0.
RC_GTEST_PROP(CgalOracle, RandomBoxMatchesAnalyticDistance, ()) {
  const auto unit = [] { return *rc::gen::inRange(0, 1 << 20) / double(1 << 20); };
  const Vec3 lo(10.0 * unit() - 5.0, 10.0 * unit() - 5.0, 10.0 * unit() - 5.0);
  const Vec3 hi = lo + Vec3(0.1 + 5.0 * unit(), 0.1 + 5.0 * unit(), 0.1 + 5.0 * unit());
  const Vec3 origin = lo - Vec3::Constant(2.0 * unit());
  const Vec3 spacing = (hi - origin + Vec3::Constant(2.0 * unit())) / 4.0 +
                       Vec3(1e-3 * unit(), 1e-3 * unit(), 1e-3 * unit());
  const GridSpec g = make_grid(origin, spacing, {6, 6, 6});
  const ScalarField oracle = cgal_signed_distance(box_mesh(lo, hi), g);
  const double magnitude = std::max({origin.cwiseAbs().maxCoeff(),
                                     g.upper_corner().cwiseAbs().maxCoeff(),
                                     hi.cwiseAbs().maxCoeff(), 1.0});
  const double tolerance = 16.0 * std::numeric_limits<double>::epsilon() * magnitude;
  for (int k = 0; k < 6; ++k)
    for (int j = 0; j < 6; ++j)
      for (int i = 0; i < 6; ++i) {
        const double exact = box_sdf(lo, hi, g.position(i, j, k));
        const double got = oracle.at(i, j, k);
        RC_ASSERT(std::abs(got - exact) <= tolerance);
        if (std::abs(exact) > tolerance) RC_ASSERT((got > 0.0) == (exact > 0.0));
      }
}

TEST(CgalOracle, RejectsEmptyMeshAndBadArguments) {
  const GridSpec g = single_node(Vec3::Zero());
  EXPECT_THROW(cgal_signed_distance(TriangleMesh{}, g), InputError);
  EXPECT_THROW(cgal_signed_distance(box_mesh(kBoxLo, kBoxHi), g, 0), InputError);
  GridSpec bad = g;
  bad.spacing.x() = 0.0;
  EXPECT_THROW(cgal_signed_distance(box_mesh(kBoxLo, kBoxHi), bad), InputError);
  TriangleMesh nan_mesh = box_mesh(kBoxLo, kBoxHi);
  nan_mesh.triangles[3].v[1].y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(cgal_signed_distance(nan_mesh, g), InputError);
}

TEST(CgalOracle, BuilderInterfaceReportsInsideFraction) {
  const validation::CgalOracleBuilder builder(1);
  SdfReport report;
  const ScalarField f = builder.build(box_mesh(kBoxLo, kBoxHi), kBoxGrid, &report);
  EXPECT_EQ(builder.name(), "cgal");
  // 1155 strictly-inside nodes (counted in the box test) of 25 * 17 * 21 = 8925.
  EXPECT_DOUBLE_EQ(report.inside_fraction, 1155.0 / 8925.0);
  EXPECT_EQ(f.values.size(), 8925u);
}

}  // namespace
}  // namespace ppohdem
