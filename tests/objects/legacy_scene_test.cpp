// The legacy driver (dem/legacy_scene.hpp) on small synthetic distance data: placement of the
// data in the box, the motion's SI conversion, the sample's sheet, and the bad-input errors the
// issue asks for (resolution mismatch, window outside the data, no data length).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "ppohdem/dem/legacy_scene.hpp"
#include "ppohdem/error.hpp"
#include "ppohdem/io/distance_dat.hpp"
#include "test_paths.hpp"

namespace ppohdem::dem {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;

// Data: 20^3 nodes over L = 10 m (h = 0.5 m), node m (1-based) at 0.5 (m - 1); a linear field
// phi = z_data - 3 (a half-space, exact under trilinear interpolation).
constexpr int kDataNodes = 20;
constexpr double kDataLength = 10.0;
constexpr double kH = kDataLength / kDataNodes;

struct Params {
  double lx = 4.5;  // window 10 nodes: h = 4.5 / 9 = 0.5, equal to the data's
  int n = 10;
  int winstart = 3;
  double vel_z = 0.01;
  double w = 100.0;
  std::string centroid = "5 5 5";
};

fs::path write_case(const Params& p, bool with_voxelizer_file) {
  const fs::path dir = test::scratch_dir();
  std::vector<double> values;
  for (int k = 0; k < kDataNodes; ++k)
    for (int j = 0; j < kDataNodes; ++j)
      for (int i = 0; i < kDataNodes; ++i) values.push_back(kH * k - 3.0);
  write_distance_dat(dir, values, {kDataNodes, kDataNodes, kDataNodes}, 1);
  std::ofstream(dir / "input_params_update.dat")
      << "Lx_Ly_Lz: " << p.lx << " " << p.lx << " " << p.lx << "\nTime_finish: 3\nObj_n_x_y_z: " << p.n << " "
      << p.n << " " << p.n << "\nObj_winstart_x_y_z: " << p.winstart << " " << p.winstart << " " << p.winstart
      << "\nObj_velocity_x_y_z: 0 0 " << p.vel_z << "\nObj_omega_x_y_z: 0 0 2\nObj_omega_Pi_rad_per_w: " << p.w
      << "\nObj_centroid_x_y_z: " << p.centroid << "\n";
  if (with_voxelizer_file) {
    std::ofstream(dir / "input_constants_voxelizer.dat")
        << "m.stl\n./\n20 20 20\nLx_Ly_Lz: 10 10 10\nsizeX_sizeY_sizeZ: 1 1 1\nposX_posY_posZ: 5 5 5\n";
  }
  return dir / "input_params_update.dat";
}

std::string error_of(const fs::path& file, const LegacySceneOptions& options = {}) {
  try {
    read_legacy_scene(file, options);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(LegacyScene, DataIsPlacedSoTheWindowCoversTheBox) {
  const Scene scene = read_legacy_scene(write_case(Params{}, true), {});
  ASSERT_EQ(scene.objects.size(), 1u);
  const DistanceFieldObject& object = *scene.objects[0].object;
  // Window start 3: data node 3 (data z = 1.0 m) sits at world z = 0, so the plane
  // z_data = 3 is at world z = 2.0 m. A sphere of R = 0.1 at world z = 2.05 overlaps it by
  // 0.05 m (exact: the field is linear, trilinear interpolation reproduces it).
  const auto c = object.contact(Vec3(1.0, 1.0, 2.05), 0.1, 0.0);
  ASSERT_TRUE(c.has_value());
  EXPECT_NEAR(c->overlap, 0.05, 1e-12);  // round-off of sums of O(1) numbers
  EXPECT_NEAR(c->normal.z(), 1.0, 1e-12);
  // 6 walls of the box [0, 4.5]^3 plus the object.
  EXPECT_EQ(scene.setup.boundaries.size(), 7u);
  EXPECT_EQ(scene.steps, 1500);  // Time_finish 3 / dt 0.002
}

TEST(LegacyScene, MotionPerFrameIsTheOriginalsIndexDisplacementAndAngle) {
  Params p;
  const Scene scene = read_legacy_scene(write_case(p, true), {});
  const DistanceFieldObject& object = *scene.objects[0].object;
  const double frame = 500 * 0.002;  // one output frame [s]
  const RigidTransform pose = object.pose_at(3 * frame);
  // Centroid: data (5, 5, 5) minus the window origin (winstart - 1) h = 1.0 m.
  EXPECT_NEAR((object.centroid_at(0.0) - Vec3(4.0, 4.0, 4.0)).norm(), 0.0, 1e-12);
  // Translation along the rotation axis: vel h per frame = 0.01 * 0.5 = 0.005 m, 3 frames.
  EXPECT_NEAR(object.centroid_at(3 * frame).z() - 4.0, 3 * p.vel_z * kH, 1e-12);
  // Rotation: +pi / w per frame about +z (the axis (0, 0, 2) normalised).
  const Eigen::AngleAxisd aa(pose.rotation);
  EXPECT_NEAR(aa.angle(), 3 * std::numbers::pi / p.w, 1e-12);
  EXPECT_NEAR(aa.axis().z(), 1.0, 1e-12);
}

TEST(LegacyScene, SampleSheetHasTheOriginalLayoutWithoutOverlaps) {
  Params p;
  p.lx = 9.5;  // window 20 nodes, h = 9.5 / 19 = 0.5 (only the sheet is checked here)
  p.n = 20;
  p.winstart = 1;
  const Scene scene = read_legacy_scene(write_case(p, true), {});
  const Particles& ps = scene.setup.particles;
  ASSERT_EQ(ps.size(), 600u);
  for (std::size_t i = 0; i < ps.size(); ++i) {
    EXPECT_GE(ps[i].radius, 0.1);
    EXPECT_LT(ps[i].radius, 0.12);
    EXPECT_DOUBLE_EQ(ps[i].position.y(), 5.5);
    EXPECT_NEAR(ps[i].position.x(), 0.1 + 0.3 * static_cast<double>(i % 33), 0.005 + 1e-12);
    EXPECT_NEAR(ps[i].position.z(), 5.0 + 0.3 * static_cast<double>(i / 33), 0.005 + 1e-12);
    // Mass 1 at radius 0.1 (the original's Mass), so m = (R / 0.1)^3.
    EXPECT_NEAR(scene.setup.material.mass(ps[i].radius), std::pow(ps[i].radius / 0.1, 3), 1e-12);
  }
  EXPECT_TRUE(overlapping_pairs(ps, 0.0).empty());
}

TEST(LegacyScene, RestitutionIsTheOriginalDashpotOnAPair) {
  // k = 30, c = 1, m* = 1/2: zeta = 1 / (2 sqrt(15)) = 0.129099, e = exp(-pi zeta /
  // sqrt(1 - zeta^2)) = 0.664314 (hand computation, 6 digits).
  EXPECT_NEAR(linear_restitution(30.0, 1.0, 0.5), 0.664314, 1e-6);
  // Undamped limit: zeta -> 0 gives e -> 1.
  EXPECT_NEAR(linear_restitution(30.0, 1e-12, 0.5), 1.0, 1e-9);
}

TEST(LegacyScene, ResolutionMismatchIsAnErrorGivingBothValues) {
  Params p;
  p.lx = 5.4;  // 5.4 / 9 = 0.6 m vs the data's 0.5 m
  const std::string what = error_of(write_case(p, true));
  EXPECT_THAT(what, HasSubstr("resolution mismatch"));
  EXPECT_THAT(what, HasSubstr("= 0.6 m"));
  EXPECT_THAT(what, HasSubstr("= 0.5 m"));
}

TEST(LegacyScene, WindowOutsideTheDataIsAnErrorNamingBoth) {
  Params p;
  p.winstart = 12;  // nodes 12..21 but the data has 1..20
  const std::string what = error_of(write_case(p, true));
  EXPECT_THAT(what, HasSubstr("nodes 12..21"));
  EXPECT_THAT(what, HasSubstr("1..20"));
}

TEST(LegacyScene, DataLengthComesFromTheOptionOrIsAnError) {
  const fs::path file = write_case(Params{}, false);
  EXPECT_THAT(error_of(file), HasSubstr("--data-length"));
  LegacySceneOptions options;
  options.data_length = kDataLength;
  EXPECT_EQ(error_of(file, options), "no error");
  options.data_length = 12.0;  // h = 0.6 m: mismatch
  EXPECT_THAT(error_of(file, options), HasSubstr("resolution mismatch"));
}


// The display mesh: object_mesh.stl (data coordinates, node m at h (m - 1)) moves with the field
// to node m at h (m - winstart): by -(3 - 1) 0.5 = -1 m per axis for the default window start 3.
TEST(LegacyScene, DisplayMeshIsTheObjectMeshShiftedLikeTheField) {
  const fs::path params = write_case(Params{}, true);
  std::ofstream(params.parent_path() / "object_mesh.stl")
      << "solid t\nfacet normal 0 0 1\nouter loop\nvertex 1 2 3\nvertex 4 2 3\nvertex 1 5 3\n"
         "endloop\nendfacet\nendsolid t\n";
  const Scene scene = read_legacy_scene(params, {});
  ASSERT_EQ(scene.objects.size(), 1u);
  const TriangleMesh* mesh = scene.objects[0].object->display_mesh();
  ASSERT_NE(mesh, nullptr);
  ASSERT_EQ(mesh->size(), 1u);
  const Vec3 expected[3] = {Vec3(0, 1, 2), Vec3(3, 1, 2), Vec3(0, 4, 2)};  // by hand
  for (int k = 0; k < 3; ++k) {
    // 1e-15: one subtraction of exactly representable numbers (h = 0.5) is exact; margin only.
    EXPECT_LT((mesh->triangles[0].v[static_cast<std::size_t>(k)] - expected[k]).norm(), 1e-15) << "vertex " << k;
  }
}

TEST(LegacyScene, NoObjectMeshFileMeansNoDisplayMesh) {
  const Scene scene = read_legacy_scene(write_case(Params{}, true), {});
  ASSERT_EQ(scene.objects.size(), 1u);
  EXPECT_EQ(scene.objects[0].object->display_mesh(), nullptr);
}

}  // namespace
}  // namespace ppohdem::dem
