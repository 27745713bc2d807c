// `ppohdem simulate --alternate-threads A,B --alternate-every K` (apps/cmd_simulate.cpp): the
// run switches the OpenMP thread count every K steps and reports each count's steps and
// particle-steps per second. Checked through the command line, as ci/bench-dem.sh calls it:
// - the files are the ones of a plain one-thread run, byte for byte (header lines aside): the
//   fast engine's results do not depend on the thread count, also when it changes mid-run;
// - each count is charged exactly the steps of its blocks (order 1 2 2 1 ...), counted here from
//   the definition;
// - bad values get a clear error.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "../apps/cli_runner.hpp"
#include "bed_scene.hpp"

namespace fs = std::filesystem;
using ppohdem::test::body;
using ppohdem::test::CommandResult;

namespace {

fs::path scratch(const std::string& name) { return ppohdem::test::scratch("alternate_threads", name); }

CommandResult simulate(const fs::path& scene, int threads, const std::string& args) {
  return ppohdem::test::run_shell("cd '" + scene.parent_path().string() + "' && env OMP_NUM_THREADS=" +
                                  std::to_string(threads) + " OMP_WAIT_POLICY=passive '" + std::string(PPOHDEM_EXE) +
                                  "' simulate '" + scene.string() + "' " + args + " 2>&1");
}


/// The steps the report charges to `threads` threads, or -1 if it has no line for them.
long reported_steps(const std::string& output, int threads) {
  const std::string key = "alternate threads: " + std::to_string(threads) + " thread(s) ";
  const auto at = output.find(key);
  if (at == std::string::npos) return -1;
  long steps = -1;
  std::sscanf(output.c_str() + at + key.size(), "%ld steps", &steps);
  return steps;
}

}  // namespace

// 12 x 12 x 8 = 1152 spheres: above kParallelMin (1024), so the kernel really runs on 2 threads
// in the 2-thread blocks (and lays its springs out afresh at every switch).
TEST(AlternateThreads, SwitchingMidRunChangesNoBitAndChargesEachCountItsSteps) {
  constexpr long kSteps = 130;  // 18 blocks of 7 and a last block of 4 (strict turns would charge 67 and 63)
  constexpr long kEvery = 7;
  const fs::path plain_dir = scratch("plain");
  const fs::path plain = ppohdem::test::write_bed(plain_dir, 12, 12, 8, kSteps, 40);
  const CommandResult p = simulate(plain, 1, "--engine fast");
  ASSERT_EQ(p.exit_code, 0) << p.output;

  const fs::path alt_dir = scratch("alternating");
  const fs::path alternating = ppohdem::test::write_bed(alt_dir, 12, 12, 8, kSteps, 40);
  const CommandResult a = simulate(alternating, 2, "--engine fast --alternate-threads 1,2 --alternate-every 7");
  ASSERT_EQ(a.exit_code, 0) << a.output;
  for (const char* file : {"final.csv", "energy.csv", "frame_000040.csv", "frame_000080.csv"}) {
    EXPECT_EQ(body(alt_dir / "out" / file), body(plain_dir / "out" / file)) << file;
  }
  // Step s (1-based) belongs to block b = (s - 1) / kEvery; the blocks go 1 2 2 1 1 2 2 1 ...
  // threads (pairs of blocks, the second pair reversed).
  long expected[2] = {0, 0};
  for (long s = 1; s <= kSteps; ++s) {
    const long b = (s - 1) / kEvery;
    ++expected[(b / 2) % 2 == 0 ? b % 2 : 1 - b % 2];
  }
  EXPECT_EQ(expected[0] + expected[1], kSteps);
  EXPECT_EQ(reported_steps(a.output, 1), expected[0]) << a.output;
  EXPECT_EQ(reported_steps(a.output, 2), expected[1]) << a.output;
}

TEST(AlternateThreads, BadValuesAreRefusedWithAClearMessage) {
  const fs::path dir = scratch("bad");
  const fs::path scene = ppohdem::test::write_bed(dir, 3, 3, 2, 10, 0);
  const CommandResult zero = simulate(scene, 1, "--engine fast --alternate-threads 1,0");
  EXPECT_NE(zero.exit_code, 0);
  EXPECT_NE(zero.output.find("--alternate-threads: expected thread counts >= 1, got 0"), std::string::npos) << zero.output;
  const CommandResult every = simulate(scene, 1, "--engine fast --alternate-threads 1,2 --alternate-every 0");
  EXPECT_NE(every.exit_code, 0);
  EXPECT_NE(every.output.find("--alternate-every: expected >= 1 step"), std::string::npos) << every.output;
  const CommandResult reference = simulate(scene, 1, "--engine reference --alternate-threads 1,2");
  EXPECT_NE(reference.exit_code, 0);
  EXPECT_NE(reference.output.find("use --engine fast"), std::string::npos) << reference.output;
}
