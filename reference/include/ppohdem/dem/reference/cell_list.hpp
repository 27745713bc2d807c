#pragma once
// Contact detection for the reference engine: a uniform cell list (Allen & Tildesley 1987,
// sec. 5.3.2, "linked lists", here stored as a counting sort of the particles by cell).
// Cells are cubes of side 2 R_max, so two touching spheres are in the same or in adjacent
// cells; each particle looks at its own cell and the 26 neighbours and keeps pairs a < b.
//
// The grid is dense and covers the bulk of the particles: per axis from the 1st to the 99th
// percentile of the centres (plus one cell), at most ~8 N cells in all. Particles outside it
// (e.g. escaped ones falling away) are CLAMPED into the border cells. Clamping is correct:
// cell indices of two centres closer than one cell differ by at most 1 per axis, and the
// clamp (monotone, never increasing distances) keeps that true; outliers only crowd the
// border cells. Cost O(N + pairs examined); no hashing.
#include <cstddef>
#include <utility>
#include <vector>

#include "ppohdem/dem/particle.hpp"

namespace ppohdem::dem::reference {

/// Indices (a, b) of particle pairs whose spheres overlap (|x_a - x_b| < R_a + R_b), with
/// id_a < id_b, sorted by (id_a, id_b).
std::vector<std::pair<std::size_t, std::size_t>> touching_pairs(const ppohdem::dem::Particles& particles);

/// The same by the O(N^2) definition (the oracle for tests).
std::vector<std::pair<std::size_t, std::size_t>> touching_pairs_brute_force(
    const ppohdem::dem::Particles& particles);

}  // namespace ppohdem::dem::reference
