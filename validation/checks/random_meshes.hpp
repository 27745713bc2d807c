#pragma once
// Random watertight meshes for the SDF property tests (tests/validation/sdf_property_test.cpp):
// convex hulls of point clouds (CGAL::convex_hull_3) and unions of lattice boxes (their
// boundary faces, built here). CGAL stays private to validation/.
#include <array>
#include <vector>

#include "ppohdem/mesh/triangle_mesh.hpp"

namespace ppohdem::validation {

/// The convex hull of `points` (>= 4, not coplanar) as outward-oriented triangles, by
/// CGAL::convex_hull_3 (Epick kernel). Throws InputError if the hull is degenerate.
TriangleMesh convex_hull_mesh(const std::vector<Vec3>& points);

/// The union of unit cells {cells[c] + [0,1]^3} * h + origin as a closed, outward-oriented
/// triangle mesh (two triangles per exposed cell face). The union must be a 2-manifold: use
/// is_manifold_cell_union() first (cells meeting only along an edge or at a vertex are not).
TriangleMesh cell_union_mesh(const std::vector<std::array<int, 3>>& cells, double h, const Vec3& origin);

/// False if two cells of the set meet only along an edge or at a vertex without a face path
/// around it (non-manifold edges or vertices); the test is local: every 2x2x2 block of the
/// occupancy lattice must be one of the manifold configurations.
bool is_manifold_cell_union(const std::vector<std::array<int, 3>>& cells);

/// Exact distance from x to the union of the cells' closed boxes, for x OUTSIDE the union:
/// the minimum over cells of the point-box distance (exact: the distance to a union is the
/// minimum of the distances). Inside points have distance 0 here.
double cell_union_outside_distance(const std::vector<std::array<int, 3>>& cells, double h,
                                   const Vec3& origin, const Vec3& x);

}  // namespace ppohdem::validation
