#pragma once
// Observables of one run of a port-validation scene, read from its output folder (the frames
// frame_NNNNNN.csv at the scene's observable steps, and objects.csv for a scene with an object;
// docs/port-validation.md "Observables" and "Output format for other codes").
#include <filesystem>
#include <string>
#include <vector>

#include "port_scenes.hpp"

namespace ppohdem::port {

struct Observables {
  std::vector<std::string> names;  // "mean_height@10000", ...
  std::vector<double> values;
};

/// The observables of the run in `run_dir`. Throws std::runtime_error naming the missing file.
Observables run_observables(const PortScene& scene, const std::filesystem::path& run_dir);

/// Particle count and sum of radii [m] of a run's first observable frame: which scene it is.
struct RunFingerprint {
  std::size_t count = 0;
  double radius_sum = 0.0;
};
RunFingerprint run_fingerprint(const std::filesystem::path& run_dir);

/// The observable frame of `step` in run_dir (frame_NNNNNN.csv).
std::filesystem::path frame_file(const std::filesystem::path& run_dir, long step);

}  // namespace ppohdem::port
