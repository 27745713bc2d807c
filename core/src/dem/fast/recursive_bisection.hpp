#pragma once
// Recursive coordinate bisection of the particles over P ranks by particle count (docs/dem.md
// "Load balance"). Private to core/src/dem/fast.
//
// The ranks [first, first + n) of a node split into n / 2 (left) and the rest; the node's
// particles are cut across the longest axis of their bounding box so that the left part holds
// round(count * (n / 2) / n) of them exactly: a particle goes left iff (x[axis], id) <= (cut,
// cut id) in the order of ordered_key and ordered_id, so particles on the cut plane (a lattice
// layer) are split by id. The cuts are found by a search over the 64-bit keys, 15 probes per
// node and round (4 bits a round), counting through `comm` (SerialComm: the particles given
// are the whole system; a world communicator: each rank gives its own and the counts are
// summed). The counts are exact integers, so every rank, and the whole-system and the
// distributed versions, find the same cuts.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "ppohdem/comm/comm.hpp"
#include "ppohdem/dem/particle.hpp"

namespace ppohdem::dem::fast {

/// Orders doubles as < does (-0 just before +0; NaN at the ends).
inline std::uint64_t ordered_key(double v) {
  const auto bits = std::bit_cast<std::uint64_t>(v);
  return (bits >> 63) != 0 ? ~bits : bits | (std::uint64_t{1} << 63);
}
/// The inverse of ordered_key.
inline double from_ordered_key(std::uint64_t k) {
  return std::bit_cast<double>((k >> 63) != 0 ? k & ~(std::uint64_t{1} << 63) : ~k);
}
/// Orders ids as < does.
inline std::uint64_t ordered_id(std::int64_t id) { return static_cast<std::uint64_t>(id) ^ (std::uint64_t{1} << 63); }

struct BisectionNode {
  int first_rank = 0;
  int ranks = 1;  ///< 1: a leaf (rank first_rank)
  int axis = 0;
  std::uint64_t key = 0, id = 0;  ///< left iff (ordered_key(x[axis]), ordered_id(id)) <= (key, id)
  int left = -1, right = -1;

  bool goes_left(const Vec3& x, std::int64_t particle_id) const {
    const std::uint64_t k = ordered_key(x[axis]);
    return k < key || (k == key && ordered_id(particle_id) <= id);
  }
};

namespace bisection_detail {

/// For every node j of a round: the smallest q in [lo[j], hi[j]] with F_j(q) >= target[j],
/// where F_j(q) counts the node's particles whose search value is <= q and `value(k, j)`
/// gives particle k's search value (false: k does not count). F_j(hi[j]) >= target[j]; at_hi[j]
/// is F_j(hi[j]) (on entry and on return).
template <class NodeOf, class Value>
void search(const Comm& comm, std::size_t n, const NodeOf& node_of, const Value& value, std::vector<std::uint64_t>& lo,
            std::vector<std::uint64_t>& hi, const std::vector<std::uint64_t>& target, std::vector<double>& at_hi) {
  constexpr std::size_t kProbes = 15;
  const std::size_t m = lo.size();
  for (std::size_t j = 0; j < m; ++j) {
    if (target[j] == 0) hi[j] = lo[j];  // F >= 0 everywhere (at_hi is not needed then)
  }
  std::vector<std::array<std::uint64_t, kProbes>> probes(m);
  std::vector<std::size_t> used(m);
  for (;;) {
    bool open = false;
    for (std::size_t j = 0; j < m; ++j) {
      const std::uint64_t width = hi[j] - lo[j];
      const std::uint64_t step = std::max<std::uint64_t>(width / (kProbes + 1), 1);
      used[j] = 0;
      for (std::size_t i = 1; i <= kProbes; ++i) {
        const std::uint64_t q = lo[j] + step * i - 1;
        if (q >= hi[j]) break;
        probes[j][used[j]++] = q;
      }
      open = open || used[j] > 0;
    }
    if (!open) return;  // the same on every rank: lo and hi come from the summed counts
    std::vector<double> counts(m * kProbes, 0.0);  // counts[j * kProbes + i]: values <= probe i
    for (std::size_t k = 0; k < n; ++k) {
      const int j = node_of(k);
      if (j < 0) continue;
      std::uint64_t v = 0;
      if (!value(k, static_cast<std::size_t>(j), v)) continue;
      const auto& p = probes[static_cast<std::size_t>(j)];
      const std::size_t u = used[static_cast<std::size_t>(j)];
      const std::size_t first = static_cast<std::size_t>(std::lower_bound(p.begin(), p.begin() + u, v) - p.begin());
      if (first < u) counts[static_cast<std::size_t>(j) * kProbes + first] += 1.0;
    }
    counts = comm.sum_each_over_ranks(std::move(counts));
    for (std::size_t j = 0; j < m; ++j) {
      double below = 0.0;
      std::size_t i = 0;
      for (; i < used[j]; ++i) {
        below += counts[j * kProbes + i];
        if (below >= static_cast<double>(target[j])) break;
      }
      if (i < used[j]) {
        hi[j] = probes[j][i];
        at_hi[j] = below;
        if (i > 0) lo[j] = probes[j][i - 1] + 1;
      } else if (used[j] > 0) {
        lo[j] = probes[j][used[j] - 1] + 1;
      }
    }
  }
}

}  // namespace bisection_detail

/// The bisection tree of `ranks` over the particles x[0..n) with ids id[0..n) (see the top of
/// this file); nodes[0] is the root. Collective over `comm` when it has several ranks.
inline std::vector<BisectionNode> bisect(int ranks, const std::vector<Vec3>& x, const std::vector<std::int64_t>& id,
                                         std::size_t n, const Comm& comm) {
  std::vector<BisectionNode> nodes(1);
  nodes[0].ranks = ranks;
  std::vector<int> node(n, 0);  // each particle's node in the tree so far
  std::vector<int> frontier;
  if (ranks > 1) frontier.push_back(0);
  while (!frontier.empty()) {
    const std::size_t m = frontier.size();
    std::vector<int> slot(nodes.size(), -1);
    for (std::size_t j = 0; j < m; ++j) slot[static_cast<std::size_t>(frontier[j])] = static_cast<int>(j);
    auto node_of = [&](std::size_t k) { return slot[static_cast<std::size_t>(node[k])]; };
    // Counts and bounding boxes of the nodes' particles.
    std::vector<double> counts(m, 0.0);
    const double inf = std::numeric_limits<double>::infinity();
    std::vector<double> extremes(6 * m, -inf);  // max x, y, z and -min x, y, z
    for (std::size_t k = 0; k < n; ++k) {
      const int j = node_of(k);
      if (j < 0) continue;
      counts[static_cast<std::size_t>(j)] += 1.0;
      for (int a = 0; a < 3; ++a) {
        double& high = extremes[6 * static_cast<std::size_t>(j) + static_cast<std::size_t>(a)];
        double& low = extremes[6 * static_cast<std::size_t>(j) + 3 + static_cast<std::size_t>(a)];
        high = std::max(high, x[k][a]);
        low = std::max(low, -x[k][a]);
      }
    }
    counts = comm.sum_each_over_ranks(std::move(counts));
    extremes = comm.max_each_over_ranks(std::move(extremes));
    std::vector<std::uint64_t> target(m), lo(m, 0), hi(m, std::numeric_limits<std::uint64_t>::max());
    for (std::size_t j = 0; j < m; ++j) {
      BisectionNode& b = nodes[static_cast<std::size_t>(frontier[j])];
      b.axis = 0;  // the longest extent; ties to the lower axis
      for (int a = 1; a < 3; ++a) {
        const auto extent = [&](int e) { return extremes[6 * j + e] + extremes[6 * j + 3 + e]; };
        if (extent(a) > extent(b.axis)) b.axis = a;
      }
      const auto count = static_cast<std::uint64_t>(counts[j]);
      const auto left = static_cast<std::uint64_t>(b.ranks / 2), all = static_cast<std::uint64_t>(b.ranks);
      target[j] = (count * left + all / 2) / all;
    }
    // The cut key: the smallest key with at least target particles at or below it.
    std::vector<double> at_hi = counts;
    auto axis_of = [&](std::size_t j) { return nodes[static_cast<std::size_t>(frontier[j])].axis; };
    bisection_detail::search(
        comm, n, node_of,
        [&](std::size_t k, std::size_t j, std::uint64_t& v) {
          v = ordered_key(x[k][axis_of(j)]);
          return true;
        },
        lo, hi, target, at_hi);
    const std::vector<std::uint64_t> key = hi;
    // The cut id among the particles on the cut key (those below it count for every probe);
    // all of them go left when that makes the target (no particle on the cut: no search).
    for (std::size_t j = 0; j < m; ++j) {
      hi[j] = std::numeric_limits<std::uint64_t>::max();
      lo[j] = at_hi[j] == static_cast<double>(target[j]) ? hi[j] : 0;
    }
    bisection_detail::search(
        comm, n, node_of,
        [&](std::size_t k, std::size_t j, std::uint64_t& v) {
          const std::uint64_t kk = ordered_key(x[k][axis_of(j)]);
          if (kk > key[j]) return false;
          v = kk < key[j] ? 0 : ordered_id(id[k]);
          return true;
        },
        lo, hi, target, at_hi);
    std::vector<int> next;
    for (std::size_t j = 0; j < m; ++j) {
      const auto at = static_cast<std::size_t>(frontier[j]);
      nodes[at].key = key[j];
      nodes[at].id = hi[j];
      BisectionNode left, right;
      left.first_rank = nodes[at].first_rank;
      left.ranks = nodes[at].ranks / 2;
      right.first_rank = left.first_rank + left.ranks;
      right.ranks = nodes[at].ranks - left.ranks;
      nodes[at].left = static_cast<int>(nodes.size());
      nodes[at].right = static_cast<int>(nodes.size() + 1);
      nodes.push_back(left);
      nodes.push_back(right);
      if (left.ranks > 1) next.push_back(nodes[at].left);
      if (right.ranks > 1) next.push_back(nodes[at].right);
    }
    for (std::size_t k = 0; k < n; ++k) {
      const BisectionNode& b = nodes[static_cast<std::size_t>(node[k])];
      if (b.ranks > 1) node[k] = b.goes_left(x[k], id[k]) ? b.left : b.right;
    }
    frontier.swap(next);
  }
  return nodes;
}

}  // namespace ppohdem::dem::fast
