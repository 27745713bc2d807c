// One-ulp seeded perturbation of particle centres (ppohdem/dem/perturb.hpp).
#include "ppohdem/dem/perturb.hpp"

#include <cmath>
#include <limits>

namespace ppohdem::dem {
namespace {

/// splitmix64's finaliser (Steele, Lea & Flood 2014): a bijective mix with full avalanche, so
/// neighbouring ids and seeds get unrelated bits.
std::uint64_t mix(std::uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

}  // namespace

int perturbation_direction(std::uint64_t seed, std::int64_t id, int axis) {
  const std::uint64_t h = mix(mix(mix(seed) ^ static_cast<std::uint64_t>(id)) ^ static_cast<std::uint64_t>(axis));
  return (h & 1U) != 0 ? 1 : -1;
}

void perturb_positions_by_one_ulp(Particles& particles, std::uint64_t seed) {
  constexpr double up = std::numeric_limits<double>::infinity();
  for (Particle& p : particles) {
    for (int axis = 0; axis < 3; ++axis) {
      const double x = p.position[axis];
      p.position[axis] = std::nextafter(x, perturbation_direction(seed, p.id, axis) > 0 ? up : -up);
    }
  }
}

}  // namespace ppohdem::dem
