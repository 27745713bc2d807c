#pragma once
/// \file triangle_bvh.hpp
/// A bounding-volume hierarchy of axis-aligned boxes over the triangles of a mesh, for the
/// nearest-triangle query "which triangle is closest to p, and how far is it" [m].
///
/// Build (top-down, e.g. Ericson, Real-Time Collision Detection, 2005, section 6.2): a node holds a
/// contiguous range of triangle indices; the range is split at the median of the triangle
/// centroids along the longest axis of the centroids' bounding box, until <= 4 triangles remain.
///
/// Query (branch and bound): the squared distance from p to a box,
///   dist^2(p, [lo, hi]) = sum_a max(lo_a - p_a, 0, p_a - hi_a)^2,
/// is a lower bound on the squared distance to every triangle inside it; a subtree is skipped when
/// that bound is not smaller than the best squared distance found so far. The nearer child is
/// visited first so the bound tightens early. The result is the minimum over all triangles of
/// squared_distance_to_triangle(), bit for bit the brute-force answer.
#include <cstddef>
#include <vector>

#include "ppohdem/mesh/triangle_mesh.hpp"

namespace ppohdem::sdf::reference {

/// The nearest triangle to a query point.
struct NearestTriangle {
  std::size_t triangle = 0;  ///< index into mesh.triangles
  Vec3 point = Vec3::Zero();  ///< closest point on that triangle [m]
  double squared_distance = 0.0;  ///< |point - p|^2 [m^2]
};

class TriangleBvh {
 public:
  static constexpr std::size_t kMaxLeafSize = 4;

  /// Copies the triangle vertices; the mesh need not outlive the hierarchy. Needs a non-empty mesh.
  explicit TriangleBvh(const TriangleMesh& mesh);

  NearestTriangle nearest(const Vec3& p) const;

  /// A node of the tree. Nodes are stored in depth-first pre-order: nodes()[0] is the root and
  /// every child has a larger index than its parent (so a reverse scan visits children first).
  struct Node {
    BoundingBox box;          ///< box of all vertices of the node's triangles (contains them)
    std::size_t first = 0;    ///< first position in triangle_order()
    std::size_t count = 0;    ///< number of triangles (leaf) or 0 (inner node)
    std::size_t left = 0;     ///< child node indices (inner node only)
    std::size_t right = 0;
    bool leaf() const { return count > 0; }
  };

  // Read-only view of the structure, for other hierarchical queries (winding_number_tree.hpp).
  std::size_t node_count() const { return nodes_.size(); }
  const std::vector<Node>& nodes() const { return nodes_; }
  /// Triangle indices grouped by node: the node covering positions [first, first + n) holds
  /// triangles triangle_order()[first .. first + n - 1]; an inner node covers its children's ranges.
  const std::vector<std::size_t>& triangle_order() const { return order_; }
  /// The vertices of mesh triangle t (a copy made at construction).
  const std::array<Vec3, 3>& triangle(std::size_t t) const { return triangles_[t]; }
  std::size_t triangle_count() const { return triangles_.size(); }

 private:
  std::size_t build_node(std::size_t first, std::size_t count);
  void search(std::size_t node, const Vec3& p, NearestTriangle& best) const;

  std::vector<std::array<Vec3, 3>> triangles_;
  std::vector<Vec3> centroids_;
  std::vector<std::size_t> order_;  ///< triangle indices, grouped so that each node is a range
  std::vector<Node> nodes_;         ///< nodes_[0] is the root
};

/// Squared distance from p to the box (0 inside) [m^2].
double squared_distance_to_box(const Vec3& p, const BoundingBox& box);

/// Brute force: the nearest triangle by looking at every triangle (the BVH's oracle).
NearestTriangle nearest_triangle_brute_force(const TriangleMesh& mesh, const Vec3& p);

}  // namespace ppohdem::sdf::reference
