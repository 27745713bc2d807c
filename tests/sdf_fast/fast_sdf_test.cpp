// The fast builder against two independent answers: the CGAL oracle (distance by CGAL's AABB
// tree, side by CGAL::Side_of_triangle_mesh) and the reference "exact" builder; plus the
// invariance claims (threads, slabs, float storage) checked bit for bit.
#include <gtest/gtest.h>

#include <cstring>
#include <span>

#include "../reference/test_meshes.hpp"
#include "ppohdem/error.hpp"
#include "ppohdem/mesh/stl_io.hpp"
#include "ppohdem/reference/sdf/builders.hpp"
#include "ppohdem/sdf/fast/fast_sdf_builder.hpp"
#include "ppohdem/sdf/field_metrics.hpp"
#include "ppohdem/validation/cgal_signed_distance.hpp"
#include "test_paths.hpp"

namespace ppohdem {
namespace {

GridSpec grid_around(const TriangleMesh& mesh, int n, double margin = 0.1) {
  const BoundingBox box = bounding_box(mesh);
  const Vec3 pad = Vec3::Constant(margin * box.extent().maxCoeff());
  return GridSpec::spanning(box.min - pad, box.max + pad, {n, n, n});
}

ScalarField fast_field(const TriangleMesh& mesh, const GridSpec& grid, int threads = 2) {
  FastSdfOptions options;
  options.threads = threads;
  return FastSdfBuilder(options).build(mesh, grid);
}

bool bitwise_equal(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

// Both builders are exact up to the rounding of a closest-point construction on coordinates of
// size ~1: a few ulps, i.e. ~1e-15 of the coordinates. 1e-9 h leaves a wide margin on grids with
// h >~ 1e-3 of the coordinates and is still 1000x below the 1e-6 h.
constexpr double kExactTolH = 1e-9;

void expect_matches_cgal(const TriangleMesh& mesh, const GridSpec& grid, double tol_h = kExactTolH) {
  const ScalarField fast = fast_field(mesh, grid);
  const ScalarField oracle = validation::cgal_signed_distance(mesh, grid, 1);
  // Signs compared where |oracle| > 1e-9 h: closer nodes are on the surface to rounding.
  const FieldComparison c = compare_fields(fast, oracle, 2.0, 1e-9);
  EXPECT_LE(c.all.max_error_h, tol_h);
  EXPECT_EQ(c.sign_mismatches, 0u);
  EXPECT_EQ(c.non_finite_candidate, 0u);
}

void expect_matches_reference(const TriangleMesh& mesh, const GridSpec& grid, double tol_h = kExactTolH) {
  const ScalarField fast = fast_field(mesh, grid);
  const ScalarField reference = reference::make_reference_sdf_builder("exact")->build(mesh, grid);
  // Sign tolerance 0: every node the reference does not put exactly on the surface must agree.
  const FieldComparison c = compare_fields(fast, reference, 2.0, 0.0);
  EXPECT_LE(c.all.max_error_h, tol_h);
  EXPECT_EQ(c.sign_mismatches, 0u);
}

TriangleMesh fixture_mesh(const char* name) { return read_stl(test::fixture(std::string("meshes/") + name)); }

TEST(FastSdf, MatchesCgalOracleOnFixtureMeshes) {
  for (const char* name : {"bunny_closed.stl", "dragon_100k.stl", "fandisk.stl", "icosphere.stl"}) {
    SCOPED_TRACE(name);
    expect_matches_cgal(fixture_mesh(name), grid_around(fixture_mesh(name), 14));
  }
}

TEST(FastSdf, MatchesReferenceExactOnFixtureMeshes) {
  for (const char* name : {"bunny_closed.stl", "fandisk.stl", "bunny.stl"}) {
    SCOPED_TRACE(name);
    expect_matches_reference(fixture_mesh(name), grid_around(fixture_mesh(name), 12));
  }
}

TEST(FastSdf, BoxWithFacesOnGridPlanesMatchesOracleAndReference) {
  // Grid spacing 0.25 from -1: the faces x, y, z = 0 and 1 lie exactly on grid planes and edges
  // and vertices exactly on columns, the degenerate cases of the column parity.
  const TriangleMesh box = test::box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 1));
  const GridSpec grid = GridSpec::spanning(Vec3(-1, -1, -1), Vec3(2, 2, 2), {13, 13, 13});
  expect_matches_cgal(box, grid);
  expect_matches_reference(box, grid);
  // Analytic check at a node whose answer is obvious: the centre (0.5, 0.5, 0.5) is 0.5 inside.
  const ScalarField phi = fast_field(box, grid);
  EXPECT_EQ(phi.at(6, 6, 6), -0.5);
}

TEST(FastSdf, ThinPlateMatchesOracleAndReference) {
  // A plate 1e-3 thick, thinner than h = 0.1: most columns cross it between two nodes.
  const TriangleMesh plate = test::box_mesh(Vec3(0, 0, 0.5), Vec3(1, 1, 0.501));
  const GridSpec grid = GridSpec::spanning(Vec3(-0.3, -0.3, -0.3), Vec3(1.3, 1.3, 1.3), {17, 17, 17});
  expect_matches_cgal(plate, grid);
  expect_matches_reference(plate, grid);
}

TEST(FastSdf, MeshOffsetByAMillionMatchesOracleAndReference) {
  const Vec3 offset = Vec3::Constant(1e6);
  const TriangleMesh sphere = test::transformed(test::icosphere(Vec3::Zero(), 1.0, 2), Eigen::Matrix3d::Identity(), offset);
  const GridSpec grid = GridSpec::spanning(offset - Vec3::Constant(1.3), offset + Vec3::Constant(1.3), {12, 12, 12});
  // Coordinates ~1e6 carry ~1e6 eps = 2e-10 absolute rounding in every closest point, i.e.
  // ~1e-9 h here (h = 0.24): the bound 1e-6 h is the meaningful one.
  expect_matches_cgal(sphere, grid, 1e-6);
  expect_matches_reference(sphere, grid, 1e-6);
}

TEST(FastSdf, OpenMeshSignAgreesWithReferenceWindingNumber) {
  // A box without its top (2 triangles removed): open, the sign comes from the winding number.
  TriangleMesh open = test::box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 1));
  open.triangles.erase(open.triangles.begin() + 2, open.triangles.begin() + 4);
  const GridSpec grid = GridSpec::spanning(Vec3(-0.45, -0.45, -0.45), Vec3(1.45, 1.45, 1.45), {11, 11, 11});
  expect_matches_reference(open, grid);
  SdfReport report;
  (void)FastSdfBuilder().build(open, grid, &report);
  ASSERT_FALSE(report.warnings.empty());
  EXPECT_NE(report.warnings[0].find("winding number"), std::string::npos);
}

TEST(FastSdf, FlippedTriangleKeepsParitySignLikeReferenceAndOracle) {
  TriangleMesh box = test::box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 1));
  std::swap(box.triangles[5].v[1], box.triangles[5].v[2]);  // one face wound the wrong way
  const GridSpec grid = GridSpec::spanning(Vec3(-0.45, -0.45, -0.45), Vec3(1.45, 1.45, 1.45), {11, 11, 11});
  expect_matches_cgal(box, grid);
  expect_matches_reference(box, grid);
}

TEST(FastSdf, FieldIsBitwiseIdenticalForOneAndTwoThreads) {
  const TriangleMesh mesh = fixture_mesh("bunny_closed.stl");
  const GridSpec grid = grid_around(mesh, 20);
  EXPECT_TRUE(bitwise_equal(fast_field(mesh, grid, 1).values, fast_field(mesh, grid, 2).values));
}

TEST(FastSdf, SlabsConcatenateToTheWholeFieldBitwise) {
  const TriangleMesh mesh = fixture_mesh("fandisk.stl");
  const GridSpec grid = grid_around(mesh, 15);
  const ScalarField whole = fast_field(mesh, grid);
  std::vector<double> pieces(grid.node_count());
  std::size_t offset = 0;
  for (int r = 0; r < 3; ++r) {  // 3 uneven slabs (15 = 5 + 5 + 5 planes, then shifted by one)
    const SlabRange slab = slab_of_rank(grid.nodes[2], r, 3);
    const std::size_t count = slab.node_count(grid);
    FastSdfBuilder().build_slab(mesh, grid, slab, std::span<double>(pieces.data() + offset, count));
    offset += count;
  }
  EXPECT_EQ(offset, grid.node_count());
  EXPECT_TRUE(bitwise_equal(whole.values, pieces));
}

TEST(FastSdf, FloatStorageIsTheDoubleFieldRounded) {
  const TriangleMesh mesh = fixture_mesh("icosphere.stl");
  const GridSpec grid = grid_around(mesh, 10);
  const ScalarField dbl = fast_field(mesh, grid);
  std::vector<float> flt(grid.node_count());
  FastSdfBuilder().build_slab(mesh, grid, {0, grid.nodes[2]}, std::span<float>(flt));
  for (std::size_t n = 0; n < flt.size(); ++n) ASSERT_EQ(flt[n], static_cast<float>(dbl.values[n])) << n;
}

TEST(FastSdf, SlabsOfRanksCoverTheGridInOrder) {
  for (int nz : {1, 2, 7, 64}) {
    for (int ranks : {1, 2, 3, 4, 9}) {
      int next = 0;
      for (int r = 0; r < ranks; ++r) {
        const SlabRange s = slab_of_rank(nz, r, ranks);
        EXPECT_EQ(s.k_begin, next);
        EXPECT_LE(s.k_end - s.k_begin, nz / ranks + 1);
        next = s.k_end;
      }
      EXPECT_EQ(next, nz);
    }
  }
}

TEST(FastSdf, RejectsEmptyMeshAndWrongOutputSize) {
  const GridSpec grid = GridSpec::spanning(Vec3::Zero(), Vec3::Ones(), {3, 3, 3});
  EXPECT_THROW((void)FastSdfBuilder().build(TriangleMesh{}, grid), InputError);
  std::vector<double> small(5);
  EXPECT_THROW(FastSdfBuilder().build_slab(test::box_mesh(Vec3::Zero(), Vec3::Ones()), grid, {0, 3},
                                           std::span<double>(small)),
               InputError);
}

}  // namespace
}  // namespace ppohdem
