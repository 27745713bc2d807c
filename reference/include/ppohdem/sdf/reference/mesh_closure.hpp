#pragma once
/// \file mesh_closure.hpp
/// Is a triangle soup a closed surface, and is it consistently oriented? Decides how the sign of
/// the distance is found (ray parity needs a closed surface; the winding number needs orientation).
///
/// Vertices are welded when their coordinates are bit-identical (0.0 and -0.0 count as equal).
/// With welded vertex ids, every triangle (u, v, w) uses the directed edges u->v, v->w, w->u
/// (edges from a vertex to itself, in triangles with a repeated vertex, are skipped). Then
///   closed                 : every undirected edge is used exactly twice;
///   consistently oriented  : closed, and the two uses run in opposite directions
///                            (u->v once and v->u once), as on an orientable surface.
#include <cstddef>

#include "ppohdem/mesh/triangle_mesh.hpp"

namespace ppohdem::sdf::reference {

struct MeshClosure {
  std::size_t welded_vertices = 0;
  std::size_t edges = 0;               ///< undirected edges
  std::size_t boundary_edges = 0;      ///< used once
  std::size_t non_manifold_edges = 0;  ///< used three or more times
  std::size_t misoriented_edges = 0;   ///< used twice in the same direction

  bool closed() const { return boundary_edges == 0 && non_manifold_edges == 0; }
  bool consistently_oriented() const { return closed() && misoriented_edges == 0; }
};

MeshClosure check_mesh_closure(const TriangleMesh& mesh);

}  // namespace ppohdem::sdf::reference
