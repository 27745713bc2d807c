// Bad input for moving objects, end to end through `ppohdem simulate` (issue 6, "bad input"):
//   - a window outside the distance data and a resolution mismatch between the window and the
//     data are errors (exit status 2, InputError) whose message gives both values;
//   - a particle outside an object's distance grid is treated as far away (no contact: it
//     falls freely through where the object would be), counted in objects.csv and warned
//     about once, if it lies within its radius of the object (docs/objects.md "Outside the
//     grid"): a mesh object whose grid is cut to the mesh's box warns, the same object with
//     the default margin does not.
// The library-level checks of the same messages are in legacy_scene_test.cpp; these run the
// executable as a user does.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "../apps/cli_runner.hpp"
#include "ppohdem/dem/particle_csv.hpp"
#include "ppohdem/grid/scalar_field.hpp"
#include "ppohdem/io/distance_dat.hpp"
#include "ppohdem/io/vtk_structured_points.hpp"
#include "test_paths.hpp"

namespace ppohdem::dem {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;

// Data: 20^3 nodes over L = 10 m (h = 0.5 m), phi = z_data - 3 m (a half-space).
constexpr int kDataNodes = 20;

/// A legacy case in a scratch directory: distance_0000.dat, input_constants_voxelizer.dat
/// (L = 10 m) and input_params_update.dat with the window Lx, Obj_n, Obj_winstart given.
fs::path legacy_case(double lx, int n, int winstart) {
  const fs::path dir = test::scratch_dir();
  const double h = 10.0 / kDataNodes;
  std::vector<double> values;
  for (int k = 0; k < kDataNodes; ++k)
    for (int j = 0; j < kDataNodes; ++j)
      for (int i = 0; i < kDataNodes; ++i) values.push_back(h * k - 3.0);
  write_distance_dat(dir, values, {kDataNodes, kDataNodes, kDataNodes}, 1);
  std::ofstream(dir / "input_constants_voxelizer.dat")
      << "m.stl\n./\n20 20 20\nLx_Ly_Lz: 10 10 10\nsizeX_sizeY_sizeZ: 1 1 1\nposX_posY_posZ: 5 5 5\n";
  std::ofstream(dir / "input_params_update.dat")
      << "Lx_Ly_Lz: " << lx << " " << lx << " " << lx << "\nTime_finish: 3\nObj_n_x_y_z: " << n << " " << n << " " << n
      << "\nObj_winstart_x_y_z: " << winstart << " " << winstart << " " << winstart
      << "\nObj_velocity_x_y_z: 0 0 0.01\nObj_omega_x_y_z: 0 0 1\nObj_omega_Pi_rad_per_w: 100\n"
      << "Obj_centroid_x_y_z: 5 5 5\n";
  return dir;
}

TEST(ObjectsCli, WindowOutsideTheDistanceDataIsAnErrorGivingBothRanges) {
  // Window 10 nodes from node 12: nodes 12..21, but the data has nodes 1..20.
  const fs::path dir = legacy_case(4.5, 10, 12);
  const auto r = test::run_ppohdem("simulate --quiet --steps 1 input_params_update.dat", dir.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;  // InputError
  EXPECT_THAT(r.output, HasSubstr("input_params_update.dat"));
  EXPECT_THAT(r.output, HasSubstr("nodes 12..21"));
  EXPECT_THAT(r.output, HasSubstr("nodes 1..20"));
  EXPECT_FALSE(fs::exists(dir / "out" / "final.csv"));  // nothing ran
}

TEST(ObjectsCli, ResolutionMismatchIsAnErrorGivingBothSpacings) {
  // Window h = Lx / (Obj_n - 1) = 5.4 / 9 = 0.6 m, data h = L / n = 10 / 20 = 0.5 m.
  const fs::path dir = legacy_case(5.4, 10, 3);
  const auto r = test::run_ppohdem("simulate --quiet --steps 1 input_params_update.dat", dir.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("resolution mismatch"));
  EXPECT_THAT(r.output, HasSubstr("5.4 / 9 = 0.6 m"));
  EXPECT_THAT(r.output, HasSubstr("10 / 20 = 0.5 m"));
  // The same through --data-length (no voxelizer file needed): 12 / 20 = 0.6 m vs 4.5 / 9 = 0.5 m.
  const fs::path dir2 = legacy_case(4.5, 10, 3);
  fs::remove(dir2 / "input_constants_voxelizer.dat");
  const auto r2 = test::run_ppohdem("simulate --quiet --steps 1 --data-length 12 input_params_update.dat", dir2.string());
  EXPECT_EQ(r2.exit_code, 2) << r2.output;
  EXPECT_THAT(r2.output, HasSubstr("4.5 / 9 = 0.5 m"));
  EXPECT_THAT(r2.output, HasSubstr("12 / 20 = 0.6 m"));
  // Control: the matching case runs.
  const fs::path ok = legacy_case(4.5, 10, 3);
  // (0 steps: the seed's particle sheet does not fit in this small box, which is beside the point)
  const auto r3 = test::run_ppohdem("simulate --quiet --steps 0 input_params_update.dat", ok.string());
  EXPECT_EQ(r3.exit_code, 0) << r3.output;
}

TEST(ObjectsCli, ParticleOutsideTheDistanceGridFallsFreelyIsCountedAndWarnedOnce) {
  const fs::path dir = test::scratch_dir();
  // A plate object phi = z on a grid over x, y in [-2, 2] mm, z in [-1, 1] mm.
  GridSpec grid{Vec3(-2e-3, -2e-3, -1e-3), Vec3::Constant(0.5e-3), {9, 9, 5}};
  ScalarField field(grid);
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j < 9; ++j)
      for (int i = 0; i < 9; ++i) field.at(i, j, k) = grid.position(i, j, k).z();
  write_vtk_structured_points(dir / "plate.vtk", field, "distance", "test plate");
  // Particle 1 rests on the plate; particle 2 is just outside the grid (x = 2.6 mm, the grid
  // ends at 2 mm) and lower, where the plate's field, extended, would hold it: it must fall
  // through, and it is counted, as the plate (a half-space) goes on beyond its grid (its
  // inside nodes reach the grid's faces: docs/objects.md "Outside the grid"). Particle 3 is
  // far outside (x = 10 mm): it falls too, and is not counted (farther than R from the plate's
  // box, one cell beyond the grid).
  constexpr double kR = 0.5e-3;  // m
  std::ofstream(dir / "p.csv") << "id,x,y,z,vx,vy,vz,wx,wy,wz,radius\n"
                               << "1,0,0,0.0005,0,0,0,0,0,0," << kR << "\n"
                               << "2,0.0026,0,0.0004,0,0,0,0,0,0," << kR << "\n"
                               << "3,0.01,0,0.0005,0,0,0,0,0,0," << kR << "\n";
  constexpr long kSteps = 200;
  constexpr double kDt = 1e-6;  // s
  std::ofstream(dir / "scene.toml") << "[simulation]\ndt = 1e-6\nsteps = " << kSteps
                                    << "\ngravity = [0.0, 0.0, -9.81]\n"
                                    << "[material]\ndensity = 2500.0\nyoung = 1e7\npoisson = 0.3\nrestitution = 0.5\n"
                                    << "[contact]\nmodel = \"hertz-mindlin\"\n[particles]\nfile = \"p.csv\"\n"
                                    << "[[object]]\nname = \"plate\"\ndistance = \"plate.vtk\"\n"
                                    << "[output]\ndir = \"out\"\nevery = 50\nformats = [\"csv\"]\n";
  const auto r = test::run_ppohdem("simulate scene.toml", dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // Warned once, naming the object.
  const std::string warning = "warning: a particle was outside the distance grid of object";
  const auto first = r.output.find(warning);
  ASSERT_NE(first, std::string::npos) << r.output;
  EXPECT_EQ(r.output.substr(first + warning.size(), 20), " 'scene.toml: plate'");
  EXPECT_EQ(r.output.find(warning, first + 1), std::string::npos) << "warned more than once:\n" << r.output;
  // Counted: one sample per force evaluation (start-up + one per step) for particle 2 only.
  std::ifstream objects(dir / "out" / "objects.csv");
  std::string line, last;
  while (std::getline(objects, line)) {
    if (!line.empty() && line[0] != '#') last = line;
  }
  EXPECT_EQ(last.substr(last.rfind(',') + 1), std::to_string(kSteps + 1)) << last;
  // Far away = no force: particle 2 falls freely, z = z0 - g t^2 / 2 (velocity Verlet is exact
  // for a constant acceleration: round-off of 200 steps, 1e-15 m), while particle 1 is held.
  const Particles end = read_particles_csv(dir / "out" / "final.csv");
  const double t = kSteps * kDt;
  EXPECT_NEAR(end[1].position.z(), 0.0004 - 0.5 * 9.81 * t * t, 1e-15);
  EXPECT_NEAR(end[2].position.z(), 0.0005 - 0.5 * 9.81 * t * t, 1e-15);
  EXPECT_GT(end[0].position.z(), 0.0005 - 0.5 * 9.81 * t * t + 1e-8);  // the plate pushed back
}

TEST(ObjectsCli, MeshObjectWhoseGridIsCutToItsMeshWarnsWithItsNameAndTheTime) {
  // A sphere touching the scoop's plate from below (its centre 1.5 mm under the plate, R = 2 mm)
  // and one far away. With margin = 0 the grid is the mesh's box: the centre is outside it,
  // within R of the object, so the contact is missed and the run warns at t = 0. With the
  // default margin (2 R) the contact is found and nothing is warned or counted.
  for (const bool cut : {true, false}) {
    const fs::path dir = test::scratch_dir();
    fs::copy(test::fixture("scenes/scoop/scoop.stl"), dir / "scoop.stl");
    std::ofstream(dir / "p.csv") << "id,x,y,z,vx,vy,vz,wx,wy,wz,radius\n"
                                 << "1,0.06,0.014,0.0435,0,0,0,0,0,0,0.002\n"
                                 << "2,0.01,0.014,0.01,0,0,0,0,0,0,0.002\n";
    std::ofstream(dir / "scene.toml") << "[simulation]\ndt = 1e-5\nsteps = 20\ngravity = [0.0, 0.0, -9.81]\n"
                                      << "[material]\ndensity = 2500.0\nyoung = 2e7\npoisson = 0.3\nrestitution = 0.5\n"
                                      << "[contact]\nmodel = \"hertz-mindlin\"\n[particles]\nfile = \"p.csv\"\n"
                                      << "[[object]]\nname = \"scoop\"\nmesh = \"scoop.stl\"\ncells = [15, 10, 12]\n"
                                      << (cut ? "margin = 0.0\n" : "")
                                      << "[output]\ndir = \"out\"\nevery = 10\nformats = [\"csv\"]\n";
    const auto r = test::run_ppohdem("simulate scene.toml --quiet", dir.string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const std::string warning = "warning: a particle was outside the distance grid of object 'scene.toml: scoop'";
    std::ifstream objects(dir / "out" / "objects.csv");
    std::string line, last;
    while (std::getline(objects, line)) {
      if (!line.empty() && line[0] != '#') last = line;
    }
    const std::string count = last.substr(last.rfind(',') + 1);
    const Particles end = read_particles_csv(dir / "out" / "final.csv");
    if (cut) {
      EXPECT_THAT(r.output, HasSubstr(warning)) << r.output;
      EXPECT_THAT(r.output, HasSubstr("at t = 0 s within its radius of the object")) << r.output;
      EXPECT_EQ(count, "21") << last;  // particle 1 at every evaluation (start-up + 20 steps)
      EXPECT_NEAR(end[0].velocity.z(), -9.81 * 20 * 1e-5, 1e-12);  // free fall: no contact
    } else {
      EXPECT_EQ(r.output.find("outside the distance grid"), std::string::npos) << r.output;
      EXPECT_EQ(count, "0") << last;
      EXPECT_LT(end[0].velocity.z(), -0.1);  // pushed down by the plate it overlaps by 0.5 mm
    }
  }
}

}  // namespace
}  // namespace ppohdem::dem
