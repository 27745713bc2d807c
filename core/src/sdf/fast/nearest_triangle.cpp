/// \file nearest_triangle.cpp
/// Ericson's closest point on a triangle and a flat median-split BVH. See nearest_triangle.hpp.
#include "ppohdem/sdf/fast/nearest_triangle.hpp"

#include <algorithm>
#include <cmath>

namespace ppohdem::fast {

namespace {

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

double squared_distance(const Vec3& p, const PreparedTriangle& t) {
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

TriangleTree::TriangleTree(const TriangleMesh& mesh, double coordinate_scale) {
  const std::size_t n = mesh.size();
  std::vector<Vec3> centroid(n);
  std::vector<std::uint32_t> order(n);
  double scale = 0.0;
  for (std::size_t t = 0; t < n; ++t) {
    const auto& v = mesh.triangles[t].v;
    centroid[t] = (v[0] + v[1] + v[2]) / 3.0;
    order[t] = static_cast<std::uint32_t>(t);
    for (const Vec3& x : v) scale = std::max(scale, x.cwiseAbs().maxCoeff());
  }
  // Pruning slack: the closest-point arithmetic above works on coordinates of magnitude <= S and
  // makes absolute errors of a few tens of eps S; 1e-12 S (~4500 eps S) is far above that and
  // far below any grid spacing worth computing.
  // Query points far from the mesh round at their own scale: the larger of the two counts.
  slack_ = 1e-12 * std::max({scale, std::abs(coordinate_scale), 1e-300});
  nodes_.reserve(2 * n / kLeafSize + 2);
  if (n > 0) build(order, centroid, mesh.triangles, 0, static_cast<std::uint32_t>(n));
  triangles_.reserve(n);
  for (std::uint32_t t : order) triangles_.push_back(prepare_triangle(mesh.triangles[t], t));
}

std::uint32_t TriangleTree::build(std::vector<std::uint32_t>& order, const std::vector<Vec3>& centroid,
                                  const std::vector<Triangle>& input, std::uint32_t begin, std::uint32_t end) {
  const auto index = static_cast<std::uint32_t>(nodes_.size());
  nodes_.emplace_back();
  Node node;
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = -lo;
  Vec3 clo = lo, chi = hi;
  for (std::uint32_t s = begin; s < end; ++s) {
    for (const Vec3& v : input[order[s]].v) {
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
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
    nodes_[index] = node;
    return index;
  }
  // Median split of the centroids along the longest axis of their box.
  int axis = 0;
  const Vec3 extent = chi - clo;
  if (extent.y() > extent[axis]) axis = 1;
  if (extent.z() > extent[axis]) axis = 2;
  const std::uint32_t middle = begin + (end - begin) / 2;
  std::nth_element(order.begin() + begin, order.begin() + middle, order.begin() + end,
                   [&](std::uint32_t s, std::uint32_t t) {
                     if (centroid[s][axis] != centroid[t][axis]) return centroid[s][axis] < centroid[t][axis];
                     return s < t;  // total order: the tree does not depend on the library's algorithm
                   });
  build(order, centroid, input, begin, middle);
  node.first = build(order, centroid, input, middle, end);
  node.count = 0;
  nodes_[index] = node;
  return index;
}

namespace {

/// |p - box|^2, the same value as the former loop (max of three, then (x^2 + y^2) + z^2); always
/// inlined: GCC 12 kept box_squared_distance() out of line with an initializer-list max, 0.29e9 of
/// the 0.61e9 instructions of the brick-centre queries (dragon 256^3, band 3); exact mode, dragon
/// 64^3, whole program: 5.24e9 -> 4.83e9 instructions (callgrind, 2026-12-01).
[[gnu::always_inline]] inline double point_box_squared(const double lo[3], const double hi[3], double px, double py,
                                                       double pz) {
  const double dx = std::max(std::max(lo[0] - px, px - hi[0]), 0.0);
  const double dy = std::max(std::max(lo[1] - py, py - hi[1]), 0.0);
  const double dz = std::max(std::max(lo[2] - pz, pz - hi[2]), 0.0);
  return dx * dx + dy * dy + dz * dz;
}

}  // namespace

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

void TriangleTree::refine_in_subtree(const Vec3& p, std::uint32_t root, Nearest& best) const {
  // prune_bound = (sqrt(best) + slack)^2: boxes farther than that cannot hold a triangle whose
  // computed distance is <= best (see the header).
  double prune_bound = std::numeric_limits<double>::infinity();
  auto improve = [&](double d2, std::uint32_t t) {
    if (d2 < best.squared_distance || (d2 == best.squared_distance && t < best.triangle)) {
      best.squared_distance = d2;
      best.triangle = t;
      const double r = std::sqrt(d2) + slack_;
      prune_bound = r * r;
    }
  };
  if (std::isfinite(best.squared_distance)) {
    const double r = std::sqrt(best.squared_distance) + slack_;
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
  if (point_box_squared(nodes_[root].lo, nodes_[root].hi, px, py, pz) > prune_bound) return;
  for (;;) {
    const Node& node = nodes_[current];
    if (node.count > 0) {
      for (std::uint32_t s = node.first; s < node.first + node.count; ++s) {
        const PreparedTriangle& t = triangles_[s];
        if (point_box_squared(t.lo, t.hi, px, py, pz) > prune_bound) continue;  // cannot beat the bound
        improve(squared_distance(p, t), s);
      }
    } else {
      const std::uint32_t left = current + 1;
      const std::uint32_t right = node.first;
      const double dl = point_box_squared(nodes_[left].lo, nodes_[left].hi, px, py, pz);
      const double dr = point_box_squared(nodes_[right].lo, nodes_[right].hi, px, py, pz);
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

std::size_t TriangleTree::memory_bytes() const {
  return nodes_.capacity() * sizeof(Node) + triangles_.capacity() * sizeof(PreparedTriangle);
}

}  // namespace ppohdem::fast
