// The BVH's nearest triangle is the brute-force minimum over all triangles, bit for bit; its node
// view is a consistent partition of the triangles.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <vector>

#include "ppohdem/error.hpp"
#include "ppohdem/sdf/reference/triangle_bvh.hpp"
#include "test_meshes.hpp"

using ppohdem::Vec3;
using namespace ppohdem::sdf::reference;

namespace {

Vec3 random_point(double half) {
  const int x = *rc::gen::inRange(-1000, 1001), y = *rc::gen::inRange(-1000, 1001), z = *rc::gen::inRange(-1000, 1001);
  return Vec3(x, y, z) * (half / 1000.0);
}

}  // namespace

RC_GTEST_PROP(TriangleBvh, NearestEqualsBruteForceOnTriangleSoup, ()) {
  const int count = *rc::gen::inRange(1, 120);
  ppohdem::TriangleMesh mesh;
  for (int t = 0; t < count; ++t) {
    ppohdem::Triangle tri;
    const Vec3 centre = random_point(1.0);
    tri.v = {centre + random_point(0.2), centre + random_point(0.2), centre + random_point(0.2)};
    mesh.triangles.push_back(tri);
  }
  const TriangleBvh bvh(mesh);
  for (int q = 0; q < 20; ++q) {
    const Vec3 p = random_point(2.0);
    const NearestTriangle fast = bvh.nearest(p);
    const NearestTriangle slow = nearest_triangle_brute_force(mesh, p);
    RC_ASSERT(fast.squared_distance == slow.squared_distance);  // identical, not close
    RC_ASSERT(fast.triangle == slow.triangle);                  // ties go to the lower index in both
  }
}

TEST(TriangleBvh, NearestEqualsBruteForceOnSphere) {
  const auto mesh = ppohdem::test::icosphere(Vec3(0.1, -0.2, 0.3), 1.0, 3);  // 1280 triangles
  const TriangleBvh bvh(mesh);
  EXPECT_GT(bvh.node_count(), mesh.size() / TriangleBvh::kMaxLeafSize);
  for (int n = 0; n < 500; ++n) {
    const Vec3 p = 1.5 * Vec3(std::sin(n * 1.1), std::cos(n * 0.7), std::sin(n * 0.37 + 1.0)) * ((n % 7) / 6.0);
    EXPECT_EQ(bvh.nearest(p).squared_distance, nearest_triangle_brute_force(mesh, p).squared_distance) << "point " << n;
  }
}

TEST(TriangleBvh, RejectsEmptyMesh) { EXPECT_THROW(TriangleBvh{ppohdem::TriangleMesh{}}, ppohdem::InputError); }

TEST(TriangleBvh, NodesAreInPreOrderAndPartitionTheTriangles) {
  // The read-only view used by WindingNumberTree: children after their parent, each inner node's
  // triangle range the concatenation of its children's, leaves covering every triangle once, and
  // every node's box containing its triangles' vertices.
  const auto mesh = ppohdem::test::icosphere(Vec3(0.1, -0.2, 0.3), 1.0, 2);  // 320 triangles
  const TriangleBvh bvh(mesh);
  const auto& nodes = bvh.nodes();
  std::vector<std::size_t> subtree_count(nodes.size(), 0);
  for (std::size_t n = nodes.size(); n-- > 0;) {
    const auto& node = nodes[n];
    if (node.leaf()) {
      subtree_count[n] = node.count;
    } else {
      ASSERT_GT(node.left, n);
      ASSERT_GT(node.right, n);
      EXPECT_EQ(nodes[node.left].first, node.first);
      EXPECT_EQ(nodes[node.right].first, node.first + subtree_count[node.left]);
      subtree_count[n] = subtree_count[node.left] + subtree_count[node.right];
    }
    for (std::size_t k = node.first; k < node.first + subtree_count[n]; ++k) {
      for (const Vec3& v : bvh.triangle(bvh.triangle_order()[k])) {
        EXPECT_TRUE((v.array() >= node.box.min.array()).all() && (v.array() <= node.box.max.array()).all());
      }
    }
  }
  EXPECT_EQ(subtree_count[0], mesh.size());
  std::vector<std::size_t> order = bvh.triangle_order();
  std::sort(order.begin(), order.end());
  for (std::size_t t = 0; t < order.size(); ++t) EXPECT_EQ(order[t], t);  // a permutation
  for (std::size_t t = 0; t < mesh.size(); ++t) EXPECT_EQ(bvh.triangle(t), mesh.triangles[t].v);
}
