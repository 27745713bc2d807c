#include "ppohdem/dem/run.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <vector>

#include "ppohdem/dem/output_writers.hpp"
#include "ppohdem/dem/particle_csv.hpp"
#include "ppohdem/error.hpp"

namespace ppohdem::dem {

RunSummary run_scene(DemEngine& engine, const Scene& scene, const std::string& header,
                     std::ostream& log) {
  namespace fs = std::filesystem;
  const OutputSpec& out = scene.output;
  std::error_code ec;
  fs::create_directories(out.dir, ec);
  if (!fs::is_directory(out.dir)) {
    throw InputError(out.dir.string(), 0, "cannot create the output directory");
  }
  EnergyLog energy(out.dir / "energy.csv", header);
  const long energy_every = out.every > 0 ? out.every : std::max(1L, scene.steps / 100);
  RunSummary summary;
  summary.initial = engine.energies();
  // Objects: poses and loads with every energy row; a warning the first time an object is
  // sampled outside its grid (the particle is then treated as far from it).
  ObjectLog object_log(out.dir / "objects.csv", header);
  std::vector<bool> warned_outside(scene.objects.size(), false);
  auto log_objects = [&](long step) {
    if (scene.objects.empty()) return;
    const std::vector<BoundaryLoad> loads = engine.boundary_loads();
    for (std::size_t o = 0; o < scene.objects.size(); ++o) {
      const SceneObject& so = scene.objects[o];
      const BoundaryLoad load = so.boundary_index < loads.size() ? loads[so.boundary_index] : BoundaryLoad{};
      object_log.add(step, engine.time(), o, *so.object, load);
    }
  };
  auto warn_outside = [&] {
    for (std::size_t o = 0; o < scene.objects.size(); ++o) {
      const DistanceFieldObject& object = *scene.objects[o].object;
      if (!warned_outside[o] && object.outside_grid_count() > 0) {
        warned_outside[o] = true;
        std::fprintf(stderr, "warning: a particle was outside the distance grid of %s at t = %g s "
                     "(treated as far from the object; counted in objects.csv)\n",
                     object.describe().c_str(), engine.time());
      }
    }
  };

  // Objects' display meshes go into the POV frames and objects/object_K_NNNNNN.vtk.
  std::vector<std::shared_ptr<const DistanceFieldObject>> object_ptrs;
  bool any_display_mesh = false;
  for (const SceneObject& so : scene.objects) {
    object_ptrs.push_back(so.object);
    any_display_mesh = any_display_mesh || so.object->display_mesh() != nullptr;
  }
  auto write_frame = [&](long step) {
    const fs::path stem = out.dir / frame_stem(step);
    if (out.csv) write_particles_csv(fs::path(stem).concat(".csv"), engine.particles(), header);
    if (out.vtk) write_vtk_frame(fs::path(stem).concat(".vtk"), engine.particles(), header);
    if (out.pov) write_pov_frame(fs::path(stem).concat(".pov"), engine.particles(), header, object_ptrs, engine.time());
    if ((out.vtk || out.pov) && any_display_mesh) {
      fs::create_directories(out.dir / "objects", ec);
      for (std::size_t o = 0; o < object_ptrs.size(); ++o) {
        const DistanceFieldObject& object = *object_ptrs[o];
        if (!object.display_mesh()) continue;
        write_mesh_vtk(out.dir / "objects" / object_mesh_file_name(o, step),
                       transformed(*object.display_mesh(), object.pose_at(engine.time())), header);
      }
    }
    if (out.csv || out.vtk || out.pov) ++summary.frames;
  };

  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  auto last_report = start;
  long last_percent = 0;
  energy.add(engine.step_count(), engine.time(), summary.initial);
  log_objects(engine.step_count());
  warn_outside();
  if (out.every > 0) write_frame(engine.step_count());
  for (long s = 1; s <= scene.steps; ++s) {
    engine.step();
    const long step = engine.step_count();
    warn_outside();
    if (s % energy_every == 0 || s == scene.steps) {
      energy.add(step, engine.time(), engine.energies());
      log_objects(step);
    }
    if (out.every > 0 && s % out.every == 0) {
      write_frame(step);
      energy.flush();
      if (!scene.objects.empty()) object_log.flush();
    }
    if (out.progress && scene.steps >= 1000) {
      const long percent = 100 * s / scene.steps;
      const auto now = clock::now();
      if (percent >= last_percent + 10 || now - last_report > std::chrono::seconds(5)) {
        const double elapsed = std::chrono::duration<double>(now - start).count();
        std::fprintf(stderr, "simulate: step %ld / %ld (%ld %%), %.1f s elapsed, %.0f s left\n", s,
                     scene.steps, percent, elapsed,
                     elapsed * static_cast<double>(scene.steps - s) / static_cast<double>(s));
        last_percent = percent - percent % 10;
        last_report = now;
      }
    }
  }
  summary.wall_seconds = std::chrono::duration<double>(clock::now() - start).count();
  summary.steps = scene.steps;
  summary.final = engine.energies();
  summary.escaped = engine.escaped_count();
  log << "simulate: " << scene.steps << " steps of " << engine.particles().size()
      << " particles in " << summary.wall_seconds << " s (" << engine.name() << " engine)\n";
  energy.flush();
  if (!scene.objects.empty()) object_log.flush();
  write_particles_csv(out.dir / "final.csv", engine.particles(), header);
  return summary;
}

}  // namespace ppohdem::dem
