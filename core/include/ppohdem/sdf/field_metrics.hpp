#pragma once
/// \file field_metrics.hpp
/// How far a candidate distance field is from an oracle field on the same grid.
///
/// All errors are reported in units of h = grid.min_spacing() ("voxel units"), because what a
/// DEM contact cares about is the error relative to the resolution the field can represent.
///   e_n          = |candidate_n - oracle_n| / h                       [h]
///   max error    = max_n e_n                                          [h]
///   RMS error    = sqrt( (1/N) sum_n e_n^2 )                          [h]
/// both over all nodes and over the narrow band |oracle_n| < band_in_h * h (where contacts are
/// evaluated).
///   sign mismatch: a node with |oracle_n| > sign_tolerance_in_h * h whose candidate does not
///     have the oracle's strict sign (a candidate of exactly 0, or NaN, counts as a mismatch).
///     The tolerance is in h because "close enough to the surface that its side does not
///     matter" is a statement about resolution, not about metres.
///   relative error = max_n |c_n - o_n| / max(|o_n|, DBL_MIN)  (dimensionless), for claims that
///     a builder is exact to rounding; a node with o_n = 0 and c_n != 0 makes it huge, on purpose.
///   Lipschitz ratio = max over neighbouring node pairs (a, b) of |phi_a - phi_b| / |x_a - x_b|
///     (dimensionless). The neighbourhood is the full 26-neighbourhood (axis, face-diagonal and
///     body-diagonal neighbours; each unordered pair once). A true distance function is
///     1-Lipschitz, so a sampled exact SDF has ratio <= 1 (up to rounding); a ratio > 1 flags
///     kinks or wrong values.
/// Non-finite candidate values are counted and count as infinite error.
#include <cstddef>
#include <string>

#include "ppohdem/grid/scalar_field.hpp"

namespace ppohdem {

/// Error statistics over one set of nodes (all nodes, or the narrow band).
struct ErrorStats {
  std::size_t nodes = 0;       ///< nodes in the set
  double max_error_h = 0.0;    ///< max |c - o| / h  [h]  (0 for an empty set)
  double rms_error_h = 0.0;    ///< sqrt(mean((c - o)^2)) / h  [h]  (0 for an empty set)
  Index3 worst_node = {-1, -1, -1};  ///< (i, j, k) of the max error, -1s for an empty set
};

struct FieldComparison {
  double h = 0.0;                   ///< grid.min_spacing() [world units]
  double band_in_h = 0.0;           ///< narrow band half-width [h]
  double sign_tolerance_in_h = 0.0; ///< |oracle| above which signs are compared [h]
  ErrorStats all;                   ///< every node
  ErrorStats band;                  ///< nodes with |oracle| < band_in_h * h
  std::size_t sign_checked_nodes = 0;  ///< nodes with |oracle| > sign_tolerance_in_h * h
  std::size_t sign_mismatches = 0;     ///< of those, candidate sign != oracle sign
  std::size_t non_finite_candidate = 0;  ///< candidate NaN/Inf nodes (counted as infinite error)
  double max_relative_error = 0.0;     ///< max |c - o| / max(|o|, DBL_MIN) (dimensionless)
};

/// Compare `candidate` with `oracle`. Throws InputError if the grids differ (counts, origin
/// or spacing, compared exactly), if a value array has the wrong length, if the oracle has a
/// non-finite value, or if band_in_h or sign_tolerance_in_h is negative or not finite.
FieldComparison compare_fields(const ScalarField& candidate, const ScalarField& oracle,
                               double band_in_h = 2.0, double sign_tolerance_in_h = 1e-9);

/// Max over 26-neighbour node pairs of |phi_a - phi_b| / |x_a - x_b| (dimensionless; 0 for a
/// single-node grid). Non-finite values give +infinity.
double lipschitz_ratio(const ScalarField& field);

/// A small aligned table of `comparison` (one quantity per line), for terminals and logs.
std::string format_comparison(const FieldComparison& comparison);

}  // namespace ppohdem
