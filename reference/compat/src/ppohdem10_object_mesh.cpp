// object_mesh.stl in the original's format (ppohdem10_object_mesh_stl, ppohdem10_voxelizer.hpp):
// output_object_mesh of ppohDEM_v_inivar.f90 writes each line with `write(211,*)`.
#include <string>

#include "ppohdem/compat/ppohdem10_voxelizer.hpp"
#include "ppohdem10_dem_format.hpp"

namespace ppohdem::compat {

std::string ppohdem10_object_mesh_stl(const TriangleMesh& placed_mesh) {
  using fortran::list_directed_real;
  auto three = [](const Vec3& v) {
    return list_directed_real(v.x()) + ' ' + list_directed_real(v.y()) + ' ' + list_directed_real(v.z());
  };
  // write(211,*) 'solid Object01 ': list-directed output starts each record with a blank.
  std::string text = " solid Object01 \n";
  for (const Triangle& t : placed_mesh.triangles) {
    // buf = write(*) ' facet normal ' (a blank + the text), trimmed, then write(211,*) buf // ' ' // x ...
    text += "   facet normal " + three(t.file_normal) + "\n";
    text += "     outer loop \n";
    for (const Vec3& v : t.v) text += "        vertex " + three(v) + "\n";
    text += "     endloop \n";
    text += "   endfacet \n";
  }
  text += " endsolid Object01 \n";
  return text;
}

}  // namespace ppohdem::compat
