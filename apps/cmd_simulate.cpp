// `ppohdem simulate`: run a DEM scene.
//
//   ppohdem simulate SCENE.toml [--engine reference] [--force] [--quiet]
//       Reads the TOML scene (ppohdem/dem/scene.hpp), runs it with the chosen engine and writes
//       final.csv, energy.csv and frames into the scene's [output] dir.
// Dispatch on the input file: a TOML scene today; the legacy ppohDEM input_params_update.dat
// (recognised by its content, not its name) will be a second branch in `run_input`.
#include <cstdio>
#include <iostream>
#include <map>
#include <string>

#include "commands.hpp"
#include "ppohdem/dem/engine.hpp"
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
};

const std::map<std::string, dem::EngineFactory>& engines() {
  static const std::map<std::string, dem::EngineFactory> table{
      {"reference", &reference::dem::ReferenceEngine::make}};
  return table;
}

void run_toml_scene(const SimulateOptions& options) {
  dem::Scene scene = dem::read_scene(options.input);
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
  std::printf("wrote %s (final.csv, energy.csv, %zu frames)\n", scene.output.dir.string().c_str(),
              s.frames);
}

void run_input(const SimulateOptions& options) {
  // Future: if the file's content is a legacy input_params_update.dat, run the legacy driver.
  run_toml_scene(options);
}

}  // namespace

void register_simulate(CLI::App& app) {
  auto options = std::make_shared<SimulateOptions>();
  CLI::App* cmd = app.add_subcommand("simulate", "run a DEM scene (TOML) and write its outputs");
  cmd->add_option("scene", options->input, "scene file (TOML)")->required();
  cmd->add_option("--engine", options->engine, "engine: reference")->capture_default_str();
  cmd->add_flag("--force", options->force, "run even if dt is above the stability limit");
  cmd->add_flag("--quiet", options->quiet, "no progress lines on stderr");
  cmd->callback([options] { run_input(*options); });
}

}  // namespace ppohdem::app
