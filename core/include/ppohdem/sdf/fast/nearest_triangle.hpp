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
/// stack keeps each box's distance so it is not recomputed when popped (docs/performance.md
/// "Cheaper queries"). The slack makes the
/// pruning conservative with respect to the rounding of the triangle distance, so the returned
/// squared distance is the minimum of the computed per-triangle values over ALL triangles,
/// whatever the starting guess: the result does not depend on the traversal order, on the hint,
/// on the thread or on the MPI rank (the basis of the bitwise invariance claims).
///
/// Oriented boxes (default; exact mode): the nodes of at most 1024 triangles are measured by an
/// oriented box instead of their axis-aligned one, in the frame of the triangles' area-weighted
/// mean normal and their principal directions across it (kept only where its volume is the
/// smaller). Around an oblique patch an axis-aligned box is as thick as it is wide, so a query
/// ball tangent to the surface met many leaves beside the nearest one; the oriented boxes of
/// nearly flat leaves are thin. Any orthonormal frame gives a valid bound, so no cone test is
/// needed; the box's extents are widened by the slack, which covers the rounding of the frame's
/// orthonormality and of the projections (see lower_bound_squared()). The query reads both
/// children's boxes from their parent (ChildPair, two SSE2 lanes). A query opens fewer than half
/// the leaves it opened with axis-aligned boxes, and the result is unchanged bit for bit
/// (docs/performance.md "Oriented boxes in the BVH"). Band mode builds the tree without them:
/// fitting them costs more than its few brick-centre queries gain.
///
/// Packets (exact mode): the brick's nodes are queried 2 x 2 rows at a time, one traversal per
/// packet of 4 nodes (nearest_packet()). A query is bound by latency (each visit waits for its
/// box distances and a branch on them); the 4 points' independent box distances of a visit (two
/// AVX passes for the children, one for a leaf's triangle boxes) overlap, and the branches are
/// shared; the field is unchanged bit for bit (docs/performance.md "Packets of grid nodes"; the
/// 4-wide nodes tried instead took fewer instructions but no less time: "Trials that were
/// dropped").
///
/// Lanes: one point per SIMD lane, 16 points (4 x 4 rows) per traversal in two AVX-512
/// registers, 4 in AVX (a 16-point packet then takes four traversals of 2 x 2). Both children's bounds of all
/// points are whole-register operations, the masks of the points within their bounds are register
/// compares, a pending node keeps one register of bounds (NaN where a point is not active), each
/// point's minimum, triangle and prune bound stay in its lane and are lowered by blends
/// (reloading them from memory stalled on the store), and the
/// distances to a regular triangle of 2 or more points within its box (1 or more in the 16-lane
/// packets) are computed in lanes
/// (Ericson's regions in the scalar order, each lane taking the first that holds). Every lane does
/// the scalar code's operations without FMA (nearest_triangle.cpp is compiled with
/// -ffp-contract=off), so the results are unchanged bit for bit (docs/performance.md, "Lanes of 8
/// grid nodes").
///
/// Split: with oriented boxes, a binned surface-area heuristic (32 bins; fewer leaves visited per
/// query, results unchanged bit for bit: docs/performance.md "Surface-area-heuristic split");
/// without (band mode), the median of the centroids along their longest extent, which is cheaper
/// to build. See kSahBins in nearest_triangle.cpp.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "ppohdem/geometry/vector.hpp"
#include "ppohdem/mesh/triangle_mesh.hpp"

namespace ppohdem::sdf::fast {

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
  /// `oriented_boxes`: fit oriented boxes to the lower levels (fewer boxes opened per query, a
  /// dearer build: worth it when every node of a grid is queried, not in band mode);
  /// without, the query measures the axis-aligned boxes. The results are the same either way.
  /// Constructed inside an OpenMP parallel region (by one thread), the large subtrees are built
  /// as tasks; the tree is the same node for node.
  explicit TriangleTree(const TriangleMesh& mesh, double coordinate_scale = 0.0, bool oriented_boxes = true);

  /// A BVH node, depth-first order (the root is 0).
  struct Node {
    double lo[3];
    double hi[3];
    std::uint32_t first = 0;   ///< leaf: first triangle; internal: index of the right child
    std::uint32_t count = 0;   ///< leaf: triangle count (> 0); internal: 0 (left child = this + 1)
  };
  /// The same node as the query measures it: an oriented box holding the node's triangles. For
  /// each row u of `axis`, lo <= u.x <= hi for every point x of them (widened by slack()); the
  /// rows are orthonormal to rounding: the area-weighted mean normal of the triangles and their
  /// principal directions across it, or x, y, z (then lo, hi = the node's axis-aligned box) where
  /// that box is smaller or the tree was built without oriented boxes. first, count as in Node.
  struct OrientedNode {
    double axis[3][3] = {{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}};
    double lo[3] = {0.0, 0.0, 0.0};
    double hi[3] = {0.0, 0.0, 0.0};
    std::uint32_t first = 0;
    std::uint32_t count = 0;
  };
  /// An internal node's two children's oriented boxes, interleaved [.][child] so the query
  /// measures both in one pass of 2-wide arithmetic (the same operations as lower_bound_squared()).
  struct alignas(16) ChildPair {
    double axis[3][3][2];
    double lo[3][2];
    double hi[3][2];
  };
  /// Lower bound of |p - x|^2 over the points x of a node's triangles (computed; exceeds the true
  /// minimum by far less than slack()): the squared distance to its oriented box.
  static double lower_bound_squared(const OrientedNode& n, const Vec3& p);
  /// Diagonal of a node's box [m] (how coarse a cluster of triangles it is).
  static double diagonal(const Node& n);

  struct Nearest {
    double squared_distance = std::numeric_limits<double>::infinity();
    std::uint32_t triangle = 0;  ///< index into triangles() (BVH order), valid if finite
  };
  /// Nearest triangle to p. `hint` (an index into triangles(), or -1) is evaluated first and
  /// only speeds the search up; the result does not depend on it.
  Nearest nearest(const Vec3& p, std::int64_t hint = -1) const;
  /// Points per packet of nearest_packet() at most.
  static constexpr int kPacket = 16;
  /// The instruction sets of nearest_packet(), widest first; `best`: the widest the CPU has.
  enum class PacketSimd { best, avx512, avx, sse2 };
  /// The widest of them this CPU runs (checked at run time), or narrower if PPOHDEM_SIMD says so
  /// (ppohdem/simd_level.hpp).
  static PacketSimd packet_simd_available();
  /// nearest(p[c], hint[c]) for c < count <= kPacket in one traversal of the tree: a node is
  /// opened while it is within the bound of one of the points still active in it, and each
  /// point's bounds, triangle tests and minimum are its own, so out[c] is nearest(p[c]) bit for
  /// bit. For neighbouring points (grid nodes) the paths nearly coincide; the points' box
  /// distances are independent arithmetic within one visit (one point per lane: 16 in two
  /// AVX-512 registers, 8 in one, 4 in AVX, so more points take several traversals; SSE2: 2
  /// lanes), and the branches are taken once per packet. `simd`: the widest instruction set to use (tests; the CPU's own limit applies too).
  void nearest_packet(const Vec3* p, const std::int64_t* hint, int count, Nearest* out,
                      PacketSimd simd = PacketSimd::best) const;

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
  /// Parallel to nodes(); empty for a tree built without oriented boxes.
  const std::vector<OrientedNode>& oriented_nodes() const { return oriented_; }
  std::size_t node_count() const { return nodes_.size(); }
  std::size_t memory_bytes() const;

 private:
  struct BuildInput;
  struct BuildOutput;
  std::uint32_t build(BuildInput& in, BuildOutput& out, std::uint32_t begin, std::uint32_t end, int depth);
  void reserve_nodes(BuildOutput& out, std::size_t triangles) const;
  void place(const BuildOutput& part);
  static double box_squared_distance(const double lo[3], const double hi[3], const Vec3& p);

  void fit_oriented_box(const std::vector<Triangle>& input, const std::vector<std::uint32_t>& order,
                        std::uint32_t begin, std::uint32_t end, std::uint32_t index, BuildOutput& out) const;

  std::vector<Node> nodes_;
  std::vector<OrientedNode> oriented_;  ///< parallel to nodes_ (if oriented)
  std::vector<ChildPair> pairs_;        ///< parallel to nodes_ (if oriented; leaves' unused): what the query reads
  bool oriented_boxes_ = true;
  std::vector<PreparedTriangle> triangles_;
  double slack_ = 0.0;  ///< absolute distance slack of the pruning [m]
};

}  // namespace ppohdem::sdf::fast
