// Run under mpirun at 2 ranks x 2 threads and 4 ranks x 1 thread: the halo layer and the overlapped halo
// refresh (docs/dem.md "Domain decomposition (MPI)"). After every list build no interior
// particle has a ghost partner: every slot of its list and a brute-force distance test against
// every ghost (FastEngine::interior_near_ghosts). The bed is the one of
// FastEngineMpi.FrictionalBedIsBitwiseIdenticalAcrossRanksAndThreads (which checks the bits
// against one rank and the reference engine), and this test shows that that run has both parts
// nonempty on every rank and overlaps every refresh it can: every step that neither builds
// nor is the first (whose drift no closing kick predicted). Balance on and off.
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
  const std::filesystem::path dir =
      run.scratch("dem_halo_layer", [](const std::filesystem::path& d) { test::write_bed(d, 15, 15, 19, 200, 100); });
  for (const bool balance : {true, false}) {
    const std::string mode = balance ? "balance rcb" : "balance off";
    dem::Scene scene = dem::read_scene(dir / "bed.toml");
    dem::fast::FastOptions options;
    options.comm = &comm;
    options.balance = balance ? dem::fast::FastOptions::Balance::kBisection : dem::fast::FastOptions::Balance::kOff;
    dem::fast::FastEngine engine(scene.setup, options);
    long builds = 0, step_builds = 0;
    std::size_t fewest_interior = engine.interior_count();
    std::size_t fewest_layer = engine.owned_count() - engine.interior_count();
    auto check_build = [&](long step) {
      ++builds;
      const std::size_t interior = engine.interior_count();
      if (interior > engine.owned_count()) run.fail(mode + ": more interior particles than owned ones");
      fewest_interior = std::min(fewest_interior, interior);
      fewest_layer = std::min(fewest_layer, engine.owned_count() - interior);
      if (const std::size_t near = engine.interior_near_ghosts(); near != 0) {
        run.fail(mode + ": after the build of step " + std::to_string(step) + ", " + std::to_string(near) +
                 " interior particles have a ghost partner");
      }
    };
    check_build(0);  // the construction's build
    for (long step = 1; step <= scene.steps; ++step) {
      const long before = engine.neighbour_list_builds();
      engine.step();
      if (engine.neighbour_list_builds() != before) {
        ++step_builds;
        check_build(step);
      }
    }
    const dem::fast::LoadReport report = engine.load_report();
    const long expected = scene.steps - step_builds - 1;  // not step 1, not a build
    if (report.overlapped_refreshes != expected) {
      run.fail(mode + ": " + std::to_string(report.overlapped_refreshes) + " overlapped refreshes, expected " +
               std::to_string(expected));
    }
    if (fewest_interior == 0) run.fail(mode + ": a build left no interior particle");
    if (fewest_layer == 0) run.fail(mode + ": a build left an empty halo layer");
    if (step_builds < 2) run.fail(mode + ": fewer than 2 list builds in the run: the test exercises too little");
    std::printf("rank %d of %d, %s: %ld builds, interior >= %zu, halo layer >= %zu of %zu owned, %ld refreshes overlapped\n",
                comm.rank(), comm.size(), mode.c_str(), builds, fewest_interior, fewest_layer, engine.owned_count(),
                report.overlapped_refreshes);
  }
  return run.exit_code();
}
