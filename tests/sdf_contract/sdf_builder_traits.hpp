#pragma once
/// \file sdf_builder_traits.hpp
/// Every SDF builder of ppohdem, with its gaps declared in one place (as ArborX declares what each
/// of its search trees supports). The contract tests (sdf_contract_test.cpp) run the same bodies
/// on every builder below and consult these traits: a declared gap replaces the exact expectation
/// by the builder's documented bound at that node; no test is skipped. docs/sdf.md §6.
///
/// What a traits struct declares:
///   build(mesh, grid, report)   the builder under test, returning a double field [m]
///   exact_everywhere            exact (to rounding) at every node; otherwise
///   exact_band(grid)            exact_in_band_only: exact wherever the true |phi| <= this [m]
///   exact_when_no_node_in_band  if no node lies within exact_band, every node is exact
///   beyond_band_below/above     beyond exact_band: |phi| - |true phi| lies in [-below, +above] [m]
///   storage_rounding(v)         what storing v costs (0 for double, 2^-24 |v| for float) [m]
///   lipschitz                   which neighbour pairs satisfy |phi_a - phi_b| <= |x_a - x_b|
///   sign_exact_everywhere       the sign is exact at every node off the surface
///   sign_defined_for_open_meshes  open meshes get a sign (generalized winding number)
///   warns_when_no_node_in_band  one warning when the grid does not reach the band
#include <cmath>
#include <limits>
#include <span>

#include "ppohdem/comm/comm.hpp"
#include "ppohdem/sdf/fast/fast_sdf_builder.hpp"
#include "ppohdem/sdf/reference/exact_sdf_builder.hpp"
#include "ppohdem/sdf/reference/seed_pipeline_sdf_builder.hpp"

namespace ppohdem::test::sdf_contract {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// Which neighbour pairs a builder promises to be 1-Lipschitz on.
enum class Lipschitz {
  all_neighbours,   ///< every 26-neighbour pair (a sampled true distance function)
  axis_neighbours,  ///< axis neighbours only: |phi_a - phi_b| <= h_axis (first-order eikonal)
  within_band,      ///< pairs with both |phi| within exact_band; others off by at most beyond_band_above
};

/// Defaults for a builder that claims the exact signed distance at every node (no gap).
struct ExactEverywhere {
  static constexpr bool exact_everywhere = true;
  static double exact_band(const GridSpec&) { return kInfinity; }
  static constexpr bool exact_when_no_node_in_band = true;
  static double beyond_band_below(const GridSpec&) { return 0.0; }
  static double beyond_band_above(const GridSpec&) { return 0.0; }
  static double storage_rounding(double) { return 0.0; }
  static constexpr Lipschitz lipschitz = Lipschitz::all_neighbours;
  static constexpr bool sign_exact_everywhere = true;
  static constexpr bool sign_defined_for_open_meshes = true;
  static constexpr bool warns_when_no_node_in_band = false;
};

// ---- reference (ppohdem::sdf::reference) ----

/// "exact": nearest triangle by BVH at every node. No gaps.
struct ReferenceExact : ExactEverywhere {
  static constexpr const char* name = "reference_exact";
  static ScalarField build(const TriangleMesh& mesh, const GridSpec& grid, SdfReport* report) {
    return sdf::reference::ExactSdfBuilder().build(mesh, grid, report);
  }
};

/// "seed": the original pipeline made correct. Gap: exact only in its band of 2 sqrt(3) h_max;
/// beyond it a first-order fast-sweeping solution.
struct ReferenceSeed : ExactEverywhere {
  static constexpr const char* name = "reference_seed";
  static ScalarField build(const TriangleMesh& mesh, const GridSpec& grid, SdfReport* report) {
    return sdf::reference::SeedPipelineSdfBuilder().build(mesh, grid, report);
  }
  /// exact_in_band_only(2 sqrt(3) h_max): the band nodes are the exact builder's, bit for bit.
  static constexpr bool exact_everywhere = false;
  static double exact_band(const GridSpec& grid) {
    return sdf::reference::SeedPipelineSdfBuilder::kOriginalBandInH * grid.spacing.maxCoeff();
  }
  /// With no node in the band there is nothing to sweep from: exact distances and a warning.
  static constexpr bool exact_when_no_node_in_band = true;
  static constexpr bool warns_when_no_node_in_band = true;
  /// Beyond the band: 2 h, above the largest far-field error documented for the first-order
  /// sweep (docs/sdf-accuracy.md, "Summary"; the margin on the suite's grids: docs/sdf.md §6).
  static double beyond_band_below(const GridSpec& grid) { return 2.0 * grid.spacing.maxCoeff(); }
  static double beyond_band_above(const GridSpec& grid) { return 2.0 * grid.spacing.maxCoeff(); }
  /// A first-order eikonal solution is 1-Lipschitz across axis neighbours only (the Godunov
  /// update never lets a neighbour differ by more than h); not along diagonals
  /// (docs/sdf-accuracy.md, "Summary").
  static constexpr Lipschitz lipschitz = Lipschitz::axis_neighbours;
};

// ---- fast (ppohdem::sdf::fast) ----

inline ScalarField fast_build(const sdf::fast::FastSdfOptions& options, const TriangleMesh& mesh,
                              const GridSpec& grid, SdfReport* report) {
  return sdf::fast::FastSdfBuilder(options).build(mesh, grid, report);
}

/// The optimized builder, exact mode (one BVH query per node). No gaps.
struct FastExact : ExactEverywhere {
  static constexpr const char* name = "fast_exact";
  static ScalarField build(const TriangleMesh& mesh, const GridSpec& grid, SdfReport* report) {
    sdf::fast::FastSdfOptions options;
    options.threads = 2;
    return fast_build(options, mesh, grid, report);
  }
};

/// The documented alternative exact scheme (candidates shared by bricks of nodes). No gaps.
struct FastSharedCandidates : ExactEverywhere {
  static constexpr const char* name = "fast_shared_candidates";
  static ScalarField build(const TriangleMesh& mesh, const GridSpec& grid, SdfReport* report) {
    sdf::fast::FastSdfOptions options;
    options.threads = 2;
    options.shared_candidates = true;
    return fast_build(options, mesh, grid, report);
  }
};

/// Band mode, `--band 1`. Gap: exact_in_band_only(1 h_max); beyond it the distance to one
/// transferred triangle: never below the truth, at most 2 r_b + r' above it (brick_distance.hpp:
/// r_b = 3.5 |h| the 8^3 brick's half-diagonal, r' = 1.5 |h| the 4^3 box's). Sign exact.
struct FastBand : ExactEverywhere {
  static constexpr const char* name = "fast_band";
  static constexpr double kBandCells = 1.0;
  static ScalarField build(const TriangleMesh& mesh, const GridSpec& grid, SdfReport* report) {
    sdf::fast::FastSdfOptions options;
    options.threads = 2;
    options.band_cells = kBandCells;
    return fast_build(options, mesh, grid, report);
  }
  /// exact_in_band_only(W h_max), W = kBandCells.
  static constexpr bool exact_everywhere = false;
  static double exact_band(const GridSpec& grid) { return kBandCells * grid.spacing.maxCoeff(); }
  static constexpr bool exact_when_no_node_in_band = false;
  static double beyond_band_below(const GridSpec&) { return 0.0; }
  static double beyond_band_above(const GridSpec& grid) { return (2.0 * 3.5 + 1.5) * grid.spacing.norm(); }
  static constexpr Lipschitz lipschitz = Lipschitz::within_band;
};

/// Float storage (`--precision float`): the exact double field rounded to nearest float.
/// Gap: storage rounding, at most half an ulp, 2^-24 |phi| (normal range).
struct FastFloat : ExactEverywhere {
  static constexpr const char* name = "fast_float";
  static ScalarField build(const TriangleMesh& mesh, const GridSpec& grid, SdfReport* report) {
    sdf::fast::FastSdfOptions options;
    options.threads = 2;
    std::vector<float> values(grid.node_count());
    sdf::fast::FastSdfBuilder(options).build_slab(mesh, grid, {0, grid.nodes[2]}, std::span<float>(values), report);
    ScalarField phi(grid);
    for (std::size_t n = 0; n < values.size(); ++n) phi.values[n] = values[n];
    return phi;
  }
  static double storage_rounding(double v) { return std::ldexp(std::abs(v), -24); }
};

/// The distributed entry point (build_sdf_distributed) on one rank, through the serial
/// communicator: the path `ppohdem voxelize` takes under mpirun -np 1. No gaps. (More ranks:
/// tests/sdf_fast/mpi_rank_invariance_test.cpp, bit for bit against the serial field.)
struct FastDistributedOneRank : ExactEverywhere {
  static constexpr const char* name = "fast_distributed_1rank";
  static ScalarField build(const TriangleMesh& mesh, const GridSpec& grid, SdfReport* report) {
    sdf::fast::FastSdfOptions options;
    options.threads = 1;
    return sdf::fast::build_sdf_distributed(sdf::fast::FastSdfBuilder(options), SerialComm(), mesh, grid, report);
  }
};

/// Three z-slabs built separately and concatenated: the decomposition three ranks would use,
/// in one process. No gaps.
struct FastThreeSlabs : ExactEverywhere {
  static constexpr const char* name = "fast_three_slabs";
  static ScalarField build(const TriangleMesh& mesh, const GridSpec& grid, SdfReport* report) {
    ScalarField phi(grid);
    std::size_t offset = 0;
    std::size_t negatives = 0;
    for (int r = 0; r < 3; ++r) {
      const sdf::fast::SlabRange slab = sdf::fast::slab_of_rank(grid.nodes[2], r, 3);
      const std::size_t count = slab.node_count(grid);
      SdfReport slab_report;
      sdf::fast::FastSdfBuilder().build_slab(mesh, grid, slab, std::span<double>(phi.values.data() + offset, count),
                                             &slab_report);
      negatives += static_cast<std::size_t>(std::llround(slab_report.inside_fraction * static_cast<double>(count)));
      if (report != nullptr && r == 0) report->warnings = slab_report.warnings;  // every slab warns alike
      offset += count;
    }
    if (report != nullptr) report->inside_fraction = static_cast<double>(negatives) / static_cast<double>(grid.node_count());
    return phi;
  }
};

}  // namespace ppohdem::test::sdf_contract
