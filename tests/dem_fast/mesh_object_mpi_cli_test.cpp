// A mesh object with exact (per-feature) contacts and a motion program, through the fast
// engine's decomposition (docs/objects.md "Exact contacts for mesh objects", docs/dem.md
// "Domain decomposition"): `mpirun -n P ppohdem simulate` writes the REFERENCE engine's final
// state and the same sums for P = 1, 2, 4 and 1 or 2 threads, and a checkpoint taken at 2 ranks
// inside the program's second segment restarts at 1 and 4 ranks bit for bit.
// Label mpi; built only with PPOHDEM_ENABLE_MPI.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "../apps/cli_runner.hpp"
#include "bed_scene.hpp"
#include "box_over_bed.hpp"
#include "mpi_runner.hpp"

namespace fs = std::filesystem;
using ppohdem::test::body;
using ppohdem::test::CommandResult;
using ppohdem::test::run_mpi;

namespace {

// The bed of write_bed (9 x 9 x 9 spheres of 1 mm in an 18.9 mm box, moving at up to 0.3 m/s)
// and a closed 6 mm box mesh resting on its top layer, over the middle of the bed. Its
// program: down at 0.5 m/s into the bed for 2 ms, then a turn about x at 20 rad/s (through the
// centroid), so that the box's faces, edges and vertices all touch particles, and the
// contacts' springs cross the switch at step 200.
fs::path write_box_in_bed(const fs::path& dir, long steps) {
  const fs::path scene = ppohdem::test::write_bed(dir, 9, 9, 9, steps, 100);
  ppohdem::test::append_box_over_bed(dir, scene,
                                     "[[object.motion]]\nstart = 0.0\ntype = \"translate\"\nvelocity = [0.0, 0.0, -0.5]\n"
                                     "[[object.motion]]\nstart = 0.002\ntype = \"rotate\"\naxis = [1.0, 0.0, 0.0]\nomega = 20.0\n");
  return scene;
}

fs::path scratch(const std::string& name) { return ppohdem::test::scratch("dem_fast_mesh_mpi", name); }

}  // namespace

TEST(MeshObjectMpi, ExactContactsAreTheReferencesAcrossRanksAndThreads) {
  const long steps = 400;
  const fs::path ref_dir = scratch("reference");
  const CommandResult ref =
      ppohdem::test::run_ppohdem("simulate '" + write_box_in_bed(ref_dir, steps).string() + "' --engine reference --quiet");
  ASSERT_EQ(ref.exit_code, 0) << ref.output;
  const std::string ref_final = body(ref_dir / "out" / "final.csv");
  // Not vacuous: the box pushes into the bed before the switch (a load in the row of step 200).
  const std::string ref_objects = body(ref_dir / "out" / "objects.csv");
  const std::size_t row200 = ref_objects.find("\n200,");
  ASSERT_NE(row200, std::string::npos) << ref_objects;
  const std::string row = ref_objects.substr(row200 + 1, ref_objects.find('\n', row200 + 1) - row200 - 1);
  EXPECT_EQ(row.find(",0,0,0,0,0,0,"), std::string::npos) << row;
  // final.csv is the reference's bit for bit; the sums (energy.csv, objects.csv) are summed in
  // another order by the reference (docs/dem.md), so they are compared between the fast runs.
  std::string first_energy, first_objects;
  for (const int ranks : {1, 2, 4}) {
    for (const int threads : {1, 2}) {
      SCOPED_TRACE(std::to_string(ranks) + " ranks x " + std::to_string(threads) + " threads");
      const fs::path dir = scratch("np" + std::to_string(ranks) + "_t" + std::to_string(threads));
      const CommandResult run = run_mpi(ranks, threads, write_box_in_bed(dir, steps), "--engine fast --quiet");
      ASSERT_EQ(run.exit_code, 0) << run.output;
      EXPECT_EQ(body(dir / "out" / "final.csv"), ref_final);
      if (first_energy.empty()) {
        first_energy = body(dir / "out" / "energy.csv");
        first_objects = body(dir / "out" / "objects.csv");
      }
      EXPECT_EQ(body(dir / "out" / "energy.csv"), first_energy);
      EXPECT_EQ(body(dir / "out" / "objects.csv"), first_objects);
    }
  }
}

// The checkpoint at step 300 (a frame step) lies in the rotation segment (t = 3 ms > 2 ms).
TEST(MeshObjectMpi, RestartInsideTheSecondSegmentAtAnotherRankCountIsBitwise) {
  const long steps = 400;
  const fs::path whole_dir = scratch("restart_whole");
  const CommandResult whole = run_mpi(2, 1, write_box_in_bed(whole_dir, steps), "--engine fast --quiet");
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  for (const int ranks : {1, 4}) {
    SCOPED_TRACE("restart at " + std::to_string(ranks) + " ranks");
    const fs::path dir = scratch("restart_np" + std::to_string(ranks));
    const fs::path scene = write_box_in_bed(dir, steps);
    const CommandResult first = run_mpi(2, 1, scene, "--engine fast --quiet --steps 300 --checkpoint-every 300");
    ASSERT_EQ(first.exit_code, 0) << first.output;
    const CommandResult second =
        run_mpi(ranks, 1, scene, "--engine fast --quiet --restart '" + (dir / "out" / "checkpoint.bin").string() + "'");
    ASSERT_EQ(second.exit_code, 0) << second.output;
    for (const char* file : {"final.csv", "energy.csv", "objects.csv"}) {
      EXPECT_EQ(body(dir / "out" / file), body(whole_dir / "out" / file)) << file;
    }
  }
}

// The far-object skip (docs/objects.md "Far objects cost nothing") under the decomposition: the
// box's reach (its 6 mm body and the 2.5 mm margin) covers a small part of the 18.9 mm bed, so
// most particles of every rank are skipped; with the skip off every particle is evaluated
// against the object. The outputs are the same bits either way, at 2 and 4 ranks.
TEST(MeshObjectMpi, FarObjectSkipChangesNoBitAcrossRanks) {
  const long steps = 300;
  for (const int ranks : {2, 4}) {
    SCOPED_TRACE(std::to_string(ranks) + " ranks");
    const fs::path skip_dir = scratch("skip_np" + std::to_string(ranks));
    const fs::path all_dir = scratch("noskip_np" + std::to_string(ranks));
    const CommandResult skip = run_mpi(ranks, 1, write_box_in_bed(skip_dir, steps), "--engine fast --quiet");
    ASSERT_EQ(skip.exit_code, 0) << skip.output;
    const CommandResult all = run_mpi(ranks, 1, write_box_in_bed(all_dir, steps), "--engine fast --quiet --no-object-skip");
    ASSERT_EQ(all.exit_code, 0) << all.output;
    for (const char* file : {"final.csv", "energy.csv", "objects.csv"}) {
      EXPECT_EQ(body(skip_dir / "out" / file), body(all_dir / "out" / file)) << file;
    }
  }
}
