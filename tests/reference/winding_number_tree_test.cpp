// The hierarchical winding number (closing caps over a BVH) against closed-form values and against
// the brute-force sum over all triangles (winding_number(), the oracle).
//
// Tolerance kRoundOff = 1e-10 on w (dimensionless) throughout: both evaluations add up to
// N <= 69,451 solid angles in different groupings, and recursive summation errs by at most
// ~ N u sum_t |Omega_t| (Higham 2002, section 4.2; u = 1.1e-16). sum_t |Omega_t| / 4 pi is a few
// for these meshes (the number of sheets a ray from p crosses), giving a worst case of a few 1e-11;
// the cap terms add ~ 2e-13 sr each (winding_number_tree.hpp). A wrong cap orientation or a
// missed boundary edge changes w by the solid angle of a whole patch, >= 1e-6 at these points.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <numbers>
#include <random>

#include "ppohdem/mesh/stl_io.hpp"
#include "ppohdem/sdf/reference/winding_number.hpp"
#include "ppohdem/sdf/reference/winding_number_tree.hpp"
#include "test_meshes.hpp"
#include "test_paths.hpp"

using ppohdem::Triangle;
using ppohdem::TriangleMesh;
using ppohdem::Vec3;
using namespace ppohdem::sdf::reference;
using namespace ppohdem::test;

namespace {

constexpr double kRoundOff = 1e-10;  // see the file comment

/// max over `points` of |tree - brute force|; fails the test at the first point beyond kRoundOff.
double max_difference_to_brute_force(const TriangleMesh& mesh, const std::vector<Vec3>& points) {
  const WindingNumberTree tree(mesh);
  double worst = 0.0;
  for (std::size_t n = 0; n < points.size(); ++n) {
    const double fast = tree.winding_number(points[n]);
    const double slow = winding_number(mesh, points[n]);
    EXPECT_NEAR(fast, slow, kRoundOff) << "point " << n << " = " << points[n].transpose();
    worst = std::max(worst, std::abs(fast - slow));
  }
  return worst;
}

/// `count` points: uniform in the mesh's box grown by `grow` times its size, plus points within
/// `near` of random vertices (close to the surface, where the caps of nearby nodes matter).
std::vector<Vec3> points_around(const TriangleMesh& mesh, int count, double grow, double near, unsigned seed) {
  const ppohdem::BoundingBox box = ppohdem::bounding_box(mesh);
  const Vec3 size = box.extent();
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<std::size_t> which(0, mesh.size() - 1);
  std::vector<Vec3> points;
  for (int n = 0; n < count; ++n) {
    const Vec3 u(unit(random), unit(random), unit(random));
    if (n % 2 == 0) {
      points.push_back(box.centre() + (0.5 + grow) * size.cwiseProduct(u));
    } else {
      points.push_back(mesh.triangles[which(random)].v[0] + near * size.norm() * u);
    }
  }
  return points;
}

/// Removes the triangles whose centroid is within `radius` of `centre` (punches a hole).
TriangleMesh punch_hole(TriangleMesh mesh, const Vec3& centre, double radius) {
  std::erase_if(mesh.triangles, [&](const Triangle& t) {
    return ((t.v[0] + t.v[1] + t.v[2]) / 3.0 - centre).norm() < radius;
  });
  return mesh;
}

/// The directed edges of `mesh` whose reverse is not used (the rim of its holes), as vertex pairs.
std::vector<std::array<Vec3, 2>> rim_edges(const TriangleMesh& mesh) {
  std::map<std::array<double, 6>, int> uses;  // (from, to) coordinates -> uses
  for (const Triangle& t : mesh.triangles) {
    for (std::size_t c = 0; c < 3; ++c) {
      const Vec3 &a = t.v[c], &b = t.v[(c + 1) % 3];
      ++uses[{a.x(), a.y(), a.z(), b.x(), b.y(), b.z()}];
    }
  }
  std::vector<std::array<Vec3, 2>> rim;
  for (const auto& [key, count] : uses) {
    if (!uses.contains({key[3], key[4], key[5], key[0], key[1], key[2]})) {
      rim.push_back({Vec3(key[0], key[1], key[2]), Vec3(key[3], key[4], key[5])});
    }
  }
  return rim;
}

}  // namespace

TEST(WindingNumberTree, CapOfAnOpenBoxGivesTheAnalyticValue) {
  // Unit cube without its x = 1 face. Closed cube: w = 0 outside, so w_open(p) = -w_face(p), and
  // the face (normal +x) seen from p = (1.5, 0.5, 0.5) on its outer side subtends the square's solid
  // angle 4 arcsin(a b / sqrt((a^2 + 4 d^2)(b^2 + 4 d^2))) = 4 arcsin(1/2) = 2 pi / 3 at a = b = 1,
  // d = 1/2: w_open = (2 pi / 3) / (4 pi) = 1/6. A reversed cap would give -1/6.
  TriangleMesh open = box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 1));
  open.triangles.resize(10);  // box_mesh lists the x = hi face last
  const WindingNumberTree tree(open);
  EXPECT_EQ(tree.boundary_edge_count(0), 4u);  // the root's boundary: the square rim
  const auto far = tree.evaluate(Vec3(1.5, 0.5, 0.5));
  EXPECT_EQ(far.solid_angles, 4u);  // p is outside the root box: the root's 4-triangle cap
  // 4 solid angles, each within a few eps: 1e-14.
  EXPECT_NEAR(far.winding_number, 1.0 / 6.0, 1e-14);
  EXPECT_NEAR(far.winding_number, winding_number(open, Vec3(1.5, 0.5, 0.5)), 1e-14);
}

TEST(WindingNumberTree, ClosedMeshIsZeroOutsideWithoutAnySolidAngle) {
  const auto sphere = icosphere(Vec3(0.2, 0.1, -0.3), 1.0, 3);  // 1280 triangles, closed
  const WindingNumberTree tree(sphere);
  EXPECT_EQ(tree.boundary_edge_count(0), 0u);
  const auto outside = tree.evaluate(Vec3(3, 0, 0));
  EXPECT_EQ(outside.winding_number, 0.0);  // a closed root contributes exactly 0 from outside its box
  EXPECT_EQ(outside.solid_angles, 0u);
  // Inside: caps of the sub-patches; sums of ~ hundreds of terms: round-off far below 1e-12.
  const auto inside = tree.evaluate(Vec3(0.2, 0.1, -0.3));
  EXPECT_NEAR(inside.winding_number, 1.0, 1e-12);
  EXPECT_LT(inside.solid_angles, sphere.size());  // the caps replaced some of the triangles
}

TEST(WindingNumberTree, EqualsBruteForceAroundAnOpenBox) {
  TriangleMesh open = box_mesh(Vec3(-1, -0.5, 0), Vec3(1, 2, 0.5));
  open.triangles.resize(10);
  EXPECT_LE(max_difference_to_brute_force(open, points_around(open, 200, 1.0, 0.05, 1)), kRoundOff);
}

TEST(WindingNumberTree, EqualsBruteForceAroundASphereWithHoles) {
  TriangleMesh sphere = icosphere(Vec3(0.1, -0.2, 0.3), 1.0, 4);  // 5120 triangles
  for (const Vec3& hole : {Vec3(1, 0, 0), Vec3(0, 0.7, 0.7), Vec3(-0.6, -0.6, -0.5)}) {
    sphere = punch_hole(sphere, Vec3(0.1, -0.2, 0.3) + hole.normalized(), 0.3);
  }
  ASSERT_LT(sphere.size(), 5000u);
  ASSERT_GT(WindingNumberTree(sphere).boundary_edge_count(0), 0u);
  EXPECT_LE(max_difference_to_brute_force(sphere, points_around(sphere, 300, 0.5, 0.02, 2)), kRoundOff);
}

TEST(WindingNumberTree, EqualsBruteForceWithInconsistentOrientation) {
  // A closed sphere with every 7th triangle flipped: its edges are used twice in one direction,
  // so the boundaries carry edges with multiplicity 2 and the root is not closed.
  TriangleMesh sphere = icosphere(Vec3(0, 0, 0), 1.0, 3);
  for (std::size_t t = 0; t < sphere.size(); t += 7) std::swap(sphere.triangles[t].v[1], sphere.triangles[t].v[2]);
  ASSERT_GT(WindingNumberTree(sphere).boundary_edge_count(0), 0u);
  EXPECT_LE(max_difference_to_brute_force(sphere, points_around(sphere, 300, 0.5, 0.02, 3)), kRoundOff);
}

RC_GTEST_PROP(WindingNumberTree, EqualsBruteForceOnRandomIndexedSoups, ()) {
  // Faces drawn from a small vertex pool: shared, repeated, reversed, non-manifold and degenerate
  // (repeated index) triangles, so edges cancel in every multiplicity. ~60 terms: 1e-12.
  std::vector<Vec3> pool;
  const int vertices = *rc::gen::inRange(3, 13);
  for (int v = 0; v < vertices; ++v) {
    pool.emplace_back(*rc::gen::inRange(-100, 101) / 100.0, *rc::gen::inRange(-100, 101) / 100.0,
                      *rc::gen::inRange(-100, 101) / 100.0);
  }
  std::vector<std::array<int, 3>> faces(static_cast<std::size_t>(*rc::gen::inRange(1, 60)));
  for (auto& f : faces) {
    for (int& index : f) index = *rc::gen::inRange(0, vertices);
  }
  const TriangleMesh mesh = indexed_mesh(pool, faces);
  const WindingNumberTree tree(mesh);
  for (int q = 0; q < 20; ++q) {
    const Vec3 p(*rc::gen::inRange(-300, 301) / 100.0, *rc::gen::inRange(-300, 301) / 100.0,
                 *rc::gen::inRange(-300, 301) / 100.0);
    RC_ASSERT(std::abs(tree.winding_number(p) - winding_number(mesh, p)) <= 1e-12);
  }
}

TEST(WindingNumberTree, EqualsBruteForceAroundTheOpenBunny) {
  const TriangleMesh bunny = ppohdem::read_stl(fixture("meshes/bunny.stl"));
  ASSERT_EQ(bunny.size(), 69451u);
  const auto rim = rim_edges(bunny);
  ASSERT_EQ(rim.size(), 223u);  // fixtures/meshes/README.md: 5 holes, 223 boundary edges
  std::vector<Vec3> points = points_around(bunny, 200, 0.3, 0.01, 4);
  // 100 points near the holes: edge midpoints moved by up to 1e-3 of the bunny's size (~1.5e-4 m).
  const double size = ppohdem::bounding_box(bunny).extent().norm();
  std::mt19937 random(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (std::size_t n = 0; n < 100; ++n) {
    const auto& edge = rim[(n * 37) % rim.size()];
    points.push_back(0.5 * (edge[0] + edge[1]) + 1e-3 * size * Vec3(unit(random), unit(random), unit(random)));
  }
  const double worst = max_difference_to_brute_force(bunny, points);
  std::cout << "bunny: max |tree - brute force| over " << points.size() << " points = " << worst << "\n";
}

TEST(WindingNumberTree, ClassifiesTheOpenBunnyGridLikeBruteForce) {
  // The voxelize box of docs/sdf.md at 12^3 cells. Nodes with |w - 1/2| < 1e-9 (far more than the
  // 1e-10 round-off) could legitimately fall either way and are skipped; there are none in practice
  // but the test does not depend on it.
  const TriangleMesh bunny = ppohdem::read_stl(fixture("meshes/bunny.stl"));
  const auto grid = ppohdem::GridSpec::spanning(Vec3(-0.1, 0.02, -0.07), Vec3(0.07, 0.2, 0.07), {13, 13, 13});
  const std::vector<bool> inside = inside_by_winding_number(bunny, grid);
  std::size_t compared = 0, inside_count = 0;
  for (int k = 0; k < grid.nodes[2]; ++k) {
    for (int j = 0; j < grid.nodes[1]; ++j) {
      for (int i = 0; i < grid.nodes[0]; ++i) {
        const double w = winding_number(bunny, grid.position(i, j, k));
        if (std::abs(w - 0.5) < 1e-9) continue;
        ++compared;
        inside_count += (w > 0.5);
        EXPECT_EQ(inside[grid.index(i, j, k)], w > 0.5) << "node " << i << " " << j << " " << k << " w = " << w;
      }
    }
  }
  EXPECT_GT(compared, grid.node_count() - 10);
  EXPECT_GT(inside_count, 50u);  // the bunny fills part of the box: both answers occur
  EXPECT_LT(inside_count, compared - 50);
}

TEST(WindingNumberTree, EmptyMeshIsOutsideEverywhere) {
  const auto grid = ppohdem::GridSpec::spanning(Vec3(0, 0, 0), Vec3(1, 1, 1), {2, 2, 2});
  const std::vector<bool> inside = inside_by_winding_number(TriangleMesh{}, grid);
  EXPECT_EQ(std::count(inside.begin(), inside.end(), true), 0);
}
