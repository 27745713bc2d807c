#pragma once
/// \file column_sign.hpp
/// Inside/outside for the fast builder, from crossings of the grid's z-columns with the mesh.
///
/// Closed meshes (every welded edge used exactly twice; the reference's rule): column ray
/// parity, as in reference/sdf/ray_parity.hpp, the original voxeliser made robust. A node is
/// inside iff an odd number of its column's crossings lie strictly above it; the column is moved
/// to (x + e, y + e^2) by simulation of simplicity (exact orient2d, exact_orient2d.hpp), so edges
/// and vertices on a column are decided consistently. Same crossing heights and tie rule as the
/// reference, so both give the same sign at every node.
///
/// Open or non-manifold meshes: the generalized winding number w (Jacobson et al., ACM TOG
/// 32(4) 2013), inside iff w > 1/2, computed WITHOUT summing over all triangles:
///   the chain boundary dM of the soup M (directed edges with net multiplicity
///   m(u->v) = uses(u->v) - uses(v->u) != 0) is closed off by a cone K of triangles
///   (v, u, C) over those edges, C = the centroid of the boundary vertices. M + K is a cycle
///   (d(M + K) = 0 because ddM = 0), so its winding number is an integer, the signed count of
///   crossings above the node:  W(x) = sum over crossings above x of sign(orient2d of the
///   projected triangle)  (+1 for a face whose normal points up: the ray leaves through it).
///   Then w_M(x) = W(x) - w_K(x), where w_K = (1/4pi) sum_{t in K} Omega_t(x) is summed over
///   the few cone triangles only (Van Oosterom & Strackee's solid angle).
/// This is the same number the reference sums triangle by triangle; the two differ by rounding,
/// so they can disagree only where w is within rounding of 1/2.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "ppohdem/grid/grid_spec.hpp"
#include "ppohdem/mesh/triangle_mesh.hpp"

namespace ppohdem::sdf::fast {

/// Edge statistics after welding bit-identical vertices (0.0 == -0.0).
struct EdgeCensus {
  std::size_t welded_vertices = 0;
  std::size_t boundary_edges = 0;      ///< undirected edges used once
  std::size_t non_manifold_edges = 0;  ///< used three or more times
  std::size_t misoriented_edges = 0;   ///< used twice in the same direction
  bool closed() const { return boundary_edges == 0 && non_manifold_edges == 0; }
};

EdgeCensus count_edges(const TriangleMesh& mesh);

class ColumnSign {
 public:
  /// Prepares the crossings of every column of `grid` (all columns: any slab can be asked).
  ColumnSign(const TriangleMesh& mesh, const GridSpec& grid);

  bool uses_winding_number() const { return winding_; }
  const EdgeCensus& census() const { return census_; }
  std::size_t cone_triangles() const { return cone_.size(); }
  /// Human-readable notes for SdfReport::warnings (same wording as the reference's).
  std::vector<std::string> warnings() const;

  /// inside[i] for the nodes (i, j, k), i = 0..nx-1 (one x-line).
  void inside_on_line(int j, int k, std::vector<char>& inside) const;
  /// inside[i - i_begin] for the nodes (i, j, k), i = i_begin..i_end-1 (part of an x-line).
  void inside_on_segment(int j, int k, int i_begin, int i_end, char* inside) const;
  /// inside[(k - k_begin) * stride] for the nodes (i, j, k), k = k_begin..k_end-1 (part of a
  /// z-column): the same answers as inside_on_segment, from one walk up the column's sorted
  /// crossings instead of one binary search per node.
  void inside_on_column(int i, int j, int k_begin, int k_end, char* inside, std::size_t stride) const;

  std::size_t memory_bytes() const;

 private:
  struct Crossing {
    double z;
    std::int32_t direction;  ///< +1 face normal up, -1 down (winding); unused for parity
  };
  GridSpec grid_;
  EdgeCensus census_;
  bool winding_ = false;
  std::vector<std::uint32_t> column_start_;  ///< CSR offsets, size nx*ny + 1
  std::vector<Crossing> crossings_;          ///< per column sorted by z
  std::vector<Triangle> cone_;               ///< winding-number mode: the cone K
};

}  // namespace ppohdem::sdf::fast
