#pragma once
/// \file legacy_inputs.hpp
/// The original program's two control files (seed user's guide, Lists 2.1 and 2.2).
/// Each value line may start with a label word ending in ':' (e.g. `Lx_Ly_Lz:`); if a label
/// is present it must be the expected one. Errors name file:line and what was expected.
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "ppohdem/geometry/vector.hpp"

namespace ppohdem {

/// input_constants_voxelizer.dat (seed List 2.1):
///   1 mesh file name            ./data/dragon.stl
///   2 output directory          ./
///   3 voxel counts              76 76 76
///   4 Lx_Ly_Lz:                 44 44 44      data-space length
///   5 sizeX_sizeY_sizeZ:        10 10 10      object size
///   6 posX_posY_posZ:           22 22 11      object centre
struct VoxelizerInput {
  std::string mesh_file;   ///< as written on line 1 (resolved by the caller)
  std::string output_dir;  ///< as written on line 2
  Index3 voxels = {0, 0, 0};
  Vec3 length = Vec3::Zero();           ///< [m] > 0
  Vec3 object_size = Vec3::Zero();      ///< [m] > 0
  Vec3 object_position = Vec3::Zero();  ///< [m]
};

/// input_params_update.dat (seed List 2.2):
///   1 Lx_Ly_Lz:                 11 11 11      computational-space length
///   2 Time_finish:              300           end time
///   3 Obj_n_x_y_z:              20 20 20      window node counts
///   4 Obj_winstart_x_y_z:       28 28 28      window start (1-based node index in the data)
///   5 Obj_velocity_x_y_z:       0 0 0.005     object velocity
///   6 Obj_omega_x_y_z:          0 0 1         rotation axis
///   7 Obj_omega_Pi_rad_per_w:   1200          rotation: pi / w radians per output frame
///   8 Obj_centroid_x_y_z:       22 22 11      centre of rotation (data-space coordinates)
struct UpdateParamsInput {
  Vec3 domain_length = Vec3::Zero();  ///< > 0
  double time_finish = 0.0;           ///< > 0
  Index3 window_nodes = {0, 0, 0};    ///< >= 1
  Index3 window_start = {0, 0, 0};    ///< >= 1 (1-based)
  Vec3 velocity = Vec3::Zero();
  Vec3 rotation_axis = Vec3::Zero();  ///< any length; zero means no rotation
  double omega_pi_rad_per_w = 0.0;    ///< the divisor w; 0 means no rotation
  Vec3 centroid = Vec3::Zero();
};

VoxelizerInput read_voxelizer_input(const std::filesystem::path& path);
VoxelizerInput parse_voxelizer_input(std::string_view text, const std::string& source_name);
UpdateParamsInput read_update_params_input(const std::filesystem::path& path);
UpdateParamsInput parse_update_params_input(std::string_view text, const std::string& source_name);

/// Read a whole file into memory; InputError naming the file if it cannot be opened.
std::string read_file_bytes(const std::filesystem::path& path);

/// One Fortran real as written by people or by Fortran programs: `300.`, `.5`, `+7`, `1.0D-3`,
/// `1.0d-3`, `2.5E+01`, and the exponent-letter-free form Fortran writes for 3-digit exponents
/// (`0.10000000-199`). The whole token must be the number. Returns nullopt if it is not a
/// number; `inf`/`nan` spellings are returned as non-finite values for the caller to reject.
std::optional<double> parse_fortran_real(std::string_view token);

}  // namespace ppohdem
