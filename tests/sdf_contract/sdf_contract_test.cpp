// The SDF contract: the same hard cases on every builder (builder_list.hpp), each against an
// oracle that uses no triangle (analytic box, ball, closed-form solid angle) and against the
// reference exact builder. Where a builder declares a gap (sdf_builder_traits.hpp) the
// expectation at a node becomes its documented bound there; nothing is skipped. docs/sdf.md §6.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "../reference/analytic_sdf.hpp"
#include "../reference/test_meshes.hpp"
#include "builder_list.hpp"
#include "contract_checks.hpp"

namespace ppohdem::test::sdf_contract {
namespace {

// Round-off allowance for O(1) coordinates: the closest point takes tens of operations.
constexpr double kRoundoff = 1e-13;
// Signs are compared where the analytic oracle is farther than kRoundoff from 0: its own
// evaluation at a node on a face rounds to +-1e-17 rather than 0.
// Agreement between two exact builders, in h: a few ulps of O(1) coordinates, with a wide margin
// on grids with h >~ 1e-3 of the coordinates (tests/sdf_fast).
constexpr double kExactTolH = 1e-9;

template <typename B>
class SdfContract : public ::testing::Test {};
TYPED_TEST_SUITE(SdfContract, AllBuilders, BuilderName);

auto analytic(auto sdf) {
  return [sdf](const Vec3& p) { return OracleInterval::exactly(sdf(p)); };
}

/// R minus the smallest distance from the centre to a triangle plane: the inscribed polyhedron P
/// satisfies ball(R - sag) within P within ball(R), so phi_ball <= phi_P <= phi_ball + sag.
double inscribed_sag(const TriangleMesh& mesh, const Vec3& centre, double radius) {
  double closest_plane = radius;
  for (const auto& t : mesh.triangles) closest_plane = std::min(closest_plane, std::abs(t.area_vector().normalized().dot(t.v[0] - centre)));
  return radius - closest_plane;
}

auto inscribed_sphere_oracle(const Vec3& centre, double radius, double sag) {
  return [=](const Vec3& p) {
    const double ball = sphere_sdf(p, centre, radius);
    return OracleInterval{ball, ball + sag, false};
  };
}

TYPED_TEST(SdfContract, DeclaredGapsAreConsistent) {
  using B = TypeParam;
  // exact_everywhere and exact_in_band_only(width) are the two forms of one declaration.
  const GridSpec grid = cube_grid(0.0, 1.0, 5);
  EXPECT_EQ(B::exact_everywhere, B::exact_band(grid) == kInfinity);
  if (!B::exact_everywhere) {
    EXPECT_GT(B::exact_band(grid), 0.0);  // the surface itself is always exact
    EXPECT_GT(B::beyond_band_below(grid) + B::beyond_band_above(grid), 0.0);
  }
  EXPECT_EQ(B::storage_rounding(0.0), 0.0);
}

TYPED_TEST(SdfContract, BoxWithFacesOnGridPlanes) {
  using B = TypeParam;
  {
    // h = 0.25 from 0: the faces 0.5 and 1.5 lie on grid planes.
    const Vec3 lo(0.5, 0.5, 0.5), hi(1.5, 1.5, 1.5);
    const ScalarField phi = B::build(box_mesh(lo, hi), cube_grid(0.0, 2.0, 9), nullptr);
    expect_contract<B>(phi, analytic([&](const Vec3& p) { return box_sdf(p, lo, hi); }), kRoundoff, kRoundoff);
    EXPECT_EQ(phi.at(2, 4, 4), 0.0);  // a node on the face x = 0.5: |phi| = 0 is in every exact band
  }
  {
    // Grid spacing 0.25 from -1: the faces x, y, z = 0 and 1 lie exactly on grid planes and edges
    // and vertices exactly on columns, the degenerate cases of the column parity.
    const TriangleMesh box = box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 1));
    const GridSpec grid = GridSpec::spanning(Vec3(-1, -1, -1), Vec3(2, 2, 2), {13, 13, 13});
    const ScalarField phi = B::build(box, grid, nullptr);
    expect_contract<B>(phi, analytic([](const Vec3& p) { return box_sdf(p, Vec3(0, 0, 0), Vec3(1, 1, 1)); }), kRoundoff, kRoundoff);
    expect_agrees_with_reference_exact<B>(phi, box, kExactTolH);
    // Analytic check at a node whose answer is obvious: the centre (0.5, 0.5, 0.5) is 0.5 inside.
    if (claims_exact<B>(OracleInterval::exactly(-0.5), grid, false)) {
      EXPECT_EQ(phi.at(6, 6, 6), -0.5);
    } else {  // declared gap (band mode): the centre lies beyond the exact band
      EXPECT_LT(phi.at(6, 6, 6), 0.0);
      EXPECT_LE(std::abs(phi.at(6, 6, 6)), 0.5 + B::beyond_band_above(grid));
    }
  }
}

TYPED_TEST(SdfContract, PlateThinnerThanOneVoxel) {
  using B = TypeParam;
  {
    // Nodes at z = ..., 0.25, 0.5, ...: the plate 0.3 <= z <= 0.35 holds no node.
    const Vec3 lo(0.2, 0.2, 0.3), hi(1.8, 1.8, 0.35);
    const ScalarField phi = B::build(box_mesh(lo, hi), cube_grid(0.0, 2.0, 9), nullptr);
    static_assert(B::sign_exact_everywhere, "a builder without exact signs needs its own plate expectation");
    for (double value : phi.values) EXPECT_GT(value, 0.0);
    const ContractTally tally =
        expect_contract<B>(phi, analytic([&](const Vec3& p) { return box_sdf(p, lo, hi); }), kRoundoff, kRoundoff);
    EXPECT_EQ(tally.sign_checked, phi.values.size());
  }
  {
    // A plate 1e-3 thick, thinner than h = 0.1: most columns cross it between two nodes.
    const Vec3 lo(0, 0, 0.5), hi(1, 1, 0.501);
    const TriangleMesh plate = box_mesh(lo, hi);
    const GridSpec grid = GridSpec::spanning(Vec3(-0.3, -0.3, -0.3), Vec3(1.3, 1.3, 1.3), {17, 17, 17});
    const ScalarField phi = B::build(plate, grid, nullptr);
    expect_contract<B>(phi, analytic([&](const Vec3& p) { return box_sdf(p, lo, hi); }), kRoundoff, kRoundoff);
    expect_agrees_with_reference_exact<B>(phi, plate, kExactTolH);
  }
}

TYPED_TEST(SdfContract, MeshFarOutsideTheGrid) {
  using B = TypeParam;
  {
    // No node within 2 sqrt(3) h of the unit box: the seed pipeline has nothing to sweep from.
    GridSpec grid = cube_grid(0.0, 0.2, 3);
    grid.origin = Vec3(5, 5, 5);
    SdfReport report;
    const ScalarField phi = B::build(box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 1)), grid, &report);
    ASSERT_EQ(report.warnings.size(), B::warns_when_no_node_in_band ? 1u : 0u);
    const ContractTally tally = expect_contract<B>(
        phi, analytic([](const Vec3& p) { return box_sdf(p, Vec3(0, 0, 0), Vec3(1, 1, 1)); }), 1e-13, kRoundoff);
    EXPECT_EQ(tally.exact_nodes + tally.bounded_nodes, 27u);
  }
  {
    // A ball 30 away from a 9^3 grid around the origin (farther than any brick or band).
    const Vec3 centre(30.0, 0.5, -0.25);
    const TriangleMesh sphere = icosphere(centre, 1.0, 2);
    const ScalarField phi = B::build(sphere, cube_grid(-1.0, 1.0, 9), nullptr);
    expect_contract<B>(phi, inscribed_sphere_oracle(centre, 1.0, inscribed_sag(sphere, centre, 1.0)), 100 * kRoundoff, kRoundoff);
  }
}

TYPED_TEST(SdfContract, MeshFarFromTheOrigin) {
  using B = TypeParam;
  {
    const Vec3 centre(1e6 + 0.3, 1e6 - 0.2, 1e6 + 0.1);
    const TriangleMesh mesh = icosphere(centre, 1.0, 2);
    GridSpec grid = cube_grid(-1.5, 1.5, 19);
    grid.origin += Vec3::Constant(1e6);
    // Coordinates ~1e6 carry an absolute rounding of 1e6 eps ~ 2.2e-10 per operation; the vertex
    // positions, node positions and closest point take a few tens of such operations.
    const double tolerance = 100.0 * 1e6 * std::numeric_limits<double>::epsilon();
    const ScalarField phi = B::build(mesh, grid, nullptr);
    // Signs where the ball's bounds decide them: exact < -sag - tol inside, exact > tol outside.
    expect_contract<B>(phi, inscribed_sphere_oracle(centre, 1.0, inscribed_sag(mesh, centre, 1.0)), tolerance, tolerance);
  }
  {
    const Vec3 offset = Vec3::Constant(1e6);
    const TriangleMesh sphere = transformed(icosphere(Vec3::Zero(), 1.0, 2), Eigen::Matrix3d::Identity(), offset);
    const GridSpec grid = GridSpec::spanning(offset - Vec3::Constant(1.3), offset + Vec3::Constant(1.3), {12, 12, 12});
    // Coordinates ~1e6 carry ~1e6 eps = 2e-10 absolute rounding in every closest point, i.e.
    // ~1e-9 h here (h = 0.24): the bound 1e-6 h is the meaningful one.
    expect_agrees_with_reference_exact<B>(B::build(sphere, grid, nullptr), sphere, 1e-6);
  }
}

/// Solid angle of the rectangle [x1,x2] x [y1,y2] in the plane z = z0 seen from p (> 0), by the
/// closed form Omega = sum over corners of +-atan(x y / (d sqrt(x^2 + y^2 + d^2))), d = |z0 - p.z|.
double rectangle_solid_angle(const Vec3& p, double x1, double x2, double y1, double y2, double z0) {
  const double d = std::abs(z0 - p.z());
  auto corner = [&](double x, double y) { return std::atan(x * y / (d * std::sqrt(x * x + y * y + d * d))); };
  const double a1 = x1 - p.x(), a2 = x2 - p.x(), b1 = y1 - p.y(), b2 = y2 - p.y();
  return corner(a2, b2) - corner(a1, b2) - corner(a2, b1) + corner(a1, b1);
}

TYPED_TEST(SdfContract, OpenBoxSignFromWindingNumber) {
  using B = TypeParam;
  // Unit box without its top face (z = 1). For a node inside the box, w = 1 - Omega_top / (4 pi);
  // outside below the top plane w = -Omega_top / (4 pi) < 0, above it w = Omega_top / (4 pi) <= 1/2.
  // So the node is inside iff it is in the box and Omega_top < 2 pi.
  TriangleMesh open = box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 1));
  open.triangles.erase(open.triangles.begin() + 2, open.triangles.begin() + 4);
  const std::vector<AxisBox> faces = {{{0, 0, 0}, {1, 1, 0}}, {{0, 0, 0}, {1, 0, 1}}, {{0, 1, 0}, {1, 1, 1}},
                                      {{0, 0, 0}, {0, 1, 1}}, {{1, 0, 0}, {1, 1, 1}}};
  auto oracle = [&](const Vec3& p) {
    double distance = std::numeric_limits<double>::infinity();
    for (const AxisBox& f : faces) distance = std::min(distance, f.distance(p));
    if (distance < 1e-12) return OracleInterval{0, 0, true};  // on the surface
    const double omega = rectangle_solid_angle(p, 0, 1, 0, 1, 1);
    if (std::abs(omega - 2 * std::numbers::pi) < 1e-9) return OracleInterval{0, 0, true};  // w = 1/2: undecidable
    const bool inside = (p.array() > 0).all() && (p.array() < 1).all() && omega < 2 * std::numbers::pi;
    if (!B::sign_defined_for_open_meshes) return OracleInterval{-distance, distance, false};
    return OracleInterval::exactly(inside ? -distance : distance);
  };
  SdfReport report;
  const ScalarField phi = B::build(open, cube_grid(-0.3, 1.3, 17), &report);  // h = 0.1
  expect_contract<B>(phi, oracle, kRoundoff, kRoundoff);
  int inside_count = 0;
  for (int n = 0; n < 17 * 17 * 17; ++n) {
    const OracleInterval o = oracle(phi.grid.position(n % 17, (n / 17) % 17, n / 289));
    inside_count += !o.skip && o.hi < 0.0 ? 1 : 0;
  }
  EXPECT_GT(inside_count, 100);
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_TRUE(has_warning_containing(report, "not watertight"));
  EXPECT_TRUE(has_warning_containing(report, "winding number"));
  // A second grid, against the reference's winding-number sign (sign tolerance 0).
  const GridSpec grid = GridSpec::spanning(Vec3(-0.45, -0.45, -0.45), Vec3(1.45, 1.45, 1.45), {11, 11, 11});
  expect_agrees_with_reference_exact<B>(B::build(open, grid, nullptr), open, kExactTolH);
}

TYPED_TEST(SdfContract, FlippedFaceKeepsParitySign) {
  using B = TypeParam;
  {
    TriangleMesh mesh = box_mesh(Vec3(-0.5, -0.5, -0.5), Vec3(0.5, 0.5, 0.5));
    std::swap(mesh.triangles[4].v[1], mesh.triangles[4].v[2]);
    SdfReport report;
    const ScalarField phi = B::build(mesh, cube_grid(-1.0, 1.0, 11), &report);
    EXPECT_TRUE(has_warning_containing(report, "not consistently oriented"));
    EXPECT_TRUE(has_warning_containing(report, "ray parity"));
    expect_contract<B>(phi, analytic([](const Vec3& p) { return box_sdf(p, Vec3::Constant(-0.5), Vec3::Constant(0.5)); }),
                       kRoundoff, kRoundoff);
  }
  {
    TriangleMesh box = box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 1));
    std::swap(box.triangles[5].v[1], box.triangles[5].v[2]);  // one face wound the wrong way
    const GridSpec grid = GridSpec::spanning(Vec3(-0.45, -0.45, -0.45), Vec3(1.45, 1.45, 1.45), {11, 11, 11});
    const ScalarField phi = B::build(box, grid, nullptr);
    expect_contract<B>(phi, analytic([](const Vec3& p) { return box_sdf(p, Vec3(0, 0, 0), Vec3(1, 1, 1)); }), kRoundoff, kRoundoff);
    expect_agrees_with_reference_exact<B>(phi, box, kExactTolH);
  }
}

TYPED_TEST(SdfContract, LipschitzOnCubicAndAnisotropicGrids) {
  using B = TypeParam;
  GridSpec anisotropic;
  anisotropic.origin = Vec3(-1.6, -1.55, -1.7);
  anisotropic.spacing = Vec3(0.1, 0.13, 0.07);
  anisotropic.nodes = {33, 25, 49};
  for (const GridSpec& grid : {cube_grid(-1.6, 1.6, 25), anisotropic}) {
    EXPECT_EQ(lipschitz_violations<B>(B::build(icosphere(Vec3(0.05, -0.03, 0.02), 1.0, 3), grid, nullptr)), 0u);
    EXPECT_EQ(lipschitz_violations<B>(B::build(box_mesh(Vec3(-0.7, -0.4, -0.55), Vec3(0.6, 0.5, 0.45)), grid, nullptr)), 0u);
    EXPECT_EQ(lipschitz_violations<B>(B::build(l_shape(0.8, Vec3(-0.75, -0.7, -0.4)), grid, nullptr)), 0u);
  }
}

TYPED_TEST(SdfContract, LShapeConcaveEdgesWithinContract) {
  using B = TypeParam;
  // Concave edges and corners against the oracle built from axis-aligned rectangles.
  const LShapeOracle oracle{0.8, Vec3(-0.75, -0.7, -0.4)};
  SdfReport report;
  const ScalarField phi = B::build(l_shape(oracle.s, oracle.offset), cube_grid(-1.2, 1.2, 25), &report);
  EXPECT_TRUE(report.warnings.empty());
  const ContractTally tally = expect_contract<B>(phi, analytic([&](const Vec3& p) { return oracle.sdf(p); }), kRoundoff, kRoundoff);
  EXPECT_GT(tally.exact_nodes, 0u);
}

}  // namespace
}  // namespace ppohdem::test::sdf_contract
