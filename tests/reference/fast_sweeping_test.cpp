// Fast sweeping: the Godunov update by hand, planar fronts reproduced exactly (the scheme is
// exact for linear distance functions), and convergence (one more round changes nothing).
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <limits>

#include "ppohdem/sdf/reference/fast_sweeping.hpp"

using ppohdem::GridSpec;
using ppohdem::ScalarField;
using ppohdem::Vec3;
using namespace ppohdem::sdf::reference;

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}

TEST(GodunovUpdate, HandComputedOneTwoThreeTerms) {
  EXPECT_DOUBLE_EQ(godunov_update({0.0, kInf, kInf}, {1, 1, 1}), 1.0);
  EXPECT_DOUBLE_EQ(godunov_update({0.0, 5.0, 5.0}, {0.5, 1, 1}), 0.5);       // 1 term, x <= a2
  EXPECT_DOUBLE_EQ(godunov_update({0.0, 0.0, kInf}, {1, 1, 1}), std::sqrt(0.5));  // 2 (x - 0)^2 = 1
  EXPECT_DOUBLE_EQ(godunov_update({0.0, 0.0, 0.0}, {1, 1, 1}), std::sqrt(1.0 / 3.0));
  EXPECT_EQ(godunov_update({kInf, kInf, kInf}, {1, 1, 1}), kInf);
  // Anisotropic: (x/3)^2 + (x/4)^2 = 1 -> x = 12/5.
  EXPECT_DOUBLE_EQ(godunov_update({0.0, 0.0, kInf}, {3, 4, 1}), 2.4);
}

RC_GTEST_PROP(GodunovUpdate, ExactForLinearFunctions, ()) {
  // u(x) = n.x with |n| = 1, n >= 0: the upwind neighbours hold u - h_m n_m, the update returns u.
  const Vec3 n = Vec3(*rc::gen::inRange(0, 100), *rc::gen::inRange(0, 100), *rc::gen::inRange(1, 100)).normalized();
  const Vec3 h = Vec3(*rc::gen::inRange(1, 100), *rc::gen::inRange(1, 100), *rc::gen::inRange(1, 100)) / 50.0;
  const double u = *rc::gen::inRange(0, 1000) / 10.0;
  const double x = godunov_update({u - h.x() * n.x(), u - h.y() * n.y(), u - h.z() * n.z()}, {h.x(), h.y(), h.z()});
  RC_ASSERT(std::abs(x - u) <= 1e-12 * (1.0 + u));  // a few roundings of O(u) quantities
}

namespace {

/// |n.x - c| on every node, with the nodes within `band` frozen and the rest set to +inf.
ScalarField plane_distance_problem(const GridSpec& g, const Vec3& n, double c, double band, std::vector<bool>& frozen,
                                   ScalarField& exact) {
  ScalarField u(g, kInf);
  exact = ScalarField(g);
  frozen.assign(g.node_count(), false);
  for (int k = 0; k < g.nodes[2]; ++k)
    for (int j = 0; j < g.nodes[1]; ++j)
      for (int i = 0; i < g.nodes[0]; ++i) {
        const double d = std::abs(n.dot(g.position(i, j, k)) - c);
        exact.at(i, j, k) = d;
        if (d <= band) {
          u.at(i, j, k) = d;
          frozen[g.index(i, j, k)] = true;
        }
      }
  return u;
}

}  // namespace

TEST(FastSweeping, ReproducesPlanarDistanceOnAnisotropicGrid) {
  GridSpec g;
  g.origin = Vec3(-1, -1, -1);
  g.spacing = Vec3(0.1, 0.13, 0.07);
  g.nodes = {21, 16, 29};
  const Vec3 n = Vec3(0.3, -0.5, 0.8).normalized();
  std::vector<bool> frozen;
  ScalarField exact;
  ScalarField u = plane_distance_problem(g, n, 0.05, 0.2, frozen, exact);
  const int sweeps = fast_sweep(u, frozen);
  EXPECT_EQ(sweeps % 8, 0);
  // The upwind stencil of node p reaches the plane at its three "axis feet" p - (d / m_a) e_a
  // (d = distance, m = unit normal pointing from the plane to p). If they all lie in the grid,
  // the whole domain of dependence does, and the scheme reproduces the linear function exactly.
  // Otherwise the characteristics enter through the domain boundary, where no data is given.
  const Vec3 lo = g.origin, hi = g.upper_corner();
  double worst = 0.0;
  int checked = 0;
  for (int k = 0; k < g.nodes[2]; ++k)
    for (int j = 0; j < g.nodes[1]; ++j)
      for (int i = 0; i < g.nodes[0]; ++i) {
        const Vec3 p = g.position(i, j, k);
        const double signed_distance = n.dot(p) - 0.05;
        const Vec3 m = signed_distance > 0 ? n : Vec3(-n);
        bool feet_inside = true;
        for (int a = 0; a < 3; ++a) {
          const double foot = p[a] - std::abs(signed_distance) / m[a];
          feet_inside = feet_inside && foot >= lo[a] && foot <= hi[a];
        }
        if (!feet_inside) continue;
        worst = std::max(worst, std::abs(u.at(i, j, k) - exact.at(i, j, k)));
        ++checked;
      }
  std::cout << "planar front, anisotropic h: max error " << worst << " over " << checked << " nodes, " << sweeps
            << " sweeps\n";
  EXPECT_GT(checked, 1000);
  EXPECT_LE(worst, 1e-13);  // exact scheme: only round-off accumulated along ~60 updates
}

TEST(FastSweeping, ConvergedFieldIsAFixedPoint) {
  GridSpec g;
  g.origin = Vec3(0, 0, 0);
  g.spacing = Vec3(0.1, 0.1, 0.1);
  g.nodes = {15, 15, 15};
  // A point source at the centre node: the classical non-planar front.
  ScalarField u(g, kInf);
  std::vector<bool> frozen(g.node_count(), false);
  u.at(7, 7, 7) = 0.0;
  frozen[g.index(7, 7, 7)] = true;
  const int sweeps = fast_sweep(u, frozen);
  EXPECT_GE(sweeps, 8);
  const ScalarField converged = u;
  EXPECT_EQ(fast_sweep(u, frozen), 8);  // one round, no change
  EXPECT_EQ(u.values, converged.values);
  // Along the axes the 1-term update is exact: distance = n h.
  EXPECT_DOUBLE_EQ(u.at(14, 7, 7), 0.7);
  // First-order scheme over-estimates off-axis distances of a point source (Zhao 2005, sec. 3).
  EXPECT_GE(u.at(14, 14, 14), std::sqrt(3.0) * 0.7);
}
