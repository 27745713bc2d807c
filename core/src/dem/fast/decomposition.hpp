#pragma once
// Cartesian domain decomposition of the fast engine (docs/dem.md, "Domain decomposition").
// Private to core/src/dem/fast.
//
// The box is the bounding box of the particle centres at construction, cut into
// dims[0] x dims[1] x dims[2] = P equal bricks; dims come from a balanced factorisation of P
// (prime factors, largest first, each given to the axis whose bricks are currently longest;
// like MPI_Dims_create but weighted by the box's extents). Rank r has brick coordinates
// c = (r mod d0, (r / d0) mod d1, r / (d0 d1)). The outer bricks extend to infinity, so every
// point has exactly one owner: owner(x) = the brick index floor((x - lo) / h) clamped to
// [0, d - 1] on each axis. Ownership only changes at a neighbour-list build (migration).
//
// Or (bisected(): `[parallel] balance = "rcb"`, docs/dem.md "Load balance") the bricks of a
// recursive coordinate bisection by particle count (recursive_bisection.hpp), re-cut during
// the run; owner() walks its tree. Either way each rank's brick is a box (outer faces at
// infinity), and the peers of a rank are the ranks whose bricks lie within the halo reach of
// its own: the only ranks it exchanges ghosts and migrants with.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "ppohdem/dem/particle.hpp"
#include "recursive_bisection.hpp"

namespace ppohdem::dem::fast {

class Decomposition {
 public:
  Decomposition() = default;
  /// `ranks` bricks over the bounding box of `centres` (the same on every rank).
  Decomposition(int ranks, const std::vector<Vec3>& centres)
      : Decomposition(ranks, box_of(centres).first, box_of(centres).second) {}
  /// `ranks` bricks over the box [lo, hi].
  Decomposition(int ranks, const Vec3& lo, const Vec3& hi) : ranks_(ranks), lo_(lo) {
    const Vec3 extent = hi - lo_;
    std::vector<int> factors;
    for (int n = ranks, f = 2; n > 1;) {
      if (n % f == 0) {
        factors.push_back(f);
        n /= f;
      } else {
        ++f;
      }
    }
    std::sort(factors.rbegin(), factors.rend());
    for (const int f : factors) {
      int axis = 0;  // longest brick edge; ties to the lower axis
      for (int a = 1; a < 3; ++a) {
        if (extent[a] / dims_[a] > extent[axis] / dims_[axis]) axis = a;
      }
      dims_[axis] *= f;
    }
    for (int a = 0; a < 3; ++a) h_[a] = extent[a] > 0.0 ? extent[a] / dims_[a] : 1.0;
    const double inf = std::numeric_limits<double>::infinity();
    boxes_.resize(static_cast<std::size_t>(ranks));
    for (int r = 0; r < ranks; ++r) {
      const std::array<int, 3> c = {r % dims_[0], (r / dims_[0]) % dims_[1], r / (dims_[0] * dims_[1])};
      for (int a = 0; a < 3; ++a) {
        boxes_[static_cast<std::size_t>(r)].lower[a] = c[a] == 0 ? -inf : lo_[a] + c[a] * h_[a];
        boxes_[static_cast<std::size_t>(r)].upper[a] = c[a] == dims_[a] - 1 ? inf : lo_[a] + (c[a] + 1) * h_[a];
      }
    }
  }

  /// The bricks of a recursive coordinate bisection of the particles x[0..n), id[0..n) by count
  /// (recursive_bisection.hpp): the whole system with a SerialComm, else each rank's own
  /// particles (collective).
  static Decomposition bisection(int ranks, const std::vector<Vec3>& x, const std::vector<std::int64_t>& id,
                                 std::size_t n, const Comm& comm) {
    Decomposition d;
    d.ranks_ = ranks;
    d.dims_ = {0, 0, 0};
    d.tree_ = bisect(ranks, x, id, n, comm);
    const double inf = std::numeric_limits<double>::infinity();
    d.boxes_.assign(static_cast<std::size_t>(ranks), Box{{-inf, -inf, -inf}, {inf, inf, inf}});
    d.set_boxes(0, d.boxes_.front());
    return d;
  }

  int ranks() const { return ranks_; }
  /// Bricks per axis of the equal bricks; {0, 0, 0} for a bisection.
  const std::array<int, 3>& dims() const { return dims_; }
  bool bisected() const { return !tree_.empty(); }

  /// The rank owning a particle centred at x with this id (the id decides on a bisection's
  /// cut plane only).
  int owner(const Vec3& x, std::int64_t id) const {
    if (bisected()) {
      std::size_t at = 0;
      while (tree_[at].ranks > 1) at = static_cast<std::size_t>(tree_[at].goes_left(x, id) ? tree_[at].left : tree_[at].right);
      return tree_[at].first_rank;
    }
    std::array<int, 3> c{};
    for (int a = 0; a < 3; ++a) c[a] = coordinate(a, x[a]);
    return c[0] + dims_[0] * (c[1] + dims_[1] * c[2]);
  }

  /// Squared distance from x to rank r's brick (0 inside) [m^2]. Bricks are taken
  /// `slack` [m] larger on every side, so rounding at a face never hides a neighbour.
  double distance2(int r, const Vec3& x, double slack) const {
    const Box& b = boxes_[static_cast<std::size_t>(r)];
    double d2 = 0.0;
    for (int a = 0; a < 3; ++a) {
      const double lower = b.lower[a] - slack, upper = b.upper[a] + slack;
      const double gap = x[a] < lower ? lower - x[a] : (x[a] > upper ? x[a] - upper : 0.0);
      d2 += gap * gap;
    }
    return d2;
  }

  /// The ranks other than `me` whose bricks, each `slack` larger on every side, come closer
  /// than `reach` to me's (ascending). Symmetric: r is a peer of me iff me is one of r's.
  std::vector<int> peers(int me, double reach, double slack) const {
    std::vector<int> out;
    const Box& mine = boxes_[static_cast<std::size_t>(me)];
    for (int r = 0; r < ranks_; ++r) {
      if (r == me) continue;
      const Box& b = boxes_[static_cast<std::size_t>(r)];
      double d2 = 0.0;
      for (int a = 0; a < 3; ++a) {
        // Gap between [lo1, hi1] and [lo2, hi2], both grown by slack (and empty gaps 0).
        const double gap = std::max({0.0, (b.lower[a] - slack) - (mine.upper[a] + slack),
                                     (mine.lower[a] - slack) - (b.upper[a] + slack)});
        d2 += gap * gap;
      }
      if (d2 < reach * reach) out.push_back(r);
    }
    return out;
  }

 private:
  /// The smallest box holding `centres` (zero: none).
  static std::pair<Vec3, Vec3> box_of(const std::vector<Vec3>& centres) {
    if (centres.empty()) return {Vec3::Zero(), Vec3::Zero()};
    Vec3 lo = centres.front(), hi = centres.front();
    for (const Vec3& x : centres) {
      lo = lo.cwiseMin(x);
      hi = hi.cwiseMax(x);
    }
    return {lo, hi};
  }

  struct Box {
    std::array<double, 3> lower, upper;
  };

  /// The boxes of the leaves under tree node `at`, whose box is `box`. A cut's plane is the
  /// double of its key, kept inside the node's box (a NaN or outside cut: an empty side).
  void set_boxes(std::size_t at, const Box& box) {
    const BisectionNode& node = tree_[at];
    if (node.ranks == 1) {
      boxes_[static_cast<std::size_t>(node.first_rank)] = box;
      return;
    }
    const int a = node.axis;
    double cut = from_ordered_key(node.key);
    if (!(cut >= box.lower[a])) cut = box.lower[a];  // also NaN
    cut = std::min(cut, box.upper[a]);
    Box left = box, right = box;
    left.upper[a] = cut;
    right.lower[a] = cut;
    set_boxes(static_cast<std::size_t>(node.left), left);
    set_boxes(static_cast<std::size_t>(node.right), right);
  }

  int coordinate(int a, double x) const {
    const double u = std::floor((x - lo_[a]) / h_[a]);
    if (!(u >= 0.0)) return 0;  // also NaN: rank 0 on this axis (the run diagnostics stop the run)
    return u >= dims_[a] - 1 ? dims_[a] - 1 : static_cast<int>(u);
  }

  int ranks_ = 1;
  std::array<int, 3> dims_ = {1, 1, 1};
  Vec3 lo_ = Vec3::Zero();
  std::array<double, 3> h_ = {1.0, 1.0, 1.0};
  std::vector<Box> boxes_ = std::vector<Box>(1, Box{{-kInf, -kInf, -kInf}, {kInf, kInf, kInf}});
  std::vector<BisectionNode> tree_;  ///< empty: the equal bricks
  static constexpr double kInf = std::numeric_limits<double>::infinity();
};

/// The halo rule (halo.cpp, and the projection to many ranks, halo_projection.cpp): a particle
/// centred at x is a ghost on rank r iff it lies within `reach` = 2 R_max + skin of r's brick,
/// each brick taken one part in 1e6 of the reach larger, so that the rounding of a brick face
/// (relative 1e-16 of the coordinates) never hides a partner; extra ghosts cost nothing but
/// memory (the list keeps only pairs within R_i + R_j + skin).
inline double halo_slack(double reach) { return 1e-6 * reach; }
/// The halo reach [m]: two of the largest radius and the Verlet skin.
inline double halo_reach(double r_max, double skin) { return 2.0 * r_max + skin; }
/// The ranks rank `me` exchanges ghosts and migrants with under the halo rule.
inline std::vector<int> halo_peers(const Decomposition& d, int me, double reach) {
  return d.peers(me, reach, halo_slack(reach));
}
/// Whether a particle centred at x is a ghost on rank r under the halo rule.
inline bool in_halo(const Decomposition& d, int r, const Vec3& x, double reach) {
  return d.distance2(r, x, halo_slack(reach)) < reach * reach;
}

}  // namespace ppohdem::dem::fast
