#pragma once
/// \file particle.hpp
/// One spherical particle: the seed's `ppohDEM_particles` record (pos, vel, force, omega,
/// rforce), as an array-of-structures element. Contact lists live in the engine (they are
/// per contact, not per particle). SI units throughout (ppohdem/units.hpp).
#include <cstdint>
#include <vector>

#include "ppohdem/geometry/vector.hpp"

namespace ppohdem::dem {

struct Particle {
  std::int64_t id = 0;         ///< user-visible identity, unique in a scene (CSV column `id`)
  Vec3 position = Vec3::Zero();          ///< centre x [m]
  Vec3 velocity = Vec3::Zero();          ///< v [m/s]
  Vec3 angular_velocity = Vec3::Zero();  ///< omega [rad/s]
  double radius = 0.0;                   ///< R [m]
  /// Index of the particle's material in the scene (SimulationSetup::material_at); 0 in a
  /// one-material scene (CSV column `material`, by name)
  std::uint16_t material = 0;
  Vec3 force = Vec3::Zero();   ///< contact force of the last force evaluation, no gravity [N]
  Vec3 torque = Vec3::Zero();  ///< contact torque about the centre, last evaluation [N m]
};

using Particles = std::vector<Particle>;

}  // namespace ppohdem::dem
