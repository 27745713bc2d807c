#pragma once
/// \file orientation.hpp
/// The 2-D orientation predicate with the EXACT sign, and its simulation-of-simplicity version.
///
///   orient2d(a, b, p) = (b.x - a.x)(p.y - a.y) - (b.y - a.y)(p.x - a.x)
///                     = (a.x - p.x)(b.y - p.y) - (a.y - p.y)(b.x - p.x)     (same determinant)
/// is > 0 if p lies to the left of the directed line a -> b, < 0 to the right, 0 on it.
///
/// Exact sign: evaluate the second form in double; Shewchuk's static error bound ("Adaptive
/// precision floating-point arithmetic and fast robust geometric predicates", Discrete Comput.
/// Geom. 18:305-363, 1997, predicates.c, ccwerrboundA) guarantees the sign when
///   |det| > (3 + 16 eps) eps (|(a.x - p.x)(b.y - p.y)| + |(a.y - p.y)(b.x - p.x)|),  eps = 2^-53.
/// Otherwise the determinant is recomputed exactly in rational arithmetic (every double is a
/// rational number, so boost::multiprecision::cpp_rational holds the inputs exactly).
/// Assumption: no intermediate product underflows (coordinates far above 1e-150 in magnitude, or 0).
///
/// Simulation of simplicity (Edelsbrunner & Muecke, ACM Trans. Graphics 9:66-104, 1990): the query
/// point p is replaced by p' = (p.x + e, p.y + e^2) for an infinitesimal e > 0, so
///   orient2d(a, b, p') = orient2d(a, b, p) - e (b.y - a.y) + e^2 (b.x - a.x),
/// whose sign is that of the first non-zero coefficient. It is never zero unless a == b in xy.
/// p' lies on no line through two distinct input points, so "on the edge" and "at the vertex"
/// cannot happen and every ray through p' crosses a closed surface an even number of times.
#include <Eigen/Core>

namespace ppohdem::sdf::reference {

using Vec2 = Eigen::Vector2d;

/// Sign (-1, 0, +1) of orient2d(a, b, p), exact.
int orient2d_sign(const Vec2& a, const Vec2& b, const Vec2& p);

/// The same sign computed in rational arithmetic only (slow; the filter's fallback and its oracle).
int orient2d_sign_exact(const Vec2& a, const Vec2& b, const Vec2& p);

/// Sign of orient2d(a, b, p') with p' = (p.x + e, p.y + e^2): never 0 unless a == b.
int orient2d_sign_perturbed(const Vec2& a, const Vec2& b, const Vec2& p);

}  // namespace ppohdem::sdf::reference
