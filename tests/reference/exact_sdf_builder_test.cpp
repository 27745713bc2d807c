// The "exact" builder against analytic signed distances. The hard cases every builder shares
// (faces on grid planes, thin plate, far meshes, open mesh, flipped face, L-shape, Lipschitz) are
// the contract suite's: tests/sdf_contract (docs/sdf.md §6).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <iostream>

#include "analytic_sdf.hpp"
#include "ppohdem/error.hpp"
#include "ppohdem/sdf/reference/builders.hpp"
#include "ppohdem/sdf/reference/exact_sdf_builder.hpp"
#include "test_meshes.hpp"

using ppohdem::GridSpec;
using ppohdem::ScalarField;
using ppohdem::SdfReport;
using ppohdem::TriangleMesh;
using ppohdem::Vec3;
using namespace ppohdem::sdf::reference;
using namespace ppohdem::test;

namespace {

/// Max |phi - oracle(p)| over all nodes.
template <typename Oracle>
double max_error(const ScalarField& phi, Oracle oracle) {
  double worst = 0.0;
  const GridSpec& g = phi.grid;
  for (int k = 0; k < g.nodes[2]; ++k)
    for (int j = 0; j < g.nodes[1]; ++j)
      for (int i = 0; i < g.nodes[0]; ++i) worst = std::max(worst, std::abs(phi.at(i, j, k) - oracle(g.position(i, j, k))));
  return worst;
}

/// R minus the smallest distance from the centre to a triangle plane (see the sphere test).
double inscribed_sag(const TriangleMesh& mesh, const Vec3& centre, double radius) {
  double closest_plane = radius;
  for (const auto& t : mesh.triangles) closest_plane = std::min(closest_plane, std::abs(t.area_vector().normalized().dot(t.v[0] - centre)));
  return radius - closest_plane;
}

// Round-off allowance for O(1) coordinates: the closest point takes tens of operations.
constexpr double kRoundoff = 1e-13;

}  // namespace

TEST(ExactSdfBuilder, SphereWithinChordErrorOfAnalytic) {
  // The mesh P is inscribed in the ball B (vertices on the sphere), so phi_P >= phi_B; and P
  // contains the ball of radius r_min = min distance from the centre to a triangle plane, so
  // phi_P <= |p - c| - r_min = phi_B + sag with sag = R - r_min (both are monotone under inclusion).
  const Vec3 centre(0.05, -0.03, 0.02);
  const auto mesh = icosphere(centre, 1.0, 3);  // 1280 triangles
  const double sag = inscribed_sag(mesh, centre, 1.0);
  std::cout << "icosphere level 3: chord (sag) bound " << sag << "\n";
  EXPECT_LT(sag, 0.01);
  const ScalarField phi = ExactSdfBuilder().build(mesh, cube_grid(-1.6, 1.6, 25));
  for (int k = 0; k < 25; ++k)
    for (int j = 0; j < 25; ++j)
      for (int i = 0; i < 25; ++i) {
        const double difference = phi.at(i, j, k) - sphere_sdf(phi.grid.position(i, j, k), centre, 1.0);
        ASSERT_GE(difference, -kRoundoff);
        ASSERT_LE(difference, sag + kRoundoff);
      }
}

TEST(ExactSdfBuilder, AxisAlignedBoxIsExactToRoundOff) {
  const Vec3 lo(-0.7, -0.4, -0.55), hi(0.6, 0.5, 0.45);
  SdfReport report;
  const ScalarField phi = ExactSdfBuilder().build(box_mesh(lo, hi), cube_grid(-1.0, 1.0, 21), &report);
  EXPECT_LE(max_error(phi, [&](const Vec3& p) { return box_sdf(p, lo, hi); }), kRoundoff);
  EXPECT_TRUE(report.warnings.empty());
  // inside_fraction is the fraction of phi < 0 (its definition) ...
  const GridSpec g = phi.grid;
  int negative = 0;
  for (double value : phi.values) negative += value < 0.0 ? 1 : 0;
  EXPECT_DOUBLE_EQ(report.inside_fraction, negative / double(g.node_count()));
  // ... which, counted independently by exact comparisons, lies between the nodes strictly inside
  // and the half-open box [lo, hi) (nodes exactly on a lo face are "inside" by the ray-parity
  // tie rule and get phi = -(a round-off of ~1e-17) or -0).
  int strictly_inside = 0, half_open = 0;
  for (int k = 0; k < 21; ++k)
    for (int j = 0; j < 21; ++j)
      for (int i = 0; i < 21; ++i) {
        const Vec3 p = g.position(i, j, k);
        strictly_inside += (p.array() > lo.array()).all() && (p.array() < hi.array()).all() ? 1 : 0;
        half_open += (p.array() >= lo.array()).all() && (p.array() < hi.array()).all() ? 1 : 0;
      }
  EXPECT_GE(negative, strictly_inside);
  EXPECT_LE(negative, half_open);
  EXPECT_GT(strictly_inside, 500);
}

TEST(ExactSdfBuilder, SliverAndZeroAreaTrianglesChangeNothing) {
  // Unit box whose top face (z = 1) is re-triangulated with a sliver (apex 1e-12 off edge 4-5)
  // and a zero-area triangle (apex exactly at the middle of the diagonal 4-7, over the node column
  // x = y = 0.5). Still closed and consistently oriented; the solid is still the unit box.
  TriangleMesh mesh = box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 1));
  const Vec3 v4(0, 0, 1), v5(1, 0, 1), v6(0, 1, 1), v7(1, 1, 1);
  const Vec3 p(0.5, 1e-12, 1), q(0.5, 0.5, 1);
  mesh.triangles.erase(mesh.triangles.begin() + 2, mesh.triangles.begin() + 4);  // the old top face
  for (const auto& tri : {std::array<Vec3, 3>{v4, v5, p}, {v5, v7, p}, {v7, v4, p},
                          {v4, v7, q}, {v7, v6, q}, {v6, v4, q}}) {
    ppohdem::Triangle t;
    t.v = tri;
    mesh.triangles.push_back(t);
  }
  SdfReport report;
  const ScalarField phi = ExactSdfBuilder().build(mesh, cube_grid(-0.5, 1.5, 17), &report);
  EXPECT_TRUE(report.warnings.empty());
  EXPECT_LE(max_error(phi, [](const Vec3& x) { return box_sdf(x, Vec3(0, 0, 0), Vec3(1, 1, 1)); }), kRoundoff);
}

TEST(ExactSdfBuilder, RejectsEmptyMeshAndBadGrid) {
  EXPECT_THROW(ExactSdfBuilder().build(TriangleMesh{}, cube_grid(0, 1, 3)), ppohdem::InputError);
  GridSpec bad = cube_grid(0, 1, 3);
  bad.spacing.x() = 0.0;
  EXPECT_THROW(ExactSdfBuilder().build(box_mesh(Vec3::Zero(), Vec3::Ones()), bad), ppohdem::InputError);
}

TEST(ReferenceSdfFactory, MakesBuildersByNameAndRejectsOthers) {
  EXPECT_EQ(make_reference_sdf_builder("exact")->name(), "exact");
  EXPECT_EQ(make_reference_sdf_builder("seed")->name(), "seed");
  try {
    make_reference_sdf_builder("fastest");
    FAIL() << "expected InputError";
  } catch (const ppohdem::InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("fastest"), std::string::npos);
    EXPECT_NE(message.find("exact"), std::string::npos);
    EXPECT_NE(message.find("seed"), std::string::npos);
  }
}

TEST(ExactSdfBuilder, TimingOn40kTriangleSphereAt32Cubed) {
  const auto mesh = uv_sphere(Vec3(0.01, 0.02, 0.03), 1.0, 200, 101);  // 2 * 200 * 100 triangles
  ASSERT_EQ(mesh.size(), 40000u);
  const GridSpec grid = cube_grid(-1.5, 1.5, 32);
  const auto start = std::chrono::steady_clock::now();
  const ScalarField phi = ExactSdfBuilder().build(mesh, grid);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "exact builder, 40000-triangle sphere, 32^3 nodes: " << seconds << " s\n";
  // Sanity of the result: the UV sphere's sag is < 2e-3 at this resolution.
  EXPECT_LE(max_error(phi, [](const Vec3& p) { return sphere_sdf(p, Vec3(0.01, 0.02, 0.03), 1.0); }), 2e-3);
}
