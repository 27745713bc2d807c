// `ppohdem simulate --phases A,B` (apps/phase_timing.hpp): one line per phase with its steps,
// as ci/bench-dem.sh reads them. Checked through the command line:
// - the phases are (first, A], (A, B], (B, end], on a fresh start and after a restart;
// - the phases' wall times add up to no more than the run's wall time (they time disjoint
//   stretches of the same loop), and the files are those of a plain run;
// - marks outside the run or not increasing are refused with a clear error.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "../apps/cli_runner.hpp"
#include "bed_scene.hpp"

namespace fs = std::filesystem;
using ppohdem::test::body;
using ppohdem::test::CommandResult;

namespace {

fs::path scratch(const std::string& name) { return ppohdem::test::scratch("phases", name); }

CommandResult simulate(const fs::path& scene, const std::string& args) {
  return ppohdem::test::run_shell("cd '" + scene.parent_path().string() + "' && env OMP_NUM_THREADS=1 '" +
                                  std::string(PPOHDEM_EXE) + "' simulate '" + scene.string() + "' " + args + " 2>&1");
}

struct Phase {
  long first, last;
  double seconds;
};

std::vector<Phase> phases(const std::string& output) {
  std::vector<Phase> found;
  for (std::size_t at = output.find("phase "); at != std::string::npos; at = output.find("phase ", at + 1)) {
    int k = 0;
    Phase p{};
    if (std::sscanf(output.c_str() + at, "phase %d: steps %ld-%ld, wall %lf s", &k, &p.first, &p.last, &p.seconds) == 4) {
      EXPECT_EQ(k, static_cast<int>(found.size()) + 1);
      found.push_back(p);
    }
  }
  return found;
}

double run_wall(const std::string& output) {
  const auto at = output.find("wall ");
  double wall = -1.0;
  if (at != std::string::npos) std::sscanf(output.c_str() + at, "wall %lf s", &wall);
  return wall;
}

}  // namespace

TEST(SimulatePhases, EachPhaseIsReportedWithItsStepsAndTheFilesAreAPlainRunsOnes) {
  const fs::path plain_dir = scratch("plain");
  const fs::path plain = ppohdem::test::write_bed(plain_dir, 4, 4, 3, 60, 0);
  const CommandResult p = simulate(plain, "");
  ASSERT_EQ(p.exit_code, 0) << p.output;
  EXPECT_TRUE(phases(p.output).empty()) << p.output;

  const fs::path timed_dir = scratch("timed");
  const fs::path timed = ppohdem::test::write_bed(timed_dir, 4, 4, 3, 60, 0);
  const CommandResult t = simulate(timed, "--phases 10,35");
  ASSERT_EQ(t.exit_code, 0) << t.output;
  const std::vector<Phase> got = phases(t.output);
  ASSERT_EQ(got.size(), 3u) << t.output;
  const long expected[3][2] = {{0, 10}, {10, 35}, {35, 60}};
  double sum = 0.0;
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(got[k].first, expected[k][0]);
    EXPECT_EQ(got[k].last, expected[k][1]);
    EXPECT_GE(got[k].seconds, 0.0);
    sum += got[k].seconds;
  }
  // Disjoint stretches of the timed loop: at most the run's wall time (printed with 3 decimals).
  EXPECT_LE(sum, run_wall(t.output) + 5e-4) << t.output;
  for (const char* file : {"final.csv", "energy.csv"}) {
    EXPECT_EQ(body(timed_dir / "out" / file), body(plain_dir / "out" / file)) << file;
  }

  // After a restart at step 20 the first phase starts there.
  const CommandResult half = simulate(plain, "--steps 20 --checkpoint-every 20 --output-dir half");
  ASSERT_EQ(half.exit_code, 0) << half.output;
  const CommandResult r = simulate(plain, "--restart '" + (plain_dir / "half" / "checkpoint.bin").string() +
                                              "' --phases 40 --output-dir restarted");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::vector<Phase> after = phases(r.output);
  ASSERT_EQ(after.size(), 2u) << r.output;
  EXPECT_EQ(after[0].first, 20);
  EXPECT_EQ(after[0].last, 40);
  EXPECT_EQ(after[1].first, 40);
  EXPECT_EQ(after[1].last, 60);
}

TEST(SimulatePhases, MarksOutsideTheRunOrNotIncreasingAreRefused) {
  const fs::path dir = scratch("bad");
  const fs::path scene = ppohdem::test::write_bed(dir, 3, 3, 2, 10, 0);
  for (const char* marks : {"10", "0", "5,5", "6,4", "11"}) {
    const CommandResult c = simulate(scene, std::string("--phases ") + marks);
    EXPECT_NE(c.exit_code, 0) << marks;
    EXPECT_NE(c.output.find("--phases: expected step numbers increasing strictly between the first step (0) and the "
                            "last (10)"),
              std::string::npos)
        << marks << ": " << c.output;
  }
}
