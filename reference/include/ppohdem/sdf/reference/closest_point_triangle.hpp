#pragma once
/// \file closest_point_triangle.hpp
/// Closest point on a triangle (or a segment) to a query point, world units [m].
///
/// Method: Voronoi-region classification of Ericson, "Real-Time Collision Detection", Morgan
/// Kaufmann 2005, section 5.1.5 (ClosestPtPointTriangle). The plane of triangle (a, b, c) is cut
/// into 7 regions (3 vertex, 3 edge, 1 face region) by the signs of the dot products
///   d1 = ab.ap, d2 = ac.ap, d3 = ab.bp, d4 = ac.bp, d5 = ab.cp, d6 = ac.cp
/// and of the (unnormalised) barycentric coordinates
///   va = d3 d6 - d5 d4,  vb = d5 d2 - d1 d6,  vc = d1 d4 - d3 d2.
/// Face region: closest point = a + ab vb/(va+vb+vc) + ac vc/(va+vb+vc).
///
/// Degenerate (zero-area) triangles: va + vb + vc = |ab x ac|^2 vanishes and the face formula
/// divides by zero; they are treated as the union of their three edges, which is what they are.
/// Slivers (smallest angle theta < ~1e-4): va, vb, vc cancel, with relative errors ~ eps / theta^2.
/// The face point is then clamped onto the triangle and compared with the three edges' closest
/// points, so the result lies on the triangle (never closer than the truth) and is off by at most
/// the sliver's width L theta in the plane: for points at height z above the sliver the distance
/// error is second order, ~ (in-plane error)^2 / (2 z).
#include "ppohdem/geometry/vector.hpp"

namespace ppohdem::sdf::reference {

/// Closest point on segment [a, b] to p (a == b allowed: returns a).
Vec3 closest_point_on_segment(const Vec3& p, const Vec3& a, const Vec3& b);

/// True if |ab x ac|^2 <= (64 eps)^2 |ab|^2 |ac|^2 |bc|^2 / max edge^2, i.e. the triangle's
/// smallest angle is below ~1e-14 rad: Ericson's face formula would lose all digits.
bool is_degenerate_triangle(const Vec3& a, const Vec3& b, const Vec3& c);

/// Closest point on triangle (a, b, c) to p. Any vertex order; any shape including zero area.
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

/// |p - closest_point_on_triangle(p, a, b, c)|^2 [m^2].
double squared_distance_to_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace ppohdem::sdf::reference
