// Mesh placement: the three modes of placement.hpp, the original program's formula checked by
// hand on its own test cube, and against the placed mesh the original program wrote.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "mesh_test_support.hpp"
#include "ppohdem/mesh/placement.hpp"
#include "ppohdem/mesh/stl_io.hpp"
#include "test_paths.hpp"

namespace ppohdem {
namespace {

using test::capture_input_error;
constexpr double kEps = std::numeric_limits<double>::epsilon();

/// A two-triangle mesh whose bounding box is exactly [lo, hi].
TriangleMesh box_mesh(const Vec3& lo, const Vec3& hi) {
  TriangleMesh mesh;
  mesh.triangles.push_back(test::make_triangle(lo, Vec3(hi.x(), lo.y(), lo.z()), hi));
  mesh.triangles.push_back(test::make_triangle(hi, Vec3(lo.x(), hi.y(), hi.z()), lo));
  return mesh;
}

rc::Gen<double> positive(int lo, int hi) {  // a value in [lo, hi] / 100 (hundredths)
  return rc::gen::map(rc::gen::inRange(lo, hi + 1), [](int i) { return i / 100.0; });
}

struct RandomCase {
  Vec3 lo, hi, size, pos;
};

RandomCase random_case() {
  RandomCase c;
  for (int a = 0; a < 3; ++a) {
    c.lo[a] = *rc::gen::inRange(-1000, 1000) / 100.0;
    c.hi[a] = c.lo[a] + *positive(1, 2000);
    c.size[a] = *positive(1, 1000);
    c.pos[a] = *rc::gen::inRange(-5000, 5000) / 100.0;
  }
  return c;
}

/// Scale of the values involved, for tolerances of a few ulps of the result.
double magnitude(const RandomCase& c) {
  return c.pos.cwiseAbs().maxCoeff() + c.size.maxCoeff();
}

RC_GTEST_PROP(PlacementUniformFit, CentresTheBoxAndFitsTheLimitingAxis, ()) {
  const RandomCase c = random_case();
  const TriangleMesh placed =
      place_mesh(box_mesh(c.lo, c.hi), {c.size, c.pos, PlacementMode::kUniformFit});
  const BoundingBox box = bounding_box(placed);
  // Each placed coordinate is (v - centre) s + pos: about 3 roundings of values up to
  // magnitude(): allow 8 ulps of it.
  const double tol = 8 * kEps * magnitude(c);
  RC_ASSERT((box.centre() - c.pos).cwiseAbs().maxCoeff() <= tol);
  const Vec3 placed_extent = box.extent();
  RC_ASSERT(((placed_extent - c.size).array() <= tol).all());  // every axis within its size
  const Vec3 ratio = c.size.cwiseQuotient(c.hi - c.lo);
  int limiting = 0;
  ratio.minCoeff(&limiting);
  RC_ASSERT(std::abs(placed_extent[limiting] - c.size[limiting]) <= tol);
  // Shape kept: extents stay proportional to the original ones.
  const Vec3 original_extent = c.hi - c.lo;
  for (int a = 0; a < 3; ++a) {
    RC_ASSERT(std::abs(placed_extent[a] * original_extent[limiting] -
                       placed_extent[limiting] * original_extent[a]) <=
              tol * (original_extent[limiting] + original_extent[a]));
  }
}

RC_GTEST_PROP(PlacementPerAxis, MapsTheBoxOntoTheSizeBox, ()) {
  const RandomCase c = random_case();
  const TriangleMesh placed =
      place_mesh(box_mesh(c.lo, c.hi), {c.size, c.pos, PlacementMode::kPerAxis});
  const BoundingBox box = bounding_box(placed);
  const double tol = 8 * kEps * magnitude(c);  // a few roundings, as above
  RC_ASSERT((box.min - (c.pos - 0.5 * c.size)).cwiseAbs().maxCoeff() <= tol);
  RC_ASSERT((box.max - (c.pos + 0.5 * c.size)).cwiseAbs().maxCoeff() <= tol);
}

RC_GTEST_PROP(PlacementMap, AgreesWithPlaceMeshInEveryMode, ()) {
  const RandomCase c = random_case();
  const auto mode = *rc::gen::element(PlacementMode::kUniformFit, PlacementMode::kPerAxis,
                                      PlacementMode::kPpohdem10);
  const TriangleMesh mesh = box_mesh(c.lo, c.hi);
  const Placement placement{c.size, c.pos, mode};
  const AxisAlignedMap map = placement_map(bounding_box(mesh), placement);
  const TriangleMesh placed = place_mesh(mesh, placement);
  // Same affine map, different evaluation order: allow rounding of terms up to
  // |scale v| + |offset|.
  for (std::size_t t = 0; t < mesh.size(); ++t) {
    for (std::size_t k = 0; k < 3; ++k) {
      const Vec3 v = mesh.triangles[t].v[k];
      const double scale_of_terms =
          map.scale.cwiseProduct(v).cwiseAbs().maxCoeff() + map.offset.cwiseAbs().maxCoeff();
      RC_ASSERT((map.apply(v) - placed.triangles[t].v[k]).cwiseAbs().maxCoeff() <=
                8 * kEps * (scale_of_terms + magnitude(c)));
    }
  }
}

// The original's formula on its own test cube, worked by hand. The cube's coordinates are
// +-1 except y_min = -1.000001 (vertex "-1.000001e+000") and a few 0.99999xx values inside
// the range. So R = 1 - (-1.000001) = 2.000001 (axis y), size_L = 6, and per axis
//   v' = (v - min) / 2.000001 * 6 + pos - 3,  pos = (22, 22, 16):
//   x in [19, 19 + 12/2.000001], y in [19, 25], z in [13, 13 + 12/2.000001].
TEST(PlacementPpohdem10, TestCubeGoesToTheBoxOfTheOriginalReadme) {
  const TriangleMesh cube = read_stl(test::fixture("ppohdem-1.0/test-cube.stl"));
  ASSERT_EQ(cube.size(), 12u);
  const TriangleMesh placed =
      place_mesh(cube, {Vec3(6, 6, 6), Vec3(22, 22, 16), PlacementMode::kPpohdem10});
  const BoundingBox box = bounding_box(placed);
  const double shrunk_side = 12.0 / 2.000001;  // 5.99999700000150..., by hand
  // The minima are exact: (min - min) = 0, then 0 + 22 - 3 = 19 (and 16 - 3 = 13).
  EXPECT_EQ(box.min, Vec3(19, 19, 13));
  // y spans exactly R: (R / R) * 6 = 6 exactly, 6 + 22 - 3 = 25.
  EXPECT_EQ(box.max.y(), 25.0);
  // x and z: a few roundings of numbers ~25: 4 ulps.
  EXPECT_NEAR(box.max.x(), 19.0 + shrunk_side, 4 * kEps * 25);
  EXPECT_NEAR(box.max.z(), 13.0 + shrunk_side, 4 * kEps * 25);
  // The README's printed figures: faces at 24.999997 and 18.999997 (7 decimals shown).
  EXPECT_NEAR(box.max.x(), 24.999997, 5e-7);
  EXPECT_NEAR(box.max.z(), 18.999997, 5e-7);
  // And the intended box [19,25]x[19,25]x[13,19] within the 1e-6 relative effect x 6.
  EXPECT_TRUE((box.max - Vec3(25, 25, 19)).cwiseAbs().maxCoeff() < 6 * 1e-6);
}

// The original program's own placed mesh (util-cube/np1/object_mesh.stl, 17 significant
// digits, which identify a double uniquely) against ours, bit for bit.
TEST(PlacementPpohdem10, MatchesTheOriginalProgramsPlacedMeshBitwise) {
  const TriangleMesh cube = read_stl(test::fixture("ppohdem-1.0/test-cube.stl"));
  const TriangleMesh theirs = read_stl(test::fixture("ppohdem-1.0/object_mesh_cube.stl"));
  const TriangleMesh ours =
      place_mesh(cube, {Vec3(6, 6, 6), Vec3(22, 22, 16), PlacementMode::kPpohdem10});
  ASSERT_EQ(ours.size(), theirs.size());
  std::size_t differing = 0;
  double largest_difference = 0.0;
  for (std::size_t t = 0; t < ours.size(); ++t) {
    for (std::size_t k = 0; k < 3; ++k) {
      for (int a = 0; a < 3; ++a) {
        const double x = ours.triangles[t].v[k][a];
        const double y = theirs.triangles[t].v[k][a];
        if (std::bit_cast<std::uint64_t>(x) != std::bit_cast<std::uint64_t>(y)) ++differing;
        largest_difference = std::max(largest_difference, std::abs(x - y));
      }
    }
    // The original copies the file normals unchanged, as place_mesh does.
    EXPECT_EQ(ours.triangles[t].file_normal, theirs.triangles[t].file_normal) << "triangle " << t;
  }
  EXPECT_EQ(differing, 0u) << "largest difference " << largest_difference;
}

TEST(Placement, RejectsBadSizePositionAndEmptyMesh) {
  const TriangleMesh cube = test::unit_cube();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const auto mode :
       {PlacementMode::kUniformFit, PlacementMode::kPerAxis, PlacementMode::kPpohdem10}) {
    auto e = capture_input_error([&] { place_mesh(cube, {Vec3(1, 0, 1), Vec3::Zero(), mode}); });
    EXPECT_NE(e.message().find("placement size: expected three positive finite numbers"),
              std::string::npos)
        << e.what();
    EXPECT_THROW(place_mesh(cube, {Vec3(1, -2, 1), Vec3::Zero(), mode}), InputError);
    EXPECT_THROW(place_mesh(cube, {Vec3(1, nan, 1), Vec3::Zero(), mode}), InputError);
    e = capture_input_error([&] { place_mesh(cube, {Vec3::Ones(), Vec3(0, nan, 0), mode}); });
    EXPECT_NE(e.message().find("placement position"), std::string::npos) << e.what();
    e = capture_input_error([&] { place_mesh(TriangleMesh{}, {Vec3::Ones(), Vec3::Zero(), mode}); });
    EXPECT_NE(e.message().find("empty mesh"), std::string::npos) << e.what();
    const TriangleMesh point = box_mesh(Vec3(1, 2, 3), Vec3(1, 2, 3));
    EXPECT_THROW(place_mesh(point, {Vec3::Ones(), Vec3::Zero(), mode}), InputError);
  }
}

TEST(Placement, PerAxisRejectsFlatMeshButUniformFitPlacesIt) {
  const TriangleMesh flat = box_mesh(Vec3(0, 0, 5), Vec3(2, 1, 5));  // flat in z
  const auto e = capture_input_error(
      [&] { place_mesh(flat, {Vec3::Ones(), Vec3::Zero(), PlacementMode::kPerAxis}); });
  EXPECT_NE(e.message().find("flat in z"), std::string::npos) << e.what();
  // Uniform: s = min(1/2, 1/1) = 1/2 from the x axis; z is not limiting.
  const BoundingBox box = bounding_box(
      place_mesh(flat, {Vec3::Ones(), Vec3(1, 1, 1), PlacementMode::kUniformFit}));
  EXPECT_EQ(box.min, Vec3(0.5, 0.75, 1));  // exact: halves of small binary fractions
  EXPECT_EQ(box.max, Vec3(1.5, 1.25, 1));
}

}  // namespace
}  // namespace ppohdem
