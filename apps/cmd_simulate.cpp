// `ppohdem simulate`: run a DEM scene.
//
//   ppohdem simulate SCENE.toml [--engine reference] [--force] [--quiet]
//       Reads the TOML scene (ppohdem/dem/scene.hpp), runs it with the chosen engine and writes
//       final.csv, energy.csv and frames into the scene's [output] dir.
//   ppohdem simulate input_params_update.dat [--data-length L] [--steps N | --time-finish T]
//       The seed's sample_main01 (dem/legacy_scene.hpp), recognised by the first label
//       `Lx_Ly_Lz:` or forced with --legacy; run in the directory holding the distance files.
// --steps / --time-finish override the end of any scene (short test runs).
#include <cstdio>
#include <fstream>
#include <iostream>
#include <cmath>
#include <map>
#include <optional>
#include <string>

#include "commands.hpp"
#include "ppohdem/dem/engine.hpp"
#include "ppohdem/dem/legacy_scene.hpp"
#include "ppohdem/dem/run.hpp"
#include "ppohdem/dem/scene.hpp"
#include "ppohdem/error.hpp"
#include "ppohdem/provenance.hpp"
#include "ppohdem/reference/dem/reference_engine.hpp"

namespace ppohdem::app {
namespace {

struct SimulateOptions {
  std::string input;
  std::string engine = "reference";
  bool force = false;
  bool quiet = false;
  bool legacy = false;
  std::optional<long> steps;          // overrides the scene's step count
  std::optional<double> time_finish;  // [s], overrides it as round(T / dt) steps
  std::optional<double> data_length;  // legacy: L of the distance data [m]
};

const std::map<std::string, dem::EngineFactory>& engines() {
  static const std::map<std::string, dem::EngineFactory> table{
      {"reference", &reference::dem::ReferenceEngine::make}};
  return table;
}

void run_scene_file(const SimulateOptions& options, dem::Scene scene) {
  if (options.steps) scene.steps = *options.steps;
  if (options.time_finish) {
    if (!(*options.time_finish >= 0.0)) throw InputError("--time-finish: expected a time >= 0 s");
    scene.steps = std::lround(*options.time_finish / scene.setup.dt);
  }
  if (scene.steps < 0) throw InputError("--steps: expected >= 0");
  scene.setup.force_time_step = options.force;
  if (options.quiet) scene.output.progress = false;
  const auto factory = engines().find(options.engine);
  if (factory == engines().end()) {
    throw InputError("--engine: expected 'reference', got '" + options.engine + "'");
  }
  const dem::TimeStepLimit limit = dem::time_step_limit(scene.setup);
  auto engine = factory->second(scene.setup);  // validates (dt, overlaps, ...)
  const std::string header = provenance_line() + "; engine " + engine->name();
  std::fprintf(stderr, "%s\n", header.c_str());
  std::fprintf(stderr, "simulate: %zu particles, %zu boundaries, dt %g s (limit %g s: %s), %ld steps\n",
               engine->particles().size(), scene.setup.boundaries.size(), scene.setup.dt,
               limit.limit, limit.reason.c_str(), scene.steps);
  if (scene.setup.dt > limit.limit) {
    std::fprintf(stderr, "warning: dt is above the stability limit (--force)\n");
  }
  const dem::RunSummary s = dem::run_scene(*engine, scene, header, std::cerr);
  const double e0 = s.initial.total();
  const double e1 = s.final.total();
  std::printf("steps %ld, time %.6g s, wall %.3f s\n", s.steps, engine->time(), s.wall_seconds);
  std::printf("energy [J]: kinetic %.6e rotational %.6e gravitational %.6e elastic %.6e "
              "dissipated %.6e boundary_work %.6e\n",
              s.final.kinetic, s.final.rotational, s.final.gravitational, s.final.elastic,
              s.final.dissipated, s.final.boundary_work);
  std::printf("energy balance: total %.9e -> %.9e J (relative change %.2e)\n", e0, e1,
              e0 != 0.0 ? (e1 - e0) / std::abs(e0) : e1 - e0);
  const dem::ContactCounts c = engine->contact_counts();
  std::printf("contacts: %zu particle-particle, %zu particle-wall; escaped particles: %zu\n",
              c.particle_pairs, c.particle_boundary, s.escaped);
  for (const dem::SceneObject& o : scene.objects) {
    std::printf("%s: %zu samples outside its grid\n", o.object->describe().c_str(), o.object->outside_grid_count());
  }
  std::printf("wrote %s (final.csv, energy.csv, %zu frames)\n", scene.output.dir.string().c_str(),
              s.frames);
}

// A legacy ppohDEM input_params_update.dat starts (after blank lines) with the label
// `Lx_Ly_Lz:` (users' guide List 2.2); a TOML scene cannot (it would be a syntax error).
bool looks_like_legacy_input(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos) continue;
    return line.compare(first, 9, "Lx_Ly_Lz:") == 0;
  }
  return false;
}

void run_input(const SimulateOptions& options) {
  if (options.legacy || looks_like_legacy_input(options.input)) {
    dem::LegacySceneOptions legacy;
    legacy.data_length = options.data_length;
    run_scene_file(options, dem::read_legacy_scene(options.input, legacy));
    return;
  }
  if (options.data_length) throw InputError("--data-length applies to legacy inputs only");
  run_scene_file(options, dem::read_scene(options.input));
}

}  // namespace

void register_simulate(CLI::App& app) {
  auto options = std::make_shared<SimulateOptions>();
  CLI::App* cmd = app.add_subcommand("simulate", "run a DEM scene (TOML) and write its outputs");
  cmd->add_option("scene", options->input, "scene file (TOML)")->required();
  cmd->add_option("--engine", options->engine, "engine: reference")->capture_default_str();
  cmd->add_flag("--force", options->force, "run even if dt is above the stability limit");
  cmd->add_flag("--quiet", options->quiet, "no progress lines on stderr");
  cmd->add_flag("--legacy", options->legacy, "read the input as a legacy input_params_update.dat");
  cmd->add_option("--steps", options->steps, "run this many steps instead of the scene's");
  cmd->add_option("--time-finish", options->time_finish, "run to this time [s] instead of the scene's end");
  cmd->add_option("--data-length", options->data_length,
                  "legacy: length L [m] of the distance data (default: from input_constants_voxelizer.dat)");
  cmd->callback([options] { run_input(*options); });
}

}  // namespace ppohdem::app
