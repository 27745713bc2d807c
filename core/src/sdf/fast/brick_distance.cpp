/// \file brick_distance.cpp
/// Shared-candidate exact distances for bricks of nodes, and the band mode's transfer.
/// See brick_distance.hpp for the argument that makes the result exact.
#include "ppohdem/sdf/fast/brick_distance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ppohdem::sdf::fast {

namespace {

/// A box of at most this many nodes, or with at most this many candidates, is not split further:
/// its nodes scan its candidates directly.
constexpr std::size_t kLeafNodes = 8;
constexpr std::size_t kFewCandidates = 8;
constexpr int kMaxDepth = 8;
/// Band mode, beyond the band: one transferred triangle per box of at most kTransferLeaf nodes per
/// axis. 4 rather than 2 trades a larger (still proven) error beyond the band for fewer distance
/// evaluations per node, for the speed target (docs/performance.md "Trials that were dropped").
constexpr int kTransferLeaf = 4;

/// max(a, 0) written so that the compiler turns it into a vector max (no branch).
inline double positive(double a) { return a > 0.0 ? a : 0.0; }

/// Squared gap from point c to a triangle's bounding box [m^2] (0 inside): a lower bound of the
/// squared distance to the triangle, for pruning.
template <class Tri, class Point>
inline double gap2_to_bounds(const Tri& tri, const Point& c) {
  const double gx = positive(tri.lo[0] - c.x()) + positive(c.x() - tri.hi[0]);
  const double gy = positive(tri.lo[1] - c.y()) + positive(c.y() - tri.hi[1]);
  const double gz = positive(tri.lo[2] - c.z()) + positive(c.z() - tri.hi[2]);
  return gx * gx + gy * gy + gz * gz;
}
/// Shared candidates: clusters are kept whole while their box diagonal is at most kOpenRatio x
/// the half-diagonal of the box of nodes they are filtered for (4 took the fewest instructions of
/// 0.5, 1, 2 and 4).
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

TriangleTree::Nearest BrickDistance::scan_buckets(const Workspace::Candidates& c, const Vec3& p, std::uint32_t hint,
                                                  Workspace& ws) const {
  // As scan(), over a prefix of the leaf's triangle candidates, which band_box() grouped in buckets
  // of increasing squared box-to-box gap to the leaf box. A bucket whose smallest gap exceeds the
  // pruning bound needs no test: p lies in that box, and its point-to-box gap, computed with
  // monotone roundings from the same coordinates, is never below the box-to-box one, so each of
  // the bucket's candidates would be pruned by its own test. The candidates after the last bucket
  // within the bound are left out; the result is the same minimum (ties: the lowest index).
  TriangleTree::Nearest best;
  const auto& triangles = tree_.triangles();
  best.squared_distance = squared_distance(p, triangles[hint]);
  best.triangle = hint;
  ++ws.counters.distance_evaluations;
  double r = std::sqrt(best.squared_distance) + slack_;
  double prune = r * r;
  std::size_t n = 0;
  for (int k = 0; k < kLeafBuckets; ++k) {
    if (ws.leaf_bucket_min[k] <= prune) n = ws.leaf_bucket_start[k + 1];
  }
  ws.box_d2.resize(c.size());
  double* out = ws.box_d2.data();
  const double px = p.x(), py = p.y(), pz = p.z();
  const double *lx = c.lo[0].data(), *ly = c.lo[1].data(), *lz = c.lo[2].data();
  const double *hx = c.hi[0].data(), *hy = c.hi[1].data(), *hz = c.hi[2].data();
  for (std::size_t s = 0; s < n; ++s) {  // vectorized, as scan()'s
    const double gx = positive(lx[s] - px) + positive(px - hx[s]);
    const double gy = positive(ly[s] - py) + positive(py - hy[s]);
    const double gz = positive(lz[s] - pz) + positive(pz - hz[s]);
    out[s] = gx * gx + gy * gy + gz * gz;
  }
  ws.counters.candidate_tests += n;
  for (std::size_t s = 0; s < n; ++s) {
    if (out[s] > prune) continue;
    const std::uint32_t t = c.index[s];
    const double d2 = squared_distance(p, triangles[t]);
    ++ws.counters.distance_evaluations;
    if (d2 < best.squared_distance || (d2 == best.squared_distance && t < best.triangle)) {
      best.squared_distance = d2;
      best.triangle = t;
      r = std::sqrt(d2) + slack_;
      prune = r * r;
    }
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
  if (ws.children.size() < static_cast<std::size_t>(kMaxDepth + 1)) ws.children.resize(kMaxDepth + 1);
  if (std::isfinite(band_)) {
    ws.brick_triangle = centre.triangle;
    ws.brick_d2 = centre.squared_distance;
    if (std::sqrt(centre.squared_distance) - half_diagonal(brick) > band_ + 2.0 * slack_) {
      // No node of this brick is within the band (d(x) >= d(c) - r): transfer only, by 4^3 boxes.
      for_each_child(brick, [&](const NodeBox& child) { transfer_box(child, ws, d2); });
    } else {
      band_box(brick, 0, nullptr, ws, d2);
    }
    return;
  }
  solve_box(brick, 0, nullptr, centre, ws, d2);
}

namespace {

/// Which branch squared_distance() takes, decided for a whole axis-aligned box of points at once
/// when possible. squared_distance() returns |p - a|^2 when its computed d1 = ab.(p - a) <= 0 and
/// d2 = ac.(p - a) <= 0 (vertex a, tested first); |p - b|^2 when that fails and d3 = ab.(p - b) >=
/// 0, d4 <= d3 (d4 = ac.(p - b)); |p - c|^2 when both fail, edge ab's test fails (it needs d1 >= 0,
/// d3 <= 0) and d6 = ac.(p - c) >= 0, d5 <= d6 (d5 = ab.(p - c)). Each d (and d4 - d3, d5 - d6) is
/// a linear function g.p - g.q, so its range over a box is its value at the centre +- sum |g_i| w_i
/// (w the half widths). A test counts as decided for every point of the box only when the whole
/// range clears zero by `margin` = 1e-9 S (|ab|_1 + |ac|_1) (S the coordinate scale): the computed
/// d's differ from the exact ones by a few eps S |g|_1 (point coordinates and dot products
/// rounded), and so does this range, far less than the margin. Then each point's value is
/// |p - v|^2, computed as squared_distance() does: the same bits.
class VertexRegions {
 public:
  VertexRegions(const PreparedTriangle& t, double slack) : t_(t) {
    const Vec3 bc = t.ac - t.ab;  // d4 - d3 = (ac - ab).(p - b), d5 - d6 = (ab - ac).(p - c)
    const Vec3 g[kTests] = {t.ab, t.ac, t.ab, bc, t.ac, -bc};
    const Vec3* q[kTests] = {&t.a, &t.a, &t.b, &t.b, &t.c, &t.c};
    for (int m = 0; m < kTests; ++m) {
      g_[m] = g[m];
      abs_[m] = g[m].cwiseAbs();
      offset_[m] = g[m].dot(*q[m]);
    }
    margin_ = 1e3 * slack * (t.ab.lpNorm<1>() + t.ac.lpNorm<1>());
  }

  /// The vertex whose |p - v|^2 squared_distance() returns for every p in the box with this
  /// centre and these half widths, or nullptr if that is not certain.
  const Vec3* common_vertex(const Vec3& centre, const Vec3& half) const {
    double lo[kTests], hi[kTests];
    for (int m = 0; m < kTests; ++m) {
      const double mid = g_[m].dot(centre) - offset_[m];
      const double spread = abs_[m].dot(half);
      lo[m] = mid - spread;
      hi[m] = mid + spread;
    }
    const double e = margin_;
    if (hi[0] <= -e && hi[1] <= -e) return &t_.a;
    if (!(lo[0] >= e || lo[1] >= e)) return nullptr;  // vertex a's test not certain to fail
    if (lo[2] >= e && hi[3] <= -e) return &t_.b;
    const bool not_b = hi[2] <= -e || lo[3] >= e;
    const bool not_ab = lo[2] >= e || hi[0] <= -e;
    if (not_b && not_ab && lo[4] >= e && hi[5] <= -e) return &t_.c;
    return nullptr;
  }

 private:
  static constexpr int kTests = 6;  // d1, d2, d3, d4 - d3, d6, d5 - d6
  const PreparedTriangle& t_;
  Vec3 g_[kTests], abs_[kTests];
  double offset_[kTests];
  double margin_ = 0.0;
};

}  // namespace

void BrickDistance::transfer_fill(const NodeBox& part, const PreparedTriangle& t, Workspace& ws, double* d2) const {
  const NodeBox& b = ws.brick;
  const int ex = b.extent(0), ey = b.extent(1);
  ws.counters.distance_evaluations += part.count();
  const auto general = [&](int j, int k, double* row) {
    for (int i = part.lo[0]; i < part.hi[0]; ++i) row[i - b.lo[0]] = squared_distance(grid_.position(i, j, k), t);
  };
  const auto at_vertex = [&](int j, int k, double* row, const Vec3& v) {
    for (int i = part.lo[0]; i < part.hi[0]; ++i) row[i - b.lo[0]] = (grid_.position(i, j, k) - v).squaredNorm();
  };
  const auto row_of = [&](int j, int k) {
    return d2 + static_cast<std::size_t>(((k - b.lo[2]) * ey + (j - b.lo[1])) * ex);
  };
  if (t.kind == 2) {  // degenerate: squared_distance() takes the edges
    for (int k = part.lo[2]; k < part.hi[2]; ++k) {
      for (int j = part.lo[1]; j < part.hi[1]; ++j) general(j, k, row_of(j, k));
    }
    return;
  }
  // The whole box at once when its nodes are all in one vertex's region (about half of the
  // transferred nodes of the dragon at 256^3).
  const VertexRegions regions(t, slack_);
  const Vec3 lo = grid_.position(part.lo[0], part.lo[1], part.lo[2]);
  const Vec3 hi = grid_.position(part.hi[0] - 1, part.hi[1] - 1, part.hi[2] - 1);
  const Vec3 centre = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  if (const Vec3* v = regions.common_vertex(centre, half)) {
    for (int k = part.lo[2]; k < part.hi[2]; ++k) {
      for (int j = part.lo[1]; j < part.hi[1]; ++j) at_vertex(j, k, row_of(j, k), *v);
    }
    return;
  }
  // (Deciding each x-row of an undecided box as well was tried: fewer distance calls, but more
  // instructions in all.)
  for (int k = part.lo[2]; k < part.hi[2]; ++k) {
    for (int j = part.lo[1]; j < part.hi[1]; ++j) general(j, k, row_of(j, k));
  }
}

void BrickDistance::transfer_box(const NodeBox& box, Workspace& ws, double* d2) const {
  const NodeBox nodes = box.intersect(ws.clip);
  if (nodes.empty()) return;
  const auto& triangles = tree_.triangles();
  // The set S: the nearest triangles of the 27 brick centres around and t_b, the brick centre's
  // own. A triangle t can be the minimum of S at some node x of the box only if
  // dist(c, t) - r <= dist(x, t) <= dist(x, t_c) <= dist(c, t_c) + r (c the box centre, t_c the
  // set's nearest to c, r the half-diagonal): the kept set K gives every node the minimum over S.
  const Vec3 c = box_centre(box);
  const std::uint32_t tb = ws.brick_triangle;
  ws.transfer_kept.clear();
  if (box.extent(0) <= kTransferLeaf && box.extent(1) <= kTransferLeaf && box.extent(2) <= kTransferLeaf) {
    // One box of at most kTransferLeaf^3 nodes (every box in practice): its triangle t_c, the
    // nearest of K to c (ties: the lowest index; t_b first), is the nearest of S u {t_b} to c with
    // the same tie rule, since every minimizer is in K. So K is not needed: the minimum over S,
    // with the bounding-box pruning of scan() (conservative: a skipped triangle's computed
    // distance exceeds the best one, so it can be neither the minimum nor tied with it).
    double best = squared_distance(c, triangles[tb]);
    std::uint32_t tc = tb;
    double rb = std::sqrt(best) + slack_;
    double prune = rb * rb;
    std::size_t evaluations = 1;
    for (const std::uint32_t t : ws.transfer) {
      if (t == tb) continue;
      const PreparedTriangle& tri = triangles[t];
      if (gap2_to_bounds(tri, c) > prune) continue;
      const double d = squared_distance(c, tri);
      ++evaluations;
      if (d < best || (d == best && t < tc)) {
        best = d;
        tc = t;
        rb = std::sqrt(best) + slack_;
        prune = rb * rb;
      }
    }
    ws.counters.distance_evaluations += evaluations;
    transfer_fill(nodes, triangles[tc], ws, d2);
    ws.counters.transferred_nodes += nodes.count();
    return;
  }
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
    transfer_fill(part, triangles[tc], ws, d2);
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

void BrickDistance::band_children(const NodeBox& box, const std::uint32_t* index, std::size_t n, double bound2,
                                  Workspace::Children& out) const {
  // The halves of `box` in for_each_child's order, and per axis the world bounds of the lower and
  // upper half (the same expressions as band_box's lo/hi, so the gaps below are bit for bit the
  // ones a half would compute for itself).
  int parts[3], mid[3];
  double plo[3][2], phi[3][2];
  for (int a = 0; a < 3; ++a) {
    mid[a] = box.lo[a] + (box.extent(a) + 1) / 2;
    parts[a] = box.extent(a) > 1 ? 2 : 1;
    const double o = grid_.origin[a], h = grid_.spacing[a];
    plo[a][0] = o + static_cast<double>(box.lo[a]) * h;
    phi[a][0] = o + static_cast<double>(mid[a] - 1) * h;
    plo[a][1] = o + static_cast<double>(mid[a]) * h;
    phi[a][1] = o + static_cast<double>(box.hi[a] - 1) * h;
  }
  int pick[8][3];
  out.count = 0;
  for (int cz = 0; cz < parts[2]; ++cz) {
    for (int cy = 0; cy < parts[1]; ++cy) {
      for (int cx = 0; cx < parts[0]; ++cx) {
        const int c = out.count++;
        const int p[3] = {cx, cy, cz};
        NodeBox& child = out.box[c];
        for (int a = 0; a < 3; ++a) {
          pick[c][a] = p[a];
          child.lo[a] = p[a] == 0 ? box.lo[a] : mid[a];
          child.hi[a] = p[a] == 0 ? (parts[a] == 2 ? mid[a] : box.hi[a]) : box.hi[a];
        }
        Workspace::ChildList& list = out.list[c];
        if (list.index.size() < n + 1) {
          list.index.resize(n + 1);
          list.gap2.resize(n + 1);
        }
        list.size = 0;
      }
    }
  }
  const auto& triangles = tree_.triangles();
  const int count = out.count;
  std::uint32_t* idx[8];
  double* gap[8];
  std::size_t size[8];
  for (int c = 0; c < count; ++c) {
    idx[c] = out.list[c].index.data();
    gap[c] = out.list[c].gap2.data();
    size[c] = 0;
  }
  // One pass over the box's candidates: the per-axis squared gaps to both halves, then each half's
  // box-to-box squared gap summed in band_box's order ((x + y) + z), appended without a branch.
  for (std::size_t s = 0; s < n; ++s) {
    const std::uint32_t t = index[s];
    const PreparedTriangle& tri = triangles[t];
    double sq[3][2];
    for (int a = 0; a < 3; ++a) {
      for (int p = 0; p < 2; ++p) {
        const double g = positive(tri.lo[a] - phi[a][p]) + positive(plo[a][p] - tri.hi[a]);
        sq[a][p] = g * g;
      }
    }
    for (int c = 0; c < count; ++c) {
      const double g2 = sq[0][pick[c][0]] + sq[1][pick[c][1]] + sq[2][pick[c][2]];
      idx[c][size[c]] = t;
      gap[c][size[c]] = g2;
      size[c] += g2 <= bound2 ? 1 : 0;
    }
  }
  for (int c = 0; c < count; ++c) out.list[c].size = size[c];
}

void BrickDistance::band_box(const NodeBox& box, int depth, Workspace::ChildList* own, Workspace& ws,
                             double* d2) const {
  if (box.intersect(ws.clip).empty()) return;
  const auto& triangles = tree_.triangles();
  double lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = grid_.origin[a] + static_cast<double>(box.lo[a]) * grid_.spacing[a];
    hi[a] = grid_.origin[a] + static_cast<double>(box.hi[a] - 1) * grid_.spacing[a];
  }
  // Candidates of this box: the triangles whose bounding box is within `near` of the box, with
  // near = min(B, d(c) + r), B = the band plus slack, c the box centre, r its half-diagonal.
  // A node x of the box has d(x) <= dist(x, t_c) <= d_S(c) + r (t_c the nearest triangle to c
  // found, d_S(c) its distance), and its nearest triangle's bounding box is within d(x) of x:
  // so if d(x) <= band, or if near = d_S(c) + r, that triangle is a candidate and the node's
  // minimum over the candidates is its minimum over ALL triangles (any other triangle is
  // computed farther than near: B and the Lipschitz radius include the slack).
  // A half's candidates are those of its parent within B of it (band_children(), one pass for all
  // halves), then those within its own near.
  const double bound = band_ * (1.0 + 1e-12) + 3.0 * slack_;
  const double r = half_diagonal(box);
  const Vec3 c = box_centre(box);
  std::uint32_t tc = ws.brick_triangle;
  double dc = 0.0;
  const std::uint32_t* kept = nullptr;
  std::size_t kept_n = 0;
  if (depth == 0) {
    std::vector<std::uint32_t>& list = ws.transfer_level[0];
    list.clear();
    dc = std::sqrt(ws.brick_d2);  // the brick centre's exact distance (its BVH query)
    const double near = std::min(bound, (dc + r) * (1.0 + 1e-12) + 3.0 * slack_);
    tree_.collect_near_box(lo, hi, near * near, list);
    kept = list.data();
    kept_n = list.size();
  } else {
    std::uint32_t* index = own->index.data();
    double* gap2 = own->gap2.data();
    std::size_t n = own->size;
    // The minimum at c over t_b and the candidates (pruned by their bounding boxes).
    double best = squared_distance(c, triangles[tc]);
    double rb = std::sqrt(best) + slack_;
    double prune = rb * rb;
    for (std::size_t s = 0; s < n; ++s) {
      // c lies in this box, so its gap to a candidate's bounding box (monotone roundings from the
      // same coordinates) is at least the box's: skip on the stored box gap first.
      if (gap2[s] > prune) continue;
      const std::uint32_t t = index[s];
      const PreparedTriangle& tri = triangles[t];
      if (gap2_to_bounds(tri, c) > prune) continue;
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
      std::size_t m = 0;  // in place, without a branch
      for (std::size_t s = 0; s < n; ++s) {
        const double g2 = gap2[s];
        index[m] = index[s];
        gap2[m] = g2;
        m += g2 <= near2 ? 1 : 0;
      }
      n = m;
    }
    kept = index;
    kept_n = n;
  }
  if (kept_n == 0) {
    transfer_box(box, ws, d2);  // no triangle within the band of the box
    return;
  }
  if (box.count() > kLeafNodes && depth < kMaxDepth) {
    Workspace::Children& next = ws.children[static_cast<std::size_t>(depth)];
    band_children(box, kept, kept_n, bound * bound, next);
    for (int k = 0; k < next.count; ++k) band_box(next.box[k], depth + 1, &next.list[k], ws, d2);
    return;
  }
  // The leaf: candidates as arrays of bounding boxes, grouped by their squared box-to-box gap g2
  // to this box (computed as band_children() did for this box) into kLeafBuckets buckets of
  // increasing g2, each with its smallest g2 (scan_buckets()). A counting sort: O(n).
  const std::size_t n = kept_n;
  auto& gaps = ws.leaf_gap2;
  gaps.resize(n);
  if (depth == 0) {
    for (std::size_t s = 0; s < n; ++s) {
      const PreparedTriangle& tri = triangles[kept[s]];
      double g2 = 0.0;
      for (int a = 0; a < 3; ++a) {
        const double g = positive(tri.lo[a] - hi[a]) + positive(lo[a] - tri.hi[a]);
        g2 += g * g;
      }
      gaps[s] = g2;
    }
  } else {
    std::copy(own->gap2.data(), own->gap2.data() + n, gaps.data());
  }
  double largest = 0.0;
  for (std::size_t s = 0; s < n; ++s) largest = std::max(largest, gaps[s]);
  const double to_bucket = largest > 0.0 ? static_cast<double>(kLeafBuckets) / largest : 0.0;
  auto& bucket_of = ws.leaf_bucket;
  bucket_of.resize(n);
  std::size_t start[kLeafBuckets + 1] = {};
  double* bucket_min = ws.leaf_bucket_min;
  for (int k = 0; k < kLeafBuckets; ++k) bucket_min[k] = std::numeric_limits<double>::infinity();
  for (std::size_t s = 0; s < n; ++s) {
    // Any assignment is correct (a node skips only buckets whose OWN smallest gap is beyond its
    // bound); this one is monotone in g2. Written so that 0 x inf (NaN) lands in the last bucket.
    const double scaled = gaps[s] * to_bucket;
    const int k = scaled < static_cast<double>(kLeafBuckets) ? static_cast<int>(scaled) : kLeafBuckets - 1;
    bucket_of[s] = static_cast<std::uint8_t>(k);
    ++start[k + 1];
    bucket_min[k] = std::min(bucket_min[k], gaps[s]);
  }
  for (int k = 0; k < kLeafBuckets; ++k) start[k + 1] += start[k];
  for (int k = 0; k <= kLeafBuckets; ++k) ws.leaf_bucket_start[k] = start[k];
  Workspace::Candidates& cand = ws.leaf;
  cand.triangles = true;
  cand.index.resize(n);
  for (int a = 0; a < 3; ++a) {
    cand.lo[a].resize(n);
    cand.hi[a].resize(n);
  }
  for (std::size_t s = 0; s < n; ++s) {
    const std::size_t at = start[bucket_of[s]]++;
    const PreparedTriangle& tri = triangles[kept[s]];
    cand.index[at] = kept[s];
    for (int a = 0; a < 3; ++a) {
      cand.lo[a][at] = tri.lo[a];
      cand.hi[a][at] = tri.hi[a];
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
        TriangleTree::Nearest nn = scan_buckets(cand, p, hint, ws);
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
    // Each row starts from the previous row's first node (a neighbour), not from its last; then
    // each node from the previous node of its row. The rows are queried in blocks of 4 x 4 (j, k),
    // one packet per x (TriangleTree::nearest_packet(): the same results as one query per node),
    // listed as four 2 x 2 blocks: the quarters of the packet where it takes four traversals (AVX,
    // no AVX-512) are the 2 x 2 packets measured before.
    std::int64_t row_hint = centre.triangle;
    constexpr int kPacket = TriangleTree::kPacket;
    static_assert(kPacket == 16, "4 x 4 rows per packet");
    Vec3 points[kPacket];
    std::int64_t hints[kPacket];
    int rj[kPacket], rk[kPacket];
    TriangleTree::Nearest found[kPacket];
    for (int k0 = nodes.lo[2]; k0 < nodes.hi[2]; k0 += 4) {
      for (int j0 = nodes.lo[1]; j0 < nodes.hi[1]; j0 += 4) {
        int count = 0;
        for (int k_half = 0; k_half < 4; k_half += 2) {
          for (int j_half = 0; j_half < 4; j_half += 2) {
            for (int dk = k_half; dk < k_half + 2 && k0 + dk < nodes.hi[2]; ++dk) {
              for (int dj = j_half; dj < j_half + 2 && j0 + dj < nodes.hi[1]; ++dj) {
                rj[count] = j0 + dj, rk[count] = k0 + dk, hints[count] = row_hint;
                ++count;
              }
            }
          }
        }
        for (int i = nodes.lo[0]; i < nodes.hi[0]; ++i) {
          for (int c = 0; c < count; ++c) points[c] = grid_.position(i, rj[c], rk[c]);
          tree_.nearest_packet(points, hints, count, found);
          for (int c = 0; c < count; ++c) {
            hints[c] = found[c].triangle;
            d2[static_cast<std::size_t>(((rk[c] - b.lo[2]) * ey + (rj[c] - b.lo[1])) * ex + (i - b.lo[0]))] =
                found[c].squared_distance;
          }
          if (i == nodes.lo[0]) row_hint = found[0].triangle;
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

}  // namespace ppohdem::sdf::fast
