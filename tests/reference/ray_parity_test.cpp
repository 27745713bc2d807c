// Column ray parity: exact inside sets in the degenerate cases that broke the original program
// (faces on grid planes, columns through shared edges and vertices), and random rigid motions.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "analytic_sdf.hpp"
#include "ppohdem/sdf/reference/ray_parity.hpp"
#include "ppohdem/sdf/reference/winding_number.hpp"
#include "test_meshes.hpp"

using ppohdem::GridSpec;
using ppohdem::Vec3;
using namespace ppohdem::sdf::reference;
using namespace ppohdem::test;

namespace {

/// Largest gap between the sphere of radius R and an inscribed mesh: R minus the smallest distance
/// from the centre to a triangle's plane. Points with |p - c| < R - sag are inside the mesh,
/// points with |p - c| > R outside (the inscribed polyhedron lies inside the ball).
double inscribed_sag(const ppohdem::TriangleMesh& mesh, const Vec3& centre, double radius) {
  double closest_plane = radius;
  for (const auto& t : mesh.triangles) {
    const Vec3 n = t.area_vector().normalized();
    closest_plane = std::min(closest_plane, std::abs(n.dot(t.v[0] - centre)));
  }
  return radius - closest_plane;
}

}  // namespace

TEST(RayParity, BoxWithFacesOnGridPlanesGivesTheHalfOpenBox) {
  // h = 0.25 is exact in binary; the faces x, y, z = 0.5 and 1.5 are node planes, the box's edges
  // and vertices lie on grid columns, and the face diagonals pass through columns too.
  const GridSpec grid = cube_grid(0.0, 2.0, 9);
  const Vec3 lo(0.5, 0.5, 0.5), hi(1.5, 1.5, 1.5);
  const auto inside = inside_by_column_parity(box_mesh(lo, hi), grid);
  int count = 0;
  for (int k = 0; k < 9; ++k)
    for (int j = 0; j < 9; ++j)
      for (int i = 0; i < 9; ++i) {
        const Vec3 p = grid.position(i, j, k);
        // Simulation of simplicity moves the column to (x + e, y + e^2) and the node up by an
        // infinitesimal, so the inside set is [lo, hi) on every axis.
        const bool expected = (p.array() >= lo.array()).all() && (p.array() < hi.array()).all();
        EXPECT_EQ(inside[grid.index(i, j, k)], expected) << "node " << i << " " << j << " " << k;
        count += expected ? 1 : 0;
      }
  EXPECT_EQ(count, 4 * 4 * 4);
}

TEST(RayParity, SphereWithPolesOnAGridColumnMatchesTheBall) {
  // The README's failing case: the column through the centre holds both poles (every meridian
  // meets there), and with 64 longitudes the 0 and 90 degree meridians lie in the node planes
  // x = c and y = c, so many columns run through shared edges and vertices.
  const GridSpec grid = cube_grid(-2.0, 2.0, 33);  // h = 0.125, node 16 at 0
  const Vec3 centre(0, 0, 0);
  for (double radius : {1.5, 1.3}) {  // 1.5: poles exactly on nodes; 1.3: poles between nodes
    const auto mesh = uv_sphere(centre, radius, 64, 32);
    const double sag = inscribed_sag(mesh, centre, radius);
    const auto inside = inside_by_column_parity(mesh, grid);
    int checked = 0;
    for (int k = 0; k < 33; ++k)
      for (int j = 0; j < 33; ++j)
        for (int i = 0; i < 33; ++i) {
          const double r = (grid.position(i, j, k) - centre).norm();
          if (r < radius - sag) {
            EXPECT_TRUE(inside[grid.index(i, j, k)]) << "r " << r;
            ++checked;
          } else if (r > radius) {
            EXPECT_FALSE(inside[grid.index(i, j, k)]) << "r " << r;
          }
        }
    EXPECT_GT(checked, 1000);
  }
}

TEST(RayParity, OriginalProgramsCentredSphereCaseHasNoSignErrors) {
  // ppohdem-original/README.md section 1: the original grid (76^3 nodes, h = 44/76, origin 0) and
  // the 64 x 32 UV sphere of radius 3 centred at (22, 22, 16), where the original made 214 sign
  // errors (columns x = 22, y = 22 hold the poles and the 0/90 degree meridians).
  GridSpec grid;
  grid.origin = Vec3::Zero();
  grid.spacing = Vec3::Constant(44.0 / 76.0);
  grid.nodes = {76, 76, 76};
  const Vec3 centre(22, 22, 16);
  const auto mesh = uv_sphere(centre, 3.0, 64, 32);
  const double sag = inscribed_sag(mesh, centre, 3.0);
  const auto inside = inside_by_column_parity(mesh, grid);
  int sign_errors = 0, checked = 0;
  for (int k = 0; k < 76; ++k)
    for (int j = 0; j < 76; ++j)
      for (int i = 0; i < 76; ++i) {
        const double r = (grid.position(i, j, k) - centre).norm();
        if (r < 3.0 - sag || r > 3.0) {
          sign_errors += inside[grid.index(i, j, k)] != (r < 3.0) ? 1 : 0;
          ++checked;
        }
      }
  EXPECT_EQ(sign_errors, 0);
  EXPECT_GT(checked, 430000);
}

TEST(RayParity, AgreesWithWindingNumberOffTheSurface) {
  const GridSpec grid = cube_grid(-2.0, 2.0, 17);  // h = 0.25: columns through the poles and meridians
  const auto mesh = uv_sphere(Vec3(0, 0, 0), 1.5, 16, 8);
  const auto parity = inside_by_column_parity(mesh, grid);
  for (int k = 0; k < 17; ++k)
    for (int j = 0; j < 17; ++j)
      for (int i = 0; i < 17; ++i) {
        const double w = winding_number(mesh, grid.position(i, j, k));
        if (std::abs(w - 0.5) < 0.25) continue;  // on the surface: w is 1/2 or so, either answer is right
        EXPECT_EQ(parity[grid.index(i, j, k)], w > 0.5) << i << " " << j << " " << k << " w " << w;
      }
}

RC_GTEST_PROP(RayParity, MatchesBallAfterRandomRigidMotion, ()) {
  const double angle = *rc::gen::inRange(0, 6283) / 1000.0;
  const Vec3 axis = Vec3(*rc::gen::inRange(-100, 101), *rc::gen::inRange(-100, 101), *rc::gen::inRange(1, 101)).normalized();
  const Vec3 shift = Vec3(*rc::gen::inRange(-100, 101), *rc::gen::inRange(-100, 101), *rc::gen::inRange(-100, 101)) / 400.0;
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
  const double radius = 1.2;
  const auto mesh = transformed(icosphere(Vec3::Zero(), radius, 2), rotation, shift);
  const double sag = inscribed_sag(mesh, shift, radius);
  const GridSpec grid = cube_grid(-1.75, 1.75, 15);  // h = 0.25
  const auto inside = inside_by_column_parity(mesh, grid);
  for (int k = 0; k < 15; ++k)
    for (int j = 0; j < 15; ++j)
      for (int i = 0; i < 15; ++i) {
        const double r = (grid.position(i, j, k) - shift).norm();
        if (r < radius - sag) RC_ASSERT(inside[grid.index(i, j, k)]);
        if (r > radius) RC_ASSERT(!inside[grid.index(i, j, k)]);
      }
}

RC_GTEST_PROP(RayParity, RotatedBoxMatchesAnalyticInside, ()) {
  // A box under a random rotation: inside iff the analytic box SDF (in the box's frame) is < 0,
  // for every node not on the surface.
  const double angle = *rc::gen::inRange(0, 6283) / 1000.0;
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(angle, Vec3(0.3, -0.2, 1.0).normalized()).toRotationMatrix();
  const auto mesh = transformed(box_mesh(Vec3(-0.8, -0.6, -0.5), Vec3(0.8, 0.6, 0.5)), rotation, Vec3::Zero());
  const GridSpec grid = cube_grid(-1.5, 1.5, 13);
  const auto inside = inside_by_column_parity(mesh, grid);
  for (int k = 0; k < 13; ++k)
    for (int j = 0; j < 13; ++j)
      for (int i = 0; i < 13; ++i) {
        const Vec3 local = rotation.transpose() * grid.position(i, j, k);
        const double phi = box_sdf(local, Vec3(-0.8, -0.6, -0.5), Vec3(0.8, 0.6, 0.5));
        if (std::abs(phi) < 1e-12) continue;  // on the surface (rounding of the rotation)
        RC_ASSERT(inside[grid.index(i, j, k)] == (phi < 0));
      }
}

TEST(RayParity, VerticalFacesAreNeverCrossed) {
  // A triangle in the plane x = 0.5 projects to a segment.
  EXPECT_FALSE(projection_contains({0.5, 0}, {0.5, 1}, {0.5, 2}, {0.5, 0.5}));
  // A column exactly through a vertex shared by a fan counts exactly one of the fan's triangles.
  const Vec2 centre(0, 0);
  int hits = 0;
  for (int s = 0; s < 6; ++s) {
    const double a0 = s * std::numbers::pi / 3, a1 = (s + 1) * std::numbers::pi / 3;
    hits += projection_contains(centre, {std::cos(a0), std::sin(a0)}, {std::cos(a1), std::sin(a1)}, centre) ? 1 : 0;
  }
  EXPECT_EQ(hits, 1);
}

TEST(RayParity, CrossingHeightOfHorizontalFaceIsExact) {
  EXPECT_EQ(crossing_height(Vec3(0, 0, 0.3), Vec3(1, 0, 0.3), Vec3(0, 1, 0.3), {0.2, 0.7}), 0.3);
  // A tilted plane z = x + 2y through (0,0,0), (1,0,1), (0,1,2).
  EXPECT_NEAR(crossing_height(Vec3(0, 0, 0), Vec3(1, 0, 1), Vec3(0, 1, 2), {0.25, 0.5}), 1.25, 1e-15);
}
