// The reference SDF builders against the CGAL oracle (validation/), on the real fixture meshes.
//
// Claims checked (issue 3, "Accuracy and hard cases"):
//  - `exact` equals the oracle to 1e-12 relative, where "relative" is |c - o| / max(|o|, h): the
//    round-off of a point-triangle distance is set by the magnitude of the coordinates (~ eps *
//    |x|), not by |phi|, so near the surface a pure |c - o| / |o| measures nothing but the
//    conditioning of the question; h is the scale the field is used at;
//  - zero sign mismatches wherever |oracle| > 1e-9 (absolute, world units);
//  - Lipschitz ratio <= 1 + 1e-9 (a sampled distance function is 1-Lipschitz; 1e-9 absorbs
//    round-off of the node positions);
//  - `seed` stays within the error bound measured on these grids (see docs/sdf-accuracy.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>
#include <string>

#include "ppohdem/mesh/mesh_stats.hpp"
#include "ppohdem/mesh/stl_io.hpp"
#include "ppohdem/sdf/reference/builders.hpp"
#include "ppohdem/sdf/field_metrics.hpp"
#include "ppohdem/validation/cgal_signed_distance.hpp"
#include "test_paths.hpp"

namespace ppohdem {
namespace {

// The seed method's error on the dragon at 32^3 against CGAL, measured with this
// test (printed below) and ppohdem-sdf-study: max 0.764963 h, RMS 0.2380 h. The test allows 10 %
// more, so a change that makes the sweep worse fails while rounding-level changes do not.
constexpr double kSeedDragon32MaxErrorH = 0.765;
constexpr double kSeedDragon32RmsErrorH = 0.238;

// A cube grid of n^3 nodes centred on the mesh, side 1.2 x its largest extent (as the study).
GridSpec grid_around(const TriangleMesh& mesh, int n) {
  const BoundingBox box = compute_mesh_stats(mesh).box;
  const Vec3 half = Vec3::Constant(0.6 * box.extent().maxCoeff());
  return GridSpec::spanning(box.centre() - half, box.centre() + half, {n, n, n});
}

struct Case {
  std::string mesh;
  int nodes;
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.mesh << " at " << c.nodes << "^3"; }

class ExactMatchesCgal : public ::testing::TestWithParam<Case> {};

TEST_P(ExactMatchesCgal, ToRoundOffWithCorrectSignsAndLipschitz) {
  const TriangleMesh mesh = read_stl(test::fixture("meshes/" + GetParam().mesh));
  const GridSpec grid = grid_around(mesh, GetParam().nodes);
  validation::OracleReport oracle_report;
  const ScalarField oracle = validation::cgal_signed_distance(mesh, grid, 2, &oracle_report);
  ASSERT_TRUE(oracle_report.sign_valid) << GetParam().mesh << " should be closed";
  const ScalarField exact = sdf::reference::make_reference_sdf_builder("exact")->build(mesh, grid);

  const double h = grid.min_spacing();
  double worst = 0.0;
  std::size_t sign_mismatches = 0;
  for (std::size_t n = 0; n < oracle.values.size(); ++n) {
    const double c = exact.values[n], o = oracle.values[n];
    worst = std::max(worst, std::abs(c - o) / std::max(std::abs(o), h));
    if (std::abs(o) > 1e-9 && (c < 0) != (o < 0)) ++sign_mismatches;
  }
  EXPECT_LT(worst, 1e-12);
  EXPECT_EQ(sign_mismatches, 0u);
  EXPECT_LE(lipschitz_ratio(exact), 1.0 + 1e-9);
}

INSTANTIATE_TEST_SUITE_P(FixtureMeshes, ExactMatchesCgal,
                         ::testing::Values(Case{"box.stl", 33}, Case{"icosphere.stl", 32},
                                           Case{"fandisk.stl", 32}, Case{"bunny_closed.stl", 32},
                                           Case{"dragon_100k.stl", 32}),
                         [](const auto& param_info) {
                           const Case& c = param_info.param;
                           return c.mesh.substr(0, c.mesh.find('.')) + "_" + std::to_string(c.nodes);
                         });

TEST(ExactMatchesCgal, OpenBunnyDistanceMagnitudesAgree) {
  // The open scan has no inside for CGAL (unsigned oracle); compare |phi| only. The sign comes
  // from the winding number and is checked against brute force in tests/reference.
  const TriangleMesh mesh = read_stl(test::fixture("meshes/bunny.stl"));
  const GridSpec grid = grid_around(mesh, 12);
  validation::OracleReport oracle_report;
  const ScalarField oracle = validation::cgal_signed_distance(mesh, grid, 2, &oracle_report);
  EXPECT_FALSE(oracle_report.sign_valid);
  SdfReport report;
  const ScalarField exact = sdf::reference::make_reference_sdf_builder("exact")->build(mesh, grid, &report);
  const double h = grid.min_spacing();
  double worst = 0.0;
  for (std::size_t n = 0; n < oracle.values.size(); ++n) {
    worst = std::max(worst, std::abs(std::abs(exact.values[n]) - oracle.values[n]) / std::max(oracle.values[n], h));
  }
  EXPECT_LT(worst, 1e-12);
  ASSERT_FALSE(report.warnings.empty());
  EXPECT_NE(report.warnings.front().find("not watertight"), std::string::npos);
}

TEST(SeedMethodAgainstCgal, DragonErrorWithinMeasuredBound) {
  // Measured with ppohdem-sdf-study (docs/sdf-accuracy.md) on this grid: the seed method is
  // exact in its band and first-order outside it. Bounds: the measured values plus 10 %.
  const TriangleMesh mesh = read_stl(test::fixture("meshes/dragon_100k.stl"));
  const GridSpec grid = grid_around(mesh, 32);
  const ScalarField oracle = validation::cgal_signed_distance(mesh, grid, 2);
  const ScalarField seed = sdf::reference::make_reference_sdf_builder("seed")->build(mesh, grid);
  const FieldComparison cmp = compare_fields(seed, oracle, 2.0, 1e-9 / grid.min_spacing());
  EXPECT_EQ(cmp.sign_mismatches, 0u);
  EXPECT_LT(cmp.band.max_error_h, 1e-12);  // the band is computed exactly
  std::printf("seed dragon 32: max %.6g h, rms %.6g h\n", cmp.all.max_error_h, cmp.all.rms_error_h);
  EXPECT_LT(cmp.all.max_error_h, kSeedDragon32MaxErrorH * 1.1);
  EXPECT_LT(cmp.all.rms_error_h, kSeedDragon32RmsErrorH * 1.1);
}

}  // namespace
}  // namespace ppohdem
