#pragma once
/// \file perturb.hpp
/// Round-off perturbation of a particle state, for ensembles of a chaotic run
/// (docs/port-validation.md "Reference ensemble"): `ppohdem simulate SCENE --perturb-seed K`.
#include <cstdint>

#include "ppohdem/dem/particle.hpp"

namespace ppohdem::dem {

/// Moves every coordinate of every particle centre by exactly one ulp, up or down
/// (std::nextafter towards +inf or -inf). The direction of coordinate `axis` of the particle
/// with id `id` is bit 0 of splitmix64(seed, id, axis), so a given seed gives the same state
/// whatever the particle order, rank or thread count. Velocities, spins and radii are left
/// as they are. A zero coordinate moves to +-4.9e-324 (the smallest subnormal).
void perturb_positions_by_one_ulp(Particles& particles, std::uint64_t seed);

/// +1 or -1: the direction of that coordinate's ulp (exposed for the tests).
int perturbation_direction(std::uint64_t seed, std::int64_t id, int axis);

}  // namespace ppohdem::dem
