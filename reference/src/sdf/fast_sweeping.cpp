/// \file fast_sweeping.cpp
/// Zhao (2005) fast sweeping with the anisotropic Godunov update. See fast_sweeping.hpp.
#include "ppohdem/sdf/reference/fast_sweeping.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace ppohdem::sdf::reference {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// Larger root of sum_{m < n} ((x - a_m) / h_m)^2 = 1.
/// Solved for y = x - a_0 with the offsets d_m = a_m - a_0 (a_0 is the smallest neighbour): the
/// coefficients then stay O(1/h^2) instead of O(a^2/h^2), which avoids the catastrophic
/// cancellation in B^2 - A C far from the surface (a ~ 400 h lost ~6 digits before this shift).
double solve_with_terms(const std::array<double, 3>& a, const std::array<double, 3>& h, int n) {
  double quadratic = 0.0, linear = 0.0, constant = -1.0;  // A y^2 - 2 B y + C = 0
  for (std::size_t m = 0; m < static_cast<std::size_t>(n); ++m) {
    const double w = 1.0 / (h[m] * h[m]);
    const double d = a[m] - a[0];
    quadratic += w;
    linear += d * w;
    constant += d * d * w;
  }
  // B^2 - A C >= 0 whenever x_(n-1) > a_(n-1); clamp the rounding below zero.
  const double discriminant = std::max(linear * linear - quadratic * constant, 0.0);
  return a[0] + (linear + std::sqrt(discriminant)) / quadratic;
}

/// Smaller of the two axis neighbours of node (i, j, k) along `axis`, +inf if none.
double neighbour_minimum(const ScalarField& u, int i, int j, int k, int axis) {
  Index3 lower = {i, j, k};
  Index3 upper = {i, j, k};
  const std::size_t a = static_cast<std::size_t>(axis);
  lower[a] -= 1;
  upper[a] += 1;
  double result = kInfinity;
  if (lower[a] >= 0) result = std::min(result, u.at(lower[0], lower[1], lower[2]));
  if (upper[a] < u.grid.nodes[a]) result = std::min(result, u.at(upper[0], upper[1], upper[2]));
  return result;
}

/// One sweep in the order given by the sign of each axis' step; returns true if a value changed.
bool sweep_once(ScalarField& u, const std::vector<bool>& frozen, const Index3& step) {
  const GridSpec& g = u.grid;
  const std::array<double, 3> h = {g.spacing.x(), g.spacing.y(), g.spacing.z()};
  auto first = [&](int axis) { return step[static_cast<std::size_t>(axis)] > 0 ? 0 : g.nodes[static_cast<std::size_t>(axis)] - 1; };
  auto past_end = [&](int axis) { return step[static_cast<std::size_t>(axis)] > 0 ? g.nodes[static_cast<std::size_t>(axis)] : -1; };
  bool changed = false;
  for (int k = first(2); k != past_end(2); k += step[2]) {
    for (int j = first(1); j != past_end(1); j += step[1]) {
      for (int i = first(0); i != past_end(0); i += step[0]) {
        if (frozen[g.index(i, j, k)]) continue;
        const std::array<double, 3> a = {neighbour_minimum(u, i, j, k, 0), neighbour_minimum(u, i, j, k, 1),
                                         neighbour_minimum(u, i, j, k, 2)};
        const double candidate = godunov_update(a, h);
        if (candidate < u.at(i, j, k)) {
          u.at(i, j, k) = candidate;
          changed = true;
        }
      }
    }
  }
  return changed;
}

}  // namespace

double godunov_update(std::array<double, 3> a, std::array<double, 3> h) {
  // Sort the axes by a (carrying their spacing along).
  std::array<std::size_t, 3> order = {0, 1, 2};
  std::sort(order.begin(), order.end(), [&](std::size_t s, std::size_t t) { return a[s] < a[t]; });
  const std::array<double, 3> sorted_a = {a[order[0]], a[order[1]], a[order[2]]};
  const std::array<double, 3> sorted_h = {h[order[0]], h[order[1]], h[order[2]]};
  if (sorted_a[0] == kInfinity) return kInfinity;

  double x = sorted_a[0] + sorted_h[0];  // one term
  if (x <= sorted_a[1]) return x;
  x = solve_with_terms(sorted_a, sorted_h, 2);
  if (x <= sorted_a[2]) return x;
  return solve_with_terms(sorted_a, sorted_h, 3);
}

int fast_sweep(ScalarField& distance, const std::vector<bool>& frozen) {
  int sweeps = 0;
  bool changed_in_round = true;
  while (changed_in_round) {
    changed_in_round = false;
    for (int order = 0; order < 8; ++order) {  // the 8 sign patterns of (step_i, step_j, step_k)
      const Index3 step = {(order & 1) ? -1 : 1, (order & 2) ? -1 : 1, (order & 4) ? -1 : 1};
      if (sweep_once(distance, frozen, step)) changed_in_round = true;
      ++sweeps;
    }
  }
  return sweeps;
}

}  // namespace ppohdem::sdf::reference
