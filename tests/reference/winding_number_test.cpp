// Generalized winding number and solid angle against closed-form values.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "ppohdem/sdf/reference/mesh_closure.hpp"
#include "ppohdem/sdf/reference/winding_number.hpp"
#include "test_meshes.hpp"

using ppohdem::Vec3;
using namespace ppohdem::sdf::reference;
using namespace ppohdem::test;

TEST(SolidAngle, OctantTriangleIsAnEighthOfTheSphere) {
  // The triangle (1,0,0), (0,1,0), (0,0,1) seen from the origin covers one octant: 4 pi / 8.
  // Counter-clockwise seen from outside (normal (1,1,1)): the origin is on the inner side, +.
  EXPECT_NEAR(solid_angle(Vec3::Zero(), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)), std::numbers::pi / 2, 1e-15);
  EXPECT_NEAR(solid_angle(Vec3::Zero(), Vec3(1, 0, 0), Vec3(0, 0, 1), Vec3(0, 1, 0)), -std::numbers::pi / 2, 1e-15);
}

TEST(WindingNumber, IsOneInsideAndZeroOutsideClosedMeshes) {
  const auto sphere = icosphere(Vec3(0.2, 0.1, -0.3), 1.0, 2);
  const auto box = box_mesh(Vec3(-1, -1, -1), Vec3(1, 2, 3));
  // Sums of ~300 terms of size <= 2 pi: round-off well below 1e-12.
  for (const Vec3& p : {Vec3(0.2, 0.1, -0.3), Vec3(0.5, 0.4, 0.2)}) EXPECT_NEAR(winding_number(sphere, p), 1.0, 1e-12);
  for (const Vec3& p : {Vec3(2, 0, 0), Vec3(-3, 5, 1)}) EXPECT_NEAR(winding_number(sphere, p), 0.0, 1e-12);
  EXPECT_NEAR(winding_number(box, Vec3(0.9, 1.9, 2.9)), 1.0, 1e-12);
  EXPECT_NEAR(winding_number(box, Vec3(1.1, 0, 0)), 0.0, 1e-12);
}

TEST(MeshClosure, ClassifiesClosedOpenAndMisorientedBoxes) {
  const auto box = box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 1));
  const MeshClosure closed = check_mesh_closure(box);
  EXPECT_TRUE(closed.consistently_oriented());
  EXPECT_EQ(closed.welded_vertices, 8u);
  EXPECT_EQ(closed.edges, 18u);  // 12 cube edges + 6 face diagonals

  auto open = box;
  open.triangles.resize(10);  // drop the x = hi face (its two triangles)
  const MeshClosure holed = check_mesh_closure(open);
  EXPECT_FALSE(holed.closed());
  EXPECT_EQ(holed.boundary_edges, 4u);  // the square's rim

  auto flipped = box;
  std::swap(flipped.triangles[0].v[1], flipped.triangles[0].v[2]);
  const MeshClosure misoriented = check_mesh_closure(flipped);
  EXPECT_TRUE(misoriented.closed());
  EXPECT_FALSE(misoriented.consistently_oriented());
  EXPECT_EQ(misoriented.misoriented_edges, 3u);

  auto doubled = box;
  doubled.triangles.push_back(box.triangles[0]);
  EXPECT_EQ(check_mesh_closure(doubled).non_manifold_edges, 3u);
}

TEST(MeshClosure, WeldsNegativeZeroWithZero) {
  auto box = box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 1));
  for (auto& t : box.triangles.front().v)
    for (int a = 0; a < 3; ++a)
      if (t[a] == 0.0) t[a] = -0.0;
  EXPECT_TRUE(check_mesh_closure(box).consistently_oriented());
}
