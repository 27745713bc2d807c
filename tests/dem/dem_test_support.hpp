#pragma once
// Shared helpers for the DEM tests: small scenes and impact measurements. The engine list for
// the typed contract tests is here: every engine runs the same test bodies (STYLE habit 9).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "ppohdem/dem/engine.hpp"
#include "ppohdem/dem/fast/fast_engine.hpp"
#include "ppohdem/dem/reference/reference_engine.hpp"

namespace ppohdem::dem::test {

using EngineTypes = ::testing::Types<ppohdem::dem::reference::ReferenceEngine, ppohdem::dem::fast::FastEngine>;

/// Soft glass-like material of DESIGN.md's peer comparison.
inline Material peer_material(double restitution, double friction) {
  Material m;
  m.density = 2500.0;  // kg/m^3
  m.young = 1.0e7;     // Pa
  m.poisson = 0.3;
  m.restitution = restitution;
  m.friction = friction;
  return m;
}

inline Particle sphere(std::int64_t id, const Vec3& x, const Vec3& v, double r) {
  Particle p;
  p.id = id;
  p.position = x;
  p.velocity = v;
  p.radius = r;
  return p;
}

/// Two equal spheres on the x axis, 10% of a radius apart, approaching at relative speed v.
inline SimulationSetup head_on_setup(const ContactLaw& law, const Material& m, double r, double v,
                                     double dt) {
  SimulationSetup s;
  s.dt = dt;
  s.material = m;
  s.law = law;
  s.particles = {sphere(1, Vec3(-1.05 * r, 0, 0), Vec3(0.5 * v, 0, 0), r),
                 sphere(2, Vec3(1.05 * r, 0, 0), Vec3(-0.5 * v, 0, 0), r)};
  return s;
}

struct ImpactMeasurement {
  double duration = 0.0;         ///< [s] between the gap's zero crossings (interpolated)
  double rebound_velocity = 0.0; ///< relative separation speed after the contact [m/s]
};

/// Runs a two-body contact (two particles, or one particle against a boundary when
/// `gap` says how to measure) until it has ended, measuring start and end times by linear
/// interpolation of the gap between steps (error O(dt^2)).
template <class Engine, class GapFn, class SpeedFn>
ImpactMeasurement measure_impact(Engine& engine, GapFn gap, SpeedFn separation_speed,
                                 long max_steps) {
  ImpactMeasurement m;
  double previous_gap = gap(engine.particles());
  double previous_time = engine.time();
  double start = -1.0;
  for (long s = 0; s < max_steps; ++s) {
    engine.step();
    const double g = gap(engine.particles());
    const double t = engine.time();
    const double crossing = previous_time + (t - previous_time) * previous_gap / (previous_gap - g);
    if (start < 0.0 && previous_gap > 0.0 && g <= 0.0) start = crossing;
    if (start >= 0.0 && previous_gap <= 0.0 && g > 0.0) {
      m.duration = crossing - start;
      // After the contact, velocities are constant (no gravity): read them now.
      m.rebound_velocity = separation_speed(engine.particles());
      return m;
    }
    previous_gap = g;
    previous_time = t;
  }
  ADD_FAILURE() << "contact did not end within " << max_steps << " steps";
  return m;
}

inline double pair_gap(const Particles& p) {
  return (p[0].position - p[1].position).norm() - p[0].radius - p[1].radius;
}
inline double pair_separation_speed(const Particles& p) {
  return (p[1].velocity - p[0].velocity).dot((p[1].position - p[0].position).normalized());
}

}  // namespace ppohdem::dem::test
