#pragma once
/// \file run.hpp
/// Drive an engine through a scene and write its outputs (output_writers.hpp):
///   <dir>/final.csv always; <dir>/energy.csv with a row at step 0, every `every` steps (or
///   every steps/100 if every = 0) and at the end; frames at step 0 and every `every` steps
///   in the formats asked for. Progress on stderr (at most every 10% or 5 s) if asked.
#include <ostream>
#include <string>

#include "ppohdem/dem/engine.hpp"
#include "ppohdem/dem/scene.hpp"

namespace ppohdem::dem {

struct RunSummary {
  long steps = 0;
  double wall_seconds = 0.0;  ///< time loop only [s]
  Energies initial;
  Energies final;
  std::size_t escaped = 0;
  std::size_t frames = 0;
};

/// `header` is the run header written at the top of every output (provenance + engine).
/// Creates output.dir if needed. `log` receives a one-line summary at the end.
RunSummary run_scene(DemEngine& engine, const Scene& scene, const std::string& header,
                     std::ostream& log);

}  // namespace ppohdem::dem
