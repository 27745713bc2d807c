#pragma once
/// \file exact_orient2d.hpp
/// The 2-D orientation predicate with the exact sign, without a big-number library.
///
///   orient2d(a, b, p) = (a.x - p.x)(b.y - p.y) - (a.y - p.y)(b.x - p.x)
/// is > 0 if p lies left of the directed line a -> b, < 0 right of it, 0 on it.
///
/// Stage 1 (Shewchuk, "Adaptive precision floating-point arithmetic and fast robust geometric
/// predicates", Discrete Comput. Geom. 18:305-363, 1997, ccwerrboundA): the double result has
/// the right sign when |det| > (3 + 16 eps) eps (|left| + |right|), eps = 2^-53.
/// Stage 2 (exact): each difference a - p is split exactly into x + y (Two-Diff, Knuth), each
/// product of two such pairs into 8 doubles (Two-Product with fma), and the 16 terms are summed
/// into a non-overlapping expansion with Shewchuk's Grow-Expansion; the sign of an expansion is
/// the sign of its largest non-zero component. Exact unless a product underflows (coordinates
/// far below 1e-150 in magnitude), the same assumption as the reference's rational fallback.
///
/// Simulation of simplicity (Edelsbrunner & Muecke, ACM Trans. Graphics 9:66-104, 1990): the
/// perturbed predicate moves p to (p.x + e, p.y + e^2), e -> 0+, so
///   orient2d(a, b, p') = orient2d(a, b, p) - e (b.y - a.y) + e^2 (b.x - a.x),
/// whose sign is that of the first non-zero coefficient (0 only if a == b).
namespace ppohdem::sdf::fast {

/// Sign (-1, 0, +1) of orient2d(a, b, p), exact. Points as (x, y) pairs.
int orient2d_sign(double ax, double ay, double bx, double by, double px, double py);

/// Stage 2 only (the filter's fallback; exposed so tests can compare it with a rational oracle).
int orient2d_sign_expansion(double ax, double ay, double bx, double by, double px, double py);

/// Sign of orient2d(a, b, p') with p' = (p.x + e, p.y + e^2): never 0 unless a == b.
int orient2d_sign_perturbed(double ax, double ay, double bx, double by, double px, double py);

}  // namespace ppohdem::sdf::fast
