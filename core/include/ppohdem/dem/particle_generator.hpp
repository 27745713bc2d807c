#pragma once
/// \file particle_generator.hpp
/// Particles without a file: a simple-cubic lattice or a random non-overlapping fill of an
/// axis-aligned box, reproducible from a seed (std::mt19937_64, which the C++ standard fully
/// specifies; the distributions are implemented here so the output is the same on every
/// standard library).
#include <cstdint>

#include "ppohdem/dem/particle.hpp"

namespace ppohdem::dem {

enum class GeneratorKind { kLattice, kRandom };

struct GeneratorSpec {
  GeneratorKind kind = GeneratorKind::kLattice;
  Vec3 box_min = Vec3::Zero();  ///< [m]
  Vec3 box_max = Vec3::Zero();  ///< [m]
  std::int64_t count = 0;       ///< number of particles
  double radius = 0.0;          ///< R [m] (the smallest radius if radius_max > radius)
  double radius_max = 0.0;      ///< R_max [m]; radii uniform in [radius, radius_max] if larger
  std::uint64_t seed = 1;
  Vec3 velocity = Vec3::Zero();  ///< initial velocity of every particle [m/s]
  /// Lattice: random displacement of each centre, as a fraction of the radius (breaks the
  /// perfect symmetry of a lattice so a settling pile does not stack in columns).
  double jitter = 0.0;
};

/// Lattice: spacing 2 R_max (1 + 1e-3) (+jitter room), filled x fastest, then y, then z,
/// starting at box_min + R_max. Random: random sequential addition, up to 1000 attempts per
/// particle, checked against a cell grid. Ids are 1..count. Throws InputError (naming
/// `where`) if the box cannot hold `count` particles.
Particles generate_particles(const GeneratorSpec& spec, const std::string& where);

}  // namespace ppohdem::dem
