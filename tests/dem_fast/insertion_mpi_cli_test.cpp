// Particle insertion across MPI ranks (issue 38 item 5; docs/objects.md "Particle insertion"):
// the example fill scene (fixtures/scenes/fill/box_fill.toml: starts empty, inserts every
// 2,000 steps around a mesh object) run by `mpirun -n 2 ppohdem simulate --engine fast` writes
// the same final.csv, energy.csv and insertions.csv, byte for byte (header lines aside), as the
// REFERENCE engine on one rank; a checkpoint written at 2 ranks after some insertions restarts
// at 1 and 3 ranks and ends with the same files, and a forged part is refused at 1, 2 and 3.
// Label mpi; built only with PPOHDEM_ENABLE_MPI.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "../apps/cli_runner.hpp"
#include "../reliability/reliability_scenes.hpp"
#include "bed_scene.hpp"
#include "forged_part.hpp"

namespace fs = std::filesystem;
using ppohdem::test::body;
using ppohdem::test::CommandResult;

namespace {

const fs::path kScene = fs::path(PPOHDEM_SOURCE_DIR) / "fixtures" / "scenes" / "fill" / "box_fill.toml";

CommandResult run_mpi(int ranks, const std::string& args) {
  const std::string command = "env OMP_NUM_THREADS=1 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1"
                              " OMPI_MCA_mpi_yield_when_idle=1 OMP_WAIT_POLICY=passive '" +
                              std::string(PPOHDEM_MPIEXEC) + "' -n " + std::to_string(ranks) +
                              " --oversubscribe --bind-to none '" + std::string(PPOHDEM_EXE) + "' simulate '" +
                              kScene.string() + "' " + args + " 2>&1";
  return ppohdem::test::run_shell(command);
}

}  // namespace

// 6,000 steps: events at steps 0, 2000, 4000 and 6000 (25 particles each), the first ones
// already falling onto the scoop and the floor.
TEST(InsertionMpi, FillIsTheReferencesAtTwoRanksAndRestartsAtOneAndThree) {
  const fs::path root = ppohdem::test::scratch("insertion_mpi", "fill");
  const std::string steps = " --steps 6000 --quiet";
  const CommandResult ref = ppohdem::test::run_ppohdem("simulate '" + kScene.string() + "' --engine reference --output-dir '" +
                                                       (root / "reference").string() + "'" + steps);
  ASSERT_EQ(ref.exit_code, 0) << ref.output;
  EXPECT_NE(ref.output.find("inserted 100 particles, 0 could not be inserted"), std::string::npos) << ref.output;
  const CommandResult two = run_mpi(2, "--engine fast --output-dir '" + (root / "np2").string() + "'" + steps);
  ASSERT_EQ(two.exit_code, 0) << two.output;
  for (const char* file : {"final.csv", "energy.csv", "insertions.csv"}) {
    EXPECT_EQ(body(root / "np2" / file), body(root / "reference" / file)) << file;
  }
  // A checkpoint at step 4000 (an insertion step: its particles are in it) at 2 ranks,
  // continued at 1 rank.
  const fs::path parts = root / "parts";
  const CommandResult first = run_mpi(2, "--engine fast --output-dir '" + parts.string() +
                                             "' --steps 4000 --checkpoint-every 4000 --quiet");
  ASSERT_EQ(first.exit_code, 0) << first.output;
  // Continued at 1 rank (the parts merged) and at 3 (each rank reads its parts and restores
  // the inserted particles among them: the fill starts empty, so all of them), each from a copy.
  for (const int ranks : {1, 3}) {
    SCOPED_TRACE("restarted at " + std::to_string(ranks) + " ranks");
    const fs::path again = root / ("parts_np" + std::to_string(ranks));
    fs::remove_all(again);
    fs::copy(parts, again, fs::copy_options::recursive);
    const CommandResult second = run_mpi(ranks, "--engine fast --output-dir '" + again.string() + "' --restart '" +
                                                    (again / "checkpoint.bin").string() + "'" + steps);
    ASSERT_EQ(second.exit_code, 0) << second.output;
    for (const char* file : {"final.csv", "insertions.csv"}) {
      EXPECT_EQ(body(again / file), body(root / "reference" / file)) << file;
    }
  }
  // A forged part (well framed, its CRC fixed) giving an inserted particle a material the scene
  // does not have: refused with the same words at every rank count, and no rank waits for the
  // others (the rank that holds it is one of several at 2 and 3 ranks).
  const fs::path forged = root / "forged";
  fs::remove_all(forged);
  fs::copy(parts, forged, fs::copy_options::recursive);
  ppohdem::test::forge_part(forged / "checkpoint.bin", 1, [](ppohdem::dem::CheckpointPart& p) { p.particles.at(0).material = 7; });
  for (const int ranks : {1, 2, 3}) {
    const CommandResult r = run_mpi(ranks, "--engine fast --output-dir '" + forged.string() + "' --restart '" +
                                               (forged / "checkpoint.bin").string() + "'" + steps);
    EXPECT_NE(r.exit_code, 0) << ranks << " ranks";
    EXPECT_NE(r.output.find("insert_particles: material index out of range"), std::string::npos) << ranks << " ranks: " << r.output;
  }
}
