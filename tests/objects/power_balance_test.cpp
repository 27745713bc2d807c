// Power balance of a moving object (issue 6): the work W done on the particles by the
// prescribed motion (energy.csv's boundary_work) equals the change of the particles' energy
// plus what the contacts dissipated,
//   W = d(K + K_rot + U_grav + U_el) + D,
// and W is the time integral of the object's power on the particles computed independently
// from its loads (BoundaryLoad: F on the object, moment M_0 about the origin):
//   P = sum_i f_i . (v + omega x (p_i - c)) = -(F . v + M_c . omega),  M_c = M_0 - c x F.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "../dem/dem_test_support.hpp"
#include "object_fields.hpp"
#include "ppohdem/dem/distance_field_object.hpp"

namespace ppohdem::dem::test {
namespace {

using ppohdem::reference::dem::ReferenceEngine;

constexpr double kRadius = 0.5e-3;  // m
constexpr double kG = 9.81;         // m/s^2

struct Balance {
  double work = 0.0;             // boundary_work [J]
  double work_from_loads = 0.0;  // sum of P(n+1) dt from the loads [J]
  double energy_change = 0.0;    // d(K + K_rot + U_grav + U_el) + D [J]
  double lift_work = 0.0;        // m g (z_end - z_0) [J]
};

Balance run(const RigidMotion& motion, const Particle& start, double dt, long steps) {
  const Material m = peer_material(0.5, 0.5);  // e = 0.5, mu = 0.5: dashpots and slip dissipate
  SimulationSetup s;
  s.dt = dt;
  s.gravity = Vec3(0, 0, -kG);
  s.material = m;
  s.law = HertzMindlin::from_material(m);
  s.particles = {start};
  // The plate z < 0 as a distance field phi = z (linear: exact under trilinear interpolation).
  const GridSpec grid{Vec3(-14e-3, -14e-3, -1e-3), Vec3::Constant(0.5e-3), {57, 57, 9}};
  auto plate = std::make_shared<DistanceFieldObject>(half_space_field(grid, Vec3::Zero(), Vec3::UnitZ()), motion, "plate");
  s.boundaries = {plate};
  ReferenceEngine engine(s);
  const Energies e0 = engine.energies();
  Balance b;
  for (long n = 0; n < steps; ++n) {
    engine.step();
    const BoundaryLoad load = engine.boundary_loads().at(0);
    const double t = engine.time();
    const Vec3 c = plate->centroid_at(t);
    const double power = -(load.force.dot(motion.velocity) + load.torque_about(c).dot(motion.angular_velocity));
    b.work_from_loads += power * dt;  // the engine's rule: force at t(n+1) times v_s(n+1) dt
  }
  EXPECT_EQ(plate->outside_grid_count(), 0u);
  const Energies e1 = engine.energies();
  b.work = e1.boundary_work - e0.boundary_work;
  b.energy_change = (e1.kinetic - e0.kinetic) + (e1.rotational - e0.rotational) +
                    (e1.gravitational - e0.gravitational) + (e1.elastic - e0.elastic) +
                    (e1.dissipated - e0.dissipated);
  b.lift_work = m.mass(kRadius) * kG * (engine.particles()[0].position.z() - start.position.z());
  return b;
}

/// Static Hertz overlap under gravity: m g = K delta^(3/2), K = (4/3) E* sqrt(R).
double resting_overlap() {
  const Material m = peer_material(0.5, 0.5);
  const double k = 4.0 / 3.0 * m.effective_young() * std::sqrt(kRadius);
  return std::pow(m.mass(kRadius) * kG / k, 2.0 / 3.0);
}

void expect_balanced(const Balance& b, const char* what, double tolerance) {
  std::printf("%s: W %.9e J, from loads %.9e J, d(energy) + D %.9e J (relative %.2e), m g dz %.9e J\n", what,
              b.work, b.work_from_loads, b.energy_change, (b.energy_change - b.work) / b.work, b.lift_work);
  ASSERT_GT(b.work, 0.0);
  // Same sum computed from the loads: differs only by round-off of the reaction sums.
  EXPECT_NEAR(b.work_from_loads, b.work, 1e-12 * std::abs(b.work));
  EXPECT_NEAR(b.energy_change, b.work, tolerance * std::abs(b.work));
}

TEST(PowerBalance, TranslatingPlateLiftingAndDraggingAParticle) {
  // The plate rises at 5 cm/s and slides at 2 cm/s: the particle (resting on it) is lifted,
  // bounces (e = 0.5), is dragged by friction until it rolls. 20 ms at dt = 1e-7 s.
  RigidMotion motion;
  motion.velocity = Vec3(0.02, 0, 0.05);
  const Particle p = sphere(1, Vec3(0, 0, kRadius - resting_overlap()), Vec3::Zero(), kRadius);
  const Balance b = run(motion, p, 1e-7, 200000);
  // The figure, 1e-6 (measured 1.3e-7): Verlet books the kinetic energy with the
  // trapezoid rule and the contact energies consistently with it (docs/dem.md); for a
  // translating surface the rectangle-rule boundary work differs from that only at the ends.
  expect_balanced(b, "translating plate", 1e-6);
  // Independent physics: the particle rode up with the plate by ~1 mm, so most of W is m g dz
  // plus the kinetic energy it carries (1/2 m v^2 + rolling, small) and the dissipation.
  EXPECT_GT(b.lift_work, 0.5 * b.work);
}

TEST(PowerBalance, RotatingPlateSpinningUpAParticleAtRest) {
  // Plate turning at 10 rad/s about z through the origin; the particle at r = 2 mm starts at
  // rest, slides until friction makes it roll with the plate: the plate's torque does work.
  RigidMotion motion;
  motion.angular_velocity = Vec3(0, 0, 10.0);
  const Particle p = sphere(1, Vec3(2e-3, 0, kRadius - resting_overlap()), Vec3::Zero(), kRadius);
  const Balance b = run(motion, p, 1e-7, 200000);
  // NOT the 1e-6: measured 7.2e-5 at dt = 2e-7 s and 3.6e-5 at dt = 1e-7 s, i.e. a
  // FIRST-order error. Known gap (docs/objects.md): the engine takes the surface velocity at
  // t(n+1) for the whole step's slip increment and boundary work; on a rotating surface the
  // contact point moves along a varying v_s, which costs O(omega v_slip dt^2) per step.
  // Bound 1e-4: twice the measured value, so a regression (or the fix) shows.
  expect_balanced(b, "rotating plate", 1e-4);
}

}  // namespace
}  // namespace ppohdem::dem::test
