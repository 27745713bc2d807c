// The seed's sample end to end as a user runs it (fixtures/seed-sample): `ppohdem voxelize
// input_constants_voxelizer.dat` then `ppohdem simulate input_params_update.dat`, shortened
// with --steps. Checks: it runs, the particles stay in the box [0, 11]^3, the energy balance
// closes, and the object moved by the displacement the input asks for.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "../apps/cli_runner.hpp"
#include "ppohdem/dem/particle_csv.hpp"
#include "csv_rows.hpp"
#include "test_paths.hpp"

namespace ppohdem::dem {
namespace {
namespace fs = std::filesystem;

using test::numeric_csv_rows;

/// The sample folder copied into a scratch directory; the mesh path (relative in the fixture)
/// made absolute so it still resolves there.
fs::path copy_sample() {
  const fs::path dir = test::scratch_dir();
  fs::copy_file(test::fixture("seed-sample/input_params_update.dat"), dir / "input_params_update.dat");
  std::ifstream in(test::fixture("seed-sample/input_constants_voxelizer.dat"));
  std::string first;
  std::getline(in, first);
  std::ofstream out(dir / "input_constants_voxelizer.dat");
  out << (test::fixture("seed-sample") / first).lexically_normal().string() << "\n" << in.rdbuf();
  return dir;
}

TEST(SeedSample, VoxelizeThenSimulateRunsKeepsParticlesInTheBoxAndMovesTheObject) {
  const fs::path dir = copy_sample();
  const auto vox = test::run_ppohdem("voxelize --quiet input_constants_voxelizer.dat", dir.string());
  ASSERT_EQ(vox.exit_code, 0) << vox.output;
  const long steps = 5000;  // 10 frames of 500 steps (10 s of simulated time)
  const auto sim = test::run_ppohdem("simulate --quiet --steps 5000 input_params_update.dat", dir.string());
  ASSERT_EQ(sim.exit_code, 0) << sim.output;

  const fs::path out = dir / "out";
  const Particles final = read_particles_csv(out / "final.csv");
  ASSERT_EQ(final.size(), 600u);
  for (const Particle& p : final) {
    for (int a = 0; a < 3; ++a) {
      EXPECT_GT(p.position[a], 0.0) << p.id;
      EXPECT_LT(p.position[a], 11.0) << p.id;
    }
  }
  // Energy balance as for TOML scenes: total = K + R + G + E + D - W constant. 1e-6 relative:
  // the scene's contacts last ~200 steps (pi sqrt(m*/k) / dt), where the measured error of
  // the tests in tests/dem is ~1e-7 (measured here: see docs/objects.md).
  const auto energy = numeric_csv_rows(out / "energy.csv");
  ASSERT_GE(energy.size(), 2u);
  auto total = [](const std::vector<double>& r) { return r[2] + r[3] + r[4] + r[5] + r[6] - r[7]; };
  EXPECT_NEAR(total(energy.back()) / total(energy.front()), 1.0, 1e-6);
  EXPECT_EQ(energy.back()[0], steps);

  // Object: after 10 frames it rose by vel h per frame = 0.005 * 44/76 * 10 m and turned by
  // pi/1200 per frame about +z (input_params_update.dat; conversion in legacy_scene.hpp).
  const auto objects = numeric_csv_rows(out / "objects.csv");
  ASSERT_GE(objects.size(), 2u);
  const auto& last = objects.back();
  const double h = 44.0 / 76.0;
  EXPECT_NEAR(last[5] - objects.front()[5], 0.005 * h * 10, 1e-12);  // centroid_z, round-off
  const double half_angle = 10 * std::numbers::pi / 1200 / 2;
  EXPECT_NEAR(last[6], std::cos(half_angle), 1e-12);  // qw
  EXPECT_NEAR(last[9], std::sin(half_angle), 1e-12);  // qz
  EXPECT_NEAR(last[3] - objects.front()[3], 0.0, 1e-12);  // no sideways motion
}

TEST(SeedSample, MissingDataLengthIsAClearError) {
  const fs::path dir = copy_sample();
  const auto vox = test::run_ppohdem("voxelize --quiet input_constants_voxelizer.dat", dir.string());
  ASSERT_EQ(vox.exit_code, 0) << vox.output;
  fs::remove(dir / "input_constants_voxelizer.dat");
  const auto sim = test::run_ppohdem("simulate --quiet --steps 1 input_params_update.dat", dir.string());
  EXPECT_NE(sim.exit_code, 0);
  EXPECT_THAT(sim.output, ::testing::HasSubstr("--data-length"));
  const auto with_length =
      test::run_ppohdem("simulate --quiet --steps 1 --data-length 44 input_params_update.dat", dir.string());
  EXPECT_EQ(with_length.exit_code, 0) << with_length.output;
}

}  // namespace
}  // namespace ppohdem::dem
