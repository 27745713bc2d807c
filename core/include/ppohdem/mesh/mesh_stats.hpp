#pragma once
/// \file mesh_stats.hpp
/// Mesh statistics: counts, bounding box, and topology after welding bit-identical vertices.
/// An edge is "boundary" if one triangle uses it, "non-manifold" if more than two do, and
/// "inconsistently oriented" if its two triangles traverse it in the same direction.
/// Watertight = no boundary, no non-manifold, no inconsistent edge (closed, consistently
/// oriented 2-manifold), which is what a well-defined inside needs.
#include <cstddef>
#include <string>

#include "ppohdem/mesh/triangle_mesh.hpp"

namespace ppohdem {

struct MeshStats {
  std::size_t triangles = 0;
  std::size_t vertices = 0;  ///< distinct after welding bit-identical coordinates
  std::size_t edges = 0;
  std::size_t boundary_edges = 0;
  std::size_t non_manifold_edges = 0;
  std::size_t inconsistent_edges = 0;
  std::size_t degenerate_triangles = 0;  ///< exactly zero area
  BoundingBox box;
  double surface_area = 0.0;   ///< [m^2] (world units squared)
  double signed_volume = 0.0;  ///< [m^3], positive for an outward-oriented closed mesh
  bool watertight() const {
    return triangles > 0 && boundary_edges == 0 && non_manifold_edges == 0 &&
           inconsistent_edges == 0;
  }
  long euler_characteristic() const {
    return static_cast<long>(vertices) - static_cast<long>(edges) + static_cast<long>(triangles);
  }
};

MeshStats compute_mesh_stats(const TriangleMesh& mesh);

/// Multi-line human-readable summary (used by `ppohdem mesh-info`).
std::string format_mesh_stats(const MeshStats& stats);

}  // namespace ppohdem
