// Exact sphere-mesh contacts (mesh_contact.hpp) against analytic answers: a V-notch, a corner of
// three faces, a flat face made of many triangles, convex edges and vertices of a box, a thin
// plate. Tolerances: every expected value is a closed form of the inputs; the computed ones
// differ from them by the round-off of a few dot products and a square root on coordinates of
// order 1e-2 m, i.e. a few 1e-18 m; 1e-12 relative (to R for lengths, absolute for unit
// normals) leaves four orders of magnitude and still fails on any real error (a wrong feature
// is off by O(R), a trilinear field by O(h)).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <set>
#include <vector>

#include "mesh_shapes.hpp"
#include "ppohdem/dem/mesh_contact.hpp"

namespace ppohdem::dem::test {
namespace {

constexpr double kTol = 1e-12;  // relative, see the file comment

std::vector<MeshContact> contacts_of(const MeshContactGeometry& g, const Vec3& c, double r) {
  std::vector<MeshContact> out;
  g.contacts(c, r, out);
  return out;
}

// The contact whose normal is nearest to n (the test then checks it is n).
const MeshContact& along(const std::vector<MeshContact>& cs, const Vec3& n) {
  const MeshContact* best = &cs.front();
  for (const MeshContact& c : cs) {
    if (c.normal.dot(n) > best->normal.dot(n)) best = &c;
  }
  return *best;
}

void expect_plane_contact(const MeshContact& c, const Vec3& centre, double radius, const Vec3& n, const Vec3& on_plane) {
  const double distance = (centre - on_plane).dot(n);
  EXPECT_NEAR((c.normal - n).norm(), 0.0, kTol);
  EXPECT_NEAR(c.overlap, radius - distance, kTol * radius);
  EXPECT_NEAR((c.point - (centre - distance * n)).norm(), 0.0, kTol * radius);
}

TEST(ClosestOnTriangle, RegionsOfTheSevenVoronoiZones) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_EQ(closest_on_triangle(Vec3(0.2, 0.2, 1), a, b, c).region, TriangleRegion::kInterior);
  const auto e0 = closest_on_triangle(Vec3(0.5, -1, 1), a, b, c);
  EXPECT_EQ(e0.region, TriangleRegion::kEdge);
  EXPECT_EQ(e0.index, 0);
  EXPECT_EQ(closest_on_triangle(Vec3(1, 1, 0), a, b, c).index, 1);
  EXPECT_EQ(closest_on_triangle(Vec3(-1, 0.5, 0), a, b, c).index, 2);
  const auto v1 = closest_on_triangle(Vec3(2, -1, 0), a, b, c);
  EXPECT_EQ(v1.region, TriangleRegion::kVertex);
  EXPECT_EQ(v1.index, 1);
  EXPECT_EQ((v1.point - b).norm(), 0.0);
}

// A sphere in a 90-degree V-notch touches both faces: two contacts with the faces' normals and
// overlaps R - (c . n), at any position along and across the notch (over triangle interiors,
// shared edges and shared vertices alike).
TEST(MeshContact, VNotchGivesTwoContactsWithAnalyticNormalsAndOverlaps) {
  const double depth = 0.02, length = 0.03, radius = 2.5e-3;
  const MeshContactGeometry g(v_notch(length, depth, 12));
  const Vec3 na = Vec3(0, -1, 1).normalized(), nb = Vec3(0, 1, 1).normalized();
  std::mt19937_64 rng(38);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int checked = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    // Centre within R of both planes and clear of the notch's ends and rims.
    const Vec3 c(0.005 + 0.02 * u(rng), (u(rng) - 0.5) * 2.0 * radius, radius * (0.8 + 0.6 * u(rng)));
    const double da = c.dot(na), db = c.dot(nb);
    if (!(da > 0 && db > 0 && da < radius && db < radius)) continue;
    const auto cs = contacts_of(g, c, radius);
    ASSERT_EQ(cs.size(), 2u) << "centre " << c.transpose();
    expect_plane_contact(along(cs, na), c, radius, na, Vec3::Zero());
    expect_plane_contact(along(cs, nb), c, radius, nb, Vec3::Zero());
    EXPECT_NE(cs[0].feature, cs[1].feature);
    ++checked;
  }
  EXPECT_GT(checked, 500);
  // Exactly on a crease vertex's vertical and on the symmetry plane: still two, symmetric.
  const Vec3 c(length / 2, 0.0, 0.9 * radius * std::sqrt(2.0));
  const auto cs = contacts_of(g, c, radius);
  ASSERT_EQ(cs.size(), 2u);
  EXPECT_NEAR(cs[0].overlap, radius - 0.9 * radius, kTol * radius);
  EXPECT_NEAR(cs[1].overlap, radius - 0.9 * radius, kTol * radius);
}

// Higher up one face the sphere touches that face only.
TEST(MeshContact, VNotchHighOnOneFaceGivesOneContact) {
  const double radius = 2.5e-3;
  const MeshContactGeometry g(v_notch(0.03, 0.02, 12));
  const Vec3 na = Vec3(0, -1, 1).normalized();
  const Vec3 c = Vec3(0.015, 0.008, 0.008) + 0.9 * radius * na;
  const auto cs = contacts_of(g, c, radius);
  ASSERT_EQ(cs.size(), 1u);
  expect_plane_contact(cs[0], c, radius, na, Vec3::Zero());
}

// A corner of three faces, turned by an arbitrary rotation (so the faces' triangles are
// coplanar only to round-off): three contacts along Q e_x, Q e_y, Q e_z.
TEST(MeshContact, CornerOfThreeFacesGivesThreeContacts) {
  const double radius = 2.0e-3, a = 0.01;
  const Eigen::Matrix3d q = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const Vec3 shift(0.013, -0.021, 0.005);
  const MeshContactGeometry g(transformed(three_face_corner(a, 7), q, shift));
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.3, 0.95);
  for (int trial = 0; trial < 300; ++trial) {
    const Vec3 local(u(rng) * radius, u(rng) * radius, u(rng) * radius);
    const Vec3 c = q * local + shift;
    const auto cs = contacts_of(g, c, radius);
    ASSERT_EQ(cs.size(), 3u) << "local centre " << local.transpose();
    for (int k = 0; k < 3; ++k) {
      const Vec3 n = q.col(k);
      const MeshContact& m = along(cs, n);
      EXPECT_NEAR((m.normal - n).norm(), 0.0, kTol);
      EXPECT_NEAR(m.overlap, radius - local[k], kTol * radius);
    }
  }
}

// A flat face of 2 x 20 x 20 triangles: one contact wherever the centre is, also straight above
// a shared vertex or a shared edge, always with the same feature id.
TEST(MeshContact, FlatFaceOfManyTrianglesGivesOneContact) {
  const double a = 0.02, radius = 1e-3;
  const int n = 20;
  TriangleMesh mesh;
  add_rectangle(mesh, Vec3::Zero(), Vec3(a, 0, 0), Vec3(0, a, 0), n, n);
  const MeshContactGeometry g(mesh);
  EXPECT_EQ(g.face_count(), 1u);
  std::set<std::uint32_t> features;
  const auto check = [&](const Vec3& c) {
    const auto cs = contacts_of(g, c, radius);
    ASSERT_EQ(cs.size(), 1u) << "centre " << c.transpose();
    expect_plane_contact(cs[0], c, radius, Vec3::UnitZ(), Vec3::Zero());
    features.insert(cs[0].feature);
  };
  const double h = a / n;
  for (int i = 3; i < 17; ++i) {
    for (int j = 3; j < 17; ++j) {
      check(Vec3(i * h, j * h, 0.7 * radius));                // over a shared vertex
      check(Vec3((i + 0.5) * h, j * h, 0.7 * radius));        // over a shared edge
      check(Vec3((i + 0.5) * h, (j + 0.5) * h, 0.7 * radius));  // over a diagonal
      check(Vec3((i + 0.3) * h, (j + 0.6) * h, 0.7 * radius));  // inside a triangle
    }
  }
  EXPECT_EQ(features.size(), 1u);
}

// Outside a convex edge of a box (in the edge's Voronoi region): one contact, normal from the
// edge to the centre; outside a corner: one contact, normal from the corner.
TEST(MeshContact, ConvexEdgeAndVertexGiveOneContactTowardsThem) {
  const double a = 0.01, radius = 1e-3;
  const MeshContactGeometry g(box(a, 5));
  // Beyond the edge x = a, z = a, at y = 0.37 a (inside a triangle's edge, not at a vertex).
  for (const double angle : {0.1, 0.4, 0.785, 1.2, 1.45}) {
    const double d = 0.6 * radius;
    const Vec3 q(a, 0.37 * a, a);
    const Vec3 c = q + d * Vec3(std::cos(angle), 0, std::sin(angle));
    const auto cs = contacts_of(g, c, radius);
    ASSERT_EQ(cs.size(), 1u) << "angle " << angle;
    EXPECT_NEAR((cs[0].normal - Vec3(std::cos(angle), 0, std::sin(angle))).norm(), 0.0, kTol);
    EXPECT_NEAR(cs[0].overlap, radius - d, kTol * radius);
    EXPECT_NEAR((cs[0].point - q).norm(), 0.0, kTol * radius);
  }
  // Beyond the corner (a, a, a).
  const Vec3 dir = Vec3(1, 2, 1.5).normalized();
  const Vec3 c = Vec3(a, a, a) + 0.5 * radius * dir;
  const auto cs = contacts_of(g, c, radius);
  ASSERT_EQ(cs.size(), 1u);
  EXPECT_NEAR((cs[0].normal - dir).norm(), 0.0, kTol);
  EXPECT_NEAR(cs[0].overlap, 0.5 * radius, kTol * radius);
  // Above the top face near the edge but in the face's region: the face only.
  const Vec3 above(a - 0.2 * radius, 0.5 * a, a + 0.5 * radius);
  const auto top = contacts_of(g, above, radius);
  ASSERT_EQ(top.size(), 1u);
  expect_plane_contact(top[0], above, radius, Vec3::UnitZ(), Vec3(0, 0, a));
}

// A plate thinner than the sphere's radius: only the near side pushes.
TEST(MeshContact, ThinPlateFarSideDoesNotPush) {
  const double radius = 1e-3;
  const Eigen::Matrix3d squash = Vec3(1, 1, 0.2).asDiagonal();  // 10 x 10 x 2 mm... scaled below
  const MeshContactGeometry g(transformed(box(0.01, 4), squash * 0.05, Vec3::Zero()));  // 0.5 x 0.5 x 0.1 mm
  const Vec3 c(0.25e-3, 0.25e-3, 0.1e-3 + 0.5 * radius);
  const auto cs = contacts_of(g, c, radius);
  ASSERT_EQ(cs.size(), 1u);
  expect_plane_contact(cs[0], c, radius, Vec3::UnitZ(), Vec3(0, 0, 0.1e-3));
}

TEST(MeshContact, FarAwayGivesNothing) {
  const MeshContactGeometry g(box(0.01, 3));
  EXPECT_TRUE(contacts_of(g, Vec3(0.005, 0.005, 0.0111), 1e-3).empty());
  EXPECT_EQ(contacts_of(g, Vec3(0.005, 0.005, 0.0109), 1e-3).size(), 1u);
}

}  // namespace
}  // namespace ppohdem::dem::test
