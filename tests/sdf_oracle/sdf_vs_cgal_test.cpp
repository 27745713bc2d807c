// The seed builder against the CGAL oracle (validation/) on the dragon: its measured error bound.
// The claims every builder shares (exact to 1e-12 relative where exact, zero sign mismatches,
// Lipschitz, on every fixture) are the contract suite's: tests/sdf_contract (docs/sdf.md §6).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
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
