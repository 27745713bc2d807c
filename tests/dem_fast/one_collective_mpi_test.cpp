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
#include "ppohdem/comm/comm.hpp"
#include "ppohdem/dem/fast/fast_engine.hpp"
#include "ppohdem/dem/scene.hpp"

int main(int argc, char** argv) {
  using namespace ppohdem;
  const CommEnvironment environment(&argc, &argv);
  const Comm& comm = environment.world();
  const std::filesystem::path dir = std::filesystem::path(PPOHDEM_BINARY_DIR) / "tests_scratch" / "dem_one_collective" /
                                    std::to_string(comm.size());
  // The bed of the bitwise MPI tests: particles cross brick faces and the lists are rebuilt
  // every few tens of steps (bed_scene.hpp), so both kinds of step occur in 150 steps.
  if (comm.rank() == 0) {
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    test::write_bed(dir, 12, 8, 6, 150, 0);
  }
  comm.barrier();
  int failures = 0;
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
        if (entered != 2) {
          std::printf("rank %d: step 1 (no drift predicted yet) entered %llu collectives, expected 2\n", comm.rank(),
                      static_cast<unsigned long long>(entered));
          ++failures;
        }
      } else {
        ++steady;
        if (entered != 1) {
          std::printf("rank %d: energies %s: step %ld (no list build) entered %llu collectives, expected 1\n", comm.rank(),
                      energies ? "tracked" : "untracked", step, static_cast<unsigned long long>(entered));
          ++failures;
        }
      }
    }
    if (comm.rank() == 0) {
      std::printf("%d ranks, energies %s: %ld steps without a list build, 1 collective each; %ld list builds, with%s "
                  "collectives\n",
                  comm.size(), energies ? "tracked" : "untracked", steady, builds, at_builds.c_str());
    }
    if (steady < 50 || builds < 2) {  // the window must hold both kinds of step
      std::printf("rank %d: %ld steady steps and %ld builds: the bed no longer exercises both\n", comm.rank(), steady, builds);
      ++failures;
    }
  }
  const double total = comm.sum_over_ranks(static_cast<double>(failures));
  return total == 0.0 ? 0 : 1;
}
