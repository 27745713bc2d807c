// loads.csv (issue 38, item 6): `[output] loads_every = N` writes every boundary's load at its
// own interval, `loads_average = true` the mean over the interval. Oracles:
//  - a sphere settled on a floor loads it with its weight, F = (0, 0, -m g), and the moment
//    about the origin of a force at the contact point (x, y, 0): M_0 = (y F_z, -x F_z, 0);
//  - the averaged load obeys the momentum balance of velocity Verlet exactly: over the steps
//    (n, n + N], with f the particle's total force and v its velocity,
//      m (v_{n+N} - v_n) = dt sum_{k=n}^{n+N-1} (f_k + f_{k+1}) / 2,   f = -F_floor + m g,
//    so  mean F_floor = m g - m (v_{n+N} - v_n) / (N dt) + (F_{n+N} - F_n) / (2 N),
//    computed from the frames' velocities and the instantaneous loads of a second run (the
//    loads never steer the motion, so both runs have the same trajectory).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "../apps/cli_runner.hpp"
#include "csv_rows.hpp"
#include "test_paths.hpp"

namespace ppohdem::test {
namespace {

namespace fs = std::filesystem;

constexpr double kR = 1e-3, kDensity = 2500.0, kG = 9.81, kDt = 1e-6;
constexpr double kX = 0.003, kY = -0.002;  // the sphere's centre over the floor [m]
constexpr long kEvery = 1000, kSteps = 20000;

double mass() { return kDensity * 4.0 / 3.0 * 3.141592653589793 * kR * kR * kR; }

std::string scene(bool average) {
  std::ostringstream s;
  s.precision(17);
  s << "[simulation]\ndt = " << kDt << "\nsteps = " << kSteps << "\ngravity = [0.0, 0.0, " << -kG << "]\n"
    << "[material]\ndensity = " << kDensity << "\nyoung = 1.0e7\npoisson = 0.3\nrestitution = 0.5\nfriction = 0.5\n"
    << "[contact]\nmodel = \"hertz-mindlin\"\n[particles]\nfile = \"p.csv\"\n"
    << "[[wall]]\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\n"
    << "[[wall]]\npoint = [-0.01, 0.0, 0.0]\nnormal = [1.0, 0.0, 0.0]\n"  // never touched: zero rows
    << "[output]\ndir = \"out\"\nevery = " << kEvery << "\nformats = [\"csv\"]\nloads_every = " << kEvery << "\n"
    << (average ? "loads_average = true\n" : "");
  return s.str();
}

fs::path run_case(const fs::path& scratch, const std::string& name, bool average) {
  const fs::path dir = scratch / name;
  fs::create_directories(dir);
  // Dropped from 0.02 mm above the floor, at rest: it bounces (e = 0.5) and settles.
  std::ofstream(dir / "p.csv") << "id,x,y,z,vx,vy,vz,wx,wy,wz,radius\n1," << kX << ',' << kY << ',' << kR + 2e-5
                               << ",0,0,0,0,0,0," << kR << '\n';
  std::ofstream(dir / "scene.toml") << scene(average);
  const auto r = run_ppohdem("simulate scene.toml --quiet", dir.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return dir;
}

/// loads.csv rows of boundary b, keyed by step.
std::map<long, std::vector<double>> loads(const fs::path& dir, int b) {
  std::map<long, std::vector<double>> rows;
  for (const auto& row : numeric_csv_rows(dir / "out" / "loads.csv")) {
    if (static_cast<int>(row.at(2)) == b) rows[static_cast<long>(row.at(0))] = row;
  }
  return rows;
}

/// The vertical velocity in frame_NNNNNN.csv (one particle).
double frame_vz(const fs::path& dir, long step) {
  char name[64];
  std::snprintf(name, sizeof name, "frame_%06ld.csv", step);
  std::ifstream in(dir / "out" / name);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || line[0] == 'i') continue;
    std::vector<double> v;
    std::stringstream s(line);
    std::string cell;
    while (std::getline(s, cell, ',')) v.push_back(std::stod(cell));
    return v.at(6);
  }
  ADD_FAILURE() << "no particle in " << name;
  return 0.0;
}

TEST(LoadsOutput, InstantAndAveragedLoadsOfASphereOnAFloor) {
  const fs::path scratch = scratch_dir();
  const fs::path instant = run_case(scratch, "instant", false);
  const fs::path averaged = run_case(scratch, "averaged", true);
  const double weight = mass() * kG;  // [N]
  const auto a = loads(instant, 0);
  const auto b = loads(averaged, 0);
  ASSERT_EQ(a.size(), static_cast<std::size_t>(kSteps / kEvery + 1));  // steps 0, 1000, ..., 20000
  ASSERT_EQ(b.size(), static_cast<std::size_t>(kSteps / kEvery));      // 1000, ..., 20000
  for (const auto& [step, row] : a) EXPECT_EQ(row.at(9), 1.0) << step;  // samples
  for (const auto& [step, row] : b) EXPECT_EQ(row.at(9), static_cast<double>(kEvery)) << step;
  // The wall that is never touched: zero rows at the same steps.
  for (const auto& [step, row] : loads(averaged, 1)) {
    for (int c = 3; c < 9; ++c) EXPECT_EQ(row.at(c), 0.0) << step;
  }

  // Settled (20 ms, the bounces damped by e = 0.5): the weight. What is left of the motion
  // changes the load by 5e-8 of the weight at 20 ms; bound 1e-6. The moment
  // of that force at (x, y, 0), to round-off.
  const auto& last = a.at(kSteps);
  std::printf("settled load: F_z / (m g) + 1 = %.2e\n", last.at(5) / weight + 1.0);
  EXPECT_NEAR(last.at(5), -weight, 1e-6 * weight);
  EXPECT_NEAR(last.at(3), 0.0, 1e-12 * weight);
  EXPECT_NEAR(last.at(4), 0.0, 1e-12 * weight);
  EXPECT_NEAR(last.at(6), kY * last.at(5), 1e-12 * weight * 0.01);
  EXPECT_NEAR(last.at(7), -kX * last.at(5), 1e-12 * weight * 0.01);
  EXPECT_NEAR(last.at(8), 0.0, 1e-12 * weight * 0.01);

  // The momentum balance of each averaged interval (header): an identity of the integrator, so
  // round-off only: the velocities (%.17g, up to 0.02 m/s, eps 3e-18 m/s) enter divided by
  // N dt = 1e-3 s, m 3e-18 / 1e-3 ~ 3e-20 N, and the 1000-term sums ~1e-13 of the weight.
  // Bound 1e-9 of the weight.
  bool saw_bounce = false;
  double worst = 0.0;
  for (const auto& [step, row] : b) {
    const long n = step - kEvery;
    const double dv = frame_vz(instant, step) - frame_vz(instant, n);
    const double expected = -weight - mass() * dv / (kEvery * kDt) + (a.at(step).at(5) - a.at(n).at(5)) / (2.0 * kEvery);
    EXPECT_NEAR(row.at(5), expected, 1e-9 * weight) << "interval ending at step " << step;
    worst = std::max(worst, std::abs(row.at(5) - expected) / weight);
    saw_bounce = saw_bounce || std::abs(row.at(5) + weight) > 0.01 * weight;
  }
  std::printf("momentum balance of the averaged loads: worst error %.2e of the weight\n", worst);
  EXPECT_TRUE(saw_bounce);  // not vacuous: some interval's mean is not the weight
}

/// The file without its comment lines.
std::string data_lines(const fs::path& file) {
  std::ifstream in(file);
  std::string line, out;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] != '#') out += line + '\n';
  }
  return out;
}

TEST(LoadsOutput, RestartContinuesTheFileOnDisk) {
  // The checkpoint does not carry loads.csv: a restart in the same output directory keeps the
  // rows on disk up to the checkpoint's step (here the end of an averaging interval) and the
  // file ends as the uninterrupted run's, bit for bit.
  const fs::path scratch = scratch_dir();
  const fs::path whole = run_case(scratch, "whole", true);
  const fs::path halves = scratch / "halves";
  fs::create_directories(halves);
  fs::copy(whole / "p.csv", halves / "p.csv");
  fs::copy(whole / "scene.toml", halves / "scene.toml");
  ASSERT_EQ(run_ppohdem("simulate scene.toml --quiet --steps 10000 --checkpoint-every 10000", halves.string()).exit_code, 0);
  // Rows after the checkpoint's step (a run that went on and failed) are dropped on restart.
  std::ofstream(halves / "out" / "loads.csv", std::ios::app) << "11000,0.011,0,1,2,3,4,5,6,1000\n";
  const auto rest = run_ppohdem("simulate scene.toml --quiet --restart out/checkpoint.bin", halves.string());
  ASSERT_EQ(rest.exit_code, 0) << rest.output;
  EXPECT_EQ(data_lines(whole / "out" / "loads.csv"), data_lines(halves / "out" / "loads.csv"));
  EXPECT_EQ(loads(halves, 0).size(), static_cast<std::size_t>(kSteps / kEvery));
}

TEST(LoadsOutput, AverageWithoutAnIntervalIsAnError) {
  const fs::path dir = scratch_dir();
  std::ofstream(dir / "p.csv") << "id,x,y,z,vx,vy,vz,wx,wy,wz,radius\n1,0,0,0.01,0,0,0,0,0,0,0.001\n";
  std::string text = scene(true);
  text.replace(text.find("loads_every = 1000\n"), 19, "");
  std::ofstream(dir / "scene.toml") << text;
  const auto r = run_ppohdem("simulate scene.toml --quiet", dir.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("[output] loads_average needs loads_every = N (steps) > 0"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace ppohdem::test
