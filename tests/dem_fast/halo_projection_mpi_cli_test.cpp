// `ppohdem project` (the decomposition and halo of P ranks computed in one process) against
// what `mpirun -n P ppohdem simulate` actually builds and sends: the ghosts per rank (mean and
// max, at the first list build) and the halo messages per rank per step (Comm::messages_sent,
// a few steps without a list build: the refresh only). Label mpi; also checks the command's
// errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "../apps/cli_runner.hpp"
#include "bed_scene.hpp"
#include "mpi_runner.hpp"

namespace fs = std::filesystem;
using ppohdem::test::run_mpi;
using ppohdem::test::run_ppohdem;

namespace {

struct Summary {
  double ghosts_mean = 0, ghosts_max = 0, messages_mean = 0, messages_max = 0, interior_mean = 0, interior_min = 0;
};

/// The rows of `ranks` in project's CSV, reduced as simulate reports them.
Summary from_csv(const fs::path& csv, int ranks) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line.rfind("particles,ranks,rank,owned,ghosts_in,ghosts_out,peers,messages_in,messages_out", 0), 0u) << line;
  Summary s;
  int rows = 0;
  while (std::getline(in, line)) {
    std::vector<double> f;
    std::stringstream fields(line);
    for (std::string v; std::getline(fields, v, ',');) f.push_back(std::stod(v));
    if (f.size() < 14 || static_cast<int>(f[1]) != ranks) continue;
    s.interior_min = rows == 0 ? f[13] : std::min(s.interior_min, f[13]);
    s.interior_mean += f[13];
    ++rows;
    s.ghosts_mean += f[4];
    s.ghosts_max = std::max(s.ghosts_max, f[4]);
    s.messages_mean += f[8];
    s.messages_max = std::max(s.messages_max, f[8]);
  }
  EXPECT_EQ(rows, ranks);
  s.ghosts_mean /= ranks;
  s.messages_mean /= ranks;
  s.interior_mean /= ranks;
  return s;
}

Summary from_simulate(const std::string& output) {
  Summary s;
  const auto at = output.find("exchanges: ");
  EXPECT_NE(at, std::string::npos) << output;
  if (at == std::string::npos) return s;
  const auto ghosts = output.find("ghosts per rank ", at);
  EXPECT_NE(ghosts, std::string::npos) << output;
  if (ghosts == std::string::npos) return s;
  EXPECT_EQ(std::sscanf(output.c_str() + at, "exchanges: %lf messages per rank per step (max %lf", &s.messages_mean,
                        &s.messages_max),
            2);
  EXPECT_EQ(std::sscanf(output.c_str() + ghosts, "ghosts per rank %lf (max %lf); interior particles per rank %lf (min %lf)",
                        &s.ghosts_mean, &s.ghosts_max, &s.interior_mean, &s.interior_min),
            4);
  return s;
}

}  // namespace

TEST(ProjectCli, CountsWhatAnMpiRunBuildsAndSends) {
  const fs::path dir = ppohdem::test::scratch("dem_halo_projection", "bed");
  const fs::path scene = ppohdem::test::write_bed(dir, 12, 8, 6, 1000, 0);
  const auto project = run_ppohdem("project '" + scene.string() + "' --ranks 2,4,3 --csv '" + (dir / "p.csv").string() + "'");
  ASSERT_EQ(project.exit_code, 0) << project.output;
  for (const int ranks : {2, 3, 4}) {
    SCOPED_TRACE(ranks);
    const Summary dry = from_csv(dir / "p.csv", ranks);
    // 3 steps: a displacement of at most 0.3 m/s x 3e-5 s = 9 um, below half the skin (0.1 mm),
    // so no list build: the ghosts are those of the start, the messages the refresh's.
    const auto run = run_mpi(ranks, 1, scene, "--engine fast --steps 3 --quiet");
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const Summary real = from_simulate(run.output);
    EXPECT_GT(dry.ghosts_mean, 0.0);
    EXPECT_NEAR(real.ghosts_mean, dry.ghosts_mean, 0.05 + 1e-9);  // printed with one decimal
    EXPECT_EQ(real.ghosts_max, dry.ghosts_max);
    EXPECT_NEAR(real.messages_mean, dry.messages_mean, 0.005 + 1e-9);  // two decimals
    EXPECT_EQ(real.messages_max, dry.messages_max);
    // The halo layer: the dry run's rule is the engine's (put_halo_layer_last).
    EXPECT_GT(dry.interior_mean, 0.0);
    EXPECT_NEAR(real.interior_mean, dry.interior_mean, 0.05 + 1e-9);  // one decimal
    EXPECT_EQ(real.interior_min, dry.interior_min);
  }
}

TEST(ProjectCli, ClearErrors) {
  const fs::path dir = ppohdem::test::scratch("dem_halo_projection", "errors");
  const fs::path scene = ppohdem::test::write_bed(dir, 3, 3, 3, 10, 0);
  const auto both = run_ppohdem("project '" + scene.string() + "' --lattice 4,4,4");
  EXPECT_EQ(both.exit_code, 2);
  EXPECT_NE(both.output.find("exactly one of SCENE, --lattice"), std::string::npos) << both.output;
  const auto ranks = run_ppohdem("project --lattice 4,4,4 --ranks 2,0");
  EXPECT_EQ(ranks.exit_code, 2);
  EXPECT_NE(ranks.output.find("--ranks: expected rank counts >= 1, got 0"), std::string::npos) << ranks.output;
  const auto dims = run_ppohdem("project --weak 4,4");
  EXPECT_EQ(dims.exit_code, 2);
  EXPECT_NE(dims.output.find("expected three counts >= 1"), std::string::npos) << dims.output;
  const auto balance = run_ppohdem("project --lattice 4,4,4 --balance shifted");
  EXPECT_EQ(balance.exit_code, 2);
  EXPECT_NE(balance.output.find("--balance: expected \"rcb\" or \"off\""), std::string::npos) << balance.output;
  // The make_bench.py lattice in memory (pitch 1.05 mm, jitter +-0.01 mm): 4 x 4 x 4 on 2
  // ranks is cut across x at the largest x of column 1 (the 32nd smallest). The reach is 1.1
  // mm: rank 0 receives column 2 (about 1.05 mm beyond the cut), rank 1 columns 1 (on the cut)
  // and 0 (about 1.05 mm before it): 16 and 32 ghosts.
  const auto lattice = run_ppohdem("project --lattice 4,4,4 --ranks 2");
  ASSERT_EQ(lattice.exit_code, 0) << lattice.output;
  EXPECT_NE(lattice.output.find("| 2 | 64 | 32 | 32 | 24 | 32 |"), std::string::npos) << lattice.output;
}
