#pragma once
/// \file brick_distance.hpp
/// Unsigned distances for a block ("brick") of grid nodes: exact, and (band mode) the
/// closest-triangle transfer outside a band.
///
/// Exact part (every node gets min_t |x - closest_point(x, t)|^2 over ALL triangles t, as
/// computed by squared_distance(), whatever the brick, thread or rank). Two interchangeable
/// ways, both tested to give the same field bit for bit:
///  - default: one BVH query per node (TriangleTree::nearest), started from the previous node's
///    nearest triangle (the first node from the brick centre's), conservative pruning;
///  - shared candidates (FastSdfOptions::shared_candidates): for a box of nodes with centre c
///    and half-diagonal r, and d(c) the exact distance at c, every point x of the box has
///    d(x) <= d(c) + |x - c| <= U = d(c) + r (Lipschitz, |grad d| <= 1). A triangle whose bounding
///    box is farther than U from the box cannot be the nearest of any node of the box, so the
///    candidates C(box) = {t : dist(box, bbox(t)) <= U} contain every node's nearest triangle.
///    They come from one BVH traversal per brick, as clusters (BVH nodes) no larger than 4 r;
///    the box is halved along each axis (8^3 -> 4^3 -> 2^3 nodes); a child's centre distance is
///    the minimum over the parent's candidates (exact, since the child centre lies in the parent
///    box) and its candidates are filtered out of the parent's; the nodes of a 2^3 box scan its
///    candidate triangles (vectorized bounding-box test, exact distance where it can win).
///    It takes MORE instructions per node than the per-node queries, because the candidate
///    shell of a box of half-diagonal r is ~2r thick, so it is not the default
///    (docs/performance.md "How the fast builder works").
///  Rounding: every bound carries the tree's slack (1e-12 x the coordinate scale, thousands of
///  times the rounding of one distance), so the pruning is conservative and the result is the
///  same minimum as a brute-force loop over all triangles.
///
/// Band part (band mode only, band_distance finite; the exact-part options above do not apply):
///  - a brick whose centre's exact distance satisfies d(c) - r > band (r its half-diagonal) has no
///    node with d <= band (Lipschitz): transfer only (below);
///  - other bricks: one BVH traversal collects the triangles whose bounding box is within
///    near = min(B, d(c) + r) of the brick (B the band plus slack); the brick is halved (8^3 ->
///    4^3 -> 2^3) and each half keeps those within ITS near (its d_S(c) the minimum over t_b and
///    its parent's candidates at its centre; a half with d_S(c) - r > band is transferred). A node
///    x has d(x) <= d_S(c) + r, and its nearest triangle's box is within d(x) of x, so a node
///    with d(x) <= band (or any node, where near = d_S(c) + r) finds its nearest triangle among
///    the candidates of its 2^3 box: the minimum over them (vectorized box test, exact distance
///    where it can win, warm-started from the previous node) is the minimum over ALL triangles,
///    bit for bit the exact mode's value (tested). Nodes found beyond the band also take t_b.
///    Cost (same results bit for bit): the halves' candidate lists come from ONE pass
///    over the parent's list (per-axis gaps to both halves, summed per half) with the gaps kept, so
///    the near filter and the half centre's search skip on them; a leaf's candidates are grouped
///    in buckets of increasing gap to the leaf box, and a node tests only the buckets whose
///    smallest gap is within its bound (its point-to-box gap is never below the box's).
///  Transfer (nodes beyond the band): S = the nearest triangles of the 27 brick centres around
///  (and including) the node's brick; for a 4^3 box with centre c, K = {t in S : dist(c, t) <=
///  min_S dist(c, .) + 2 r} (every triangle that can be S's minimum at a node of the box), and
///  each node gets the distance to ONE triangle: t_c, the nearest of K to the centre c' of the
///  node's box of at most kTransferLeaf^3 nodes. The value is the distance to a real triangle
///  (never below the truth) and at most d(x) + 2 r_b + r' above it (r_b the brick's
///  half-diagonal, r' the small box's; proof in brick_distance.cpp); measured errors in
///  docs/performance.md "Targets". For a box of at most kTransferLeaf^3 nodes t_c is found directly as the
///  nearest of S u {t_b} to c (every minimizer is in K; bounding-box pruning), and when the whole
///  box lies in one vertex's Voronoi region of t_c (decided with a margin) each node takes
///  |x - v|^2 as squared_distance() computes it; same values bit for bit. Everything depends only on the brick's global position: thread and
///  rank invariant as the exact part.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "ppohdem/grid/grid_spec.hpp"
#include "ppohdem/sdf/fast/nearest_triangle.hpp"

namespace ppohdem::sdf::fast {

/// A block of nodes: i in [lo[0], hi[0]), j in [lo[1], hi[1]), k in [lo[2], hi[2]) (global indices).
struct NodeBox {
  int lo[3] = {0, 0, 0};
  int hi[3] = {0, 0, 0};
  int extent(int a) const { return hi[a] - lo[a]; }
  std::size_t count() const {
    return static_cast<std::size_t>(extent(0)) * static_cast<std::size_t>(extent(1)) *
           static_cast<std::size_t>(extent(2));
  }
  bool empty() const { return extent(0) <= 0 || extent(1) <= 0 || extent(2) <= 0; }
  NodeBox intersect(const NodeBox& o) const;
};

/// Counters for profiling and the documentation (summed over bricks by the caller).
struct BrickCounters {
  std::size_t exact_nodes = 0;        ///< nodes given the exact minimum
  std::size_t transferred_nodes = 0;  ///< band mode: nodes given a transferred triangle's distance
  std::size_t candidate_tests = 0;    ///< bounding-box tests in the per-node scans
  std::size_t distance_evaluations = 0;  ///< exact point-triangle distances evaluated
};

class BrickDistance {
 public:
  /// Band mode: a leaf box's candidates are grouped in this many buckets of increasing gap.
  static constexpr int kLeafBuckets = 16;
  /// `band_distance` [m]: +infinity for exact everywhere, else the band half-width.
  /// `shared_candidates`: exact nodes by the shared-candidate scheme (true) or by one warm-started
  /// BVH query per node (false, the default: fewer instructions on the meshes measured).
  BrickDistance(const TriangleTree& tree, const GridSpec& grid, double band_distance, bool shared_candidates = false);

  /// Scratch space of one thread (reused between bricks: no allocation in the steady state).
  struct Workspace {
    struct Candidates {
      std::vector<std::uint32_t> index;  ///< BVH nodes (clusters of triangles), or triangles
      bool triangles = false;            ///< index holds triangles (into tree.triangles())
      std::vector<double> lo[3], hi[3];
      void clear();
      void push(std::uint32_t id, const double box_lo[3], const double box_hi[3]);
      std::size_t size() const { return index.size(); }
    };
    std::vector<Candidates> level;
    std::vector<double> box_d2;
    std::vector<std::uint32_t> transfer;
    std::vector<std::vector<std::uint32_t>> transfer_level;  ///< band mode: candidates per box level
    /// Band mode: the candidates of the (up to 8) halves of a box, with their box-to-box squared
    /// gaps, filled by one pass over the box's candidates (band_children()); one set per depth.
    struct ChildList {
      std::vector<std::uint32_t> index;
      std::vector<double> gap2;
      std::size_t size = 0;  ///< entries in use (the vectors only grow)
    };
    struct Children {
      ChildList list[8];
      NodeBox box[8];
      int count = 0;
    };
    std::vector<Children> children;  ///< band mode: per depth
    Candidates leaf;                       ///< band mode: a leaf box's candidates near its nodes
    std::vector<double> leaf_gap2;         ///< band mode: their squared gaps to the leaf box
    std::vector<std::uint8_t> leaf_bucket;  ///< band mode: each one's bucket (counting sort)
    std::size_t leaf_bucket_start[kLeafBuckets + 1] = {};  ///< band mode: bucket k is [start[k], start[k + 1])
    double leaf_bucket_min[kLeafBuckets] = {};  ///< band mode: smallest squared gap in bucket k
    std::vector<std::uint32_t> transfer_kept;  ///< band mode: the transferred set kept for a box
    std::uint32_t brick_triangle = 0;  ///< band mode: the brick centre's nearest triangle t_b
    double brick_d2 = 0.0;             ///< band mode: its squared distance to the brick centre
    NodeBox brick, clip;  ///< the brick being solved (offsets into d2) and the nodes to compute
    BrickCounters counters;
  };

  /// Squared distances of the nodes of `brick` that lie in `clip` into `d2`, indexed
  /// x fastest over the brick's own extents ((k - lo) ey + (j - lo)) ex + (i - lo); other
  /// entries are untouched. `centre` is the nearest triangle (exact) of the brick's centre,
  /// brick_centre(brick). `transfer`: band mode's triangles for boxes outside the band
  /// (ignored in exact mode).
  void solve(const NodeBox& brick, const NodeBox& clip, TriangleTree::Nearest centre,
             std::span<const std::uint32_t> transfer, Workspace& ws, double* d2) const;

  /// World position of the centre of a box of nodes [m].
  Vec3 box_centre(const NodeBox& box) const;

 private:
  void solve_box(const NodeBox& box, int depth, const Workspace::Candidates* parent, TriangleTree::Nearest centre,
                 Workspace& ws, double* d2) const;
  TriangleTree::Nearest scan(const Workspace::Candidates& c, const Vec3& p, std::uint32_t hint, Workspace& ws) const;
  TriangleTree::Nearest scan_buckets(const Workspace::Candidates& c, const Vec3& p, std::uint32_t hint,
                                     Workspace& ws) const;
  void transfer_box(const NodeBox& box, Workspace& ws, double* d2) const;
  void transfer_fill(const NodeBox& part, const PreparedTriangle& t, Workspace& ws, double* d2) const;
  void band_box(const NodeBox& box, int depth, Workspace::ChildList* own, Workspace& ws, double* d2) const;
  void band_children(const NodeBox& box, const std::uint32_t* index, std::size_t n, double bound2,
                     Workspace::Children& out) const;
  double half_diagonal(const NodeBox& box) const;

  const TriangleTree& tree_;
  GridSpec grid_;
  double band_ = 0.0;
  double slack_ = 0.0;
  bool shared_ = false;
};

}  // namespace ppohdem::sdf::fast
