#pragma once
// The chaotic tier's scenes (docs/port-validation.md "Scenes"): what they are, how they are
// written out for ppohdem or another code, and the numbers the observables need.
#include <array>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "ppohdem/geometry/vector.hpp"

namespace ppohdem::port {

struct PortWall {
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();  // into the domain
  std::string name;             // "floor", "x0", ...
};

struct PortScene {
  std::string name;                 // "settling_bed", "seed_sample", "small_bed"
  std::string description;
  long steps = 0;                   // run length
  long frame_every = 0;             // frames at multiples of this (the observable steps are among them)
  std::vector<long> observable_steps;
  double dt = 0.0;                  // [s]
  double gravity = 0.0;             // along -z [m/s^2]
  double density = 0.0, young = 0.0, poisson = 0.0, restitution = 0.0, friction = 0.0;
  bool linear = false;              // linear spring-dashpot (seed sample) instead of Hertz-Mindlin
  double stiffness = 0.0;           // linear: k_n [N/m]
  double tangential_ratio = 0.0;    // linear: k_t / k_n
  std::vector<PortWall> walls;
  // Packing-fraction probe: the slab probe_min.z <= z < probe_max.z over the box between the
  // walls, x and y from probe_min to probe_max [m].
  Vec3 probe_min = Vec3::Zero(), probe_max = Vec3::Zero();
  bool has_object = false;          // the dragon of the seed sample (objects.csv)
  // Lattice generator of the beds (positions written to particles.csv on export).
  Vec3 box_min = Vec3::Zero(), box_max = Vec3::Zero();
  int count = 0;
  double radius = 0.0;
  double max_overlap = 0.1;         // [checks] of the scene
};

/// The scenes by name: "settling_bed" (1,000 spheres), "seed_sample" (600 spheres and the
/// dragon), "small_bed" (216 spheres, the ctest's reduced ensemble).
const PortScene& port_scene(const std::string& name);
std::vector<std::string> port_scene_names();  // the two of a port check, not small_bed

/// Known-bad changes for the power ladder: "friction", "restitution", "young", "dt",
/// "gravity" (young applies to Hertz scenes; for the linear seed sample it scales the
/// stiffness). Throws std::invalid_argument on another name.
PortScene scaled(PortScene scene, const std::map<std::string, double>& factors);

/// Writes DIR/<name>/scene.toml and particles.csv (and for the seed sample the dragon's
/// distance field, made with `ppohdem voxelize` found at `ppohdem_program`). `source_dir` is
/// the checkout (fixtures/). Returns the scene file.
std::filesystem::path export_scene(const PortScene& scene, const std::filesystem::path& dir,
                                   const std::filesystem::path& source_dir, const std::string& ppohdem_program);

}  // namespace ppohdem::port
