#pragma once
/// \file exact_distance.hpp
/// Brute-force unsigned distance with EXACT constructions, for spot checks of the oracle's
/// rounding (and of near-degenerate configurations).
///
///   d(x) = sqrt( min_t squared_distance(x, t) )   [world units]
///
/// The squared distance is computed by CGAL::squared_distance in the Epeck kernel
/// (CGAL::Exact_predicates_exact_constructions_kernel: lazy exact rationals), so it is the
/// exact squared distance between the double-precision inputs; only the final conversion to
/// double (<= 1 ulp) and sqrt (0.5 ulp) round. O(triangles) per point and slow (exact
/// arithmetic per triangle): meant for a few hundred points on small meshes, not for fields.
#include "ppohdem/mesh/triangle_mesh.hpp"

namespace ppohdem::validation {

/// Throws InputError on an empty mesh or non-finite input.
double exact_unsigned_distance(const TriangleMesh& mesh, const Vec3& point);

}  // namespace ppohdem::validation
