#pragma once
// The deterministic tier of the port check (docs/port-validation.md "Deterministic tier"):
// what is not chaotic is compared with tolerances. Two dense scenes whose every particle is in
// contact at the start (a compressed bed with walls; the seed sample's particles touching the
// dragon) run 4 steps; the velocity and spin changes after steps 1 and 4 (the forces and
// torques times dt / m or dt / I), the energies and the object's load are compared with the
// baseline's.
#include <filesystem>
#include <string>
#include <vector>

namespace ppohdem::port {

struct DeterministicRow {
  std::string scene, quantity;  // e.g. "dense_bed", "velocity change after 4 steps"
  double measured = 0.0;        // relative difference to the baseline
  double tolerance = 0.0;
  bool passed() const { return measured <= tolerance; }
};

std::vector<std::string> deterministic_scene_names();

/// Writes DIR/<name>/scene.toml, particles.csv (and the dragon's field) for each scene.
void export_deterministic_scenes(const std::filesystem::path& dir, const std::filesystem::path& source_dir,
                                 const std::string& ppohdem_program);

/// Runs the scenes (4 steps each) with `ppohdem simulate` under `launcher` and returns the
/// output folder of each, under `work`.
std::vector<std::filesystem::path> run_deterministic_scenes(const std::filesystem::path& work,
                                                            const std::filesystem::path& source_dir,
                                                            const std::string& engine, const std::string& launcher);

/// DIR/deterministic_<scene>.csv from a run's folder (the trusted machine's numbers).
void save_deterministic_reference(const std::filesystem::path& dir, const std::string& scene,
                                  const std::filesystem::path& run_dir);

/// The comparison rows of a run against DIR/deterministic_<scene>.csv.
std::vector<DeterministicRow> compare_deterministic(const std::filesystem::path& dir, const std::string& scene,
                                                    const std::filesystem::path& run_dir);

}  // namespace ppohdem::port
