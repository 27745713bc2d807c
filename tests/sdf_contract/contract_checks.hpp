#pragma once
/// \file contract_checks.hpp
/// The checks the contract bodies share. Each takes the builder's traits (sdf_builder_traits.hpp)
/// and turns them into the expectation at one node: the exact value where the builder claims it,
/// its declared bound elsewhere. docs/sdf.md §6.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "ppohdem/grid/scalar_field.hpp"
#include "ppohdem/mesh/triangle_mesh.hpp"
#include "ppohdem/sdf/signed_distance.hpp"
#include "sdf_builder_traits.hpp"

namespace ppohdem::test::sdf_contract {

/// What an oracle knows at a node: the true signed distance lies in [lo, hi] [m]. A point value
/// has lo == hi; an inscribed polyhedron gives [ball, ball + sag]. `skip` marks a node where the
/// oracle has no answer (on the surface, or w = 1/2 exactly for a winding number).
struct OracleInterval {
  double lo = 0.0;
  double hi = 0.0;
  bool skip = false;
  static OracleInterval exactly(double value) { return {value, value, false}; }
  /// Smallest and largest |phi| in the interval.
  double distance_lo() const { return (lo <= 0.0 && hi >= 0.0) ? 0.0 : std::min(std::abs(lo), std::abs(hi)); }
  double distance_hi() const { return std::max(std::abs(lo), std::abs(hi)); }
};

/// Counts of one contract check, for the assertions and for the failure message.
struct ContractTally {
  std::size_t exact_nodes = 0;      ///< nodes where the builder claims the exact value
  std::size_t bounded_nodes = 0;    ///< nodes under the builder's declared bound instead
  std::size_t sign_checked = 0;     ///< nodes whose sign the oracle decides
  std::size_t violations = 0;       ///< value outside its expectation, or the wrong sign
  double worst_exact_error = 0.0;   ///< max distance of phi from the oracle interval, exact nodes [m]
  double worst_above_h = 0.0;       ///< max (|phi| - largest true |phi|) / h_max, bounded nodes
  double worst_below_h = 0.0;       ///< max (smallest true |phi| - |phi|) / h_max, bounded nodes
  std::string first_violation;      ///< where and by how much, for the failure message
};

/// True if a node whose true value lies in `o` is in the region where builder B claims exactness.
template <typename B>
bool claims_exact(const OracleInterval& o, const GridSpec& grid, bool no_node_in_band) {
  if (B::exact_everywhere) return true;
  if (no_node_in_band && B::exact_when_no_node_in_band) return true;
  // Nodes a rounding away from the band's edge may fall on either side: the bound applies to
  // them, and it always contains the exact value.
  return o.distance_hi() < B::exact_band(grid) * (1.0 - 1e-9);
}

/// Checks every node of `phi` (built by B) against `oracle(position) -> OracleInterval`.
/// `rounding` [m] is the case's allowance for the rounding of an exact builder (it depends on
/// the coordinates' magnitude, so the case sets it), plus `relative_rounding` max(|phi|, h_min);
/// `sign_tolerance` [m]: signs are checked where the oracle interval, widened by it, does not
/// contain 0.
template <typename B, typename Oracle>
ContractTally check_contract(const ScalarField& phi, Oracle oracle, double rounding, double sign_tolerance,
                             double relative_rounding = 0.0) {
  const GridSpec& grid = phi.grid;
  bool no_node_in_band = true;
  for (int k = 0; k < grid.nodes[2]; ++k)
    for (int j = 0; j < grid.nodes[1]; ++j)
      for (int i = 0; i < grid.nodes[0]; ++i) {
        const OracleInterval o = oracle(grid.position(i, j, k));
        if (!o.skip && o.distance_lo() <= B::exact_band(grid)) no_node_in_band = false;
      }
  ContractTally tally;
  for (int k = 0; k < grid.nodes[2]; ++k)
    for (int j = 0; j < grid.nodes[1]; ++j)
      for (int i = 0; i < grid.nodes[0]; ++i) {
        const OracleInterval o = oracle(grid.position(i, j, k));
        if (o.skip) continue;
        const double c = phi.at(i, j, k);
        const double slack = rounding + relative_rounding * std::max(o.distance_hi(), grid.min_spacing()) +
                             B::storage_rounding(std::max(std::abs(c), o.distance_hi()));
        bool ok = true;
        if (claims_exact<B>(o, grid, no_node_in_band)) {
          ++tally.exact_nodes;
          ok = c >= o.lo - slack && c <= o.hi + slack;  // false for NaN
          tally.worst_exact_error = std::max(tally.worst_exact_error, std::max(o.lo - c, c - o.hi));
        } else {
          ++tally.bounded_nodes;
          const double magnitude = std::abs(c);
          const double h = grid.spacing.maxCoeff();
          tally.worst_above_h = std::max(tally.worst_above_h, (magnitude - o.distance_hi()) / h);
          tally.worst_below_h = std::max(tally.worst_below_h, (o.distance_lo() - magnitude) / h);
          ok = magnitude >= o.distance_lo() - B::beyond_band_below(grid) - slack &&
               magnitude <= o.distance_hi() + B::beyond_band_above(grid) + slack;
        }
        const bool decided = B::sign_exact_everywhere || claims_exact<B>(o, grid, no_node_in_band);
        if (decided && (o.lo - sign_tolerance > 0.0 || o.hi + sign_tolerance < 0.0)) {
          ++tally.sign_checked;
          ok = ok && ((o.lo > 0.0) ? c > 0.0 : c < 0.0);
        }
        if (!ok && tally.violations++ == 0) {
          std::ostringstream s;
          s.precision(17);
          s << "node (" << i << ", " << j << ", " << k << "): phi " << c << ", oracle [" << o.lo << ", " << o.hi
            << "], " << (claims_exact<B>(o, grid, no_node_in_band) ? "exact claimed" : "declared bound");
          tally.first_violation = s.str();
        }
      }
  return tally;
}

template <typename B, typename Oracle>
ContractTally expect_contract(const ScalarField& phi, Oracle oracle, double rounding, double sign_tolerance,
                              double relative_rounding = 0.0) {
  const ContractTally tally = check_contract<B>(phi, oracle, rounding, sign_tolerance, relative_rounding);
  EXPECT_EQ(tally.violations, 0u) << tally.first_violation;
  return tally;
}

/// An oracle field on the same grid as a position -> OracleInterval function.
inline auto field_oracle(const ScalarField& oracle) {
  return [&oracle](const Vec3& p) {
    // The node from its position: the grid is regular and the rounding far below half a cell.
    const Vec3 f = (p - oracle.grid.origin).cwiseQuotient(oracle.grid.spacing);
    return OracleInterval::exactly(oracle.at(static_cast<int>(std::lround(f.x())), static_cast<int>(std::lround(f.y())),
                                             static_cast<int>(std::lround(f.z()))));
  };
}

/// Agreement with the reference exact builder (the exact oracle that needs no CGAL): within
/// `tol_h` h_min where B claims exactness, within its declared bound elsewhere, and the same sign
/// at every node the reference does not put exactly on the surface (sign tolerance 0).
template <typename B>
ContractTally expect_agrees_with_reference_exact(const ScalarField& phi, const TriangleMesh& mesh, double tol_h) {
  const ScalarField reference = ReferenceExact::build(mesh, phi.grid, nullptr);
  return expect_contract<B>(phi, field_oracle(reference), tol_h * phi.grid.min_spacing(), 0.0);
}

/// |phi_a - phi_b| against |x_a - x_b| over the neighbour pairs the builder's Lipschitz claim
/// covers (B::lipschitz). Returns the number of violating pairs.
template <typename B>
std::size_t lipschitz_violations(const ScalarField& phi) {
  const GridSpec& g = phi.grid;
  std::size_t violations = 0;
  for (int k = 0; k < g.nodes[2]; ++k)
    for (int j = 0; j < g.nodes[1]; ++j)
      for (int i = 0; i < g.nodes[0]; ++i)
        for (int dk = 0; dk <= 1; ++dk)
          for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
              // Each unordered pair once: forward in (k, j, i) lexicographic order.
              if (dk == 0 && (dj < 0 || (dj == 0 && di <= 0))) continue;
              const int a = i + di, b = j + dj, c = k + dk;
              if (a < 0 || b < 0 || a >= g.nodes[0] || b >= g.nodes[1] || c >= g.nodes[2]) continue;
              const bool axis_pair = std::abs(di) + std::abs(dj) + std::abs(dk) == 1;
              const double pa = phi.at(i, j, k), pb = phi.at(a, b, c);
              const double jump = std::abs(pa - pb);
              const double storage = B::storage_rounding(pa) + B::storage_rounding(pb);
              const double dx = Vec3(di * g.spacing.x(), dj * g.spacing.y(), dk * g.spacing.z()).norm();
              double allowed = 0.0;
              switch (B::lipschitz) {
                case Lipschitz::all_neighbours:
                  // 1e-9: round-off of the node positions and distances (tests/sdf_oracle).
                  allowed = dx * (1.0 + 1e-9) + storage;
                  break;
                case Lipschitz::axis_neighbours:
                  if (!axis_pair) continue;
                  // 1e-12: rounding of the update x = a + h and of the exact band values.
                  allowed = dx * (1.0 + 1e-12) + storage;
                  break;
                case Lipschitz::within_band: {
                  // |phi| within the band implies the node is exact (beyond it |phi| >= the truth).
                  const bool both_exact = std::abs(pa) <= B::exact_band(g) && std::abs(pb) <= B::exact_band(g);
                  // Otherwise both values lie in [d, d + above] and d is 1-Lipschitz.
                  allowed = dx * (1.0 + 1e-9) + storage + (both_exact ? 0.0 : B::beyond_band_above(g));
                  break;
                }
              }
              if (!(jump <= allowed)) ++violations;
            }
  return violations;
}

inline bool has_warning_containing(const SdfReport& report, const std::string& text) {
  for (const auto& w : report.warnings)
    if (w.find(text) != std::string::npos) return true;
  return false;
}

}  // namespace ppohdem::test::sdf_contract
