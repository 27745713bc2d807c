#pragma once
/// \file fast_sweeping.hpp
/// Fast sweeping method for the eikonal equation |grad u| = 1 (u = unsigned distance [m]) on a
/// grid with per-axis spacing (Zhao, "A fast sweeping method for Eikonal equations", Math. Comp.
/// 74:603-627, 2005). Replaces the original's Jacobi passes (ppohDEM_v_distancecalculate).
///
/// Discretisation (Godunov upwind, Zhao eq. (2.2) with h per axis): at a free node, with
///   a_m = min(u at the two axis-m neighbours)  (one neighbour at the domain boundary),
/// the new value x solves
///   sum_m ( max(x - a_m, 0) / h_m )^2 = 1.
/// Sorting a_1 <= a_2 <= a_3, the solution uses the first n terms for the smallest n with
/// x_n <= a_(n+1):  x_1 = a_1 + h_1; for n = 2, 3 the quadratic
///   (sum 1/h^2) x^2 - 2 (sum a/h^2) x + (sum a^2/h^2 - 1) = 0, larger root.
/// Gauss-Seidel: u <- min(u, x) in place, sweeping the grid in the 8 orders (+-i, +-j, +-k); a
/// round is 8 sweeps; rounds repeat until a whole round changes no value. Values only decrease, and
/// doubles are a finite set, so this terminates; Zhao shows 2^d sweeps already give the converged
/// discrete solution up to O(h |log h|) for a single source.
/// Frozen nodes (the exact band) keep their values; unreached nodes hold +infinity.
#include <array>
#include <vector>

#include "ppohdem/grid/scalar_field.hpp"

namespace ppohdem::sdf::reference {

/// The Godunov update x for neighbour minima a (per axis, +inf if none known) and spacings h.
/// Returns +inf if every a is +inf.
double godunov_update(std::array<double, 3> a, std::array<double, 3> h);

/// Sweeps `distance` (unsigned, +inf where unknown) to convergence; nodes with frozen[index]
/// keep their values. Returns the number of sweeps done (a multiple of 8; the last round
/// changed nothing).
int fast_sweep(ScalarField& distance, const std::vector<bool>& frozen);

}  // namespace ppohdem::sdf::reference
