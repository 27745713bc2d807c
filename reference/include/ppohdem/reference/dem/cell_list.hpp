#pragma once
// Contact detection for the reference engine: a uniform cell list (Allen & Tildesley 1987,
// sec. 5.3.2). Cells are cubes of side 2 R_max, so two touching spheres are always in the same
// or in adjacent cells (27 neighbours, each pair looked at once). Occupied cells live in a hash
// map, so particles far apart (or escaped) cost nothing.
#include <cstddef>
#include <utility>
#include <vector>

#include "ppohdem/dem/particle.hpp"

namespace ppohdem::reference::dem {

/// Indices (a, b) of particle pairs whose spheres overlap (|x_a - x_b| < R_a + R_b), with
/// id_a < id_b, sorted by (id_a, id_b).
std::vector<std::pair<std::size_t, std::size_t>> touching_pairs(const ppohdem::dem::Particles& particles);

/// The same by the O(N^2) definition (the oracle for tests).
std::vector<std::pair<std::size_t, std::size_t>> touching_pairs_brute_force(
    const ppohdem::dem::Particles& particles);

}  // namespace ppohdem::reference::dem
