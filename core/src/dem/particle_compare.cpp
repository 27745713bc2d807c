#include "ppohdem/dem/particle_compare.hpp"

#include <cmath>
#include <cstring>
#include <string>

#include "ppohdem/error.hpp"

namespace ppohdem::dem {
namespace {

// |a - b| into `worst` (NaN propagates: a run that produced NaN must not look close).
void take(double a, double b, double& worst, bool& bitwise) {
  const double d = std::abs(a - b);
  if (std::isnan(d) || d > worst) worst = std::isnan(worst) ? worst : d;
  if (std::memcmp(&a, &b, sizeof a) != 0) bitwise = false;
}

void take(const Vec3& a, const Vec3& b, double& worst, bool& bitwise) {
  for (int c = 0; c < 3; ++c) take(a[c], b[c], worst, bitwise);
}

}  // namespace

ParticleDifference compare_particles(const Particles& a, const Particles& b) {
  if (a.size() != b.size()) {
    throw InputError("compare: " + std::to_string(a.size()) + " particles against " + std::to_string(b.size()));
  }
  ParticleDifference d;
  for (std::size_t k = 0; k < a.size(); ++k) {
    const Particle& p = a[k];
    const Particle& q = b[k];
    if (p.id != q.id) {
      throw InputError("compare: particle " + std::to_string(k) + " has id " + std::to_string(p.id) +
                       " in the first run and " + std::to_string(q.id) + " in the second");
    }
    take(p.position, q.position, d.max_position, d.bitwise);
    take(p.velocity, q.velocity, d.max_velocity, d.bitwise);
    take(p.angular_velocity, q.angular_velocity, d.max_angular_velocity, d.bitwise);
    take(p.force, q.force, d.max_force, d.bitwise);
    take(p.torque, q.torque, d.max_torque, d.bitwise);
    take(p.radius, q.radius, d.max_radius, d.bitwise);
  }
  return d;
}

}  // namespace ppohdem::dem
