// `ppohdem simulate --compat ppohdem-1.0`: the original sample program's run, files and all
// (run_ppohdem10_dem in ppohdem10_dem.hpp).
#include <chrono>
#include <cstdio>
#include <string>

#include "ppohdem/error.hpp"
#include "ppohdem/io/atomic_file.hpp"
#include "ppohdem/compat/ppohdem10_dem.hpp"

namespace ppohdem::compat {
namespace {

namespace fs = std::filesystem;

void write_text(const fs::path& path, const std::string& text) {
  AtomicFileWriter out(path);
  out.stream() << text;
  out.commit();
}

std::string frame_name(const char* prefix, int frame, const char* suffix) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s%03d%s", prefix, frame, suffix);  // the original's i3.3
  return buf;
}

}  // namespace

Ppohdem10RunSummary run_ppohdem10_dem(const fs::path& params_file, const Ppohdem10RunOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const Ppohdem10DemInput input = read_ppohdem10_dem_input(params_file, options.work_dir, options.initial);
  Ppohdem10Dem dem(input);
  if (options.steps && *options.steps < 0) throw InputError("--steps: expected >= 0");
  for (const char* dir : {"data", "obj", "distance"}) fs::create_directories(options.work_dir / dir);
  // ppohDEM_prepare_objects_fromfile writes the initial field (the data grid's corner) here.
  write_text(options.work_dir / "objects_distance.csv", dem.object_field_csv());
  const long first_step = dem.counter().itime;
  const long total = options.steps ? *options.steps : -1;
  if (options.progress) {
    std::string origin = "initial sheet from ppohdem's own random numbers (not the original's values)";
    if (options.initial) origin = std::string("initial state ").append(options.initial->string());
    std::fprintf(stderr, "simulate --compat ppohdem-1.0: %zu particles, data %d x %d x %d, %zu object triangles, %s\n",
                 dem.particles().size(), input.data.nodes[0], input.data.nodes[1], input.data.nodes[2],
                 dem.object().mesh_v1.size(),
                 origin.c_str());
  }
  auto last_report = start;
  while (total < 0 || dem.counter().itime - first_step < total) {
    const Ppohdem10StepEvents events = dem.step();
    if (events.frame) {
      const int f = dem.counter().file_index;
      write_text(options.work_dir / "data" / frame_name("out", f, ".dat"), dem.frame_text());
      write_text(options.work_dir / "distance" / frame_name("objects_distance", f, ".csv"), dem.object_field_csv());
      write_text(options.work_dir / "obj" / frame_name("obj", f, ".pov"), dem.object_pov());
      const auto now = std::chrono::steady_clock::now();
      if (options.progress && now - last_report > std::chrono::seconds(5)) {
        std::fprintf(stderr, "  step %ld, t = %.6f, frame %03d, %ld re-sorts\n", dem.counter().itime,
                     dem.counter().rtime, f, dem.resort_count());
        last_report = now;
      }
    }
    if (dem.finished()) break;
  }
  Ppohdem10RunSummary s;
  s.steps = dem.counter().itime - first_step;
  s.rtime = dem.counter().rtime;
  s.frames = dem.counter().file_index - static_cast<int>(first_step / Ppohdem10DemConstants::kStepsPerFrame);
  s.resorts = dem.resort_count();
  s.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return s;
}

}  // namespace ppohdem::compat
