#pragma once
/// \file nearest_triangle.hpp
/// Nearest-triangle queries for the fast SDF builder: a flat bounding-volume hierarchy (BVH)
/// over prepared triangles, stored depth-first in one array so a query walks memory forward.
///
/// Distance to one triangle: Ericson, "Real-Time Collision Detection" (2005) section 5.1.5
/// (Voronoi regions of the vertices, edges and face), with the same degenerate- and
/// thin-triangle handling as the reference (a zero-area triangle is its three edges; a sliver
/// is also compared with its edges), so both builders agree to rounding.
///
/// Query: best-first descent, nearer child first, pruning a box when its distance exceeds the
/// best distance so far plus a slack of 1e-12 times the coordinate scale; in a leaf, a triangle
/// whose own bounding box is beyond that bound is skipped before the exact distance, and the
/// stack keeps each box's distance so it is not recomputed when popped (measured 2026-11-30:
/// about 10 % less CPU time for the whole dragon run at 80^3, 1 thread, 3 runs each). The slack makes the
/// pruning conservative with respect to the rounding of the triangle distance, so the returned
/// squared distance is the minimum of the computed per-triangle values over ALL triangles,
/// whatever the starting guess: the result does not depend on the traversal order, on the hint,
/// on the thread or on the MPI rank (the basis of the bitwise invariance claims).
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "ppohdem/geometry/vector.hpp"
#include "ppohdem/mesh/triangle_mesh.hpp"

namespace ppohdem::fast {

/// A triangle ready for distance queries: vertex a, edges ab = b - a, ac = c - a (world units).
struct PreparedTriangle {
  Vec3 a, b, c;
  Vec3 ab, ac;
  double lo[3], hi[3];               ///< the triangle's own bounding box (a cheap lower bound)
  std::uint32_t original_index = 0;  ///< index in the input mesh
  std::uint8_t kind = 0;             ///< 0 regular, 1 thin (also test edges), 2 degenerate (edges only)
};

PreparedTriangle prepare_triangle(const Triangle& t, std::uint32_t original_index);

/// |p - closest point of t|^2 [m^2] (Ericson 5.1.5 with the degenerate/thin rules above).
double squared_distance(const Vec3& p, const PreparedTriangle& t);

class TriangleTree {
 public:
  static constexpr int kLeafSize = 4;  ///< triangles per leaf at most

  /// `coordinate_scale` [m]: the largest coordinate magnitude of the query points (e.g. the
  /// grid's corners), so the pruning slack also covers the rounding of far-away queries.
  explicit TriangleTree(const TriangleMesh& mesh, double coordinate_scale = 0.0);

  /// A BVH node, depth-first order (the root is 0).
  struct Node {
    double lo[3];
    double hi[3];
    std::uint32_t first = 0;   ///< leaf: first triangle; internal: index of the right child
    std::uint32_t count = 0;   ///< leaf: triangle count (> 0); internal: 0 (left child = this + 1)
  };
  /// Diagonal of a node's box [m] (how coarse a cluster of triangles it is).
  static double diagonal(const Node& n);

  struct Nearest {
    double squared_distance = std::numeric_limits<double>::infinity();
    std::uint32_t triangle = 0;  ///< index into triangles() (BVH order), valid if finite
  };
  /// Nearest triangle to p. `hint` (an index into triangles(), or -1) is evaluated first and
  /// only speeds the search up; the result does not depend on it.
  Nearest nearest(const Vec3& p, std::int64_t hint = -1) const;

  /// Appends to `out` the index (into triangles()) of every triangle whose own bounding box is
  /// within sqrt(bound_squared) of the box [lo, hi] (box-to-box distance, computed in double;
  /// callers add the slack). One traversal for a whole block of query points.
  void collect_near_box(const double lo[3], const double hi[3], double bound_squared,
                        std::vector<std::uint32_t>& out) const;

  /// Absolute slack [m] that covers the rounding of one computed point-triangle or box distance
  /// (1e-12 x the coordinate scale of the mesh and of the queries).
  double slack() const { return slack_; }

  /// Lowers `best` to the nearest triangle of the subtree rooted at `node` if one is nearer (the
  /// same conservative pruning as nearest()); `best` is the caller's running minimum.
  void refine_in_subtree(const Vec3& p, std::uint32_t node, Nearest& best) const;

  const std::vector<PreparedTriangle>& triangles() const { return triangles_; }
  const std::vector<Node>& nodes() const { return nodes_; }
  std::size_t node_count() const { return nodes_.size(); }
  std::size_t memory_bytes() const;

 private:
  std::uint32_t build(std::vector<std::uint32_t>& order, const std::vector<Vec3>& centroid,
                      const std::vector<Triangle>& input, std::uint32_t begin, std::uint32_t end);
  static double box_squared_distance(const double lo[3], const double hi[3], const Vec3& p);

  std::vector<Node> nodes_;
  std::vector<PreparedTriangle> triangles_;
  double slack_ = 0.0;  ///< absolute distance slack of the pruning [m]
};

}  // namespace ppohdem::fast
