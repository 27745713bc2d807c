#pragma once
/// \file scene.hpp
/// Scene files (TOML). Every key, with units; keys not listed are errors that name the key.
///
///   [simulation] dt [s], steps, gravity = [gx, gy, gz] [m/s^2], energy_balance = true (false:
///                no contact energy book-keeping, which the fast engine then skips
///                (docs/performance.md "Energy book-keeping optional"); the three
///                contact terms of energy.csv are nan and the energy check is off)
///   [material]   density [kg/m^3], young [Pa], poisson, restitution, friction, name
///                (optional, default "default"): the scene's one material; OR
///   [[material]] several materials (any model), each with the keys above and a
///                unique name (required; no ',' or '"'); the first is material 0. The two
///                forms cannot be mixed (TOML refuses it). Pair laws: pair_laws.hpp.
///   [[material_pair]] materials = ["a", "b"] (two different names), restitution and/or
///                friction of that pair (otherwise min of the two materials' values)
///   [contact]    model = "hertz-mindlin" | "linear" | "hooke";
///                linear only: stiffness [N/m] or collision_time [s] (for two particles of
///                the mean radius; a scene that starts empty: of the [[insert]] sizes' mean), tangential_stiffness_ratio (default 2/7);
///                hooke only: characteristic_velocity [m/s] (required),
///                tangential_stiffness_ratio (default 1); tangential_damping = true | false
///                (default true for hooke, false otherwise; contact_law.hpp)
///   [particles]  file = "p.csv" (relative to the scene file), or
///                generator = "lattice" | "random", box_min, box_max [m], count, radius [m],
///                radius_max [m] (optional), seed, velocity [m/s] (optional), jitter (lattice),
///                material = "name" or ["a", "b", ...] (generator only; id k gets entry
///                (k - 1) mod n; default material 0); allow_overlap = false. A particle file
///                may have a 12th column `material` (names; particle_csv.hpp)
///   [[wall]]     point [m], normal (into the domain), velocity [m/s] (optional), material
///                (optional name; default: each particle meets a wall of its own material)
///   [[object]]   a rigid object (distance_field_object.hpp), exactly one of
///                  distance = "phi.vtk"  legacy VTK STRUCTURED_POINTS, phi [m] < 0 inside
///                  mesh = "m.stl" with cells = [nx, ny, nz] and optional margin [m]
///                    (default 2 R_max): voxelized on the fly with the exact builder on the
///                    mesh's bounding box grown by margin, nx+1 x ny+1 x nz+1 nodes;
///                and the motion (all optional, default at rest): velocity [m/s],
///                axis (any length, normalised), omega [rad/s] about axis through centroid
///                [m] (default: the grid's centre), start [s] (default 0), stop [s]
///                (default never), name (default "object N"), material (as [[wall]])
///   [[insert]]   particle insertion (insertion.hpp; every key: docs/formats.md
///                "Scene tables `[[insert]]` and `insertions.csv`"): region =
///                "box" (lo, hi [m]) | "cylinder" (point, axis, radius, length [m]); count
///                per event or rate [1/s]; start, every, stop [s] (or every_steps), total;
///                radius [m] | radius_min, radius_max [m] | sizes = [{radius, probability,
///                material}]; material; velocity [m/s], angular_velocity [rad/s]; seed,
///                attempts. With [[insert]], [particles] is optional (the scene starts empty).
///   [output]     dir (relative to the scene file), every (steps), formats = ["csv","vtk",
///                "pov"], progress = true (stderr)
///   [parallel]   the fast engine under MPI (docs/dem.md "Load balance"): balance = "rcb"
///                (default: recursive coordinate bisection by particle count, re-cut at a
///                list build) | "off" (equal bricks of the initial box), balance_threshold
///                (default 1.05, >= 1: re-cut when the most loaded rank owns more than this
///                times the mean particle count)
///   [checks]     run diagnostics (run_diagnostics.hpp): max_overlap [-] (default 0.1 of the
///                radius), max_energy_growth [-] (default 0.05), stop_on_escape (default
///                true), domain_min, domain_max [m] (optional box)
/// Only [simulation], [material], [contact] and [particles] are required.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ppohdem/dem/distance_field_object.hpp"
#include "ppohdem/dem/insertion.hpp"
#include "ppohdem/dem/run_diagnostics.hpp"
#include "ppohdem/dem/simulation_setup.hpp"

namespace ppohdem {
class Comm;
}

namespace ppohdem::dem {

struct OutputSpec {
  std::filesystem::path dir;  ///< absolute or relative to the working directory
  long every = 0;             ///< frame interval in steps; 0 = no frames
  bool csv = false;
  bool vtk = false;
  bool pov = false;
  bool vtu = false;  ///< VTK XML frames (vtu_writer.hpp): .vtu, .pvtu with several ranks, frames.pvd
  bool progress = true;
  long loads_every = 0;        ///< loads.csv interval in steps; 0 = no loads.csv (load_log.hpp)
  bool loads_average = false;  ///< loads.csv rows are means over the interval
};

/// A rigid object of the scene; it is also setup.boundaries[boundary_index].
struct SceneObject {
  std::shared_ptr<const DistanceFieldObject> object;
  std::size_t boundary_index = 0;
};

/// [parallel] (docs/dem.md "Load balance"): read by `ppohdem simulate` under mpirun.
struct ParallelSpec {
  bool balance = true;               ///< "rcb" (true) or "off"
  double balance_threshold = 1.05;   ///< max/mean particles per rank that triggers a re-cut
};

struct Scene {
  SimulationSetup setup;
  ParallelSpec parallel;
  std::vector<SceneObject> objects;
  long steps = 0;
  OutputSpec output;
  RunChecks checks;
  std::vector<InsertSpec> inserts;  ///< [[insert]] tables (insertion.hpp), in file order
};

/// Reads and checks a scene; throws InputError(file, line, ...) naming the key. Does not run
/// validate_setup (the engine does, so --force can still be applied). With `comm` (collective),
/// a particle file is read in shares: each rank keeps its own (SimulationSetup::share), which
/// only the fast engine takes (docs/dem.md "Reading on every rank").
Scene read_scene(const std::filesystem::path& file, const Comm* comm = nullptr);

/// The same from TOML text (the Python module's Scene.from_dict): `name` stands for the file
/// in error messages and relative paths resolve against `base_dir`. With `particles`, those
/// are the scene's particles (material = index into the scene's materials, checked here) and
/// [particles] may hold allow_overlap only; without, [particles] is required as in a file.
Scene read_scene_text(std::string text, const std::string& name, const std::filesystem::path& base_dir,
                      std::optional<Particles> particles = std::nullopt);

}  // namespace ppohdem::dem
