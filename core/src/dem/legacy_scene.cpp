// The seed's sample_main01 as a Scene (legacy_scene.hpp).
#include "ppohdem/dem/legacy_scene.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <string>

#include "ppohdem/error.hpp"
#include "ppohdem/io/distance_dat.hpp"
#include "ppohdem/io/legacy_inputs.hpp"
#include "ppohdem/mesh/stl_io.hpp"

namespace ppohdem::dem {
namespace {

namespace fs = std::filesystem;
using C = LegacySampleConstants;

std::string g(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

std::string vec_text(const Vec3& v) {
  char buf[200];  // snprintf, not "(" + std::string: GCC 12 warns falsely (-Wrestrict) there
  std::snprintf(buf, sizeof buf, "(%.9g, %.9g, %.9g)", v.x(), v.y(), v.z());
  return buf;
}

/// The sample's particle sheet (legacy_scene.hpp).
Particles sample_sheet() {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Particles particles;
  for (int n = 0; n < C::kParticles; ++n) {
    const int column = n % 33;
    const int row = n / 33;
    Particle p;
    p.id = n + 1;
    const double jx = 0.005 * (2.0 * unit(rng) - 1.0);  // +-0.005 m jitter as the original
    const double jz = 0.005 * (2.0 * unit(rng) - 1.0);
    p.position = Vec3(0.1 + 0.3 * column + jx, 5.5, 5.0 + 0.3 * row + jz);
    p.radius = C::kRadius * (1.0 + 0.2 * unit(rng));
    particles.push_back(p);
  }
  return particles;
}

/// Data length L per axis: --data-length, else input_constants_voxelizer.dat beside the
/// params file; InputError if neither.
Vec3 data_length(const fs::path& params_file, const LegacySceneOptions& options, const Index3& data_nodes) {
  if (options.data_length) {
    if (!(*options.data_length > 0.0) || !std::isfinite(*options.data_length)) {
      throw InputError("--data-length: expected a length > 0, got " + g(*options.data_length));
    }
    return Vec3::Constant(*options.data_length);
  }
  const fs::path voxelizer = params_file.parent_path() / "input_constants_voxelizer.dat";
  if (!fs::exists(voxelizer)) {
    throw InputError(params_file.string(), 0,
                     "the distance files do not store the data's length: give --data-length L or put "
                     "input_constants_voxelizer.dat (with its Lx_Ly_Lz: line) in the same directory");
  }
  const VoxelizerInput v = read_voxelizer_input(voxelizer);
  if (v.voxels != data_nodes) {
    throw InputError(voxelizer.string(), 3,
                     "voxel counts " + std::to_string(v.voxels[0]) + " " + std::to_string(v.voxels[1]) + " " +
                         std::to_string(v.voxels[2]) + " differ from the distance files' " +
                         std::to_string(data_nodes[0]) + " " + std::to_string(data_nodes[1]) + " " +
                         std::to_string(data_nodes[2]) + " nodes");
  }
  return v.length;
}

}  // namespace

double linear_restitution(double stiffness, double damping, double effective_mass) {
  const double zeta = damping / (2.0 * std::sqrt(effective_mass * stiffness));
  return std::exp(-std::numbers::pi * zeta / std::sqrt(1.0 - zeta * zeta));
}

Scene read_legacy_scene(const fs::path& params_file, const LegacySceneOptions& options) {
  const std::string name = params_file.string();
  const UpdateParamsInput in = read_update_params_input(params_file);
  const fs::path dir = params_file.parent_path().empty() ? fs::path(".") : params_file.parent_path();
  const DistanceDat data = read_distance_dat(dir);
  const Vec3 length = data_length(params_file, options, data.nodes);

  // Resolution and window checks (users' guide sec. 2: the two resolutions must be identical).
  Vec3 h;
  for (int a = 0; a < 3; ++a) {
    const char axis = "xyz"[a];
    if (in.window_nodes[a] < 2) {
      throw InputError(name, 3, std::string("Obj_n_x_y_z: need >= 2 nodes along ") + axis + ", found " +
                                    std::to_string(in.window_nodes[a]));
    }
    const double h_window = in.domain_length[a] / (in.window_nodes[a] - 1);  // Lx / (Obj_n - 1)
    const double h_data = length[a] / data.nodes[a];                         // L / n
    // 1e-9 relative: the two are the same number computed two ways (11/19 vs 44/76).
    if (std::abs(h_window - h_data) > 1e-9 * h_data) {
      throw InputError(name, 1, std::string("resolution mismatch along ") + axis + ": the computational window has h = Lx / (Obj_n - 1) = " +
                                    g(in.domain_length[a]) + " / " + std::to_string(in.window_nodes[a] - 1) + " = " +
                                    g(h_window) + " m, the distance data has h = L / n = " + g(length[a]) + " / " +
                                    std::to_string(data.nodes[a]) + " = " + g(h_data) + " m; they must be equal");
    }
    const long last = static_cast<long>(in.window_start[a]) + in.window_nodes[a] - 1;
    if (in.window_start[a] < 1 || last > data.nodes[a]) {
      throw InputError(name, 4, std::string("window along ") + axis + " is nodes " + std::to_string(in.window_start[a]) +
                                    ".." + std::to_string(last) + " (Obj_winstart + Obj_n - 1), but the distance data has nodes 1.." +
                                    std::to_string(data.nodes[a]));
    }
    h[a] = h_data;
  }

  Scene scene;
  SimulationSetup& s = scene.setup;
  s.source = name;
  s.dt = C::kTimeStep;
  s.gravity = Vec3(0.0, 0.0, -C::kGravity);
  s.material.density = C::kMass / (4.0 / 3.0 * std::numbers::pi * std::pow(C::kRadius, 3));
  s.material.friction = C::kFriction;
  // One restitution for every contact: the original's dashpot on a pair of mass-1 particles
  // (m* = 1/2). Against a wall or the object (m* = 1) the original's fixed En gives 0.750.
  s.material.restitution = linear_restitution(C::kNormalStiffness, C::kNormalDamping, C::kMass / 2.0);
  s.law = LinearSpringDashpot::from_stiffness(C::kNormalStiffness, s.material.restitution, s.material.friction,
                                              C::kTangentialStiffness / C::kNormalStiffness);
  s.particles = sample_sheet();
  // The original's sheet starts at x = 0.1 with radii up to 0.12: the first column touches the
  // wall x = 0 (as in the original). Pairs do not overlap (pitch 0.3 > 2 * 0.12 + 0.01).
  const Vec3 box = in.domain_length;
  for (int a = 0; a < 3; ++a) {
    Vec3 n = Vec3::Zero();
    n[a] = 1.0;
    s.boundaries.push_back(std::make_shared<PlaneWall>(Vec3::Zero(), n));
    Vec3 top = Vec3::Zero();
    top[a] = box[a];
    s.boundaries.push_back(std::make_shared<PlaneWall>(top, -n));
  }

  // The object: the whole data grid, placed so that the window covers the box.
  GridSpec grid;
  grid.nodes = data.nodes;
  grid.spacing = h;
  for (int a = 0; a < 3; ++a) grid.origin[a] = -(in.window_start[a] - 1) * h[a];
  ScalarField field(grid);
  field.values = data.values;
  const double frame_time = static_cast<double>(C::kStepsPerFrame) * C::kTimeStep;  // [s]
  RigidMotion motion;
  motion.velocity = in.velocity.cwiseProduct(h) / frame_time;
  if (in.omega_pi_rad_per_w != 0.0 && in.rotation_axis.norm() > 0.0) {
    motion.angular_velocity = in.rotation_axis.normalized() * (std::numbers::pi / in.omega_pi_rad_per_w / frame_time);
  }
  motion.centroid = in.centroid + grid.origin;
  auto object = std::make_shared<DistanceFieldObject>(std::move(field), motion, name + ": object");
  // Display mesh: the placed mesh `ppohdem voxelize` wrote beside the distance files, in data
  // coordinates where node m sits at h (m - 1); the field's nodes sit at h (m - winstart), so the
  // mesh moves by the same offset as the field origin, -(winstart - 1) h. None if absent.
  const fs::path mesh_file = dir / "object_mesh.stl";
  if (fs::exists(mesh_file)) {
    TriangleMesh mesh = read_stl(mesh_file);
    for (Triangle& t : mesh.triangles) {
      for (Vec3& v : t.v) v += grid.origin;
    }
    object->set_display_mesh(std::move(mesh));
  }
  scene.objects.push_back({object, s.boundaries.size()});
  s.boundaries.push_back(object);
  std::fprintf(stderr,
               "legacy: h = %.9g m (window and data agree), object origin %s, velocity %s m/s, omega %s rad/s, "
               "centroid %s m\n",
               h.x(), vec_text(grid.origin).c_str(), vec_text(motion.velocity).c_str(),
               vec_text(motion.angular_velocity).c_str(), vec_text(motion.centroid).c_str());

  // The first column starts inside the wall x = 0 by up to 0.1 + 0.005 jitter - 0.12 radius,
  // i.e. 0.025 m = 21% of its radius (as in the original; the wall pushes it out within a few
  // steps), and the seed's soft springs let the settled pile sink deep: the full 150,000-step
  // sample reaches 64.9% of a radius (docs/reliability.md). The run check
  // (run_diagnostics.hpp: initial overlap + max_overlap, default 10%) therefore allows a whole
  // radius more here: it stops only particles passing through each other or a wall.
  scene.checks.max_overlap = 1.0;

  // The original stops when the accumulated time exceeds Time_finish: 150,000 steps for 300.
  scene.steps = std::lround(in.time_finish / s.dt);
  scene.output.dir = dir / "out";
  scene.output.every = C::kStepsPerFrame;
  scene.output.csv = scene.output.vtk = scene.output.pov = true;
  return scene;
}

}  // namespace ppohdem::dem
