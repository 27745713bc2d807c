// Several ranks read one particle file, each keeping a share (docs/dem.md "Reading on every
// rank"), through the command line as a user runs it: `mpirun -n P ppohdem simulate SCENE`.
// The oracle is what the test wrote into the file: the line it spoiled, the two lines it gave
// one id, the pairs it made overlap. Every rank must stop with that error at P = 1, 2, 3, 4,
// even when the error's lines lie in different shares. A file whose ids do not increase, with
// a law that needs every radius (collision_time), and a file with a material column (written
// back in parts with it) run to the reference engine's bits.
// Label mpi; built only with PPOHDEM_ENABLE_MPI.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "../apps/cli_runner.hpp"
#include "bed_scene.hpp"
#include "mpi_runner.hpp"

namespace fs = std::filesystem;
using ppohdem::test::body;
using ppohdem::test::CommandResult;
using ppohdem::test::run_mpi;

namespace {

fs::path scratch(const std::string& name) { return ppohdem::test::scratch("dem_shared_read_mpi", name); }

/// 300 spheres of R = 1 mm on a 3 mm lattice (10 x 10 x 3), ids 1..300 in order, with
/// comments and blank lines among them: the file's lines, header first.
std::vector<std::string> lattice_lines() {
  std::vector<std::string> lines = {"# written by shared_read_mpi_cli_test", "", "id,x,y,z,vx,vy,vz,wx,wy,wz,radius"};
  for (int i = 0; i < 300; ++i) {
    std::ostringstream line;
    line << i + 1 << ',' << 0.003 * (i % 10) << ',' << 0.003 * ((i / 10) % 10) << ',' << 0.003 * (i / 100)
         << ",0,0,0,0,0,0,0.001";
    lines.push_back(line.str());
    if (i % 37 == 5) lines.push_back("# a comment among the data");
    if (i % 53 == 7) lines.push_back("");
  }
  return lines;
}

/// The 1-based line of the particle with this id.
std::size_t line_of(const std::vector<std::string>& lines, int id) {
  const std::string start = std::to_string(id) + ",";
  for (std::size_t k = 3; k < lines.size(); ++k) {
    if (lines[k].rfind(start, 0) == 0) return k + 1;
  }
  ADD_FAILURE() << "no id " << id;
  return 0;
}

/// Writes p.csv and s.toml (10 steps of free fall) into dir; returns the scene.
fs::path write_scene(const fs::path& dir, const std::vector<std::string>& lines) {
  std::ofstream csv(dir / "p.csv");
  for (const std::string& line : lines) csv << line << '\n';
  std::ofstream(dir / "s.toml") << "[simulation]\ndt = 1.0e-6\nsteps = 10\ngravity = [0.0, 0.0, -9.81]\n"
                                << "[material]\ndensity = 2500.0\nyoung = 1.0e7\npoisson = 0.3\nrestitution = 0.5\n"
                                << "friction = 0.5\n[contact]\nmodel = \"hertz-mindlin\"\n[particles]\nfile = \"p.csv\"\n"
                                << "[output]\ndir = \"out\"\nevery = 0\n";
  return dir / "s.toml";
}

/// Runs the scene at 1 to 4 ranks: each must fail, every error line must be `expected` (found
/// in it), and no final.csv may be written.
void expect_every_rank_count_names(const std::string& name, const std::vector<std::string>& lines,
                                   const std::string& expected) {
  for (const int ranks : {1, 2, 3, 4}) {
    SCOPED_TRACE(name + ", ranks " + std::to_string(ranks));
    const fs::path dir = scratch(name + "_np" + std::to_string(ranks));
    const CommandResult run = run_mpi(ranks, 1, write_scene(dir, lines), "--engine fast --quiet");
    EXPECT_NE(run.exit_code, 0) << run.output;
    std::istringstream out(run.output);
    int errors = 0;
    for (std::string line; std::getline(out, line);) {
      if (line.find("ppohdem: error:") == std::string::npos) continue;
      ++errors;
      EXPECT_NE(line.find(expected), std::string::npos) << line;
    }
    EXPECT_GE(errors, 1) << run.output;
    EXPECT_FALSE(fs::exists(dir / "out" / "final.csv"));
  }
}

/// The scene that write(dir) makes, run by the reference engine on one process and by the fast
/// engine at 2 and 3 ranks: every final.csv must be the reference's (checked by `check` too).
void expect_ranks_end_as_the_reference(const std::string& name, const std::function<fs::path(const fs::path&)>& write,
                                       const std::function<void(const std::string&)>& check = {}) {
  const fs::path ref_dir = scratch(name + "_reference");
  const CommandResult ref = ppohdem::test::run_ppohdem("simulate '" + write(ref_dir).string() + "' --engine reference --quiet");
  ASSERT_EQ(ref.exit_code, 0) << ref.output;
  const std::string ref_final = body(ref_dir / "out" / "final.csv");
  if (check) check(ref_final);
  for (const int ranks : {2, 3}) {
    SCOPED_TRACE(name + ", ranks " + std::to_string(ranks));
    const fs::path dir = scratch(name + "_np" + std::to_string(ranks));
    const CommandResult run = run_mpi(ranks, 1, write(dir), "--engine fast --quiet");
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_EQ(body(dir / "out" / "final.csv"), ref_final);
  }
}

}  // namespace

// A bad value, a repeated id (ids that do not increase: the check by hashed id), and both: the
// first in file order wins, wherever the shares are cut.
TEST(SharedReadMpi, TheFirstBadLineIsNamedAsOnOneRank) {
  const std::vector<std::string> good = lattice_lines();
  auto spoil = [](std::vector<std::string> lines, std::size_t line) {
    lines[line - 1] = "999,0.5,0.5,x,0,0,0,0,0,0,0.001";
    return lines;
  };
  auto repeat = [](std::vector<std::string> lines, std::size_t line, int id) {
    std::string& l = lines[line - 1];
    l = std::to_string(id) + l.substr(l.find(','));
    return lines;
  };
  const std::size_t late = line_of(good, 280), early = line_of(good, 150), first = line_of(good, 16);
  expect_every_rank_count_names("bad_value", spoil(good, late), "p.csv:" + std::to_string(late) +
                                                                    ": column 4: expected a number, found 'x'");
  expect_every_rank_count_names("repeated_id", repeat(good, late, 16),
                                "p.csv:" + std::to_string(late) + ": id 16 appears twice");
  expect_every_rank_count_names("repeat_before_bad_value", spoil(repeat(good, early, 16), late),
                                "p.csv:" + std::to_string(early) + ": id 16 appears twice");
  expect_every_rank_count_names("bad_value_before_repeat", repeat(spoil(good, early), late, 16),
                                "p.csv:" + std::to_string(early) + ": column 4: expected a number");
  ASSERT_LT(first, early);
}

// Three overlapping pairs, one of them between the file's first and last particles (in the
// first and the last share): counted once each, the example the pair with the smallest ids.
TEST(SharedReadMpi, OverlapsAcrossSharesAreCountedAsOnOneRank) {
  std::vector<std::string> lines = lattice_lines();
  auto move = [&](int id, const std::string& position) {
    std::string& l = lines[line_of(lines, id) - 1];
    l = std::to_string(id) + "," + position + ",0,0,0,0,0,0,0.001";
  };
  // id 300 sits at (27, 27, 6) mm: id 1 at 1.5 mm from it overlaps by 0.5 mm. Id 151 moves
  // to 1.5 mm from both id 150 (27, 12, 3) and id 160 (27, 15, 3) mm.
  move(1, "0.027,0.027,0.0075");
  move(151, "0.027,0.0135,0.003");
  expect_every_rank_count_names("overlaps", lines,
                                "3 particle pair(s) overlap by more than 1% of the smaller radius, e.g. ids 1 and 300 "
                                "by 0.000500 m");
}

// The bed with its lines shuffled (ids that do not increase) and a linear law given by its
// collision time (k_n from the mean radius of every particle, in file order): 2 and 3 ranks end
// with the reference engine's final state, bit for bit.
TEST(SharedReadMpi, ShuffledIdsAndACollisionTimeLawRunAsTheReference) {
  auto write = [](const fs::path& dir) {
    const fs::path scene = ppohdem::test::write_bed(dir, 9, 9, 9, 200, 0);
    ppohdem::test::replace_in_scene(scene, "model = \"hertz-mindlin\"\n", "model = \"linear\"\ncollision_time = 2.0e-4\n");
    std::ifstream in(dir / "bed.csv");
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    auto data = std::find_if(lines.begin(), lines.end(), [](const std::string& l) { return l.rfind("id,", 0) == 0; }) + 1;
    for (std::size_t k = 0; data + static_cast<std::ptrdiff_t>(k) < lines.end(); ++k) {  // a fixed shuffle
      std::swap(*(data + static_cast<std::ptrdiff_t>(k)), *(data + static_cast<std::ptrdiff_t>((k * 7919) % static_cast<std::size_t>(lines.end() - data))));
    }
    std::ofstream out(dir / "bed.csv");
    for (const std::string& line : lines) out << line << '\n';
    return scene;
  };
  expect_ranks_end_as_the_reference("shuffled", write);
}

// Two named materials given by the file's material column: read in shares and written in parts
// with that column, final.csv at 2 and 3 ranks is the reference engine's, bit for bit.
TEST(SharedReadMpi, AMaterialColumnIsReadInSharesAndWrittenInParts) {
  auto write = [](const fs::path& dir) {
    const fs::path scene = ppohdem::test::write_bed(dir, 9, 9, 9, 200, 0);
    ppohdem::test::replace_in_scene(
        scene, "[material]\ndensity = 2500.0\nyoung = 1.0e7\npoisson = 0.3\nrestitution = 0.5\nfriction = 0.5\n",
        "[[material]]\nname = \"soft\"\ndensity = 2500.0\nyoung = 1.0e7\npoisson = 0.3\nrestitution = 0.5\nfriction = 0.5\n"
        "[[material]]\nname = \"stiff\"\ndensity = 7800.0\nyoung = 5.0e7\npoisson = 0.25\nrestitution = 0.9\nfriction = 0.2\n");
    std::ifstream in(dir / "bed.csv");
    std::vector<std::string> lines;
    bool data = false;
    for (std::string line; std::getline(in, line);) {
      if (data) line += (std::stol(line.substr(0, line.find(','))) % 2 == 0) ? ",stiff" : ",soft";
      if (line.rfind("id,", 0) == 0) {
        line += ",material";
        data = true;
      }
      lines.push_back(line);
    }
    EXPECT_TRUE(data);
    std::ofstream out(dir / "bed.csv");
    for (const std::string& line : lines) out << line << '\n';
    return scene;
  };
  expect_ranks_end_as_the_reference("materials", write, [](const std::string& final) {
    EXPECT_NE(final.find(",stiff\n"), std::string::npos) << "no material column";
  });
}
