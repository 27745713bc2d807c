// Mesh statistics on meshes built in code, checked against analytic values.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>

#include "mesh_test_support.hpp"
#include "ppohdem/mesh/mesh_stats.hpp"

namespace ppohdem {
namespace {

TEST(MeshStats, UnitCubeHasVolumeOneAreaSixAndIsClosed) {
  const MeshStats s = compute_mesh_stats(test::unit_cube());
  EXPECT_EQ(s.triangles, 12u);
  EXPECT_EQ(s.vertices, 8u);
  EXPECT_EQ(s.edges, 18u);  // 12 cube edges + 6 face diagonals
  EXPECT_EQ(s.euler_characteristic(), 2);
  EXPECT_TRUE(s.watertight());
  EXPECT_EQ(s.degenerate_triangles, 0u);
  // Each triangle has area 1/2 exactly; the volume sums 12 terms det/6 with det in {0, +-1}:
  // rounding of k/6 and of the sum stays within a few ulps of 1.
  EXPECT_EQ(s.surface_area, 6.0);
  EXPECT_NEAR(s.signed_volume, 1.0, 4 * std::numeric_limits<double>::epsilon());
  EXPECT_EQ(s.box.min, Vec3::Zero());
  EXPECT_EQ(s.box.max, Vec3::Ones());
}

TEST(MeshStats, FlippedTriangleMakesThreeInconsistentEdges) {
  TriangleMesh cube = test::unit_cube();
  // triangle 2 is (0,0,1), (1,0,1), (1,1,1) on face z = 1: det(v0, v1, v2) = 1, term +1/6
  ASSERT_EQ(cube.triangles[2].v[2], Vec3(1, 1, 1));
  std::swap(cube.triangles[2].v[1], cube.triangles[2].v[2]);
  const MeshStats s = compute_mesh_stats(cube);
  EXPECT_EQ(s.inconsistent_edges, 3u);
  EXPECT_EQ(s.boundary_edges, 0u);
  EXPECT_FALSE(s.watertight());
  // its term changes sign: 1 - 2/6 = 2/3 (a few ulps of rounding in the sum)
  EXPECT_NEAR(s.signed_volume, 2.0 / 3.0, 8 * std::numeric_limits<double>::epsilon());
}

TEST(MeshStats, MissingTriangleLeavesThreeBoundaryEdges) {
  TriangleMesh cube = test::unit_cube();
  cube.triangles.pop_back();
  const MeshStats s = compute_mesh_stats(cube);
  EXPECT_EQ(s.boundary_edges, 3u);
  EXPECT_EQ(s.edges, 18u);
  EXPECT_EQ(s.euler_characteristic(), 1);  // a disc
  EXPECT_FALSE(s.watertight());
}

TEST(MeshStats, DuplicatedTriangleMakesNonManifoldEdges) {
  TriangleMesh cube = test::unit_cube();
  cube.triangles.push_back(cube.triangles[0]);
  const MeshStats s = compute_mesh_stats(cube);
  EXPECT_EQ(s.non_manifold_edges, 3u);
  EXPECT_FALSE(s.watertight());
}

TEST(MeshStats, CountsZeroAreaTriangles) {
  TriangleMesh cube = test::unit_cube();
  cube.triangles.push_back(test::make_triangle(Vec3(0, 0, 0), Vec3(0.5, 0.5, 0.5), Vec3(1, 1, 1)));
  EXPECT_EQ(compute_mesh_stats(cube).degenerate_triangles, 1u);
}

TEST(MeshStats, WeldsNegativeAndPositiveZero) {
  TriangleMesh cube = test::unit_cube();
  for (Triangle& t : cube.triangles) {
    if (t.v[0].x() == 0.0) t.v[0].x() = -0.0;  // same point, other bit pattern
  }
  const MeshStats s = compute_mesh_stats(cube);
  EXPECT_EQ(s.vertices, 8u);
  EXPECT_TRUE(s.watertight());
}

TEST(MeshStats, EmptyMeshIsNotWatertight) {
  const MeshStats s = compute_mesh_stats(TriangleMesh{});
  EXPECT_EQ(s.triangles, 0u);
  EXPECT_FALSE(s.watertight());
  EXPECT_TRUE(s.box.empty());
}

TEST(MeshStats, FormatListsTheCounts) {
  const std::string text = format_mesh_stats(compute_mesh_stats(test::unit_cube()));
  EXPECT_NE(text.find("triangles:             12\n"), std::string::npos) << text;
  EXPECT_NE(text.find("vertices (welded):     8\n"), std::string::npos) << text;
  EXPECT_NE(text.find("Euler characteristic:  2\n"), std::string::npos) << text;
  EXPECT_NE(text.find("watertight:            yes\n"), std::string::npos) << text;
  EXPECT_NE(text.find("bounding box max:      (1, 1, 1)\n"), std::string::npos) << text;
  EXPECT_NE(text.find("surface area:          6\n"), std::string::npos) << text;
}

// A box [t, t + d] built from the unit cube: volume d_x d_y d_z, area 2(d_x d_y + d_y d_z +
// d_z d_x), whatever the translation t.
RC_GTEST_PROP(MeshStatsProperty, BoxVolumeAndAreaMatchFormulas, ()) {
  const double dx = *rc::gen::inRange(1, 1000) / 100.0;
  const double dy = *rc::gen::inRange(1, 1000) / 100.0;
  const double dz = *rc::gen::inRange(1, 1000) / 100.0;
  const Vec3 shift(*rc::gen::inRange(-1000, 1000) / 10.0, *rc::gen::inRange(-1000, 1000) / 10.0,
                   *rc::gen::inRange(-1000, 1000) / 10.0);
  TriangleMesh box = test::unit_cube();
  for (Triangle& t : box.triangles) {
    for (Vec3& p : t.v) p = p.cwiseProduct(Vec3(dx, dy, dz)) + shift;
  }
  const MeshStats s = compute_mesh_stats(box);
  RC_ASSERT(s.watertight());
  const double volume = dx * dy * dz;
  const double area = 2 * (dx * dy + dy * dz + dz * dx);
  // Volume terms are products of coordinates up to |shift| + d ~ 110, so each term carries
  // rounding ~ 110^3 eps; 12 terms cancel down to the volume: allow 100 * 110^3 eps.
  RC_ASSERT(std::abs(s.signed_volume - volume) <= 100 * std::pow(110.0, 3) * 2.2e-16);
  // Edges v1 - v0 of coordinates up to ~110 carry absolute error ~eps * 110, relative
  // eps * 110 / d_min to edges of length >= d_min; the area inherits a few times that.
  const double d_min = std::min({dx, dy, dz});
  RC_ASSERT(std::abs(s.surface_area - area) <= 8 * 2.2e-16 * 110 / d_min * area);
}

}  // namespace
}  // namespace ppohdem
