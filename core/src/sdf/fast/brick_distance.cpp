/// \file brick_distance.cpp
/// Shared-candidate exact distances for bricks of nodes, and the band mode's transfer.
/// See brick_distance.hpp for the argument that makes the result exact.
#include "ppohdem/sdf/fast/brick_distance.hpp"

#include <algorithm>
#include <cmath>

namespace ppohdem::fast {

namespace {

/// A box of at most this many nodes, or with at most this many candidates, is not split further:
/// its nodes scan its candidates directly.
constexpr std::size_t kLeafNodes = 8;
constexpr std::size_t kFewCandidates = 8;
constexpr int kMaxDepth = 8;
/// Band mode, beyond the band: one transferred triangle per box of at most kTransferLeaf nodes per
/// axis. Dragon 128^3, band 3 (2026-12-01, docs/performance.md): 2 gives 4.5 distance evaluations
/// per node, max/RMS error 3.8/0.14 h; 4 gives 3.2 per node, 5.6/0.22 h (chosen: the speed target).
constexpr int kTransferLeaf = 4;

/// max(a, 0) written so that the compiler turns it into a vector max (no branch).
inline double positive(double a) { return a > 0.0 ? a : 0.0; }
/// Shared candidates: clusters are kept whole while their box diagonal is at most kOpenRatio x
/// the half-diagonal of the box of nodes they are filtered for (4 did best of 0.5, 1, 2, 4 on the
/// dragon at 64^3, 2026-12-01).
constexpr double kOpenRatio = 4.0;

/// Calls f(child) for the (up to 8) halves of `box`, split at the middle of every axis with more
/// than one node, in a fixed order.
template <typename F>
void for_each_child(const NodeBox& box, F&& f) {
  int mid[3];
  for (int a = 0; a < 3; ++a) mid[a] = box.lo[a] + (box.extent(a) + 1) / 2;
  for (int cz = 0; cz < 2; ++cz) {
    for (int cy = 0; cy < 2; ++cy) {
      for (int cx = 0; cx < 2; ++cx) {
        NodeBox child;
        const int pick[3] = {cx, cy, cz};
        for (int a = 0; a < 3; ++a) {
          child.lo[a] = pick[a] == 0 ? box.lo[a] : mid[a];
          child.hi[a] = pick[a] == 0 ? mid[a] : box.hi[a];
        }
        if (!child.empty()) f(child);
      }
    }
  }
}

}  // namespace

NodeBox NodeBox::intersect(const NodeBox& o) const {
  NodeBox r;
  for (int a = 0; a < 3; ++a) {
    r.lo[a] = std::max(lo[a], o.lo[a]);
    r.hi[a] = std::max(r.lo[a], std::min(hi[a], o.hi[a]));
  }
  return r;
}

void BrickDistance::Workspace::Candidates::clear() {
  index.clear();
  for (int a = 0; a < 3; ++a) {
    lo[a].clear();
    hi[a].clear();
  }
}

void BrickDistance::Workspace::Candidates::push(std::uint32_t id, const double box_lo[3], const double box_hi[3]) {
  index.push_back(id);
  for (int a = 0; a < 3; ++a) {
    lo[a].push_back(box_lo[a]);
    hi[a].push_back(box_hi[a]);
  }
}

BrickDistance::BrickDistance(const TriangleTree& tree, const GridSpec& grid, double band_distance,
                             bool shared_candidates)
    : tree_(tree), grid_(grid), band_(band_distance), slack_(tree.slack()), shared_(shared_candidates) {}

Vec3 BrickDistance::box_centre(const NodeBox& box) const {
  // Midpoint of the first and last node of the box, per axis.
  Vec3 c;
  for (int a = 0; a < 3; ++a) {
    c[a] = grid_.origin[a] + 0.5 * static_cast<double>(box.lo[a] + box.hi[a] - 1) * grid_.spacing[a];
  }
  return c;
}

double BrickDistance::half_diagonal(const NodeBox& box) const {
  double r2 = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double half = 0.5 * static_cast<double>(box.extent(a) - 1) * grid_.spacing[a];
    r2 += half * half;
  }
  return std::sqrt(r2) * (1.0 + 1e-12);  // rounded up: an upper bound of |x - c| over the box
}

TriangleTree::Nearest BrickDistance::scan(const Workspace::Candidates& c, const Vec3& p, std::uint32_t hint,
                                          Workspace& ws) const {
  TriangleTree::Nearest best;
  best.squared_distance = squared_distance(p, tree_.triangles()[hint]);
  best.triangle = hint;
  ++ws.counters.distance_evaluations;
  const std::size_t n = c.size();
  ws.box_d2.resize(n);
  double* out = ws.box_d2.data();
  const double px = p.x(), py = p.y(), pz = p.z();
  const double *lx = c.lo[0].data(), *ly = c.lo[1].data(), *lz = c.lo[2].data();
  const double *hx = c.hi[0].data(), *hy = c.hi[1].data(), *hz = c.hi[2].data();
  // Point-to-box squared distances of all candidate clusters: a branch-free loop the compiler
  // vectorizes.
  for (std::size_t s = 0; s < n; ++s) {
    const double gx = positive(lx[s] - px) + positive(px - hx[s]);  // lo <= hi: one term at most
    const double gy = positive(ly[s] - py) + positive(py - hy[s]);
    const double gz = positive(lz[s] - pz) + positive(pz - hz[s]);
    out[s] = gx * gx + gy * gy + gz * gz;
  }
  ws.counters.candidate_tests += n;
  double r = std::sqrt(best.squared_distance) + slack_;
  double prune = r * r;
  const auto& triangles = tree_.triangles();
  for (std::size_t s = 0; s < n; ++s) {
    if (out[s] > prune) continue;  // nothing in this box can beat the bound (slack included)
    if (c.triangles) {
      const std::uint32_t t = c.index[s];
      const double d2 = squared_distance(p, triangles[t]);
      if (d2 < best.squared_distance || (d2 == best.squared_distance && t < best.triangle)) {
        best.squared_distance = d2;
        best.triangle = t;
      }
    } else {
      tree_.refine_in_subtree(p, c.index[s], best);
    }
    ++ws.counters.distance_evaluations;
    r = std::sqrt(best.squared_distance) + slack_;
    prune = r * r;
  }
  return best;
}

void BrickDistance::solve(const NodeBox& brick, const NodeBox& clip, TriangleTree::Nearest centre,
                          std::span<const std::uint32_t> transfer, Workspace& ws, double* d2) const {
  ws.brick = brick;
  ws.clip = brick.intersect(clip);
  if (ws.clip.empty()) return;
  ws.transfer.assign(transfer.begin(), transfer.end());
  // Sized once: the recursion holds references into these (never resized while in use).
  if (ws.level.size() < static_cast<std::size_t>(kMaxDepth + 1)) ws.level.resize(kMaxDepth + 1);
  if (ws.transfer_level.size() < static_cast<std::size_t>(kMaxDepth + 1)) ws.transfer_level.resize(kMaxDepth + 1);
  if (std::isfinite(band_)) {
    ws.brick_triangle = centre.triangle;
    ws.brick_d2 = centre.squared_distance;
    if (std::sqrt(centre.squared_distance) - half_diagonal(brick) > band_ + 2.0 * slack_) {
      // No node of this brick is within the band (d(x) >= d(c) - r): transfer only, by 4^3 boxes.
      for_each_child(brick, [&](const NodeBox& child) { transfer_box(child, ws, d2); });
    } else {
      band_box(brick, 0, ws.transfer, ws, d2);
    }
    return;
  }
  solve_box(brick, 0, nullptr, centre, ws, d2);
}

void BrickDistance::transfer_box(const NodeBox& box, Workspace& ws, double* d2) const {
  const NodeBox nodes = box.intersect(ws.clip);
  if (nodes.empty()) return;
  const auto& triangles = tree_.triangles();
  const NodeBox& b = ws.brick;
  const int ex = b.extent(0), ey = b.extent(1);
  // The set S: the nearest triangles of the 27 brick centres around and t_b, the brick centre's
  // own. A triangle t can be the minimum of S at some node x of the box only if
  // dist(c, t) - r <= dist(x, t) <= dist(x, t_c) <= dist(c, t_c) + r (c the box centre, t_c the
  // set's nearest to c, r the half-diagonal): the kept set K gives every node the minimum over S.
  const Vec3 c = box_centre(box);
  const std::uint32_t tb = ws.brick_triangle;
  double best = squared_distance(c, triangles[tb]);
  ws.box_d2.resize(ws.transfer.size());
  for (std::size_t s = 0; s < ws.transfer.size(); ++s) {
    ws.box_d2[s] = squared_distance(c, triangles[ws.transfer[s]]);
    best = std::min(best, ws.box_d2[s]);
  }
  ws.counters.distance_evaluations += ws.transfer.size() + 1;
  const double keep = (std::sqrt(best) + 2.0 * half_diagonal(box)) * (1.0 + 1e-12) + 3.0 * slack_;
  const double keep2 = keep * keep;
  std::vector<std::uint32_t>& kept = ws.transfer_kept;
  kept.clear();
  kept.push_back(tb);  // t_b always: the bound below rests on it
  for (std::size_t s = 0; s < ws.transfer.size(); ++s) {
    if (ws.box_d2[s] <= keep2 && ws.transfer[s] != tb) kept.push_back(ws.transfer[s]);
  }
  // Per node ONE triangle of K: t_c, the nearest of K to the centre c' of the node's box of at
  // most kTransferLeaf^3 nodes (t_c = t_b when K = {t_b}). Bound: dist(x, t_c) <= dist(c', t_c) +
  // |x - c'| <= dist(c', t_b) + |x - c'| <= d(c_b) + |c' - c_b| + |x - c'| <= d(x) + |x - c_b| +
  // |c' - c_b| + |x - c'| <= d(x) + 2 r_b + r' (r_b the brick's half-diagonal, r' that box's).
  const auto per_child = [&](const NodeBox& child) {
    const NodeBox part = child.intersect(ws.clip);
    if (part.empty()) return;
    std::uint32_t tc = tb;
    if (kept.size() > 1) {
      const Vec3 cc = box_centre(child);
      double best_c = squared_distance(cc, triangles[tb]);
      for (std::size_t s = 1; s < kept.size(); ++s) {
        const double d = squared_distance(cc, triangles[kept[s]]);
        if (d < best_c || (d == best_c && kept[s] < tc)) {
          best_c = d;
          tc = kept[s];
        }
      }
      ws.counters.distance_evaluations += kept.size();
    }
    const PreparedTriangle& pc = triangles[tc];
    for (int k = part.lo[2]; k < part.hi[2]; ++k) {
      for (int j = part.lo[1]; j < part.hi[1]; ++j) {
        double* row = d2 + static_cast<std::size_t>(((k - b.lo[2]) * ey + (j - b.lo[1])) * ex);
        for (int i = part.lo[0]; i < part.hi[0]; ++i) row[i - b.lo[0]] = squared_distance(grid_.position(i, j, k), pc);
      }
    }
    ws.counters.distance_evaluations += part.count();
  };
  // Split down to boxes of at most kTransferLeaf nodes per axis, unless K = {t_b}.
  const auto split = [&](const auto& self, const NodeBox& part) -> void {
    if (kept.size() == 1 || (part.extent(0) <= kTransferLeaf && part.extent(1) <= kTransferLeaf &&
                             part.extent(2) <= kTransferLeaf)) {
      per_child(part);
      return;
    }
    for_each_child(part, [&](const NodeBox& child) { self(self, child); });
  };
  split(split, box);
  ws.counters.transferred_nodes += nodes.count();
}

void BrickDistance::band_box(const NodeBox& box, int depth, const std::vector<std::uint32_t>& parent, Workspace& ws,
                             double* d2) const {
  if (box.intersect(ws.clip).empty()) return;
  const auto& triangles = tree_.triangles();
  double lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = grid_.origin[a] + static_cast<double>(box.lo[a]) * grid_.spacing[a];
    hi[a] = grid_.origin[a] + static_cast<double>(box.hi[a] - 1) * grid_.spacing[a];
  }
  const auto box_gap2 = [&](const PreparedTriangle& t) {
    double g2 = 0.0;
    for (int a = 0; a < 3; ++a) {
      const double g = positive(t.lo[a] - hi[a]) + positive(lo[a] - t.hi[a]);
      g2 += g * g;
    }
    return g2;
  };
  // Candidates of this box: the triangles whose bounding box is within `near` of the box, with
  // near = min(B, d(c) + r), B = the band plus slack, c the box centre, r its half-diagonal.
  // A node x of the box has d(x) <= dist(x, t_c) <= d_S(c) + r (t_c the nearest triangle to c
  // found, d_S(c) its distance), and its nearest triangle's bounding box is within d(x) of x:
  // so if d(x) <= band, or if near = d_S(c) + r, that triangle is a candidate and the node's
  // minimum over the candidates is its minimum over ALL triangles (any other triangle is
  // computed farther than near: B and the Lipschitz radius include the slack).
  const double bound = band_ * (1.0 + 1e-12) + 3.0 * slack_;
  const double r = half_diagonal(box);
  const Vec3 c = box_centre(box);
  std::vector<std::uint32_t>& kept = ws.transfer_level[static_cast<std::size_t>(depth)];
  kept.clear();
  std::uint32_t tc = ws.brick_triangle;
  double dc = 0.0;
  if (depth == 0) {
    dc = std::sqrt(ws.brick_d2);  // the brick centre's exact distance (its BVH query)
    const double near = std::min(bound, (dc + r) * (1.0 + 1e-12) + 3.0 * slack_);
    tree_.collect_near_box(lo, hi, near * near, kept);
  } else {
    const double bound2 = bound * bound;
    for (std::uint32_t t : parent) {
      if (box_gap2(triangles[t]) <= bound2) kept.push_back(t);
    }
    // The minimum at c over t_b and the candidates (pruned by their bounding boxes).
    double best = squared_distance(c, triangles[tc]);
    double rb = std::sqrt(best) + slack_;
    double prune = rb * rb;
    for (std::uint32_t t : kept) {
      const PreparedTriangle& tri = triangles[t];
      const double gx = positive(tri.lo[0] - c.x()) + positive(c.x() - tri.hi[0]);
      const double gy = positive(tri.lo[1] - c.y()) + positive(c.y() - tri.hi[1]);
      const double gz = positive(tri.lo[2] - c.z()) + positive(c.z() - tri.hi[2]);
      if (gx * gx + gy * gy + gz * gz > prune) continue;
      const double d = squared_distance(c, tri);
      ++ws.counters.distance_evaluations;
      if (d < best) {
        best = d;
        tc = t;
        rb = std::sqrt(best) + slack_;
        prune = rb * rb;
      }
    }
    dc = std::sqrt(best);
    if (dc - r > band_ + 2.0 * slack_) {  // d(x) >= d(c) - r > band: no band node in the box
      transfer_box(box, ws, d2);
      return;
    }
    const double near = (dc + r) * (1.0 + 1e-12) + 3.0 * slack_;
    if (near < bound) {
      const double near2 = near * near;
      kept.erase(std::remove_if(kept.begin(), kept.end(),
                                [&](std::uint32_t t) { return box_gap2(triangles[t]) > near2; }),
                 kept.end());
    }
  }
  if (kept.empty()) {
    transfer_box(box, ws, d2);  // no triangle within the band of the box
    return;
  }
  if (box.count() > kLeafNodes && depth < kMaxDepth) {
    for_each_child(box, [&](const NodeBox& child) { band_box(child, depth + 1, kept, ws, d2); });
    return;
  }
  // The leaf: candidates as arrays of bounding boxes (vectorized lower bounds, scan()).
  Workspace::Candidates& cand = ws.leaf;
  cand.triangles = true;
  const std::size_t n = kept.size();
  cand.index.assign(kept.begin(), kept.end());
  for (int a = 0; a < 3; ++a) {
    cand.lo[a].resize(n);
    cand.hi[a].resize(n);
    for (std::size_t s = 0; s < n; ++s) {
      cand.lo[a][s] = triangles[kept[s]].lo[a];
      cand.hi[a][s] = triangles[kept[s]].hi[a];
    }
  }
  const NodeBox nodes = box.intersect(ws.clip);
  const NodeBox& b = ws.brick;
  const int ex = b.extent(0), ey = b.extent(1);
  const double band2 = band_ * band_;
  std::uint32_t hint = tc;
  for (int k = nodes.lo[2]; k < nodes.hi[2]; ++k) {
    for (int j = nodes.lo[1]; j < nodes.hi[1]; ++j) {
      for (int i = nodes.lo[0]; i < nodes.hi[0]; ++i) {
        const Vec3 p = grid_.position(i, j, k);
        TriangleTree::Nearest nn = scan(cand, p, hint, ws);
        hint = nn.triangle;
        if (nn.squared_distance <= band2) {
          ++ws.counters.exact_nodes;
        } else {
          // Beyond the band: an upper bound; t_b keeps the transfer's proven bound.
          nn.squared_distance = std::min(nn.squared_distance, squared_distance(p, triangles[ws.brick_triangle]));
          ++ws.counters.transferred_nodes;
        }
        d2[static_cast<std::size_t>(((k - b.lo[2]) * ey + (j - b.lo[1])) * ex + (i - b.lo[0]))] = nn.squared_distance;
      }
    }
  }
}

void BrickDistance::solve_box(const NodeBox& box, int depth, const Workspace::Candidates* parent,
                              TriangleTree::Nearest centre, Workspace& ws, double* d2) const {
  const double r = half_diagonal(box);
  const double dc = std::sqrt(centre.squared_distance);
  if (!shared_) {
    // Per-node BVH queries, each started from the previous node's nearest triangle.
    const NodeBox nodes = box.intersect(ws.clip);
    const NodeBox& b = ws.brick;
    const int ex = b.extent(0), ey = b.extent(1);
    // Each row starts from the previous row's first node (a neighbour), not from its last.
    std::int64_t row_hint = centre.triangle;
    for (int k = nodes.lo[2]; k < nodes.hi[2]; ++k) {
      for (int j = nodes.lo[1]; j < nodes.hi[1]; ++j) {
        std::int64_t hint = row_hint;
        for (int i = nodes.lo[0]; i < nodes.hi[0]; ++i) {
          const TriangleTree::Nearest nearest = tree_.nearest(grid_.position(i, j, k), hint);
          hint = nearest.triangle;
          if (i == nodes.lo[0]) row_hint = hint;
          d2[static_cast<std::size_t>(((k - b.lo[2]) * ey + (j - b.lo[1])) * ex + (i - b.lo[0]))] =
              nearest.squared_distance;
        }
      }
    }
    ws.counters.exact_nodes += nodes.count();
    return;
  }
  // Every point of the box is within U of the surface; candidates: triangles within U of the box.
  const double bound = (dc + r) * (1.0 + 1e-12) + 3.0 * slack_;
  const double bound2 = bound * bound;
  double lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = grid_.origin[a] + static_cast<double>(box.lo[a]) * grid_.spacing[a];
    hi[a] = grid_.origin[a] + static_cast<double>(box.hi[a] - 1) * grid_.spacing[a];
  }
  Workspace::Candidates& c = ws.level[static_cast<std::size_t>(depth)];
  c.clear();
  // Clusters (BVH nodes) are opened down to the size of this box, or to leaves for boxes whose
  // nodes scan them directly: a cluster much larger than the box is a loose bound for it.
  // Boxes whose nodes scan their candidates directly get single triangles (a tight box each).
  const bool leaf_box = box.count() <= kLeafNodes || depth == kMaxDepth;
  const double open_diagonal = leaf_box ? -1.0 : kOpenRatio * r;
  c.triangles = leaf_box;
  const auto& triangles = tree_.triangles();
  const auto& bvh = tree_.nodes();
  const auto box_box = [&](const double blo[3], const double bhi[3]) {
    double g2 = 0.0;
    for (int a = 0; a < 3; ++a) {
      const double g = positive(blo[a] - hi[a]) + positive(lo[a] - bhi[a]);
      g2 += g * g;
    }
    return g2;
  };
  const auto expand = [&](std::uint32_t root) {
    std::uint32_t stack[128];
    int top = 0;
    stack[top++] = root;
    while (top > 0) {
      const std::uint32_t id = stack[--top];
      const TriangleTree::Node& n = bvh[id];
      if (n.count > 0 && leaf_box) {
        for (std::uint32_t t = n.first; t < n.first + n.count; ++t) {
          if (box_box(triangles[t].lo, triangles[t].hi) <= bound2) c.push(t, triangles[t].lo, triangles[t].hi);
        }
        continue;
      }
      if (n.count > 0 || TriangleTree::diagonal(n) <= open_diagonal) {
        c.push(id, n.lo, n.hi);
        continue;
      }
      if (box_box(bvh[n.first].lo, bvh[n.first].hi) <= bound2) stack[top++] = n.first;
      if (box_box(bvh[id + 1].lo, bvh[id + 1].hi) <= bound2) stack[top++] = id + 1;
    }
  };
  if (parent == nullptr) {
    if (box_box(bvh[0].lo, bvh[0].hi) <= bound2) expand(0);
  } else {
    const std::size_t n = parent->size();
    ws.box_d2.resize(n);
    double* out = ws.box_d2.data();
    const double *plx = parent->lo[0].data(), *ply = parent->lo[1].data(), *plz = parent->lo[2].data();
    const double *phx = parent->hi[0].data(), *phy = parent->hi[1].data(), *phz = parent->hi[2].data();
    for (std::size_t s = 0; s < n; ++s) {
      const double gx = positive(plx[s] - hi[0]) + positive(lo[0] - phx[s]);
      const double gy = positive(ply[s] - hi[1]) + positive(lo[1] - phy[s]);
      const double gz = positive(plz[s] - hi[2]) + positive(lo[2] - phz[s]);
      out[s] = gx * gx + gy * gy + gz * gz;
    }
    for (std::size_t s = 0; s < n; ++s) {
      if (out[s] <= bound2) expand(parent->index[s]);
    }
  }
  const NodeBox nodes = box.intersect(ws.clip);
  if (leaf_box || c.size() <= kFewCandidates) {
    const NodeBox& b = ws.brick;
    const int ex = b.extent(0), ey = b.extent(1);
    std::uint32_t hint = centre.triangle;
    for (int k = nodes.lo[2]; k < nodes.hi[2]; ++k) {
      for (int j = nodes.lo[1]; j < nodes.hi[1]; ++j) {
        for (int i = nodes.lo[0]; i < nodes.hi[0]; ++i) {
          const TriangleTree::Nearest nearest = scan(c, grid_.position(i, j, k), hint, ws);
          hint = nearest.triangle;
          d2[static_cast<std::size_t>(((k - b.lo[2]) * ey + (j - b.lo[1])) * ex + (i - b.lo[0]))] =
              nearest.squared_distance;
        }
      }
    }
    ws.counters.exact_nodes += nodes.count();
    return;
  }
  // Halve every axis with more than one node; children are visited in a fixed order.
  for_each_child(box, [&](const NodeBox& child) {
    if (child.intersect(ws.clip).empty()) return;
    const TriangleTree::Nearest child_centre = scan(c, box_centre(child), centre.triangle, ws);
    solve_box(child, depth + 1, &c, child_centre, ws, d2);
  });
}

}  // namespace ppohdem::fast
