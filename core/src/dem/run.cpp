#include "ppohdem/dem/run.hpp"

#include <signal.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <regex>
#include <sstream>
#include <vector>

#include "ppohdem/dem/insertion_run.hpp"
#include "ppohdem/dem/load_log.hpp"
#include "ppohdem/dem/output_writers.hpp"
#include "ppohdem/dem/particle_csv.hpp"
#include "ppohdem/dem/vtu_writer.hpp"
#include "ppohdem/error.hpp"
#include "ppohdem/provenance.hpp"

namespace ppohdem::dem {
namespace {

/// The energies of an energy.csv data row "step,time,kinetic,...,boundary_work" (%.17g:
/// the doubles come back exactly).
Energies parse_energy_row(const std::string& row, const std::string& source) {
  std::vector<double> v;
  std::stringstream s(row);
  std::string field;
  while (std::getline(s, field, ',')) v.push_back(std::strtod(field.c_str(), nullptr));
  if (v.size() != 8) throw InputError(source, 0, "checkpoint: an energy row without 8 fields: " + row);
  Energies e;
  e.kinetic = v[2];
  e.rotational = v[3];
  e.gravitational = v[4];
  e.elastic = v[5];
  e.dissipated = v[6];
  e.boundary_work = v[7];
  return e;
}

/// The objects' poses recorded in a checkpoint must be the scene's at the checkpoint's time:
/// a changed motion would continue a different run. 1e-12: the poses are the same
/// computation in the same build (bitwise equal); the slack only admits another compiler's
/// rounding of a pose of order 1 (m, unit quaternion).
void check_object_poses(const Scene& scene, const Checkpoint& c, double time, const std::string& source) {
  if (c.objects.size() != scene.objects.size()) {
    throw InputError(source, 0, "checkpoint: " + std::to_string(c.objects.size()) + " objects, the scene has " +
                                    std::to_string(scene.objects.size()));
  }
  for (std::size_t o = 0; o < c.objects.size(); ++o) {
    const RigidTransform pose = scene.objects[o].object->pose_at(time);
    const double dq = std::min((pose.rotation.coeffs() - c.objects[o].rotation.coeffs()).norm(),
                               (pose.rotation.coeffs() + c.objects[o].rotation.coeffs()).norm());
    const double dx = (pose.translation - c.objects[o].translation).norm();
    if (!(dq <= 1e-12) || !(dx <= 1e-12 * (1.0 + pose.translation.norm()))) {
      throw InputError(source, 0, "checkpoint: object " + std::to_string(o) + " ('" + c.objects[o].name +
                                      "') is not where the scene's motion puts it at the checkpoint's time "
                                      "(the scene was changed?)");
    }
  }
}

}  // namespace

std::size_t remove_stale_temp_files(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  static const std::regex temp_name(R"(.*\.tmp\.([0-9]+)\.[0-9]+)");
  std::size_t removed = 0;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    if (!it->is_regular_file(ec)) continue;
    std::smatch m;
    const std::string name = it->path().filename().string();
    if (!std::regex_match(name, m, temp_name)) continue;
    const long pid = std::strtol(m[1].str().c_str(), nullptr, 10);
    // Only temp files of processes that no longer exist (a live writer may be renaming it).
    if (pid > 0 && ::kill(static_cast<pid_t>(pid), 0) == -1 && errno == ESRCH) {
      std::error_code rm;
      if (fs::remove(it->path(), rm)) ++removed;
    }
  }
  return removed;
}

RunSummary run_scene(DemEngine& engine, const Scene& scene, const std::string& header,
                     std::ostream& log, const RunOptions& options) {
  namespace fs = std::filesystem;
  const OutputSpec& out = scene.output;
  // Several ranks (RunOptions::comm): every rank runs this function, the engine's queries are
  // collective (so they are made on every rank), rank 0 alone writes.
  const bool writer = options.comm == nullptr || options.comm->rank() == 0;
  auto global_count = [&](std::size_t local) -> std::int64_t {  // a sum of doubles: exact below 2^53
    if (options.comm == nullptr) return static_cast<std::int64_t>(local);
    return std::llround(options.comm->sum_over_ranks(static_cast<double>(local)));
  };
  std::error_code ec;
  if (writer) fs::create_directories(out.dir, ec);
  if (writer && !fs::is_directory(out.dir)) {
    throw InputError(out.dir.string(), 0, "cannot create the output directory");
  }
  if (out.vtu && options.comm != nullptr) options.comm->barrier();  // the directory exists before any rank writes a piece
  if (const std::size_t stale = writer ? remove_stale_temp_files(out.dir) : 0; stale > 0) {
    std::fprintf(stderr, "simulate: removed %zu temp files of interrupted runs from %s\n", stale,
                 out.dir.string().c_str());
  }
  EnergyLog energy(out.dir / "energy.csv", header);
  const long energy_every = out.every > 0 ? out.every : std::max(1L, scene.steps / 100);
  RunSummary summary;
  // Objects: poses and loads with every energy row; a warning the first time a particle within
  // an object's reach is outside its grid (distance_field_object.hpp "Outside the grid").
  ObjectLog object_log(out.dir / "objects.csv", header);
  std::vector<bool> warned_outside(scene.objects.size(), false);
  std::vector<std::int64_t> outside_offset(scene.objects.size(), 0);  // restart: counts so far
  auto log_objects = [&](long step) {
    if (scene.objects.empty()) return;
    const std::vector<BoundaryLoad> loads = engine.boundary_loads();
    for (std::size_t o = 0; o < scene.objects.size(); ++o) {
      const SceneObject& so = scene.objects[o];
      const BoundaryLoad load = so.boundary_index < loads.size() ? loads[so.boundary_index] : BoundaryLoad{};
      const std::size_t local = so.object->outside_grid_count();  // this rank's samples
      object_log.add(step, engine.time(), o, *so.object, load,
                     outside_offset[o] + global_count(local) - static_cast<std::int64_t>(local));
    }
  };
  // loads.csv: every boundary's load at its own interval, optionally averaged (load_log.hpp).
  const bool log_loads = out.loads_every > 0;
  std::vector<std::string> boundary_names;
  for (const auto& b : scene.setup.boundaries) boundary_names.push_back(b->describe());
  LoadLog load_log(out.dir / "loads.csv", header, boundary_names);
  // [[insert]]: particles appended at their events (insertion_run.hpp), insertions.csv.
  InsertionRun insertion(scene.setup, scene.inserts, out.dir / "insertions.csv", header, writer);
  auto flush_logs = [&] {
    if (!writer) return;
    insertion.flush();
    energy.flush();
    if (!scene.objects.empty()) object_log.flush();
    if (log_loads) load_log.flush();
  };
  auto warn_outside = [&] {
    for (std::size_t o = 0; o < scene.objects.size(); ++o) {
      const DistanceFieldObject& object = *scene.objects[o].object;
      if (!warned_outside[o] && global_count(object.outside_grid_count()) > 0) {
        warned_outside[o] = true;
        if (writer) std::fprintf(stderr, "warning: a particle was outside the distance grid of %s at t = %g s "
                     "within its radius of the object: the grid is too small for the object (no contact "
                     "there; counted in objects.csv)\n",
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
  // A material column only with several materials (one-material outputs stay as they were).
  const std::vector<std::string> material_column =
      scene.setup.material_count() > 1 ? scene.setup.material_names : std::vector<std::string>{};
  // VTK XML frames: every rank writes its own piece (no gather), rank 0 the index of the
  // pieces (several ranks) and frames.pvd, the collection of this run's frames with their times.
  std::vector<std::pair<double, std::string>> vtu_frames;
  auto write_vtu = [&](long step) {
    const int ranks = options.comm ? options.comm->size() : 1;
    const int rank = options.comm ? options.comm->rank() : 0;
    std::string name = vtu_piece_name(step, rank, ranks);
    if (ranks == 1) {
      write_vtu_frame(out.dir / name, engine.particles(), header);
    } else {
      write_vtu_frame(out.dir / name, engine.owned_particles(), header);
      options.comm->barrier();  // every piece is on disk before the index names it
      name = frame_stem(step) + ".pvtu";
      std::vector<std::string> pieces;
      for (int r = 0; r < ranks; ++r) pieces.push_back(vtu_piece_name(step, r, ranks));
      if (writer) write_pvtu_index(out.dir / name, pieces, header);
    }
    if (!writer) return;
    vtu_frames.emplace_back(engine.time(), name);
    write_pvd_collection(out.dir / "frames.pvd", vtu_frames, header);
  };
  // Several ranks: each gives its part of a particle CSV, legacy VTK or POV-Ray frame and of
  // final.csv, in construction order (no rank holds every particle; docs/dem.md "Reading on
  // every rank"), and rank 0 writes the file; one rank: the whole file.
  const bool in_parts = options.comm != nullptr && options.comm->size() > 1;
  auto write_frame = [&](long step) {
    const fs::path stem = out.dir / frame_stem(step);
    if (out.vtu) write_vtu(step);
    if (in_parts && (out.csv || out.vtk || out.pov)) {  // collective: on every rank
      const std::uint64_t before = options.comm->messages_sent();
      const DemEngine::OrderedPart part = engine.ordered_part();
      if (out.csv) {
        write_particles_csv(fs::path(stem).concat(".csv"), part.particles, header, material_column, *options.comm);
      }
      if (out.vtk) {
        write_vtk_frame(fs::path(stem).concat(".vtk"), part.particles, part.first, part.total, header, *options.comm);
      }
      if (out.pov) {
        write_pov_frame(fs::path(stem).concat(".pov"), part.particles, part.first, part.total, header, *options.comm,
                        object_ptrs, engine.time());
      }
      summary.output_messages += options.comm->messages_sent() - before;
    }
    if (!writer) {
      if (out.csv || out.vtk || out.pov || out.vtu) ++summary.frames;
      return;
    }
    if (!in_parts) {
      if (out.csv) write_particles_csv(fs::path(stem).concat(".csv"), engine.particles(), header, material_column);
      if (out.vtk) write_vtk_frame(fs::path(stem).concat(".vtk"), engine.particles(), header);
      if (out.pov) write_pov_frame(fs::path(stem).concat(".pov"), engine.particles(), header, object_ptrs, engine.time());
    }
    if ((out.vtk || out.pov) && any_display_mesh) {
      fs::create_directories(out.dir / "objects", ec);
      for (std::size_t o = 0; o < object_ptrs.size(); ++o) {
        const DistanceFieldObject& object = *object_ptrs[o];
        if (!object.display_mesh()) continue;
        write_mesh_vtk(out.dir / "objects" / object_mesh_file_name(o, step),
                       transformed(*object.display_mesh(), object.pose_at(engine.time())), header);
      }
    }
    if (out.csv || out.vtk || out.pov || out.vtu) ++summary.frames;
  };
  // Checkpoints: one file by rank 0 on one rank; per rank on several, without a gather
  // (checkpoint.hpp "Parts"). Collective: on every rank.
  const bool checkpoint_per_rank = options.comm != nullptr && options.comm->size() > 1;
  auto make_checkpoint = [&] {  // all but the engine state
    Checkpoint c;
    c.provenance = header;
    c.scene = options.scene_name;
    for (std::size_t o = 0; o < scene.objects.size(); ++o) {
      const DistanceFieldObject& object = *scene.objects[o].object;
      const RigidTransform pose = object.pose_at(engine.time());
      c.objects.push_back({object.name(), pose.rotation, pose.translation,
                           static_cast<std::uint64_t>(global_count(object.outside_grid_count()) + outside_offset[o])});
    }
    c.run.energy_rows = energy.rows();
    c.run.object_rows = object_log.rows();
    c.run.frames = summary.frames;
    c.insertion = insertion.record();
    return c;
  };
  auto write_checkpoint_of = [&](const fs::path& file) {
    if (checkpoint_per_rank) {
      EngineStateShare share = engine.save_state_share();
      write_checkpoint_parts(file, make_checkpoint(), std::move(share), *options.comm);
      return;
    }
    Checkpoint c = make_checkpoint();
    c.engine = engine.save_state();
    if (writer) write_checkpoint(file, c);
  };

  // The deepest overlap of the initial state (the engine was built from the scene), which the
  // overlap check accepts as given (run_diagnostics.hpp).
  const std::optional<LargestOverlap> initial_deepest = engine.largest_overlap();
  const double initial_overlap = initial_deepest ? initial_deepest->ratio : 0.0;
  if (options.restart) {
    const Checkpoint& c = *options.restart;
    const std::string source = options.scene_name.empty() ? std::string("checkpoint") : options.scene_name;
    if (c.build != checkpoint_build_name()) {
      std::fprintf(stderr, "simulate: note: the checkpoint was written by %s, this is %s (same format; "
                   "bitwise continuation is promised only for the same build)\n",
                   c.build.c_str(), checkpoint_build_name().c_str());
    }
    insertion.restore(c.insertion, source);  // first: other [[insert]] tables are refused by name
    // Particles inserted before the checkpoint: appended first (restore_state sets their state).
    const std::size_t now = engine.particle_count();
    if (const auto* share = options.restart_share.get()) {  // several ranks, each with its parts
      engine.restore_state_share(*share, insertion.active() && share->total > now ? share->total - now : 0);
    } else {
      if (insertion.active() && c.engine.particles.size() > now) {
        const auto first_new = c.engine.particles.begin() + static_cast<std::ptrdiff_t>(now);
        engine.insert_particles(Particles(first_new, c.engine.particles.end()));
      }
      engine.restore_state(c.engine);
    }
    check_object_poses(scene, c, engine.time(), source);
    for (std::size_t o = 0; o < scene.objects.size(); ++o) {
      outside_offset[o] = static_cast<std::int64_t>(c.objects[o].outside_grid) -
                          global_count(scene.objects[o].object->outside_grid_count());
    }
    if (c.run.energy_rows.empty()) throw InputError(source, 0, "checkpoint: no energy rows (step 0 is missing)");
    energy.set_rows(c.run.energy_rows);
    object_log.set_rows(c.run.object_rows);
    summary.frames = static_cast<std::size_t>(c.run.frames);
    summary.initial = parse_energy_row(c.run.energy_rows.front(), source);
    if (log_loads && writer) load_log.continue_from_disk(engine.step_count());
    if (writer) std::fprintf(stderr, "simulate: restarted at step %ld (t = %g s) from a checkpoint of %s\n",
                 engine.step_count(), engine.time(), c.build.c_str());
  } else {
    insertion.at_step(engine);  // the insertions of step 0 are part of the initial state
    summary.initial = engine.energies();
  }
  RunDiagnostics diagnostics(scene.setup, scene.checks, summary.initial, initial_overlap, options.time_step_limit);
  // The energy balance counts the particles inserted after step 0 as energy brought in.
  auto insert_at = [&] {
    if (!insertion.active()) return;
    insertion.at_step(engine);
    diagnostics.set_input(insertion.input());
  };
  if (insertion.active()) diagnostics.set_input(insertion.input());  // a restart's so far
  // A failed check: keep what the run did, up to and including the failed step (energy rows
  // only while they are finite: no NaN in the outputs), and the state for inspection.
  auto stop = [&](const std::string& diagnosis) {
    const Energies e = engine.energies();
    if (std::isfinite(e.total())) {
      energy.add(engine.step_count(), engine.time(), e);
      log_objects(engine.step_count());
    }
    flush_logs();
    std::string note;
    try {
      write_checkpoint_of(out.dir / kFailedCheckpointFile);  // collective: on every rank
      // Every rank throws below; the program may then end all ranks at once (MPI_Abort):
      // not before rank 0 has written the logs and this checkpoint.
      if (options.comm != nullptr) options.comm->barrier();
      note = " The state of that step is in " + (out.dir / kFailedCheckpointFile).string() + ".";
    } catch (const std::exception& ex) {
      note = std::string(" (no checkpoint of the failed state: ") + ex.what() + ")";
    }
    throw RunFailure(diagnosis + "." + note);
  };
  if (!engine.state_finite()) {  // (screened first: the scan that names the particle gathers them)
    if (const auto diagnosis = diagnostics.check_finite(engine)) stop(*diagnosis);
  }

  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  auto last_report = start;
  long last_percent = 0;
  const long first_step = engine.step_count();
  if (!options.restart) {
    energy.add(engine.step_count(), engine.time(), summary.initial);
    log_objects(engine.step_count());
    if (log_loads && !out.loads_average) load_log.add(engine.step_count(), engine.time(), engine.boundary_loads());
    warn_outside();
    if (out.every > 0) write_frame(engine.step_count());
  }
  if (options.at_step_boundary) options.at_step_boundary(first_step);
  for (long step = first_step + 1; step <= scene.steps; ++step) {
    engine.step();
    insert_at();
    warn_outside();
    const bool energy_row = step % energy_every == 0 || step == scene.steps;
    const bool balance_now = energy_row || step % kEnergyCheckEvery == 0;
    if (const auto diagnosis = diagnostics.check(engine, balance_now)) stop(*diagnosis);
    if (energy_row) {
      energy.add(step, engine.time(), engine.energies());
      log_objects(step);
    }
    if (log_loads) {  // engine.boundary_loads() is collective: on every rank
      if (out.loads_average) load_log.accumulate(engine.boundary_loads());
      if (step % out.loads_every == 0 || step == scene.steps) {
        load_log.add(step, engine.time(), out.loads_average ? std::vector<BoundaryLoad>{} : engine.boundary_loads());
      }
    }
    if (out.every > 0 && step % out.every == 0) {
      write_frame(step);
      flush_logs();
    }
    if (options.checkpoint_every > 0 && (step % options.checkpoint_every == 0 || step == scene.steps)) {
      // The logs first: every file on disk then covers at least the checkpoint's steps.
      flush_logs();
      const auto checkpoint_start = clock::now();
      write_checkpoint_of(out.dir / kCheckpointFile);  // collective: on every rank
      summary.checkpoint_seconds += std::chrono::duration<double>(clock::now() - checkpoint_start).count();
      ++summary.checkpoints;
    }
    if (options.at_step_boundary) options.at_step_boundary(step);
    const long done = step - first_step, total = scene.steps - first_step;
    if (writer && out.progress && total >= 1000) {
      const long percent = 100 * done / total;
      const auto now = clock::now();
      if (percent >= last_percent + 10 || now - last_report > std::chrono::seconds(5)) {
        const double elapsed = std::chrono::duration<double>(now - start).count();
        std::fprintf(stderr, "simulate: step %ld / %ld (%ld %%), %.1f s elapsed, %.0f s left\n", step,
                     scene.steps, percent, elapsed,
                     elapsed * static_cast<double>(total - done) / static_cast<double>(done));
        last_percent = percent - percent % 10;
        last_report = now;
      }
    }
  }
  summary.wall_seconds = std::chrono::duration<double>(clock::now() - start).count();
  summary.steps = scene.steps;
  summary.final = engine.energies();
  summary.escaped = engine.escaped_count();
  summary.margins = diagnostics.margins();
  summary.inserted = insertion.inserted();
  summary.insert_failed = insertion.failed();
  summary.insert_seconds = insertion.seconds();
  summary.inserted_energy = insertion.input();
  const auto gather_start = clock::now();  // the end's gather (or its parts' exchange)
  // Collective: every rank its part of final.csv (several ranks), or all of them.
  const std::uint64_t messages_before_end = options.comm != nullptr ? options.comm->messages_sent() : 0;
  const DemEngine::OrderedPart final_part = in_parts ? engine.ordered_part() : DemEngine::OrderedPart{};
  const std::size_t particle_count = in_parts ? final_part.total : engine.particles().size();
  if (writer) log << "simulate: " << scene.steps - first_step << " steps of " << particle_count
      << " particles in " << summary.wall_seconds << " s (" << engine.name() << " engine)\n";
  if (writer && insertion.active()) {
    log << "simulate: inserted " << summary.inserted << " particles, " << summary.insert_failed
        << " could not be inserted (insertions.csv)\n";
  }
  flush_logs();
  const auto write_start = clock::now();
  summary.gather_seconds = std::chrono::duration<double>(write_start - gather_start).count();
  if (in_parts) {
    write_particles_csv(out.dir / "final.csv", final_part.particles, header, material_column, *options.comm);
    summary.output_messages += options.comm->messages_sent() - messages_before_end;
  } else if (writer) {
    write_particles_csv(out.dir / "final.csv", engine.particles(), header, material_column);
  }
  if (writer) {
    summary.write_seconds = std::chrono::duration<double>(clock::now() - write_start).count();
    summary.write_bytes = std::filesystem::file_size(out.dir / "final.csv");
  }
  return summary;
}

}  // namespace ppohdem::dem
