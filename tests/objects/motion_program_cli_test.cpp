// Motion programs through `ppohdem simulate` (issue 38, item 1):
//  - the fast and the reference engine give the same bits on a scene whose object runs every
//    kind of segment (the engines' bitwise contract, as for single motions);
//  - a checkpoint written inside a later segment restarts to the same bits as the
//    uninterrupted run (the pose check of run.cpp follows the program), and a checkpoint is
//    refused when the program before its time was changed;
//  - the scoop example (fixtures/scenes/scoop) runs as one scene.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "../apps/cli_runner.hpp"
#include "csv_rows.hpp"
#include "ppohdem/geometry/vector.hpp"
#include "test_paths.hpp"

namespace ppohdem::test {
namespace {

namespace fs = std::filesystem;

void write_text(const fs::path& file, const std::string& text) {
  std::ofstream out(file);
  out << text;
}

std::string slurp(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The file without its comment lines (the run header carries the date, command and engine).
std::string data_lines(const fs::path& file) {
  std::istringstream in(slurp(file));
  std::string line, out;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] != '#') out += line + '\n';
  }
  return out;
}

/// A closed box [lo, hi] as ASCII STL, outward normals (12 triangles).
std::string box_stl(const Vec3& lo, const Vec3& hi) {
  std::ostringstream s;
  s.precision(17);
  s << "solid plate\n";
  auto corner = [&](int i) { return Vec3(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z()); };
  // Each face as 4 corner indices, counter-clockwise seen from outside.
  const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) {
    for (const auto& tri : {std::array<int, 3>{f[0], f[1], f[2]}, std::array<int, 3>{f[0], f[2], f[3]}}) {
      s << "facet normal 0 0 0\nouter loop\n";
      for (int i : tri) s << "vertex " << corner(i).x() << ' ' << corner(i).y() << ' ' << corner(i).z() << '\n';
      s << "endloop\nendfacet\n";
    }
  }
  s << "endsolid plate\n";
  return s.str();
}

/// 150 spheres (R = 2 mm) in a lattice on the floor of a 5 cm x 2.8 cm box, and a plate just
/// above them driven by a program with every kind of segment, switching every 200-300 steps
/// (dt = 1.5e-5 s, 1200 steps): it presses into the bed, turns, wobbles, shakes and lifts.
/// `first_velocity` is the first moving segment's velocity (changed by the refusal test).
std::string program_scene(const std::string& first_velocity = "[-0.1, 0.0, -0.3]") {
  return "[simulation]\ndt = 1.5e-5\nsteps = 1200\ngravity = [0.0, 0.0, -9.81]\n"
         "[material]\ndensity = 2500.0\nyoung = 2.0e7\npoisson = 0.3\nrestitution = 0.5\nfriction = 0.5\n"
         "[contact]\nmodel = \"hertz-mindlin\"\n"
         "[particles]\ngenerator = \"lattice\"\nbox_min = [0.0, 0.0, 0.0]\nbox_max = [0.05, 0.028, 0.02]\n"
         "count = 150\nradius = 2.0e-3\nseed = 5\njitter = 0.1\n"
         "[[wall]]\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\n"
         "[[wall]]\npoint = [0.0, 0.0, 0.0]\nnormal = [1.0, 0.0, 0.0]\n"
         "[[wall]]\npoint = [0.05, 0.0, 0.0]\nnormal = [-1.0, 0.0, 0.0]\n"
         "[[wall]]\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 1.0, 0.0]\n"
         "[[wall]]\npoint = [0.0, 0.028, 0.0]\nnormal = [0.0, -1.0, 0.0]\n"
         "[[object]]\nname = \"plate\"\nmesh = \"plate.stl\"\ncells = [24, 14, 6]\n"
         "[[object.motion]]\nstart = 0.0\ntype = \"rest\"\n"
         "[[object.motion]]\nstart = 0.0015\ntype = \"translate\"\nvelocity = " + first_velocity + "\n"
         "[[object.motion]]\nstart = 0.006\ntype = \"rotate\"\naxis = [0.0, 1.0, 0.0]\nomega = 3.0\n"
         "[[object.motion]]\nstart = 0.009\ntype = \"vibrate_rotate\"\naxis = [0.0, 0.0, 1.0]\namplitude = 0.05\n"
         "frequency = 100.0\nphase = 0.3\n"
         "[[object.motion]]\nstart = 0.012\ntype = \"vibrate_translate\"\namplitude = [0.001, 0.0, 0.0005]\n"
         "period = 0.005\n"
         "[[object.motion]]\nstart = 0.015\ntype = \"translate_rotate\"\nvelocity = [0.0, 0.0, 0.1]\n"
         "axis = [0.0, 0.0, 1.0]\nomega = 2.0\npoint = [0.03, 0.014, 0.017]\n"
         "[output]\ndir = \"out\"\nevery = 100\nformats = [\"csv\"]\n";
}

fs::path program_scene_dir(const std::string& first_velocity = "[-0.1, 0.0, -0.3]") {
  const fs::path dir = scratch_dir();
  write_text(dir / "plate.stl", box_stl(Vec3(0.015, 0.006, 0.0135), Vec3(0.045, 0.022, 0.0175)));
  write_text(dir / "scene.toml", program_scene(first_velocity));
  return dir;
}

/// The particle rows of final.csv (id, x, y, z, ...) as doubles.
std::vector<std::vector<double>> particle_rows(const fs::path& file) { return ppohdem::test::numeric_csv_rows(file); }

const char* const kOutputs[] = {"final.csv", "energy.csv", "objects.csv", "frame_000900.csv", "frame_001200.csv"};

TEST(MotionProgramCli, FastAndReferenceEnginesGiveTheSameBits) {
  const fs::path dir = program_scene_dir();
  const auto fast = run_ppohdem("simulate scene.toml --quiet --engine fast", dir.string());
  ASSERT_EQ(fast.exit_code, 0) << fast.output;
  fs::rename(dir / "out", dir / "out_fast");
  const auto reference = run_ppohdem("simulate scene.toml --quiet --engine reference", dir.string());
  ASSERT_EQ(reference.exit_code, 0) << reference.output;
  // The particles: the same bits (the engines' contract, tests/dem_fast/fast_engine_test.cpp).
  for (const char* file : {"final.csv", "frame_000600.csv", "frame_000900.csv", "frame_001200.csv"}) {
    EXPECT_EQ(data_lines(dir / "out_fast" / file), data_lines(dir / "out" / file)) << file;
    EXPECT_FALSE(data_lines(dir / "out" / file).empty()) << file;
  }
  // Energies and loads are sums over contacts in another order (as in fast_engine_test.cpp):
  // round-off only. Energies: 1e-12 of the scale for the state terms, 1e-10 for the cumulative
  // ones (1200 evaluations); loads: 1e-12 of the bed's weight (and 5 cm for the moments).
  const auto energy_fast = numeric_csv_rows(dir / "out_fast" / "energy.csv");
  const auto energy_reference = numeric_csv_rows(dir / "out" / "energy.csv");
  ASSERT_EQ(energy_fast.size(), energy_reference.size());
  double scale = 0.0;  // the largest energy in play [J]
  for (const auto& row : energy_reference) scale = std::max({scale, row.at(2) + row.at(3) + row.at(5) + row.at(6), row.at(4)});
  int working_rows = 0;  // rows where the plate did work on the bed since the previous row
  for (std::size_t r = 0; r < energy_reference.size(); ++r) {
    for (std::size_t c = 2; c < 8; ++c) {
      EXPECT_NEAR(energy_fast[r][c], energy_reference[r][c], (c < 6 ? 1e-12 : 1e-10) * scale) << "row " << r << " column " << c;
    }
    if (r > 0 && energy_reference[r][7] != energy_reference[r - 1][7]) ++working_rows;
  }
  EXPECT_GE(working_rows, 5);  // not vacuous: the plate pushed on the bed in several segments
  const auto objects_fast = numeric_csv_rows(dir / "out_fast" / "objects.csv");
  const auto objects_reference = numeric_csv_rows(dir / "out" / "objects.csv");
  ASSERT_EQ(objects_fast.size(), objects_reference.size());
  const double weight = 150 * 2500.0 * 4.0 / 3.0 * 3.141592653589793 * 8e-9 * 9.81;  // [N]
  for (std::size_t r = 0; r < objects_reference.size(); ++r) {
    for (std::size_t c = 0; c < 13; ++c) EXPECT_EQ(objects_fast[r][c], objects_reference[r][c]) << "row " << r;  // pose
    for (std::size_t c = 13; c < 16; ++c) EXPECT_NEAR(objects_fast[r][c], objects_reference[r][c], 1e-12 * weight);
    for (std::size_t c = 16; c < 19; ++c) EXPECT_NEAR(objects_fast[r][c], objects_reference[r][c], 5e-14 * weight);
  }
}

TEST(MotionProgramCli, RestartInsideALaterSegmentGivesTheSameBits) {
  // Checkpoint at step 900, t = 0.0135 s: inside the fifth segment (vibrate_translate).
  const fs::path whole = program_scene_dir();
  const auto w = run_ppohdem("simulate scene.toml --quiet --checkpoint-every 1200", whole.string());
  ASSERT_EQ(w.exit_code, 0) << w.output;
  const fs::path halves = whole.parent_path() / (whole.filename().string() + "_halves");
  fs::remove_all(halves);
  fs::create_directories(halves);
  fs::copy(whole / "plate.stl", halves / "plate.stl");
  fs::copy(whole / "scene.toml", halves / "scene.toml");
  const auto first = run_ppohdem("simulate scene.toml --quiet --steps 900 --checkpoint-every 900", halves.string());
  ASSERT_EQ(first.exit_code, 0) << first.output;
  fs::copy(halves / "out" / "checkpoint.bin", halves / "at900.bin");
  const auto rest = run_ppohdem("simulate scene.toml --quiet --restart at900.bin --checkpoint-every 1200", halves.string());
  ASSERT_EQ(rest.exit_code, 0) << rest.output;
  EXPECT_NE(rest.output.find("restarted at step 900"), std::string::npos) << rest.output;
  for (const char* file : kOutputs) {
    EXPECT_EQ(data_lines(whole / "out" / file), data_lines(halves / "out" / file)) << file;
  }
  EXPECT_EQ(slurp(whole / "out" / "checkpoint.bin").size(), slurp(halves / "out" / "checkpoint.bin").size());

  // The same checkpoint with a program changed before its time: the object would not be where
  // the checkpoint has it, so the restart is refused (exit status 2, the message of run.cpp).
  write_text(halves / "scene.toml", program_scene("[-0.1, 0.0, -0.35]"));
  const auto changed = run_ppohdem("simulate scene.toml --quiet --restart at900.bin", halves.string());
  EXPECT_EQ(changed.exit_code, 2) << changed.output;
  EXPECT_NE(changed.output.find("is not where the scene's motion puts it"), std::string::npos) << changed.output;
  fs::remove_all(halves);
}

TEST(MotionProgramCli, ScoopExampleRunsAsOneScene) {
  // fixtures/scenes/scoop/scoop_translate_rotate.toml as a user runs it (24,000 steps, 650
  // spheres, ~3 s): it must finish with its run checks passed (energy balance, overlaps), the
  // scoop must have pushed on the bed while translating and while turning, and carried some
  // particles up: at the end the scoop rests lifted, and 27 particles are above 2.2 cm,
  // where no particle of the settled bed is (its top centres: 1.94 cm). The run is
  // chaotic, so the bound leaves room for another compiler's rounding: at least 15.
  const fs::path dir = scratch_dir();
  for (const char* f : {"scoop_translate_rotate.toml", "scoop.stl"}) {
    fs::copy(fixture(std::string("scenes/scoop/") + f), dir / f);
  }
  const auto r = run_ppohdem("simulate scoop_translate_rotate.toml --quiet", dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // A normal scene (an object smaller than the box, its grid 2 R around its mesh): no particle
  // within the scoop's reach is outside its grid, so no warning and a count of zero
  // (docs/objects.md "Outside the grid").
  EXPECT_EQ(r.output.find("outside the distance grid"), std::string::npos) << r.output;
  bool pushed_translating = false, pushed_turning = false;
  for (const auto& row : numeric_csv_rows(dir / "out_scoop" / "objects.csv")) {
    EXPECT_EQ(row.back(), 0.0);  // outside_grid
    const double t = row.at(1), force = std::abs(row.at(13)) + std::abs(row.at(14)) + std::abs(row.at(15));
    if (t > 0.12 && t < 0.22 && force > 0) pushed_translating = true;
    if (t > 0.22 && t < 0.32 && force > 0) pushed_turning = true;
  }
  EXPECT_TRUE(pushed_translating);
  EXPECT_TRUE(pushed_turning);
  int lifted = 0;
  for (const auto& row : particle_rows(dir / "out_scoop" / "final.csv")) {
    if (row.at(3) > 0.022) ++lifted;  // z [m]
  }
  EXPECT_GE(lifted, 15);
}

}  // namespace
}  // namespace ppohdem::test
