#pragma once
/// \file ray_parity.hpp
/// Inside/outside of a CLOSED triangle mesh at every grid node by the parity of ray crossings along
/// the node's z-column: the original ppohDEM voxeliser (ppohDEM_v_makecrosslist +
/// ppohDEM_v_makegridout), made robust.
///
/// Jordan-Brouwer: a point not on a closed surface is inside iff a ray from it crosses the surface
/// an odd number of times. For node (i, j, k) the ray is {(x_i, y_j, z) : z > z_k}:
///  1. makecrosslist: for each column (x_i, y_j), the triangles whose xy-projection contains the
///     column, and the height z of the crossing;
///  2. makegridout: node (i, j, k) is inside iff an odd number of the column's crossings have
///     z > z_k.
///
/// Degenerate cases (column through an edge or a vertex of the projection) are decided by
/// simulation of simplicity: the column is moved to (x + e, y + e^2) (orientation.hpp), with the
/// exact orientation sign, so each column crosses a closed surface an even number of times.
/// Triangles whose projection has zero area (faces parallel to z) are never crossed.
/// Ties in z (z_cross == z_k, a node on a face) count the crossing as NOT above, i.e. the node is
/// moved up by an infinitesimal; such a node has distance 0, so its sign does not change phi.
/// Consequence for an axis-aligned box [lo, hi] whose faces lie on grid planes: the inside set is
/// exactly the half-open box [lo, hi) per axis.
///
/// The crossing height z is computed in double (barycentric interpolation, clamped to the
/// triangle): a node within rounding of the surface may get either sign, but its distance is then
/// within rounding of 0 too.
#include <cstddef>
#include <vector>

#include "ppohdem/grid/grid_spec.hpp"
#include "ppohdem/mesh/triangle_mesh.hpp"
#include "ppohdem/sdf/reference/orientation.hpp"

namespace ppohdem::sdf::reference {

/// One crossing of a column with a triangle.
struct ColumnCrossing {
  std::size_t triangle = 0;  ///< index into mesh.triangles
  double z = 0.0;            ///< height of the crossing [m]
};

/// The crossings of every (i, j) column of a grid, each column sorted by z (makecrosslist).
struct CrossList {
  int nx = 0;
  int ny = 0;
  std::vector<std::vector<ColumnCrossing>> columns;  ///< index i + nx j

  const std::vector<ColumnCrossing>& column(int i, int j) const {
    return columns[static_cast<std::size_t>(i) + static_cast<std::size_t>(nx) * static_cast<std::size_t>(j)];
  }
};

/// True if the perturbed point p' = (p.x + e, p.y + e^2) lies inside the xy-projection of the
/// triangle (a, b, c) (any orientation). False if the projection has zero area.
bool projection_contains(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& p);

/// Height at (x, y) = p of the plane through the triangle, by barycentric interpolation in the
/// xy-projection, clamped to the triangle so it always lies within the triangle's z-range [m].
double crossing_height(const Vec3& a, const Vec3& b, const Vec3& c, const Vec2& p);

/// makecrosslist: all column crossings of the mesh on the grid's (i, j) columns.
CrossList make_cross_list(const TriangleMesh& mesh, const GridSpec& grid);

/// makegridout: inside[grid.index(i, j, k)] is true iff an odd number of column (i, j)'s crossings
/// lie strictly above z_k. Meaningful for closed meshes only (see mesh_closure.hpp).
std::vector<bool> inside_by_column_parity(const CrossList& crossings, const GridSpec& grid);

/// Both steps.
std::vector<bool> inside_by_column_parity(const TriangleMesh& mesh, const GridSpec& grid);

}  // namespace ppohdem::sdf::reference
