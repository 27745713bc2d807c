// `ppohdem simulate` end to end, run as a subprocess as users call it: the example scene of
// issue 5 (fixtures/scenes/two_spheres.toml) and a scene with an unknown key.
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
#include "test_paths.hpp"

namespace ppohdem::dem {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;

std::string quoted(const fs::path& p) {
  std::string s = "'";
  s += p.string();
  s += "'";
  return s;
}

/// The scene file `name` from fixtures/scenes copied into `dir` with its CSV, so the run
/// writes into the scratch directory ([output] dir is relative to the scene file).
fs::path copy_scene(const fs::path& dir, const std::string& name) {
  for (const char* f : {"two_spheres.csv"}) {
    fs::copy_file(test::fixture(std::string("scenes/") + f), dir / f, fs::copy_options::overwrite_existing);
  }
  fs::copy_file(test::fixture("scenes/" + name), dir / name, fs::copy_options::overwrite_existing);
  return dir / name;
}

/// Rows of a CSV file without '#' comment lines, split at commas.
std::vector<std::vector<std::string>> read_rows(const fs::path& file) {
  std::ifstream in(file);
  std::vector<std::vector<std::string>> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> row;
    std::stringstream s(line);
    std::string cell;
    while (std::getline(s, cell, ',')) row.push_back(cell);
    rows.push_back(row);
  }
  return rows;
}

TEST(SimulateCli, ExampleSceneRunsAndReboundsWithTheInputRestitution) {
  const fs::path dir = test::scratch_dir();
  const fs::path scene = copy_scene(dir, "two_spheres.toml");
  const auto r = test::run_ppohdem("simulate --quiet " + quoted(scene), dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const fs::path out = dir / "out";
  ASSERT_TRUE(fs::exists(out / "final.csv"));
  ASSERT_TRUE(fs::exists(out / "energy.csv"));
  // 40000 steps, frames every 1000: steps 0..40000 -> 41 frames in each format.
  for (const char* ext : {".csv", ".vtk", ".pov"}) {
    EXPECT_TRUE(fs::exists(out / (std::string("frame_000000") + ext))) << ext;
    EXPECT_TRUE(fs::exists(out / (std::string("frame_040000") + ext))) << ext;
  }
  // energy.csv parses: the header names the columns, every row has them all.
  const auto energy = read_rows(out / "energy.csv");
  ASSERT_GE(energy.size(), 2u);
  EXPECT_EQ(energy[0][0], "step");
  EXPECT_EQ(energy[0][6], "dissipated");
  for (const auto& row : energy) EXPECT_EQ(row.size(), energy[0].size());
  // final.csv parses with the particle reader; the spheres approached at 0.1 m/s and
  // separate at e * 0.1 m/s. 1% (the figure for Hertz; measured 0.50004).
  const Particles p = read_particles_csv(out / "final.csv");
  ASSERT_EQ(p.size(), 2u);
  const double separation = (p[1].velocity - p[0].velocity).dot((p[1].position - p[0].position).normalized());
  EXPECT_NEAR(separation / 0.1, 0.5, 0.005);
}

TEST(SimulateCli, FastAndOptimizedEnginesWriteTheReferencesFinalStateBitForBit) {
  // The engine table offers the optimized engine as "fast" and "optimized"; its trajectories
  // equal the reference's bit for bit (docs/dem.md "Optimized engine"), so final.csv (written
  // with round-trip precision) has the same rows. 20,000 steps: through the contact.
  std::vector<std::vector<std::vector<std::string>>> finals;
  for (const char* engine : {"reference", "fast", "optimized"}) {
    const fs::path dir = test::scratch_dir() / engine;
    fs::create_directories(dir);
    const fs::path scene = copy_scene(dir, "two_spheres.toml");
    const auto r = test::run_ppohdem(std::string("simulate --quiet --steps 20000 --engine ") + engine + " " + quoted(scene),
                                     dir.string());
    ASSERT_EQ(r.exit_code, 0) << engine << ": " << r.output;
    EXPECT_THAT(r.output, HasSubstr(engine == std::string("reference") ? "reference" : "fast"));
    finals.push_back(read_rows(dir / "out" / "final.csv"));
  }
  ASSERT_EQ(finals[0].size(), 3u);  // header + 2 particles
  EXPECT_EQ(finals[1], finals[0]);
  EXPECT_EQ(finals[2], finals[0]);
}

TEST(SimulateCli, UnknownKeyIsAnErrorNamingKeyFileAndLine) {
  const fs::path dir = test::scratch_dir();
  std::ifstream in(test::fixture("scenes/two_spheres.toml"));
  std::stringstream text;
  text << in.rdbuf();
  std::string scene = text.str();
  const std::string anchor = "[simulation]\n";
  scene.insert(scene.find(anchor) + anchor.size(), "dtt = 1.0e-7\n");  // typo, line 5
  const int line = 1 + static_cast<int>(std::count(scene.begin(), scene.begin() + static_cast<std::ptrdiff_t>(scene.find("dtt")), '\n'));
  { std::ofstream(dir / "bad.toml") << scene; }
  fs::copy_file(test::fixture("scenes/two_spheres.csv"), dir / "two_spheres.csv");
  const auto r = test::run_ppohdem("simulate --quiet bad.toml", dir.string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_THAT(r.output, HasSubstr("dtt"));
  EXPECT_THAT(r.output, HasSubstr("bad.toml"));
  EXPECT_THAT(r.output, HasSubstr(std::to_string(line)));
  EXPECT_FALSE(fs::exists(dir / "out" / "final.csv"));  // nothing was run
}

}  // namespace
}  // namespace ppohdem::dem
