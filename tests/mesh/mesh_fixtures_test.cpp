// The binary fixture meshes against the independently computed figures in
// fixtures/meshes/README.md (from /work/shared/meshes/SOURCES.md: triangle counts, boundary
// edges, Euler characteristic, watertightness, bounding boxes printed to a few digits).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>

#include "ppohdem/mesh/mesh_stats.hpp"
#include "ppohdem/mesh/stl_io.hpp"
#include "test_paths.hpp"

namespace ppohdem {
namespace {

/// Half a unit in the last printed decimal place of `printed` ("-0.09469" -> 0.5e-5): the
/// most a correctly rounded printout can differ from the true value.
double half_unit_in_last_place(const std::string& printed) {
  const auto dot = printed.find('.');
  const int decimals = dot == std::string::npos ? 0 : static_cast<int>(printed.size() - dot - 1);
  return 0.5 * std::pow(10.0, -decimals);
}

void expect_box(const BoundingBox& box, const std::array<std::string, 3>& min,
                const std::array<std::string, 3>& max) {
  for (int a = 0; a < 3; ++a) {
    const auto i = static_cast<std::size_t>(a);
    EXPECT_NEAR(box.min[a], std::strtod(min[i].c_str(), nullptr), half_unit_in_last_place(min[i]))
        << "min axis " << a;
    EXPECT_NEAR(box.max[a], std::strtod(max[i].c_str(), nullptr), half_unit_in_last_place(max[i]))
        << "max axis " << a;
  }
}

MeshStats stats_of(const std::string& fixture) {
  StlReadReport report;
  const TriangleMesh mesh = read_stl(test::fixture(fixture), &report);
  EXPECT_EQ(report.encoding, StlEncoding::kBinary);
  return compute_mesh_stats(mesh);
}

TEST(MeshFixtures, BunnyScanHasFiveHolesAndIsNotWatertight) {
  const MeshStats s = stats_of("meshes/bunny.stl");
  EXPECT_EQ(s.triangles, 69451u);
  EXPECT_EQ(s.boundary_edges, 223u);
  EXPECT_EQ(s.non_manifold_edges, 0u);
  EXPECT_EQ(s.inconsistent_edges, 0u);
  EXPECT_EQ(s.euler_characteristic(), -3);
  EXPECT_FALSE(s.watertight());
  expect_box(s.box, {"-0.09469", "0.03299", "-0.06187"}, {"0.06101", "0.18732", "0.05880"});
}

TEST(MeshFixtures, DragonIsClosedGenusOne) {
  const MeshStats s = stats_of("meshes/dragon_100k.stl");
  EXPECT_EQ(s.triangles, 100000u);
  EXPECT_EQ(s.vertices, 50000u);
  EXPECT_EQ(s.euler_characteristic(), 0);
  EXPECT_TRUE(s.watertight());
  EXPECT_GT(s.signed_volume, 0.0);  // closed and outward oriented
  expect_box(s.box, {"-7.0467", "0.0", "-3.1513"}, {"7.0467", "9.9399", "3.1513"});
}

TEST(MeshFixtures, ClosedBunnyIsGenusZero) {
  const MeshStats s = stats_of("meshes/bunny_closed.stl");
  EXPECT_EQ(s.triangles, 75408u);
  EXPECT_EQ(s.euler_characteristic(), 2);
  EXPECT_TRUE(s.watertight());
  EXPECT_GT(s.signed_volume, 0.0);
  expect_box(s.box, {"-0.49896", "-0.49343", "-0.38649"}, {"0.49922", "0.49377", "0.38609"});
}

TEST(MeshFixtures, FandiskIsClosedGenusZero) {
  const MeshStats s = stats_of("meshes/fandisk.stl");
  EXPECT_EQ(s.triangles, 12946u);
  EXPECT_EQ(s.euler_characteristic(), 2);
  EXPECT_TRUE(s.watertight());
  EXPECT_GT(s.signed_volume, 0.0);
  expect_box(s.box, {"-0.4603", "-0.25555", "-0.5"}, {"0.4603", "0.25555", "0.5"});
}

// Property of a closed mesh: the signed volume does not depend on where the mesh is.
TEST(MeshFixtures, ClosedBunnyVolumeIsTranslationInvariant) {
  TriangleMesh mesh = read_stl(test::fixture("meshes/bunny_closed.stl"));
  const double volume = compute_mesh_stats(mesh).signed_volume;
  for (Triangle& t : mesh.triangles) {
    for (Vec3& p : t.v) p += Vec3(3.0, -2.0, 5.0);
  }
  // Worst-case rounding: each of the n terms det/6 with |p| <= 6.5 carries ~8 eps |p|^3 error,
  // and the sum adds n eps |partial sums|: bound n * 8 eps * 6.5^3.
  const double n = static_cast<double>(mesh.size());
  const double bound = n * 8 * std::numeric_limits<double>::epsilon() * std::pow(6.5, 3);
  EXPECT_NEAR(compute_mesh_stats(mesh).signed_volume, volume, bound);
}

}  // namespace
}  // namespace ppohdem
