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
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "ppohdem/dem/particle.hpp"

namespace ppohdem::dem::fast {

class Decomposition {
 public:
  Decomposition() = default;
  /// `ranks` bricks over the bounding box of `centres` (the same on every rank).
  Decomposition(int ranks, const std::vector<Vec3>& centres) : ranks_(ranks) {
    lo_ = Vec3::Zero();
    Vec3 hi = Vec3::Zero();
    if (!centres.empty()) {
      lo_ = centres.front();
      hi = centres.front();
      for (const Vec3& x : centres) {
        lo_ = lo_.cwiseMin(x);
        hi = hi.cwiseMax(x);
      }
    }
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
  }

  int ranks() const { return ranks_; }
  const std::array<int, 3>& dims() const { return dims_; }

  /// The rank owning a particle centred at x.
  int owner(const Vec3& x) const {
    std::array<int, 3> c{};
    for (int a = 0; a < 3; ++a) c[a] = coordinate(a, x[a]);
    return c[0] + dims_[0] * (c[1] + dims_[1] * c[2]);
  }

  /// Squared distance from x to rank r's brick (0 inside) [m^2]. Bricks are taken
  /// `slack` [m] larger on every side, so rounding at a face never hides a neighbour.
  double distance2(int r, const Vec3& x, double slack) const {
    const std::array<int, 3> c = {r % dims_[0], (r / dims_[0]) % dims_[1], r / (dims_[0] * dims_[1])};
    double d2 = 0.0;
    for (int a = 0; a < 3; ++a) {
      const double inf = std::numeric_limits<double>::infinity();
      const double lower = c[a] == 0 ? -inf : lo_[a] + c[a] * h_[a] - slack;
      const double upper = c[a] == dims_[a] - 1 ? inf : lo_[a] + (c[a] + 1) * h_[a] + slack;
      const double gap = x[a] < lower ? lower - x[a] : (x[a] > upper ? x[a] - upper : 0.0);
      d2 += gap * gap;
    }
    return d2;
  }

 private:
  int coordinate(int a, double x) const {
    const double u = std::floor((x - lo_[a]) / h_[a]);
    if (!(u >= 0.0)) return 0;  // also NaN: rank 0 on this axis (the run diagnostics stop the run)
    return u >= dims_[a] - 1 ? dims_[a] - 1 : static_cast<int>(u);
  }

  int ranks_ = 1;
  std::array<int, 3> dims_ = {1, 1, 1};
  Vec3 lo_ = Vec3::Zero();
  std::array<double, 3> h_ = {1.0, 1.0, 1.0};
};

}  // namespace ppohdem::dem::fast
