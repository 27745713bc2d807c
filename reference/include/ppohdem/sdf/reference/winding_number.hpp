#pragma once
/// \file winding_number.hpp
/// Generalized winding number of a triangle mesh (Jacobson, Kavan & Sorkine-Hornung, "Robust
/// inside-outside segmentation using generalized winding numbers", ACM Trans. Graphics 32(4), 2013):
///   w(p) = (1 / 4 pi) sum_t Omega_t(p),
/// Omega_t = signed solid angle of triangle t seen from p [sr], by Van Oosterom & Strackee
/// ("The solid angle of a plane triangle", IEEE Trans. Biomed. Eng. 30:125-126, 1983): with
/// a, b, c the vertices minus p,
///   tan(Omega / 2) = a.(b x c) / (|a||b||c| + (a.b)|c| + (b.c)|a| + (c.a)|b|),
/// evaluated with atan2 so that Omega is in (-2 pi, 2 pi].
/// For a closed, outward (counter-clockwise) oriented mesh w = 1 inside and 0 outside; for a mesh
/// with holes w varies smoothly, and "inside iff w > 1/2" is the robust generalisation.
/// winding_number() is the brute force over all triangles, O(triangles) per point: slow and
/// obviously right, the oracle of WindingNumberTree (winding_number_tree.hpp), the hierarchical
/// evaluation that inside_by_winding_number() uses (same values up to rounding, far fewer terms).
#include <vector>

#include "ppohdem/grid/grid_spec.hpp"
#include "ppohdem/mesh/triangle_mesh.hpp"

namespace ppohdem::sdf::reference {

/// Signed solid angle of triangle (a, b, c) seen from p [sr]; > 0 if p is on the side the
/// counter-clockwise normal points away from (the inner side of an outward face).
double solid_angle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

/// w(p) for the whole mesh (dimensionless).
double winding_number(const TriangleMesh& mesh, const Vec3& p);

/// inside[grid.index(i, j, k)] = w(node) > 1/2, w evaluated with a WindingNumberTree built once
/// (an empty mesh has w = 0 everywhere: all outside).
std::vector<bool> inside_by_winding_number(const TriangleMesh& mesh, const GridSpec& grid);

}  // namespace ppohdem::sdf::reference
