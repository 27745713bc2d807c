// `ppohdem simulate --compat ppohdem-1.0 input_params_update.dat [--initial STATE] [--steps N]`:
// the original ppOpen-APPL/DEM 1.0 sample program, number for number
// (reference/compat/include/ppohdem/compat/ppohdem10_dem.hpp, docs/compat.md §2). Run it where the original ran: the
// directory holding distance_NNNN.dat and object_mesh.stl (from `ppohdem voxelize --compat
// ppohdem-1.0`); it writes data/outNNN.dat, obj/objNNN.pov, distance/objects_distanceNNN.csv
// and objects_distance.csv there.
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>

#include "ppohdem/error.hpp"
#include "ppohdem/provenance.hpp"
#include "ppohdem/compat/ppohdem10_dem.hpp"

namespace ppohdem::app {

void run_simulate_compat(const std::string& mode, const std::string& params_file,
                         const std::optional<std::string>& initial, std::optional<long> steps, bool quiet) {
  if (mode != "ppohdem-1.0") throw InputError("--compat: the only mode is ppohdem-1.0, got '" + mode + "'");
  compat::Ppohdem10RunOptions options;
  options.work_dir = std::filesystem::current_path();
  if (initial) options.initial = std::filesystem::path(*initial);
  options.steps = steps;
  options.progress = !quiet;
  if (!quiet) std::fprintf(stderr, "%s; compat ppohdem-1.0\n", provenance_line().c_str());
  const compat::Ppohdem10RunSummary s = compat::run_ppohdem10_dem(params_file, options);
  std::printf("simulate: compat ppohdem-1.0, %ld steps, rtime %.17g, %d frames, %ld re-sorts, wall %.3f s\n",
              s.steps, s.rtime, s.frames, s.resorts, s.wall_seconds);
}

}  // namespace ppohdem::app
