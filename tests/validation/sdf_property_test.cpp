// SDF properties over generated watertight meshes (issue 8, item 4), every exact builder
// ("exact" reference, "fast" optimized) against the independent CGAL oracle and analytic
// answers; the approximate "seed" builder only for the Lipschitz bound. rapidcheck prints the
// failing seed (replay: RC_PARAMS="reproduce=...").
//
// Tolerances (as tests/sdf_oracle/sdf_vs_cgal_test.cpp, where they are derived):
//  - distance: |c - o| <= 1e-12 max(|o|, h): point-triangle distances round at eps |x|, with
//    |x| ~ 1 here; 1e-12 is ~5e3 eps;
//  - sign: identical wherever |o| > 1e-9 (grid nodes are offset so none sits on the surface);
//  - Lipschitz: ratio <= 1 + 1e-9 over 26-neighbour node pairs (a distance function is
//    1-Lipschitz; 1e-9 absorbs the rounding of node positions).
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <vector>

#include "ppohdem/mesh/mesh_stats.hpp"
#include "ppohdem/sdf/reference/builders.hpp"
#include "ppohdem/sdf/fast/fast_sdf_builder.hpp"
#include "ppohdem/sdf/field_metrics.hpp"
#include "ppohdem/validation/cgal_signed_distance.hpp"
#include "random_meshes.hpp"

namespace ppohdem {
namespace {

using validation::cell_union_mesh;
using validation::cell_union_outside_distance;
using validation::convex_hull_mesh;
using validation::is_manifold_cell_union;

constexpr double kDistanceTolerance = 1e-12;  // relative to max(|o|, h), see above
constexpr double kSignThreshold = 1e-9;       // world units
constexpr double kLipschitzSlack = 1e-9;

/// n^3 nodes over the mesh box padded by 25% on each side, shifted by an irrational fraction
/// of a cell so no node lies on a face of a lattice mesh.
GridSpec grid_around(const TriangleMesh& mesh, int n) {
  const BoundingBox box = compute_mesh_stats(mesh).box;
  const Vec3 pad = 0.25 * Vec3::Constant(box.extent().maxCoeff());
  const Vec3 lo = box.min - pad, hi = box.max + pad;
  const Vec3 shift = (hi - lo) / (n - 1) * 0.3819660112501051;  // (3 - sqrt 5)/2 of a cell
  return GridSpec::spanning(lo + shift, hi + shift, {n, n, n});
}

std::vector<std::unique_ptr<SdfBuilder>> exact_builders() {
  std::vector<std::unique_ptr<SdfBuilder>> b;
  b.push_back(sdf::reference::make_reference_sdf_builder("exact"));
  sdf::fast::FastSdfOptions fast;
  fast.threads = 1;
  b.push_back(std::make_unique<sdf::fast::FastSdfBuilder>(fast));
  return b;
}

/// `count` points in the shell 0.6 <= |x| <= 1 from a generated seed (rapidcheck's small-size
/// integers would all start at one corner; the seed is printed with a counterexample). Hulls
/// of such clouds are fat.
std::vector<Vec3> random_shell_points(int count) {
  const auto seed = *rc::gen::noShrink(rc::gen::arbitrary<std::uint64_t>());
  RC_LOG() << "point seed " << seed << "\n";
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> radius(0.6, 1.0);
  std::vector<Vec3> points;
  for (int i = 0; i < count; ++i) {
    const Vec3 d(normal(rng), normal(rng), normal(rng));
    points.push_back(d.normalized() * radius(rng));
  }
  return points;
}

Vec3 random_unit_cube_point() {
  return Vec3(*rc::gen::inRange(-1000, 1001), *rc::gen::inRange(-1000, 1001), *rc::gen::inRange(-1000, 1001)) *
         1e-3;
}

/// Compares a builder's field with the CGAL oracle: distance and sign (see the file comment).
void expect_matches_oracle(const ScalarField& field, const ScalarField& oracle, const GridSpec& grid,
                           const std::string& who) {
  const double h = grid.min_spacing();
  for (std::size_t n = 0; n < oracle.values.size(); ++n) {
    const double c = field.values[n], o = oracle.values[n];
    RC_ASSERT(std::abs(c - o) <= kDistanceTolerance * std::max(std::abs(o), h));
    if (std::abs(o) > kSignThreshold) RC_ASSERT((c < 0) == (o < 0));
  }
  RC_LOG() << who << " matches CGAL at " << oracle.values.size() << " nodes\n";
}

RC_GTEST_PROP(SdfProperties, ExactBuildersMatchCgalOnRandomConvexHulls, ()) {
  const std::vector<Vec3> points = random_shell_points(*rc::gen::inRange(6, 40));
  // Reject thin hulls: a volume below 1e-2 of the cube is a near-coplanar cloud whose
  // "inside" is thinner than a cell (tested elsewhere: thin plates).
  TriangleMesh mesh;
  try {
    mesh = convex_hull_mesh(points);
  } catch (const std::exception&) {
    RC_DISCARD("coplanar point set");
  }
  double volume = 0.0;  // divergence theorem: sum over faces of v0 . (v1 x v2) / 6
  for (const Triangle& t : mesh.triangles) volume += t.v[0].dot(t.v[1].cross(t.v[2])) / 6.0;
  RC_PRE(volume > 0.05);  // 1/80 of the unit ball
  const GridSpec grid = grid_around(mesh, 12);
  validation::OracleReport report;
  const ScalarField oracle = validation::cgal_signed_distance(mesh, grid, 1, &report);
  RC_ASSERT(report.sign_valid);
  // Second, analytic oracle inside a convex polytope: phi = max over face planes of the signed
  // plane distance (the nearest boundary point of a convex body from inside lies on the face
  // whose plane is nearest).
  for (int k = 0; k < grid.nodes[2]; ++k)
    for (int j = 0; j < grid.nodes[1]; ++j)
      for (int i = 0; i < grid.nodes[0]; ++i) {
        const std::size_t n = grid.index(i, j, k);
        if (oracle.values[n] >= -kSignThreshold) continue;
        const Vec3 x = grid.position(i, j, k);
        double plane = -std::numeric_limits<double>::infinity();
        for (const Triangle& t : mesh.triangles) {
          const Vec3 normal = t.area_vector().normalized();
          plane = std::max(plane, normal.dot(x - t.v[0]));
        }
        RC_ASSERT(std::abs(oracle.values[n] - plane) <= kDistanceTolerance * std::max(std::abs(plane), grid.min_spacing()));
      }
  for (const auto& builder : exact_builders()) {
    const ScalarField field = builder->build(mesh, grid);
    expect_matches_oracle(field, oracle, grid, builder->name());
    RC_ASSERT(lipschitz_ratio(field) <= 1.0 + kLipschitzSlack);
  }
}

RC_GTEST_PROP(SdfProperties, ExactBuildersMatchCgalAndBoxDistanceOnRandomUnionsOfBoxes, ()) {
  // 1-5 lattice boxes with sides of 1-3 cells in a 6^3 lattice, rasterised to cells.
  std::vector<std::array<int, 3>> cells;
  const int boxes = *rc::gen::inRange(1, 6);
  for (int b = 0; b < boxes; ++b) {
    const int x0 = *rc::gen::inRange(0, 5), y0 = *rc::gen::inRange(0, 5), z0 = *rc::gen::inRange(0, 5);
    const int sx = *rc::gen::inRange(1, 4), sy = *rc::gen::inRange(1, 4), sz = *rc::gen::inRange(1, 4);
    for (int x = x0; x < x0 + sx; ++x)
      for (int y = y0; y < y0 + sy; ++y)
        for (int z = z0; z < z0 + sz; ++z) cells.push_back({x, y, z});
  }
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  RC_PRE(is_manifold_cell_union(cells));  // edge- or vertex-only contacts are not 2-manifold
  const double h = 0.25;
  const Vec3 origin(-0.75, -0.75, -0.75);
  const TriangleMesh mesh = cell_union_mesh(cells, h, origin);
  const GridSpec grid = grid_around(mesh, 14);
  validation::OracleReport report;
  const ScalarField oracle = validation::cgal_signed_distance(mesh, grid, 1, &report);
  RC_ASSERT(report.sign_valid);
  // Outside the union the exact distance is the minimum over the boxes (analytic).
  for (int k = 0; k < grid.nodes[2]; ++k)
    for (int j = 0; j < grid.nodes[1]; ++j)
      for (int i = 0; i < grid.nodes[0]; ++i) {
        const std::size_t n = grid.index(i, j, k);
        if (oracle.values[n] <= kSignThreshold) continue;
        const double exact = cell_union_outside_distance(cells, h, origin, grid.position(i, j, k));
        RC_ASSERT(std::abs(oracle.values[n] - exact) <= kDistanceTolerance * std::max(exact, grid.min_spacing()));
      }
  for (const auto& builder : exact_builders()) {
    const ScalarField field = builder->build(mesh, grid);
    expect_matches_oracle(field, oracle, grid, builder->name());
    RC_ASSERT(lipschitz_ratio(field) <= 1.0 + kLipschitzSlack);
  }
}

/// Max over axis-neighbour node pairs of |phi_a - phi_b| / h_axis.
double axis_lipschitz_ratio(const ScalarField& f) {
  const GridSpec& g = f.grid;
  double worst = 0.0;
  for (int k = 0; k < g.nodes[2]; ++k)
    for (int j = 0; j < g.nodes[1]; ++j)
      for (int i = 0; i < g.nodes[0]; ++i) {
        const double v = f.values[g.index(i, j, k)];
        if (i + 1 < g.nodes[0]) worst = std::max(worst, std::abs(f.values[g.index(i + 1, j, k)] - v) / g.spacing[0]);
        if (j + 1 < g.nodes[1]) worst = std::max(worst, std::abs(f.values[g.index(i, j + 1, k)] - v) / g.spacing[1]);
        if (k + 1 < g.nodes[2]) worst = std::max(worst, std::abs(f.values[g.index(i, j, k + 1)] - v) / g.spacing[2]);
      }
  return worst;
}

RC_GTEST_PROP(SdfProperties, SeedBuilderIsLipschitzAlongGridAxesOnRandomConvexHulls, ()) {
  const std::vector<Vec3> points = random_shell_points(12);
  TriangleMesh mesh;
  try {
    mesh = convex_hull_mesh(points);
  } catch (const std::exception&) {
    RC_DISCARD("coplanar point set");
  }
  const GridSpec grid = grid_around(mesh, 12);
  const ScalarField field = sdf::reference::make_reference_sdf_builder("seed")->build(mesh, grid);
  // The seed method (exact band + Godunov fast-sweeping updates) is an approximation; a
  // Godunov update never makes an axis neighbour difference exceed h, so the field is
  // 1-Lipschitz along the grid axes (docs/sdf-accuracy.md). It is NOT along diagonals: the
  // 26-neighbour ratio reaches 1.03-1.05 on hulls (found by this property; the upwind
  // scheme's diagonal error), so only the axis claim is checked here.
  RC_ASSERT(axis_lipschitz_ratio(field) <= 1.0 + kLipschitzSlack);
}

/// The 12 triangles of the box [-a, a] (half sides a), rotated by q and moved to c.
TriangleMesh rotated_box(const Vec3& a, const Eigen::Quaterniond& q, const Vec3& c) {
  TriangleMesh unit = cell_union_mesh({{0, 0, 0}}, 1.0, Vec3::Constant(-0.5));
  for (Triangle& t : unit.triangles)
    for (Vec3& v : t.v) v = q * Vec3(2.0 * v.cwiseProduct(a)) + c;
  return unit;
}

RC_GTEST_PROP(SdfProperties, RandomlyPlacedBoxesAndTheirFacePlanesAreExact, ()) {
  const Vec3 a(*rc::gen::inRange(100, 1001) * 1e-3, *rc::gen::inRange(100, 1001) * 1e-3,
               *rc::gen::inRange(100, 1001) * 1e-3);
  const Eigen::Quaterniond q = Eigen::Quaterniond(*rc::gen::inRange(-100, 101) * 1e-2 + 1e-3, *rc::gen::inRange(-100, 101) * 1e-2,
                                                  *rc::gen::inRange(-100, 101) * 1e-2, *rc::gen::inRange(-100, 101) * 1e-2)
                                   .normalized();
  const Vec3 c = random_unit_cube_point();
  const TriangleMesh mesh = rotated_box(a, q, c);
  const GridSpec grid = grid_around(mesh, 12);
  for (const auto& builder : exact_builders()) {
    const ScalarField field = builder->build(mesh, grid);
    for (int k = 0; k < grid.nodes[2]; ++k)
      for (int j = 0; j < grid.nodes[1]; ++j)
        for (int i = 0; i < grid.nodes[0]; ++i) {
          // Analytic box SDF in the box frame (Quilez): outside |max(d,0)|, inside max_i d_i.
          const Vec3 local = q.conjugate() * (grid.position(i, j, k) - c);
          const Vec3 d = local.cwiseAbs() - a;
          const double exact = d.cwiseMax(Vec3::Zero()).norm() + std::min(d.maxCoeff(), 0.0);
          RC_ASSERT(std::abs(field.values[grid.index(i, j, k)] - exact) <=
                    kDistanceTolerance * std::max(std::abs(exact), grid.min_spacing()));
          // Where the nearest feature is a face (one positive d component, or inside), the
          // distance is the face plane's: the planar case is exact too.
        }
  }
}

}  // namespace
}  // namespace ppohdem
