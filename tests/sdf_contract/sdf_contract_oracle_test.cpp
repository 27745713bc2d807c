// The SDF contract against the independent CGAL oracle (distance by CGAL's AABB tree, side by
// CGAL::Side_of_triangle_mesh): the real fixture meshes, and the hard cases of
// sdf_contract_test.cpp once more with CGAL as the oracle. Same builders, same declared gaps
// (sdf_builder_traits.hpp). docs/sdf.md §6.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <string>
#include <utility>

#include "../reference/test_meshes.hpp"
#include "builder_list.hpp"
#include "contract_checks.hpp"
#include "ppohdem/mesh/mesh_stats.hpp"
#include "ppohdem/mesh/stl_io.hpp"
#include "ppohdem/validation/cgal_signed_distance.hpp"
#include "test_paths.hpp"

namespace ppohdem::test::sdf_contract {
namespace {

// Exact builders equal the oracle to 1e-12 relative, "relative" being |c - o| / max(|o|, h): the
// round-off of a point-triangle distance is set by the magnitude of the coordinates, not by |phi|
// (docs/sdf-accuracy.md, "Summary").
constexpr double kExactRelative = 1e-12;
// Agreement between two exact builders on the small hard cases, in h (tests/sdf_fast).
constexpr double kExactTolH = 1e-9;

template <typename B>
class SdfContractOracle : public ::testing::Test {};
TYPED_TEST_SUITE(SdfContractOracle, AllBuilders, BuilderName);

// A cube grid of n^3 nodes centred on the mesh, side 1.2 x its largest extent (as the study).
GridSpec grid_around(const TriangleMesh& mesh, int n) {
  const BoundingBox box = compute_mesh_stats(mesh).box;
  const Vec3 half = Vec3::Constant(0.6 * box.extent().maxCoeff());
  return GridSpec::spanning(box.centre() - half, box.centre() + half, {n, n, n});
}

/// A fixture mesh and its CGAL oracle on grid_around(mesh, nodes), computed once per process:
/// ctest runs each body for all builders in one process (CMakeLists.txt), so CGAL's tree and
/// queries, the bulk of the cost, are paid once per fixture instead of once per builder.
struct FixtureWithOracle {
  TriangleMesh mesh;
  GridSpec grid;
  ScalarField oracle;
  validation::OracleReport report;
};

const FixtureWithOracle& fixture_with_oracle(const std::string& name, int nodes) {
  static std::map<std::pair<std::string, int>, FixtureWithOracle> cache;
  auto [it, inserted] = cache.try_emplace({name, nodes});
  if (inserted) {
    FixtureWithOracle& f = it->second;
    f.mesh = read_stl(test::fixture("meshes/" + name));
    f.grid = grid_around(f.mesh, nodes);
    f.oracle = validation::cgal_signed_distance(f.mesh, f.grid, 2, &f.report);
  }
  return it->second;
}

/// One closed fixture: exact to 1e-12 relative where claimed (its bound elsewhere), no sign
/// mismatch where |oracle| > 1e-9 (absolute and in h, whichever checks more nodes), Lipschitz as
/// declared, and within 1e-9 h of the reference exact builder with the same signs.
template <typename B>
void expect_closed_fixture_within_contract(const std::string& name, int nodes) {
  SCOPED_TRACE(name);
  const FixtureWithOracle& fixture = fixture_with_oracle(name, nodes);
  const TriangleMesh& mesh = fixture.mesh;
  const GridSpec& grid = fixture.grid;
  const ScalarField& oracle = fixture.oracle;
  ASSERT_TRUE(fixture.report.sign_valid) << name << " should be closed";
  const ScalarField phi = B::build(mesh, grid, nullptr);
  const double sign_tolerance = 1e-9 * std::min(1.0, grid.min_spacing());
  const ContractTally tally = expect_contract<B>(phi, field_oracle(oracle), 0.0, sign_tolerance, kExactRelative);
  EXPECT_GT(tally.exact_nodes, 0u);
  // For the docs (docs/sdf.md §6): how close each builder comes to its declared bound.
  std::printf("contract %s %s %d^3: %zu exact nodes, max error %.3g h; %zu bounded nodes, max %.3g h above, %.3g h below\n",
              B::name, name.c_str(), nodes, tally.exact_nodes, tally.worst_exact_error / grid.spacing.maxCoeff(),
              tally.bounded_nodes, tally.worst_above_h, tally.worst_below_h);
  EXPECT_EQ(lipschitz_violations<B>(phi), 0u);
  expect_agrees_with_reference_exact<B>(phi, mesh, kExactTolH);
}

TYPED_TEST(SdfContractOracle, FixtureBox) { expect_closed_fixture_within_contract<TypeParam>("box.stl", 33); }
TYPED_TEST(SdfContractOracle, FixtureIcosphere) { expect_closed_fixture_within_contract<TypeParam>("icosphere.stl", 32); }
TYPED_TEST(SdfContractOracle, FixtureFandisk) { expect_closed_fixture_within_contract<TypeParam>("fandisk.stl", 32); }
TYPED_TEST(SdfContractOracle, FixtureBunnyClosed) { expect_closed_fixture_within_contract<TypeParam>("bunny_closed.stl", 32); }
TYPED_TEST(SdfContractOracle, FixtureDragon100k) { expect_closed_fixture_within_contract<TypeParam>("dragon_100k.stl", 32); }

TYPED_TEST(SdfContractOracle, OpenBunnyMagnitudesAndReferenceSign) {
  using B = TypeParam;
  // The open scan has no inside for CGAL (unsigned oracle): |phi| against it; the sign against
  // the reference's generalized winding number (itself checked against brute force in
  // tests/reference).
  const FixtureWithOracle& fixture = fixture_with_oracle("bunny.stl", 12);
  const TriangleMesh& mesh = fixture.mesh;
  const GridSpec& grid = fixture.grid;
  const ScalarField& oracle = fixture.oracle;
  EXPECT_FALSE(fixture.report.sign_valid);
  SdfReport report;
  const ScalarField phi = B::build(mesh, grid, &report);
  ScalarField magnitude = phi;
  for (double& v : magnitude.values) v = std::abs(v);
  // Sign tolerance +inf: the unsigned oracle decides no sign.
  expect_contract<B>(magnitude, field_oracle(oracle), 0.0, kInfinity, kExactRelative);
  ASSERT_FALSE(report.warnings.empty());
  EXPECT_NE(report.warnings.front().find("not watertight"), std::string::npos);
  if (B::sign_defined_for_open_meshes) expect_agrees_with_reference_exact<B>(phi, mesh, kExactTolH);
}

/// The hard cases of sdf_contract_test.cpp with CGAL as the oracle: within `tol_h` h where the
/// builder claims exactness, no sign mismatch where |oracle| > 1e-9 h, no non-finite value.
template <typename B>
void expect_matches_cgal(const TriangleMesh& mesh, const GridSpec& grid, double tol_h = kExactTolH) {
  const ScalarField phi = B::build(mesh, grid, nullptr);
  const ScalarField oracle = validation::cgal_signed_distance(mesh, grid, 1);
  const double h = grid.min_spacing();
  expect_contract<B>(phi, field_oracle(oracle), tol_h * h, 1e-9 * h);
}

TYPED_TEST(SdfContractOracle, HardCasesMatchCgal) {
  using B = TypeParam;
  {
    SCOPED_TRACE("box with faces on grid planes");
    expect_matches_cgal<B>(box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 1)),
                           GridSpec::spanning(Vec3(-1, -1, -1), Vec3(2, 2, 2), {13, 13, 13}));
  }
  {
    SCOPED_TRACE("plate 1e-3 thick");
    expect_matches_cgal<B>(box_mesh(Vec3(0, 0, 0.5), Vec3(1, 1, 0.501)),
                           GridSpec::spanning(Vec3(-0.3, -0.3, -0.3), Vec3(1.3, 1.3, 1.3), {17, 17, 17}));
  }
  {
    SCOPED_TRACE("mesh offset by a million");
    const Vec3 offset = Vec3::Constant(1e6);
    const TriangleMesh sphere = transformed(icosphere(Vec3::Zero(), 1.0, 2), Eigen::Matrix3d::Identity(), offset);
    // Coordinates ~1e6 carry ~1e6 eps = 2e-10 absolute rounding in every closest point, i.e.
    // ~1e-9 h here (h = 0.24): the bound 1e-6 h is the meaningful one.
    expect_matches_cgal<B>(sphere, GridSpec::spanning(offset - Vec3::Constant(1.3), offset + Vec3::Constant(1.3), {12, 12, 12}),
                           1e-6);
  }
  {
    SCOPED_TRACE("one flipped triangle");
    TriangleMesh box = box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 1));
    std::swap(box.triangles[5].v[1], box.triangles[5].v[2]);
    expect_matches_cgal<B>(box, GridSpec::spanning(Vec3(-0.45, -0.45, -0.45), Vec3(1.45, 1.45, 1.45), {11, 11, 11}));
  }
}

}  // namespace
}  // namespace ppohdem::test::sdf_contract
