/// \file inside_classification.cpp
/// Chooses ray parity or the winding number from the mesh's closure. See the header.
#include "ppohdem/sdf/reference/inside_classification.hpp"

#include <cmath>

#include "ppohdem/error.hpp"
#include "ppohdem/sdf/reference/mesh_closure.hpp"
#include "ppohdem/sdf/reference/ray_parity.hpp"
#include "ppohdem/sdf/reference/winding_number.hpp"

namespace ppohdem::sdf::reference {

InsideClassification classify_inside_nodes(const TriangleMesh& mesh, const GridSpec& grid) {
  const MeshClosure closure = check_mesh_closure(mesh);
  InsideClassification result;
  if (closure.closed()) {
    result.method = SignMethod::ray_parity;
    result.inside = inside_by_column_parity(mesh, grid);
    if (!closure.consistently_oriented()) {
      result.warnings.push_back("mesh is closed but not consistently oriented (" +
                                std::to_string(closure.misoriented_edges) +
                                " edges used twice in the same direction): sign from ray parity, "
                                "which does not depend on orientation");
    }
  } else {
    result.method = SignMethod::winding_number;
    result.inside = inside_by_winding_number(mesh, grid);
    result.warnings.push_back("mesh is not watertight (" + std::to_string(closure.boundary_edges) +
                              " boundary edges, " + std::to_string(closure.non_manifold_edges) +
                              " non-manifold edges): sign from the generalized winding number");
  }
  return result;
}

void check_sdf_inputs(const TriangleMesh& mesh, const GridSpec& grid, const std::string& who) {
  if (mesh.empty()) throw InputError(who + ": expected a mesh with at least one triangle, found none");
  for (std::size_t t = 0; t < mesh.size(); ++t) {
    for (const Vec3& v : mesh.triangles[t].v) {
      if (!v.allFinite()) {
        throw InputError(who + ": triangle " + std::to_string(t) + " has a non-finite vertex coordinate");
      }
    }
  }
  for (int axis = 0; axis < 3; ++axis) {
    const double h = grid.spacing[axis];
    const int n = grid.nodes[static_cast<std::size_t>(axis)];
    if (n < 1 || !std::isfinite(h) || !(h > 0.0) || !std::isfinite(grid.origin[axis])) {
      throw InputError(who + ": expected a grid with >= 1 node and a finite spacing > 0 on axis " +
                       std::to_string(axis) + ", found " + std::to_string(n) + " nodes, spacing " +
                       std::to_string(h));
    }
  }
}

}  // namespace ppohdem::sdf::reference
