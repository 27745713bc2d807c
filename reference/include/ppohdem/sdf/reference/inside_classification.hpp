#pragma once
/// \file inside_classification.hpp
/// Which grid nodes are inside the mesh, choosing the method the mesh allows:
///   closed, consistently oriented   -> column ray parity (ray_parity.hpp), no warning;
///   closed, inconsistently oriented -> column ray parity, which never looks at orientation,
///                                      with a warning (a flipped face would spoil the winding
///                                      number near it, but not the parity);
///   not closed (holes, non-manifold) -> generalized winding number (winding_number.hpp), with a
///                                      warning: parity is meaningless for an open surface.
#include <string>
#include <vector>

#include "ppohdem/grid/grid_spec.hpp"
#include "ppohdem/mesh/triangle_mesh.hpp"

namespace ppohdem::sdf::reference {

enum class SignMethod { ray_parity, winding_number };

struct InsideClassification {
  std::vector<bool> inside;  ///< per node, grid.index order
  SignMethod method = SignMethod::ray_parity;
  std::vector<std::string> warnings;
};

InsideClassification classify_inside_nodes(const TriangleMesh& mesh, const GridSpec& grid);

/// Throws InputError unless the mesh has triangles with finite vertices and the grid has >= 1
/// node per axis and finite spacings > 0 (`who` names the caller in the message).
void check_sdf_inputs(const TriangleMesh& mesh, const GridSpec& grid, const std::string& who);

}  // namespace ppohdem::sdf::reference
