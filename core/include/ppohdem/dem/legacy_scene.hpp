#pragma once
/// \file legacy_scene.hpp
/// The seed's sample_main01 as a Scene: `ppohdem simulate input_params_update.dat`.
///
/// Inputs, all in the directory of the params file (the seed's working directory):
///   input_params_update.dat  (List 2.2, io/legacy_inputs.hpp)
///   distance_NNNN.dat        (written by `ppohdem voxelize input_constants_voxelizer.dat`)
///   input_constants_voxelizer.dat (optional: gives the data length L, see below)
/// The distance files do not store the data's length, so the data spacing h_data = L / n
/// (node (i,j,k), 1-based, at h_data (i-1, j-1, k-1)) needs L from `data_length` or from
/// input_constants_voxelizer.dat next to the params file (its `Lx_Ly_Lz:` line). The
/// computational window has Obj_n nodes over Lx: h_window = Lx / (Obj_n - 1) per axis; it must
/// equal h_data (relative 1e-9), otherwise InputError giving both values (users' guide sec. 2:
/// "the resolution ... must be identical").
///
/// World frame = the computational box [0, Lx] x [0, Ly] x [0, Lz]; data node m (1-based) sits
/// at h (m - winstart) per axis, so the window [winstart, winstart + Obj_n - 1] covers the box.
/// The object field is the WHOLE data grid placed that way (not only the window): the original
/// resamples the whole data in the window every frame, so parts of the object outside the
/// window can move into the box.
///
/// Motion (the original moves the field once per output frame of 500 steps of dt = 0.002;
/// here the motion is continuous with the same displacement per frame):
///   velocity [m/s]      v = Obj_velocity h / (500 dt)          (index units per frame)
///   angular velocity    omega = +axis/|axis| (pi / w) / (500 dt)  [rad/s]
///     The original samples the data at Rot(f) (u - c) - vel f + c with Rot(f) a rotation by
///     -pi f / w, so the OBJECT turns by +pi/w per frame (its obj/objNNN.pov meshes turn
///     counter-clockwise about +z in the sample: +15.0 degrees from frame 1 to 100).
///   centroid [m]        c0 = Obj_centroid - (winstart - 1) h   (data coordinates -> world)
/// Particles (the original's hard-coded sample): 600 spheres in a sheet at y = 5.5, 33 per
/// row along x from x = 0.1, rows up in z from z = 5.0, pitch 0.3, +-0.005 jitter, radius
/// 0.1 (1 + 0.2 u), u uniform in [0, 1) (std::mt19937_64, seed 1), at rest.
/// Walls: the 6 faces of the box. Gravity (0, 0, -0.01). Contact: linear spring-dashpot with
/// k_n = 30, k_t = 1 (ratio 1/30), mu = 0.5774, density such that a particle of radius 0.1
/// has mass 1, and restitution e = 0.66431 (the original's dashpot En = 1 on a pair of two
/// mass-1 particles, see docs/objects.md). dt = 0.002, steps = round(Time_finish / dt)
/// (the caller may change Scene::steps, e.g. `--steps`).
/// Output: <dir>/out, frames every 500 steps (csv, vtk, pov), as for TOML scenes.
#include <filesystem>
#include <optional>

#include "ppohdem/dem/scene.hpp"

namespace ppohdem::dem {

struct LegacySceneOptions {
  std::optional<double> data_length;  ///< L of the distance data [m], all axes (--data-length)
};

/// The sample's constants (the original's parameter routine, rounded values as printed).
struct LegacySampleConstants {
  static constexpr double kTimeStep = 0.002;          ///< [s]
  static constexpr long kStepsPerFrame = 500;         ///< Dstep
  static constexpr double kNormalStiffness = 30.0;    ///< Kn [N/m]
  static constexpr double kTangentialStiffness = 1.0; ///< Kt [N/m]
  static constexpr double kNormalDamping = 1.0;       ///< En [N s/m]
  static constexpr double kMass = 1.0;                ///< [kg] of a particle of radius 0.1
  static constexpr double kRadius = 0.1;              ///< [m]
  static constexpr double kFriction = 0.5774;         ///< Fric_const
  static constexpr double kGravity = 0.01;            ///< [m/s^2], along -z
  static constexpr int kParticles = 600;
};

/// Restitution of a linear spring-dashpot F = k delta + c delta_dot on effective mass m*:
/// zeta = c / (2 sqrt(m* k)), e = exp(-pi zeta / sqrt(1 - zeta^2)) (underdamped, zeta < 1).
double linear_restitution(double stiffness, double damping, double effective_mass);

/// Reads the params file, the distance data and (if present) input_constants_voxelizer.dat.
Scene read_legacy_scene(const std::filesystem::path& params_file, const LegacySceneOptions& options);

}  // namespace ppohdem::dem
