#pragma once
// The closed 6 mm box mesh that the mesh-object MPI tests put over the middle of write_bed's
// 9 x 9 x 9 bed (mesh_object_mpi_cli_test.cpp, frames_in_parts_mpi_cli_test.cpp).
#include <Eigen/Geometry>
#include <filesystem>
#include <fstream>
#include <string>

#include "../objects/mesh_shapes.hpp"
#include "ppohdem/mesh/stl_io.hpp"

namespace ppohdem::test {

/// Writes dir/box.stl, a 6 mm box resting on the bed's top layer over its middle, and appends
/// its [[object]] table (centroid at the box's centre) to `scene`, then `motions`: the
/// object's [[object.motion]] tables.
inline void append_box_over_bed(const std::filesystem::path& dir, const std::filesystem::path& scene,
                                const std::string& motions) {
  const double a = 6e-3, top = 1.05e-3 + 2.1e-3 * 8 + 1e-3;
  const ppohdem::Vec3 corner(9.45e-3 - a / 2, 9.45e-3 - a / 2, top);
  ppohdem::write_stl(dir / "box.stl",
                     ppohdem::dem::test::transformed(ppohdem::dem::test::box(a, 3), Eigen::Matrix3d::Identity(), corner),
                     ppohdem::StlEncoding::kBinary);
  const ppohdem::Vec3 centre = corner + ppohdem::Vec3::Constant(a / 2);
  std::ofstream toml(scene, std::ios::app);
  toml.precision(17);
  toml << "[[object]]\nname = \"box\"\nmesh = \"box.stl\"\ncells = [16, 16, 16]\nmargin = 0.0025\n"
       << "centroid = [" << centre.x() << ", " << centre.y() << ", " << centre.z() << "]\n"
       << motions;
}

}  // namespace ppohdem::test
