/// \file nearest_triangle.cpp
/// Ericson's closest point on a triangle and a flat BVH built by a binned surface-area-heuristic
/// split. See nearest_triangle.hpp.
#include "ppohdem/sdf/fast/nearest_triangle.hpp"

#include "ppohdem/simd_level.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <type_traits>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(PPOHDEM_WITH_OPENMP)
#include <omp.h>
#endif
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define PPOHDEM_PACKET_AVX 1  // the AVX and AVX-512 packet traversals, chosen at run time
#endif

namespace ppohdem::sdf::fast {

namespace {

/// Nodes of at most this many triangles get an oriented box (larger ones: the axis-aligned box,
/// which is about as tight on curved clusters and saves build time).
constexpr std::uint32_t kOrientedMaxTriangles = 1024;

/// Split of a node's triangles: binned surface-area heuristic (Wald, "On fast construction of
/// SAH-based bounding volume hierarchies", IEEE Symposium on Interactive Ray Tracing 2007): the
/// centroids are binned along each axis over their extent (min(kSahBins, n) bins), and the split
/// between bins minimizing area(left) count(left) + area(right) count(right) (axis-aligned boxes of
/// the triangles) is taken. Its leaves send the queries to fewer neighbouring leaves than the
/// median split along the longest centroid extent, at a dearer build; the fields are unchanged
/// bit for bit. Only the trees with oriented boxes (exact mode) use it: in band mode, with few
/// queries, the median split's cheaper build wins (docs/performance.md "Surface-area-heuristic
/// split" and "Trials that were dropped").
constexpr int kSahBins = 32;
/// Nodes of at least this many triangles split into two OpenMP tasks (in a parallel region);
/// no task waits for its children, and each subtree's nodes are copied once, into the tree, at
/// the end (TriangleTree::place).
constexpr std::uint32_t kTaskMinTriangles = 4096;
// A task's node is still being split when its parent's oriented box is fitted: that fit must not
// read the triangles (it does not above kOrientedMaxTriangles).
static_assert(kTaskMinTriangles > kOrientedMaxTriangles);
/// Below this depth the split is the SAH's, deeper the median's (a bound on the tree's depth for
/// the traversals' fixed stacks of 128 entries: at most 48 + log2(n) levels).
constexpr int kSahMaxDepth = 48;

double segment_squared_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  // t = (p - a).(b - a) / |b - a|^2 clamped to [0, 1] (a == b: the point a).
  const Vec3 ab = b - a;
  const double length_squared = ab.squaredNorm();
  if (length_squared == 0.0) return (a - p).squaredNorm();
  const double t = std::clamp((p - a).dot(ab) / length_squared, 0.0, 1.0);
  return (a + t * ab - p).squaredNorm();
}

double edges_squared_distance(const Vec3& p, const PreparedTriangle& t) {
  return std::min({segment_squared_distance(p, t.a, t.b), segment_squared_distance(p, t.b, t.c),
                   segment_squared_distance(p, t.c, t.a)});
}

}  // namespace

PreparedTriangle prepare_triangle(const Triangle& tri, std::uint32_t original_index) {
  PreparedTriangle t;
  t.a = tri.v[0];
  t.b = tri.v[1];
  t.c = tri.v[2];
  t.ab = t.b - t.a;
  t.ac = t.c - t.a;
  t.original_index = original_index;
  for (int axis = 0; axis < 3; ++axis) {
    t.lo[axis] = std::min({t.a[axis], t.b[axis], t.c[axis]});
    t.hi[axis] = std::max({t.a[axis], t.b[axis], t.c[axis]});
  }
  // Same thresholds as the reference (reference/src/sdf/closest_point_triangle.cpp):
  // degenerate if sin(smallest angle) <~ 64 eps, thin if sin^2 < 1e-8.
  const double ab2 = t.ab.squaredNorm();
  const double ac2 = t.ac.squaredNorm();
  const double bc2 = (t.c - t.b).squaredNorm();
  const double longest2 = std::max({ab2, ac2, bc2});
  const double cross2 = t.ab.cross(t.ac).squaredNorm();
  if (longest2 == 0.0) {
    t.kind = 2;
  } else {
    const double two_shorter = ab2 * ac2 * bc2 / longest2;
    const double tolerance = 64.0 * std::numeric_limits<double>::epsilon();
    if (cross2 <= tolerance * tolerance * two_shorter) {
      t.kind = 2;
    } else if (cross2 < 1e-8 * two_shorter) {
      t.kind = 1;
    }
  }
  return t;
}

namespace {

/// squared_distance(), always inlined: in the packet traversals a call would also spill their
/// vector registers (the ABI preserves none of them across calls).
[[gnu::always_inline]] inline double triangle_squared_distance(const Vec3& p, const PreparedTriangle& t) {
  if (t.kind == 2) return edges_squared_distance(p, t);
  const Vec3& a = t.a;
  const Vec3& ab = t.ab;
  const Vec3& ac = t.ac;
  const Vec3 ap = p - a;
  const double d1 = ab.dot(ap);
  const double d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return ap.squaredNorm();  // vertex a
  const Vec3 bp = p - t.b;
  const double d3 = ab.dot(bp);
  const double d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return bp.squaredNorm();  // vertex b
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return (a + (d1 / (d1 - d3)) * ab - p).squaredNorm();  // edge ab
  const Vec3 cp = p - t.c;
  const double d5 = ab.dot(cp);
  const double d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return cp.squaredNorm();  // vertex c
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return (a + (d2 / (d2 - d6)) * ac - p).squaredNorm();  // edge ac
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {  // edge bc
    return (t.b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (t.c - t.b) - p).squaredNorm();
  }
  // Face: barycentric (1 - v - w, v, w), clamped (see the reference for why).
  const double sum = va + vb + vc;
  if (!(sum > 0.0)) return edges_squared_distance(p, t);
  const double v = std::clamp(vb / sum, 0.0, 1.0);
  const double w = std::clamp(vc / sum, 0.0, 1.0 - v);
  const double on_face = (a + v * ab + w * ac - p).squaredNorm();
  if (t.kind == 0) return on_face;
  return std::min(on_face, edges_squared_distance(p, t));
}

}  // namespace

double squared_distance(const Vec3& p, const PreparedTriangle& t) { return triangle_squared_distance(p, t); }

/// What build() reads and reorders: the triangles in input order, their centroids and bounding
/// boxes (lo x, y, z, hi x, y, z), the order being built and a scratch array of the same size.
struct TriangleTree::BuildInput {
  const std::vector<Triangle>& input;
  std::vector<Vec3> centroid;
  std::vector<std::array<double, 6>> box;
  std::vector<std::uint32_t> order;
  std::vector<std::uint32_t> scratch;
};

/// The nodes of a subtree in depth-first order, numbered from 0 (internal nodes' `first` is the
/// index of the right child within the subtree; leaves' `first` indexes BuildInput::order).
struct TriangleTree::BuildOutput {
  std::vector<Node> nodes;
  std::vector<OrientedNode> oriented;  ///< parallel to nodes (if oriented)
  /// A node split into tasks: its subtrees, each built into an output of its own (`nodes` then
  /// holds this node alone, its right child's index still to be set by place()).
  std::unique_ptr<BuildOutput> left, right;
};

TriangleTree::TriangleTree(const TriangleMesh& mesh, double coordinate_scale, bool oriented_boxes)
    : oriented_boxes_(oriented_boxes) {
  const std::size_t n = mesh.size();
  // The boxes and the scratch array serve the SAH split only (trees with oriented boxes).
  const std::size_t sah_n = oriented_boxes_ ? n : 0;
  BuildInput in{mesh.triangles, std::vector<Vec3>(n), std::vector<std::array<double, 6>>(sah_n),
                std::vector<std::uint32_t>(n), std::vector<std::uint32_t>(sah_n)};
  double scale = 0.0;
  for (std::size_t t = 0; t < n; ++t) {
    const auto& v = mesh.triangles[t].v;
    in.centroid[t] = (v[0] + v[1] + v[2]) / 3.0;
    in.order[t] = static_cast<std::uint32_t>(t);
    for (int a = 0; a < 3 && t < sah_n; ++a) {
      in.box[t][a] = std::min({v[0][a], v[1][a], v[2][a]});
      in.box[t][3 + a] = std::max({v[0][a], v[1][a], v[2][a]});
    }
    for (const Vec3& x : v) scale = std::max(scale, x.cwiseAbs().maxCoeff());
  }
  // Pruning slack: the closest-point arithmetic above works on coordinates of magnitude <= S and
  // makes absolute errors of a few tens of eps S; 1e-12 S (~4500 eps S) is far above that and
  // far below any grid spacing worth computing.
  // Query points far from the mesh round at their own scale: the larger of the two counts.
  slack_ = 1e-12 * std::max({scale, std::abs(coordinate_scale), 1e-300});
  BuildOutput out;
  reserve_nodes(out, n);
  // The group waits for every task of the build; its waiting thread may run any of them (a
  // task that waited for its own children would idle while the other thread builds:
  // docs/performance.md "The whole voxelize process").
#if defined(PPOHDEM_WITH_OPENMP)
#pragma omp taskgroup
#endif
  {
    if (n > 0) build(in, out, 0, static_cast<std::uint32_t>(n), 0);
  }
  // The nodes placed (and their child pairs' storage sized) in one task, beside the triangles in
  // tree order (tasks run in order outside a parallel region).
#if defined(PPOHDEM_WITH_OPENMP)
#pragma omp task default(shared)
#endif
  {
    if (out.left) {  // built in tasks: the parts in depth-first order
      nodes_.reserve(2 * n);
      if (oriented_boxes_) oriented_.reserve(2 * n);
      place(out);
    } else {
      nodes_ = std::move(out.nodes);
      oriented_ = std::move(out.oriented);
    }
    if (oriented_boxes_) pairs_.resize(nodes_.size());
  }
  triangles_.resize(n);
#if defined(PPOHDEM_WITH_OPENMP)
#pragma omp taskloop grainsize(8192) default(shared)
#endif
  for (std::size_t s = 0; s < n; ++s) {
    const std::uint32_t t = in.order[s];
    triangles_[s] = prepare_triangle(mesh.triangles[t], t);
  }
#if defined(PPOHDEM_WITH_OPENMP)
#pragma omp taskwait
#endif
  if (!oriented_boxes_) return;
  const std::size_t node_count = nodes_.size();
#if defined(PPOHDEM_WITH_OPENMP)
#pragma omp taskloop grainsize(8192) default(shared)
#endif
  for (std::size_t i = 0; i < node_count; ++i) {
    if (nodes_[i].count > 0) continue;
    const OrientedNode* child[2] = {&oriented_[i + 1], &oriented_[nodes_[i].first]};
    for (int c = 0; c < 2; ++c) {
      for (int r = 0; r < 3; ++r) {
        for (int a = 0; a < 3; ++a) pairs_[i].axis[r][a][c] = child[c]->axis[r][a];
        pairs_[i].lo[r][c] = child[c]->lo[r];
        pairs_[i].hi[r][c] = child[c]->hi[r];
      }
    }
  }
}

namespace {

/// Median split of order[begin, end) by the centroids' coordinate `axis`; returns the middle.
std::uint32_t median_split(std::vector<std::uint32_t>& order, const std::vector<Vec3>& centroid, std::uint32_t begin,
                           std::uint32_t end, int axis) {
  const std::uint32_t middle = begin + (end - begin) / 2;
  std::nth_element(order.begin() + begin, order.begin() + middle, order.begin() + end,
                   [&](std::uint32_t s, std::uint32_t t) {
                     if (centroid[s][axis] != centroid[t][axis]) return centroid[s][axis] < centroid[t][axis];
                     return s < t;  // total order: the tree does not depend on the library's algorithm
                   });
  return middle;
}

struct SahBin {
  double lo[3], hi[3];
  std::uint32_t count;
};

/// Binned SAH split of order[begin, end) (see kSahBins); [clo, chi]: the centroids' box. Returns
/// the middle, order[begin, end) stably partitioned (left bins first), or `begin` if every axis
/// has a zero centroid extent.
std::uint32_t sah_split(std::vector<std::uint32_t>& order, std::vector<std::uint32_t>& scratch,
                        const std::vector<Vec3>& centroid, const std::vector<std::array<double, 6>>& box,
                        std::uint32_t begin, std::uint32_t end, const Vec3& clo, const Vec3& chi) {
  const int bins = static_cast<int>(std::min<std::uint32_t>(kSahBins, end - begin));
  const double inf = std::numeric_limits<double>::infinity();
  SahBin bin[3][kSahBins];
  double scale[3];
  for (int a = 0; a < 3; ++a) {
    const double extent = chi[a] - clo[a];
    scale[a] = extent > 0.0 && std::isfinite(bins / extent) ? bins / extent : 0.0;  // 0: not split on a
    for (int b = 0; b < bins; ++b) bin[a][b] = {{inf, inf, inf}, {-inf, -inf, -inf}, 0};
  }
  // The extreme centroids fall in the first and last bins (index in [0, bins], clamped), so every
  // split between bins has both sides non-empty.
  const auto bin_of = [&](double c, int a) { return std::min(static_cast<int>((c - clo[a]) * scale[a]), bins - 1); };
  for (std::uint32_t s = begin; s < end; ++s) {
    const std::uint32_t t = order[s];
    const std::array<double, 6>& bx = box[t];
    for (int a = 0; a < 3; ++a) {
      SahBin& b = bin[a][bin_of(centroid[t][a], a)];
      for (int k = 0; k < 3; ++k) b.lo[k] = std::min(b.lo[k], bx[k]), b.hi[k] = std::max(b.hi[k], bx[3 + k]);
      b.count += 1;
    }
  }
  const auto area = [](const double lo[3], const double hi[3]) {
    const double dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
    return dx * dy + dy * dz + dz * dx;
  };
  double best_cost = inf;
  int best_axis = -1, best_bin = -1;
  double right_cost[kSahBins];  // right_cost[b]: bins b .. bins - 1
  for (int a = 0; a < 3; ++a) {
    if (!(scale[a] > 0.0)) continue;
    double lo[3] = {inf, inf, inf}, hi[3] = {-inf, -inf, -inf};
    std::uint32_t count = 0;
    for (int b = bins - 1; b > 0; --b) {
      const SahBin& x = bin[a][b];
      for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], x.lo[k]), hi[k] = std::max(hi[k], x.hi[k]);
      count += x.count;
      right_cost[b] = count > 0 ? area(lo, hi) * count : inf;
    }
    for (int k = 0; k < 3; ++k) lo[k] = inf, hi[k] = -inf;
    count = 0;
    for (int b = 0; b + 1 < bins; ++b) {
      const SahBin& x = bin[a][b];
      for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], x.lo[k]), hi[k] = std::max(hi[k], x.hi[k]);
      count += x.count;
      if (count == 0) continue;
      const double cost = area(lo, hi) * count + right_cost[b + 1];
      if (cost < best_cost) best_cost = cost, best_axis = a, best_bin = b;  // first minimum: x, y, z, left to right
    }
  }
  if (best_axis < 0) return begin;
  // Stable partition written out (the tree does not depend on the library's algorithm).
  // scratch[begin, end) only: subtrees built at the same time use disjoint ranges.
  std::uint32_t left = begin;
  std::uint32_t right = begin;
  for (std::uint32_t s = begin; s < end; ++s) {
    const std::uint32_t t = order[s];
    if (bin_of(centroid[t][best_axis], best_axis) <= best_bin) {
      order[left++] = t;
    } else {
      scratch[right++] = t;
    }
  }
  std::copy(scratch.begin() + begin, scratch.begin() + right, order.begin() + left);
  return left;
}

}  // namespace

std::uint32_t TriangleTree::build(BuildInput& in, BuildOutput& out, std::uint32_t begin, std::uint32_t end,
                                  int depth) {
  const std::vector<std::uint32_t>& order = in.order;
  const std::vector<Vec3>& centroid = in.centroid;
  const std::vector<Triangle>& input = in.input;
  const auto index = static_cast<std::uint32_t>(out.nodes.size());
  out.nodes.emplace_back();
  if (oriented_boxes_) out.oriented.emplace_back();
  Node node;
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = -lo;
  Vec3 clo = lo, chi = hi;
  for (std::uint32_t s = begin; s < end; ++s) {
    if (!in.box.empty()) {  // the triangles' boxes: the same bounds, fewer operations
      const std::array<double, 6>& bx = in.box[order[s]];
      lo = lo.cwiseMin(Vec3(bx[0], bx[1], bx[2]));
      hi = hi.cwiseMax(Vec3(bx[3], bx[4], bx[5]));
    } else {
      for (const Vec3& v : input[order[s]].v) {
        lo = lo.cwiseMin(v);
        hi = hi.cwiseMax(v);
      }
    }
    clo = clo.cwiseMin(centroid[order[s]]);
    chi = chi.cwiseMax(centroid[order[s]]);
  }
  for (int a = 0; a < 3; ++a) {
    node.lo[a] = lo[a];
    node.hi[a] = hi[a];
  }
  if (end - begin <= static_cast<std::uint32_t>(kLeafSize)) {
    node.first = begin;
    node.count = end - begin;
    out.nodes[index] = node;
    fit_oriented_box(input, order, begin, end, index, out);
    return index;
  }
  // SAH split (kSahBins); the median split along the longest centroid extent where the SAH has
  // none (all centroids equal), where the tree is already kSahMaxDepth deep, and in a tree without
  // oriented boxes (band mode: the SAH's binning costs more than its few queries gain).
  const bool sah = oriented_boxes_ && depth < kSahMaxDepth;
  std::uint32_t middle = sah ? sah_split(in.order, in.scratch, centroid, in.box, begin, end, clo, chi) : begin;
  if (middle == begin) {
    int axis = 0;
    const Vec3 extent = chi - clo;
    if (extent.y() > extent[axis]) axis = 1;
    if (extent.z() > extent[axis]) axis = 2;
    middle = median_split(in.order, centroid, begin, end, axis);
  }
  bool as_tasks = false;
#if defined(PPOHDEM_WITH_OPENMP)
  // (A node this large is the first of its output: its parent, as large, split into tasks too.)
  as_tasks = end - begin >= kTaskMinTriangles && omp_in_parallel() && index == 0;
#endif
  if (as_tasks) {
    // The left subtree as a task, the right one here, each into its own output, and no wait:
    // place() puts them in depth-first order, so the tree is the one the serial build makes.
    out.left = std::make_unique<BuildOutput>();
    out.right = std::make_unique<BuildOutput>();
    reserve_nodes(*out.left, middle - begin);
    reserve_nodes(*out.right, end - middle);
    BuildInput* const input_of_task = &in;
    BuildOutput* const left = out.left.get();
#if defined(PPOHDEM_WITH_OPENMP)
#pragma omp task default(shared) firstprivate(input_of_task, left, begin, middle, depth)
#endif
    build(*input_of_task, *left, begin, middle, depth + 1);
    build(in, *out.right, middle, end, depth + 1);
    node.first = 0;  // the right child: set by place()
  } else {
    build(in, out, begin, middle, depth + 1);
    node.first = build(in, out, middle, end, depth + 1);
  }
  node.count = 0;
  out.nodes[index] = node;
  fit_oriented_box(input, order, begin, end, index, out);
  return index;
}

void TriangleTree::reserve_nodes(BuildOutput& out, std::size_t triangles) const {
  // At most 2 n - 1 nodes (leaves of 1 to kLeafSize triangles): the vectors never grow, so no
  // node is copied and no freed block was first touched for nothing (fresh pages are dear:
  // docs/performance.md "The whole voxelize process"); the capacity beyond the nodes is never
  // touched, so it costs address space only.
  out.nodes.reserve(2 * triangles);
  if (oriented_boxes_) out.oriented.reserve(2 * triangles);
}

void TriangleTree::place(const BuildOutput& part) {
  const auto offset = static_cast<std::uint32_t>(nodes_.size());
  if (part.left) {  // one node, then its subtrees; its right child follows the left subtree
    nodes_.push_back(part.nodes[0]);
    if (oriented_boxes_) oriented_.push_back(part.oriented[0]);
    place(*part.left);
    nodes_[offset].first = static_cast<std::uint32_t>(nodes_.size());
    if (oriented_boxes_) oriented_[offset].first = nodes_[offset].first;
    place(*part.right);
    return;
  }
  for (Node n : part.nodes) {
    if (n.count == 0) n.first += offset;  // an internal node's right child
    nodes_.push_back(n);
  }
  for (OrientedNode n : part.oriented) {
    if (n.count == 0) n.first += offset;
    oriented_.push_back(n);
  }
}

void TriangleTree::fit_oriented_box(const std::vector<Triangle>& input, const std::vector<std::uint32_t>& order,
                                    std::uint32_t begin, std::uint32_t end, std::uint32_t index,
                                    BuildOutput& output) const {
  if (!oriented_boxes_) return;
  const Node& node = output.nodes[index];
  OrientedNode& out = output.oriented[index];
  out.first = node.first;
  out.count = node.count;
  // Default: the identity frame, whose box is the axis-aligned one (then the query's bound is
  // bit for bit the former point-to-box distance).
  std::copy(node.lo, node.lo + 3, out.lo);
  std::copy(node.hi, node.hi + 3, out.hi);
  if (end - begin > kOrientedMaxTriangles) return;
  // Any orthonormal frame gives a valid bound; the mean normal's frame gives a thin box where the
  // triangles are nearly coplanar, whatever their slope (an axis-aligned box around an oblique
  // patch is as thick as it is wide, so a query ball tangent to the surface meets many of them).
  // The slack covers the rounding of u.x here, of u.p in the query and of the frame's
  // orthonormality (see node_lower_bound()).
  Vec3 normal = Vec3::Zero();
  for (std::uint32_t s = begin; s < end; ++s) {
    const auto& v = input[order[s]].v;
    normal += (v[1] - v[0]).cross(v[2] - v[0]);
  }
  const double length = normal.norm();
  if (!(length > 0.0) || !std::isfinite(length)) return;
  const Vec3 n = normal / length;
  int across = 0;  // the coordinate axis most across n, projected onto n's plane
  if (std::abs(n.y()) < std::abs(n[across])) across = 1;
  if (std::abs(n.z()) < std::abs(n[across])) across = 2;
  const Vec3 u = (Vec3::Unit(across) - n[across] * n).normalized();
  const Vec3 w = n.cross(u);
  // Across n, the principal directions of the vertices (a tighter box for elongated clusters).
  const Vec3 origin(node.lo[0], node.lo[1], node.lo[2]);
  double suu = 0.0, suw = 0.0, sww = 0.0, su = 0.0, sw = 0.0, count = 0.0;
  for (std::uint32_t s = begin; s < end; ++s) {
    for (const Vec3& v : input[order[s]].v) {
      const double x = u.dot(v - origin), y = w.dot(v - origin);
      suu += x * x, suw += x * y, sww += y * y, su += x, sw += y, count += 1.0;
    }
  }
  const double cuu = suu - su * su / count, cuw = suw - su * sw / count, cww = sww - sw * sw / count;
  const double angle = 0.5 * std::atan2(2.0 * cuw, cuu - cww);
  const Vec3 e1 = (std::cos(angle) * u + std::sin(angle) * w).normalized();
  const std::array<Vec3, 3> frame = {n, e1, n.cross(e1)};
  double flo[3], fhi[3];
  for (int r = 0; r < 3; ++r) {
    flo[r] = std::numeric_limits<double>::infinity();
    fhi[r] = -flo[r];
  }
  for (std::uint32_t s = begin; s < end; ++s) {
    for (const Vec3& v : input[order[s]].v) {
      for (int r = 0; r < 3; ++r) {
        const double x = frame[r].dot(v);
        flo[r] = std::min(flo[r], x);
        fhi[r] = std::max(fhi[r], x);
      }
    }
  }
  const double volume = (node.hi[0] - node.lo[0]) * (node.hi[1] - node.lo[1]) * (node.hi[2] - node.lo[2]);
  if (!((fhi[0] - flo[0]) * (fhi[1] - flo[1]) * (fhi[2] - flo[2]) < volume)) return;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out.axis[r][c] = frame[r][c];
    out.lo[r] = flo[r] - slack_;
    out.hi[r] = fhi[r] + slack_;
  }
}

namespace {

/// |p - box|^2, the same value as the former loop (max of three, then (x^2 + y^2) + z^2); always
/// inlined, because GCC 12 kept box_squared_distance() with an initializer-list max out of line,
/// in the hottest loop of the queries (docs/performance.md "Band mode, second pass").
[[gnu::always_inline]] inline double point_box_squared(const double lo[3], const double hi[3], double px, double py,
                                                       double pz) {
  const double dx = std::max(std::max(lo[0] - px, px - hi[0]), 0.0);
  const double dy = std::max(std::max(lo[1] - py, py - hi[1]), 0.0);
  const double dz = std::max(std::max(lo[2] - pz, pz - hi[2]), 0.0);
  return dx * dx + dy * dy + dz * dz;
}

/// TriangleTree::lower_bound_squared(), inlined in the traversal: sum over the frame's rows u of g^2,
/// g = max(u.p - hi, lo - u.p, 0) <= |u.(p - x)| for every x of the node's triangles, and
/// sum (u.(p - x))^2 = |p - x|^2 for an orthonormal frame. The frame is orthonormal to a few eps
/// and u.p rounds at a few eps |p|: errors of order eps S, which the slack (1e-12 S) widening
/// [lo, hi] exceeds by orders of magnitude, so the bound stays below the true distance.
[[gnu::always_inline]] inline double node_lower_bound(const TriangleTree::OrientedNode& n, double px, double py,
                                                      double pz) {
  double sum = 0.0;
  for (int r = 0; r < 3; ++r) {
    const double s = n.axis[r][0] * px + n.axis[r][1] * py + n.axis[r][2] * pz;
    const double g = std::max(std::max(s - n.hi[r], n.lo[r] - s), 0.0);
    sum += g * g;
  }
  return sum;
}

}  // namespace

double TriangleTree::lower_bound_squared(const OrientedNode& n, const Vec3& p) {
  return node_lower_bound(n, p.x(), p.y(), p.z());
}

double TriangleTree::box_squared_distance(const double lo[3], const double hi[3], const Vec3& p) {
  return point_box_squared(lo, hi, p.x(), p.y(), p.z());
}
double TriangleTree::diagonal(const Node& n) {
  const double dx = n.hi[0] - n.lo[0], dy = n.hi[1] - n.lo[1], dz = n.hi[2] - n.lo[2];
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

TriangleTree::Nearest TriangleTree::nearest(const Vec3& p, std::int64_t hint) const {
  Nearest best;
  if (nodes_.empty()) return best;
  if (hint >= 0) {
    const auto t = static_cast<std::uint32_t>(hint);
    best.squared_distance = squared_distance(p, triangles_[t]);
    best.triangle = t;
  }
  refine_in_subtree(p, 0, best);
  return best;
}

namespace {

[[gnu::always_inline]] inline double node_lower_bound(const TriangleTree::Node& n, double px, double py, double pz) {
  return point_box_squared(n.lo, n.hi, px, py, pz);
}

/// Both children's bounds from an internal node's ChildPair: node_lower_bound() of each, the same
/// operations in the same order (SSE2 without FMA rounds each lane as the scalar code does).
[[gnu::always_inline]] inline void child_bounds(const TriangleTree::ChildPair& c, double px, double py, double pz,
                                                double& left, double& right) {
#if defined(__SSE2__)
  const __m128d x = _mm_set1_pd(px), y = _mm_set1_pd(py), z = _mm_set1_pd(pz), zero = _mm_setzero_pd();
  __m128d sum = zero;
  for (int r = 0; r < 3; ++r) {
    const __m128d ux = _mm_mul_pd(_mm_load_pd(c.axis[r][0]), x);
    const __m128d uy = _mm_mul_pd(_mm_load_pd(c.axis[r][1]), y);
    const __m128d uz = _mm_mul_pd(_mm_load_pd(c.axis[r][2]), z);
    const __m128d s = _mm_add_pd(_mm_add_pd(ux, uy), uz);
    const __m128d above = _mm_sub_pd(s, _mm_load_pd(c.hi[r]));
    const __m128d below = _mm_sub_pd(_mm_load_pd(c.lo[r]), s);
    const __m128d g = _mm_max_pd(_mm_max_pd(above, below), zero);
    sum = _mm_add_pd(sum, _mm_mul_pd(g, g));
  }
  left = _mm_cvtsd_f64(sum);
  right = _mm_cvtsd_f64(_mm_unpackhi_pd(sum, sum));
#else
  double d[2];
  for (int k = 0; k < 2; ++k) {
    double sum = 0.0;
    for (int r = 0; r < 3; ++r) {
      const double s = c.axis[r][0][k] * px + c.axis[r][1][k] * py + c.axis[r][2][k] * pz;
      const double g = std::max(std::max(s - c.hi[r][k], c.lo[r][k] - s), 0.0);
      sum += g * g;
    }
    d[k] = sum;
  }
  left = d[0];
  right = d[1];
#endif
}

/// refine_in_subtree() over either node array (the same pruning rule; only the bound differs).
/// `pairs`: the children's bounds of an oriented tree, or nullptr (NodeT = Node: its boxes).
template <class NodeT>
void refine_nodes(const NodeT* nodes, const TriangleTree::ChildPair* pairs,
                  const std::vector<PreparedTriangle>& triangles, double slack, const Vec3& p, std::uint32_t root,
                  TriangleTree::Nearest& best) {
  // prune_bound = (sqrt(best) + slack)^2: boxes farther than that cannot hold a triangle whose
  // computed distance is <= best (see the header).
  double prune_bound = std::numeric_limits<double>::infinity();
  auto improve = [&](double d2, std::uint32_t t) {
    if (d2 < best.squared_distance || (d2 == best.squared_distance && t < best.triangle)) {
      best.squared_distance = d2;
      best.triangle = t;
      const double r = std::sqrt(d2) + slack;
      prune_bound = r * r;
    }
  };
  if (std::isfinite(best.squared_distance)) {
    const double r = std::sqrt(best.squared_distance) + slack;
    prune_bound = r * r;
  }
  struct Pending {
    std::uint32_t node;
    double box_squared_distance;  // kept so a popped box is not measured twice
  };
  Pending stack[128];
  int top = 0;
  std::uint32_t current = root;
  const double px = p.x(), py = p.y(), pz = p.z();
  if (node_lower_bound(nodes[root], px, py, pz) > prune_bound) return;
  for (;;) {
    const NodeT& node = nodes[current];
    if (node.count > 0) {
      for (std::uint32_t s = node.first; s < node.first + node.count; ++s) {
        const PreparedTriangle& t = triangles[s];
        if (point_box_squared(t.lo, t.hi, px, py, pz) > prune_bound) continue;  // cannot beat the bound
        improve(squared_distance(p, t), s);
      }
    } else {
      const std::uint32_t left = current + 1;
      const std::uint32_t right = node.first;
      double dl, dr;
      if constexpr (std::is_same_v<NodeT, TriangleTree::OrientedNode>) {
        child_bounds(pairs[current], px, py, pz, dl, dr);
      } else {
        dl = node_lower_bound(nodes[left], px, py, pz);
        dr = node_lower_bound(nodes[right], px, py, pz);
      }
      const bool left_first = dl <= dr;
      const std::uint32_t near = left_first ? left : right;
      const std::uint32_t far = left_first ? right : left;
      const double dnear = left_first ? dl : dr;
      const double dfar = left_first ? dr : dl;
      if (dnear <= prune_bound) {
        if (dfar <= prune_bound) stack[top++] = {far, dfar};
        current = near;
        continue;
      }
    }
    // Pop the next box still worth visiting (the bound may have shrunk since it was pushed).
    bool found = false;
    while (top > 0) {
      const Pending candidate = stack[--top];
      if (candidate.box_squared_distance <= prune_bound) {
        current = candidate.node;
        found = true;
        break;
      }
    }
    if (!found) break;
  }
}

/// The children's bounds of K points: each point's child_bounds() (SSE2 or scalar).
template <int K>
struct PacketBounds {
  [[gnu::always_inline]] static inline void get(const TriangleTree::ChildPair& pair, const double* px,
                                                const double* py, const double* pz, double* dl, double* dr) {
    for (int c = 0; c < K; ++c) child_bounds(pair, px[c], py[c], pz[c], dl[c], dr[c]);
  }
  /// Bit c: point c's distance to the triangle's box is <= prune[c].
  [[gnu::always_inline]] static inline unsigned near_box(const PreparedTriangle& t, const double* px,
                                                         const double* py, const double* pz, const double* prune) {
    unsigned mask = 0;
    for (int c = 0; c < K; ++c) {
      mask |= static_cast<unsigned>(point_box_squared(t.lo, t.hi, px[c], py[c], pz[c]) <= prune[c]) << c;
    }
    return mask;
  }
};

/// nearest_packet() over the oriented tree for K points: refine_nodes()'s pruning and tie rule
/// per point, with a mask of the points still active in the subtree (a point whose bound of a
/// node exceeds its prune bound needs nothing below it: the node's box holds all the subtree's
/// triangles, and its prune bound only shrinks). A node is opened while one point is active in
/// it; a triangle is measured for each active point its box does not exclude. So each point's
/// result is the minimum of its computed distances over all triangles, as refine_nodes()'s.
template <int K, class Bounds = PacketBounds<K>>
inline void refine_packet(const TriangleTree::OrientedNode* nodes, const TriangleTree::ChildPair* pairs,
                          const std::vector<PreparedTriangle>& triangles, double slack, const Vec3* p,
                          TriangleTree::Nearest* best) {
  double prune_bound[K];
  double px[K], py[K], pz[K];
  for (int c = 0; c < K; ++c) {
    prune_bound[c] = std::numeric_limits<double>::infinity();
    if (std::isfinite(best[c].squared_distance)) {
      const double r = std::sqrt(best[c].squared_distance) + slack;
      prune_bound[c] = r * r;
    }
    px[c] = p[c].x(), py[c] = p[c].y(), pz[c] = p[c].z();
  }
  struct Pending {
    std::uint32_t node;
    unsigned active;
    double bound[K];  // the node's bound for each active point
  };
  Pending stack[128];
  int top = 0;
  std::uint32_t current = 0;
  unsigned active = 0;
  for (int c = 0; c < K; ++c) {
    active |= static_cast<unsigned>(node_lower_bound(nodes[0], px[c], py[c], pz[c]) <= prune_bound[c]) << c;
  }
  if (active == 0) return;
  for (;;) {
    const TriangleTree::OrientedNode& node = nodes[current];
    if (node.count > 0) {
      for (std::uint32_t s = node.first; s < node.first + node.count; ++s) {
        const PreparedTriangle& t = triangles[s];
        // The points whose own bound the triangle's box does not exceed (each point's bound
        // changes only by its own distances, measured after its test).
        for (unsigned near = Bounds::near_box(t, px, py, pz, prune_bound) & active; near != 0; near &= near - 1) {
          const int c = __builtin_ctz(near);
          const double d2 = squared_distance(p[c], t);
          if (d2 < best[c].squared_distance || (d2 == best[c].squared_distance && s < best[c].triangle)) {
            best[c].squared_distance = d2;
            best[c].triangle = s;
            const double r = std::sqrt(d2) + slack;
            prune_bound[c] = r * r;
          }
        }
      }
    } else {
      const std::uint32_t left = current + 1;
      const std::uint32_t right = node.first;
      double dl[K], dr[K];
      unsigned in_left = 0, in_right = 0;
      double sum_left = 0.0, sum_right = 0.0;  // only orders the children (nearer on average first)
      Bounds::get(pairs[current], px, py, pz, dl, dr);
      for (int c = 0; c < K; ++c) {
        const unsigned on = (active >> c) & 1u;
        in_left |= (on & static_cast<unsigned>(dl[c] <= prune_bound[c])) << c;
        in_right |= (on & static_cast<unsigned>(dr[c] <= prune_bound[c])) << c;
        sum_left += on ? dl[c] : 0.0;
        sum_right += on ? dr[c] : 0.0;
      }
      if ((in_left | in_right) != 0) {
        const bool left_first = in_right == 0 || (in_left != 0 && sum_left <= sum_right);
        if (left_first) {
          if (in_right != 0) {
            Pending& e = stack[top++];
            e.node = right, e.active = in_right;
            for (int c = 0; c < K; ++c) e.bound[c] = dr[c];
          }
          current = left, active = in_left;
        } else {
          if (in_left != 0) {
            Pending& e = stack[top++];
            e.node = left, e.active = in_left;
            for (int c = 0; c < K; ++c) e.bound[c] = dl[c];
          }
          current = right, active = in_right;
        }
        continue;
      }
    }
    // Pop the next box still within the bound of one of its points.
    bool found = false;
    while (top > 0) {
      const Pending& candidate = stack[--top];
      unsigned still = 0;
      for (int c = 0; c < K; ++c) still |= static_cast<unsigned>(candidate.bound[c] <= prune_bound[c]) << c;
      still &= candidate.active;
      if (still != 0) {
        current = candidate.node;
        active = still;
        found = true;
        break;
      }
    }
    if (!found) break;
  }
}

#if defined(PPOHDEM_PACKET_AVX)
/// The lanes of refine_lanes(): one point per lane, 4 points in AVX registers. Masks are lanes of
/// all ones (compare results); bits() gives them as an integer, bit c = point c.
struct LanesAvx {
  static constexpr int kWidth = 4;
  using V = __m256d;
  using M = __m256d;
  __attribute__((target("avx"))) static inline V set1(double x) { return _mm256_set1_pd(x); }
  __attribute__((target("avx"))) static inline V load(const double* x) { return _mm256_loadu_pd(x); }
  __attribute__((target("avx"))) static inline void store(double* x, V v) { _mm256_storeu_pd(x, v); }
  __attribute__((target("avx"))) static inline V zero() { return _mm256_setzero_pd(); }
  __attribute__((target("avx"))) static inline V add(V a, V b) { return _mm256_add_pd(a, b); }
  __attribute__((target("avx"))) static inline V sub(V a, V b) { return _mm256_sub_pd(a, b); }
  __attribute__((target("avx"))) static inline V mul(V a, V b) { return _mm256_mul_pd(a, b); }
  __attribute__((target("avx"))) static inline V max(V a, V b) { return _mm256_max_pd(a, b); }
  __attribute__((target("avx"))) static inline M le(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_LE_OQ); }
  __attribute__((target("avx"))) static inline M both(M a, M b) { return _mm256_and_pd(a, b); }
  __attribute__((target("avx"))) static inline V div(V a, V b) { return _mm256_div_pd(a, b); }
  __attribute__((target("avx"))) static inline M lt(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_LT_OQ); }
  __attribute__((target("avx"))) static inline M eq(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_EQ_OQ); }
  __attribute__((target("avx"))) static inline V sqrt(V a) { return _mm256_sqrt_pd(a); }
  __attribute__((target("avx"))) static inline M either(M a, M b) { return _mm256_or_pd(a, b); }
  /// a and not b.
  __attribute__((target("avx"))) static inline M but(M a, M b) { return _mm256_andnot_pd(b, a); }
  __attribute__((target("avx"))) static inline unsigned bits(M m) {
    return static_cast<unsigned>(_mm256_movemask_pd(m));
  }
  /// m ? a : b per lane.
  __attribute__((target("avx"))) static inline V select(M m, V a, V b) { return _mm256_blendv_pd(b, a, m); }
  /// v with lane c set to x (a blend: reloading v from memory after a scalar store waits for the
  /// store to be forwarded, which a wide load spanning several stores cannot be).
  __attribute__((target("avx"))) static inline V set_lane(V v, int c, double x) {
    alignas(32) static constexpr std::int64_t kLane[4][4] = {
        {-1, 0, 0, 0}, {0, -1, 0, 0}, {0, 0, -1, 0}, {0, 0, 0, -1}};
    return _mm256_blendv_pd(v, _mm256_set1_pd(x), _mm256_load_pd(reinterpret_cast<const double*>(kLane[c])));
  }
};

/// The same for 8 points in AVX-512 registers; masks are mask registers.
struct LanesAvx512 {
  static constexpr int kWidth = 8;
  using V = __m512d;
  using M = __mmask8;
  __attribute__((target("avx512f"))) static inline V set1(double x) { return _mm512_set1_pd(x); }
  __attribute__((target("avx512f"))) static inline V load(const double* x) { return _mm512_loadu_pd(x); }
  __attribute__((target("avx512f"))) static inline void store(double* x, V v) { _mm512_storeu_pd(x, v); }
  __attribute__((target("avx512f"))) static inline V zero() { return _mm512_setzero_pd(); }
  __attribute__((target("avx512f"))) static inline V add(V a, V b) { return _mm512_add_pd(a, b); }
  __attribute__((target("avx512f"))) static inline V sub(V a, V b) { return _mm512_sub_pd(a, b); }
  __attribute__((target("avx512f"))) static inline V mul(V a, V b) { return _mm512_mul_pd(a, b); }
  // maskz_ forms with every lane: GCC 12's plain forms read an undefined register (a false
  // -Wmaybe-uninitialized); the results are the same.
  __attribute__((target("avx512f"))) static inline V max(V a, V b) { return _mm512_maskz_max_pd(0xFF, a, b); }
  __attribute__((target("avx512f"))) static inline M le(V a, V b) { return _mm512_cmp_pd_mask(a, b, _CMP_LE_OQ); }
  __attribute__((target("avx512f"))) static inline M both(M a, M b) { return static_cast<M>(a & b); }
  __attribute__((target("avx512f"))) static inline V div(V a, V b) { return _mm512_maskz_div_pd(0xFF, a, b); }
  __attribute__((target("avx512f"))) static inline M lt(V a, V b) { return _mm512_cmp_pd_mask(a, b, _CMP_LT_OQ); }
  __attribute__((target("avx512f"))) static inline M eq(V a, V b) { return _mm512_cmp_pd_mask(a, b, _CMP_EQ_OQ); }
  __attribute__((target("avx512f"))) static inline V sqrt(V a) { return _mm512_maskz_sqrt_pd(0xFF, a); }
  __attribute__((target("avx512f"))) static inline M either(M a, M b) { return static_cast<M>(a | b); }
  __attribute__((target("avx512f"))) static inline M but(M a, M b) { return static_cast<M>(a & ~b); }
  __attribute__((target("avx512f"))) static inline unsigned bits(M m) { return static_cast<unsigned>(m); }
  __attribute__((target("avx512f"))) static inline V select(M m, V a, V b) { return _mm512_mask_blend_pd(m, b, a); }
  __attribute__((target("avx512f"))) static inline V set_lane(V v, int c, double x) {
    return _mm512_mask_mov_pd(v, static_cast<M>(1u << c), _mm512_set1_pd(x));
  }
};

/// 16 lanes in two AVX-512 registers: a packet of 4 x 4 rows shares one traversal, which at
/// coarse grids (nodes 2 h apart and more) costs fewer instructions per node than two packets of
/// 8 (docs/performance.md "The whole voxelize process"). The same operations per lane.
struct LanesAvx512Pair {
  static constexpr int kWidth = 16;
  struct V {
    __m512d r[2];
  };
  using M = std::uint32_t;  ///< bit c: lane c (register c / 8, lane c % 8)
#define PPOHDEM_PAIR __attribute__((target("avx512f"), always_inline)) static inline
#define PPOHDEM_PAIR_EACH(expr) \
  V out;                        \
  for (int i = 0; i < 2; ++i) out.r[i] = (expr); \
  return out
  PPOHDEM_PAIR V set1(double x) { PPOHDEM_PAIR_EACH(_mm512_set1_pd(x)); }
  PPOHDEM_PAIR V load(const double* x) { PPOHDEM_PAIR_EACH(_mm512_loadu_pd(x + 8 * i)); }
  PPOHDEM_PAIR void store(double* x, V v) {
    for (int i = 0; i < 2; ++i) _mm512_storeu_pd(x + 8 * i, v.r[i]);
  }
  PPOHDEM_PAIR V zero() { PPOHDEM_PAIR_EACH(_mm512_setzero_pd()); }
  PPOHDEM_PAIR V add(V x, V y) { PPOHDEM_PAIR_EACH(_mm512_add_pd(x.r[i], y.r[i])); }
  PPOHDEM_PAIR V sub(V x, V y) { PPOHDEM_PAIR_EACH(_mm512_sub_pd(x.r[i], y.r[i])); }
  PPOHDEM_PAIR V mul(V x, V y) { PPOHDEM_PAIR_EACH(_mm512_mul_pd(x.r[i], y.r[i])); }
  // maskz_ forms with every lane, as LanesAvx512.
  PPOHDEM_PAIR V max(V x, V y) { PPOHDEM_PAIR_EACH(_mm512_maskz_max_pd(0xFF, x.r[i], y.r[i])); }
  PPOHDEM_PAIR V div(V x, V y) { PPOHDEM_PAIR_EACH(_mm512_maskz_div_pd(0xFF, x.r[i], y.r[i])); }
  PPOHDEM_PAIR M le(V x, V y) {
    return static_cast<M>(_mm512_cmp_pd_mask(x.r[0], y.r[0], _CMP_LE_OQ)) |
           static_cast<M>(_mm512_cmp_pd_mask(x.r[1], y.r[1], _CMP_LE_OQ)) << 8;
  }
  PPOHDEM_PAIR M lt(V x, V y) {
    return static_cast<M>(_mm512_cmp_pd_mask(x.r[0], y.r[0], _CMP_LT_OQ)) |
           static_cast<M>(_mm512_cmp_pd_mask(x.r[1], y.r[1], _CMP_LT_OQ)) << 8;
  }
  PPOHDEM_PAIR M eq(V x, V y) {
    return static_cast<M>(_mm512_cmp_pd_mask(x.r[0], y.r[0], _CMP_EQ_OQ)) |
           static_cast<M>(_mm512_cmp_pd_mask(x.r[1], y.r[1], _CMP_EQ_OQ)) << 8;
  }
  PPOHDEM_PAIR V sqrt(V x) { PPOHDEM_PAIR_EACH(_mm512_maskz_sqrt_pd(0xFF, x.r[i])); }
  PPOHDEM_PAIR M both(M x, M y) { return x & y; }
  PPOHDEM_PAIR M either(M x, M y) { return x | y; }
  PPOHDEM_PAIR M but(M x, M y) { return x & ~y; }
  PPOHDEM_PAIR unsigned bits(M m) { return m; }
  PPOHDEM_PAIR V select(M m, V x, V y) {
    PPOHDEM_PAIR_EACH(_mm512_mask_blend_pd(static_cast<__mmask8>(m >> (8 * i)), y.r[i], x.r[i]));
  }
  PPOHDEM_PAIR V set_lane(V v, int c, double x) {
    v.r[c / 8] = _mm512_mask_mov_pd(v.r[c / 8], static_cast<__mmask8>(1u << (c % 8)), _mm512_set1_pd(x));
    return v;
  }
#undef PPOHDEM_PAIR_EACH
#undef PPOHDEM_PAIR
};

/// From this many points within a triangle's box on, their distances are computed in lanes: from
/// 1 or 2 points on they are equally fast, from 3 on slower (docs/performance.md "Trials that
/// were dropped"). The 16 lanes of LanesAvx512Pair measure even one point in lanes: there the
/// scalar distance and its blend into the lane cost more (docs/performance.md "Kept
/// optimisations").
constexpr int kLanesMinPoints = 2;
template <class Lanes>
constexpr int lanes_min_points() {
  return Lanes::kWidth >= 16 ? 1 : kLanesMinPoints;
}

// The lane traversals, one namespace per instruction set (refine_lanes.inc).
namespace avx {
using L = LanesAvx;
#define PPOHDEM_LANES_TARGET "avx"
#include "refine_lanes.inc"
#undef PPOHDEM_LANES_TARGET
}  // namespace avx

namespace avx512 {
using L = LanesAvx512;
#define PPOHDEM_LANES_TARGET "avx512f"
#include "refine_lanes.inc"
#undef PPOHDEM_LANES_TARGET
}  // namespace avx512

namespace avx512_pair {
using L = LanesAvx512Pair;
#define PPOHDEM_LANES_TARGET "avx512f"
#include "refine_lanes.inc"
#undef PPOHDEM_LANES_TARGET
}  // namespace avx512_pair

#endif

}  // namespace

TriangleTree::PacketSimd TriangleTree::packet_simd_available() {
#if defined(PPOHDEM_PACKET_AVX)
  switch (simd_level()) {  // the CPU's widest, or PPOHDEM_SIMD's
    case SimdLevel::avx512: return PacketSimd::avx512;
    case SimdLevel::avx: return PacketSimd::avx;
    case SimdLevel::sse2: break;
  }
#endif
  return PacketSimd::sse2;
}

void TriangleTree::nearest_packet(const Vec3* p, const std::int64_t* hint, int count, Nearest* out,
                                  PacketSimd simd) const {
  for (int c = 0; c < count; ++c) {
    out[c] = Nearest{};
    if (hint[c] >= 0 && !nodes_.empty()) {
      const auto t = static_cast<std::uint32_t>(hint[c]);
      out[c].squared_distance = squared_distance(p[c], triangles_[t]);
      out[c].triangle = t;
    }
  }
  if (nodes_.empty()) return;
  if (!oriented_boxes_) {
    for (int c = 0; c < count; ++c) refine_in_subtree(p[c], 0, out[c]);
    return;
  }
  // The narrower of the requested and the available instruction sets (enumerators widest first).
  const PacketSimd available = packet_simd_available();
  const PacketSimd use = simd == PacketSimd::best ? available : std::max(simd, available);
  // Up to 16 points per traversal with AVX-512 (two registers from 9 points on), 4 below it:
  // the first 4, then the next 4, ...
  for (int first = 0; first < count;) {
    const int n = std::min(count - first, use == PacketSimd::avx512 ? 16 : 4);
    const Vec3* q = p + first;
    Nearest* o = out + first;
    first += n;
#if defined(PPOHDEM_PACKET_AVX)
    if (use == PacketSimd::avx512 && n > 8) {
      avx512_pair::refine_lanes(oriented_.data(), pairs_.data(), triangles_, slack_, q, n, o);
      continue;
    }
    if (use == PacketSimd::avx512 && n > 1) {
      avx512::refine_lanes(oriented_.data(), pairs_.data(), triangles_, slack_, q, n, o);
      continue;
    }
    if (use == PacketSimd::avx && n > 1) {
      avx::refine_lanes(oriented_.data(), pairs_.data(), triangles_, slack_, q, n, o);
      continue;
    }
#endif
    switch (n) {
      case 1: refine_in_subtree(q[0], 0, o[0]); break;
      case 2: refine_packet<2>(oriented_.data(), pairs_.data(), triangles_, slack_, q, o); break;
      case 3: refine_packet<3>(oriented_.data(), pairs_.data(), triangles_, slack_, q, o); break;
      default: refine_packet<4>(oriented_.data(), pairs_.data(), triangles_, slack_, q, o); break;
    }
  }
}

void TriangleTree::refine_in_subtree(const Vec3& p, std::uint32_t root, Nearest& best) const {
  if (oriented_boxes_) {
    refine_nodes(oriented_.data(), pairs_.data(), triangles_, slack_, p, root, best);
  } else {
    refine_nodes(nodes_.data(), nullptr, triangles_, slack_, p, root, best);
  }
}

void TriangleTree::collect_near_box(const double lo[3], const double hi[3], double bound_squared,
                                    std::vector<std::uint32_t>& out) const {
  if (nodes_.empty()) return;
  const auto box_box = [&](const double blo[3], const double bhi[3]) {
    double d2 = 0.0;
    for (int a = 0; a < 3; ++a) {
      const double gap = std::max({blo[a] - hi[a], lo[a] - bhi[a], 0.0});
      d2 += gap * gap;
    }
    return d2;
  };
  std::uint32_t stack[128];
  int top = 0;
  if (box_box(nodes_[0].lo, nodes_[0].hi) > bound_squared) return;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (node.count > 0) {
      for (std::uint32_t s = node.first; s < node.first + node.count; ++s) {
        if (box_box(triangles_[s].lo, triangles_[s].hi) <= bound_squared) out.push_back(s);
      }
      continue;
    }
    const std::uint32_t left = static_cast<std::uint32_t>(&node - nodes_.data()) + 1;
    const std::uint32_t right = node.first;
    if (box_box(nodes_[right].lo, nodes_[right].hi) <= bound_squared) stack[top++] = right;
    if (box_box(nodes_[left].lo, nodes_[left].hi) <= bound_squared) stack[top++] = left;
  }
}

std::size_t TriangleTree::memory_bytes() const {  // in use (the reserve beyond is never touched)
  return nodes_.size() * sizeof(Node) + oriented_.size() * sizeof(OrientedNode) + pairs_.size() * sizeof(ChildPair) +
         triangles_.size() * sizeof(PreparedTriangle);
}

}  // namespace ppohdem::sdf::fast
