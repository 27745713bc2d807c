// Run under mpirun at 2 and 4 ranks: a step of the fast engine enters ONE collective (the
// allreduce of its StepRecord, docs/dem.md "One collective a step") unless it builds the
// lists, counted by Comm::collectives(), with the queries the run checks make after every step
// (motion_finite, escaped_count, largest_overlap, contact_counts) inside the counted window:
// they read what that allreduce brought and add none. The first step after the construction
// (whose evaluation closes no kick, so no drift was predicted) asks for its drift separately.
// Energies tracked and untracked.
#include <cstdio>
#include <filesystem>
#include <string>

#include "bed_scene.hpp"
#include "mpi_case.hpp"
#include "ppohdem/comm/comm.hpp"
#include "ppohdem/dem/fast/fast_engine.hpp"
#include "ppohdem/dem/scene.hpp"

int main(int argc, char** argv) {
  using namespace ppohdem;
  test::MpiCase run(&argc, &argv);
  const Comm& comm = run.comm();
  // The bed of the bitwise MPI tests: particles cross brick faces and the lists are rebuilt
  // every few tens of steps (bed_scene.hpp), so both kinds of step occur in 150 steps.
  const std::filesystem::path dir =
      run.scratch("dem_one_collective", [](const std::filesystem::path& d) { test::write_bed(d, 12, 8, 6, 150, 0); });
  for (const bool energies : {true, false}) {
    dem::Scene scene = dem::read_scene(dir / "bed.toml");
    scene.setup.energy_balance = energies;
    dem::fast::FastOptions options;
    options.comm = &comm;
    dem::fast::FastEngine engine(scene.setup, options);
    long steady = 0, builds = 0;
    std::string at_builds;  // the collectives of each list-build step
    for (long step = 1; step <= scene.steps; ++step) {
      const std::uint64_t before = comm.collectives();
      const long builds_before = engine.neighbour_list_builds();
      engine.step();
      (void)engine.motion_finite();
      (void)engine.escaped_count();
      (void)engine.largest_overlap();
      (void)engine.contact_counts();
      const std::uint64_t entered = comm.collectives() - before;
      const bool built = engine.neighbour_list_builds() != builds_before;
      if (built) {
        ++builds;
        at_builds += ' ';
        at_builds += std::to_string(entered);
      } else if (step == 1) {
        run.expect(entered == 2,
                   "step 1 (no drift predicted yet) entered " + std::to_string(entered) + " collectives, expected 2");
      } else {
        ++steady;
        run.expect(entered == 1, std::string("energies ") + (energies ? "tracked" : "untracked") + ": step " +
                                     std::to_string(step) + " (no list build) entered " + std::to_string(entered) +
                                     " collectives, expected 1");
      }
    }
    if (comm.rank() == 0) {
      std::printf("%d ranks, energies %s: %ld steps without a list build, 1 collective each; %ld list builds, with%s "
                  "collectives\n",
                  comm.size(), energies ? "tracked" : "untracked", steady, builds, at_builds.c_str());
    }
    run.expect(steady >= 50 && builds >= 2,  // the window must hold both kinds of step
               std::to_string(steady) + " steady steps and " + std::to_string(builds) +
                   " builds: the bed no longer exercises both");
  }
  return run.exit_code();
}
