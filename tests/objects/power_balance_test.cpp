// Power balance of a moving object (issue 6): the work W done on the particles by the
// prescribed motion (energy.csv's boundary_work) equals the change of the particles' energy
// plus what the contacts dissipated,
//   W = d(K + K_rot + U_grav + U_el) + D,
// and W is the time integral of the object's power on the particles computed independently
// from its loads (BoundaryLoad: F on the object, moment M_0 about the origin):
//   P = sum_i f_i . (v + omega x (p_i - c)) = -(F . v + M_c . omega),  M_c = M_0 - c x F,
// integrated by the engine's rule (contact_force.hpp "Moving boundaries"): the dashpot's
// share at the evaluation time, the rest by the trapezoid rule.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "../dem/dem_test_support.hpp"
#include "object_fields.hpp"
#include "ppohdem/dem/distance_field_object.hpp"

namespace ppohdem::dem::test {
namespace {

using ppohdem::dem::reference::ReferenceEngine;

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
  const HertzMindlin law = HertzMindlin::from_material(m);
  SimulationSetup s;
  s.dt = dt;
  s.gravity = Vec3(0, 0, -kG);
  s.material = m;
  s.law = law;
  s.particles = {start};
  // The plate z < 0 as a distance field phi = z (linear: exact under trilinear interpolation).
  const GridSpec grid{Vec3(-14e-3, -14e-3, -1e-3), Vec3::Constant(0.5e-3), {57, 57, 9}};
  auto plate = std::make_shared<DistanceFieldObject>(half_space_field(grid, Vec3::Zero(), Vec3::UnitZ()), motion, "plate");
  s.boundaries = {plate};
  ReferenceEngine engine(s);
  const Energies e0 = engine.energies();
  Balance b;
  // The plate's power on the particle from the loads on the plate (rigid body: P = -(F . v +
  // M_c . omega)) [W], and the dashpot's share of it, reconstructed from the geometry and the
  // Hertz law: F_d = F_n - F_el(delta) along the plate normal n, delta = R - (x - x_plate) . n,
  // power F_d (v_s . n) at the foot p of the centre [W].
  struct Power {
    double total = 0.0;
    double dashpot = 0.0;
  };
  const auto power = [&] {
    const double t = engine.time();
    const BoundaryLoad load = engine.boundary_loads().at(0);
    Power p;
    p.total = -(load.force.dot(motion.velocity) + load.torque_about(plate->centroid_at(t)).dot(motion.angular_velocity));
    const RigidTransform pose = plate->pose_at(t);
    const Vec3 n = pose.rotate(Vec3::UnitZ());
    const Vec3 x = engine.particles()[0].position;
    const double gap = (x - pose.apply(Vec3::Zero())).dot(n);  // centre height above the plate [m]
    if (gap < kRadius) {
      const double f_el = law.elastic_force(kRadius - gap, PairProperties{m.mass(kRadius), kRadius});
      p.dashpot = (-load.force.dot(n) - f_el) * plate->point_velocity(x - gap * n, t).dot(n);
    }
    return p;
  };
  // The engine's rule (contact_force.hpp "Moving boundaries"): the dashpot's share at the
  // evaluation time, the rest by the trapezoid rule.
  Power previous = power();  // P(0), from the start-up force evaluation
  for (long n = 0; n < steps; ++n) {
    engine.step();
    const Power now = power();
    b.work_from_loads += now.dashpot * dt + 0.5 * ((previous.total - previous.dashpot) + (now.total - now.dashpot)) * dt;
    previous = now;
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

/// Relative balance error (d(energy) + D - W) / W.
double relative_error(const Balance& b) { return (b.energy_change - b.work) / b.work; }

void expect_balanced(const Balance& b, const char* what, double tolerance) {
  std::printf("%s: W %.9e J, from loads %.9e J, d(energy) + D %.9e J (relative %.2e), m g dz %.9e J\n", what,
              b.work, b.work_from_loads, b.energy_change, relative_error(b), b.lift_work);
  ASSERT_GT(b.work, 0.0);
  // Same sum computed from the loads, the geometry and the Hertz law: differs only by the
  // round-off of the reaction sums and of the reconstructed overlap.
  EXPECT_NEAR(b.work_from_loads, b.work, 1e-12 * std::abs(b.work));
  EXPECT_NEAR(b.energy_change, b.work, tolerance * std::abs(b.work));
}

/// The balance error must shrink 4x when dt halves: second order (contact_force.hpp "Moving
/// boundaries"). A first-order error (the rectangle rule for d_s or W) gives a ratio of 2.
/// Bounds [3.5, 4.5]: measured 4.00 for both plates; the O(dt^3) terms of the error at these
/// dt are below 1% of it.
void expect_second_order(const Balance& coarse, const Balance& fine, const char* what) {
  const double ratio = relative_error(coarse) / relative_error(fine);
  std::printf("%s: error ratio dt / (dt/2) = %.3f\n", what, ratio);
  EXPECT_GT(ratio, 3.5);
  EXPECT_LT(ratio, 4.5);
}

TEST(PowerBalance, TranslatingPlateLiftingAndDraggingAParticle) {
  // The plate rises at 5 cm/s and slides at 2 cm/s: the particle (resting on it) is lifted,
  // bounces (e = 0.5), is dragged by friction until it rolls. 20 ms at dt = 1e-7 s.
  RigidMotion motion;
  motion.velocity = Vec3(0.02, 0, 0.05);
  const Particle p = sphere(1, Vec3(0, 0, kRadius - resting_overlap()), Vec3::Zero(), kRadius);
  const Balance b = run(motion, p, 1e-7, 200000);
  // The figure, 1e-6 (measured 7.8e-8 at dt = 1e-7 s, 3.1e-7 at 2e-7 s): Verlet
  // books the kinetic energy with the trapezoid rule, the contacts and the boundary work
  // consistently with it (docs/dem.md, contact_force.hpp), so the error is O(dt^2).
  expect_balanced(b, "translating plate", 1e-6);
  // Independent physics: the particle rode up with the plate by ~1 mm, so most of W is m g dz
  // plus the kinetic energy it carries (1/2 m v^2 + rolling, small) and the dissipation.
  EXPECT_GT(b.lift_work, 0.5 * b.work);
  expect_second_order(run(motion, p, 2e-7, 100000), b, "translating plate");
}

TEST(PowerBalance, RotatingPlateSpinningUpAParticleAtRest) {
  // Plate turning at 10 rad/s about z through the origin; the particle at r = 2 mm starts at
  // rest, slides until friction makes it roll with the plate: the plate's torque does work.
  RigidMotion motion;
  motion.angular_velocity = Vec3(0, 0, 10.0);
  const Particle p = sphere(1, Vec3(2e-3, 0, kRadius - resting_overlap()), Vec3::Zero(), kRadius);
  const Balance b = run(motion, p, 1e-7, 200000);
  // The figure, 1e-6 relative. Measured 6.3e-10 at dt = 1e-7 s (2.5e-9 at 2e-7 s).
  // Before the trapezoid surface displacement and boundary work (contact_force.hpp "Moving
  // boundaries") it was 3.6e-5 and first order: the contact point moves across the rotating
  // plate, so v_s changes along it within a step. The bound is the issue's, not 3x the
  // measured value, because the order check below is the sharper guard against a relapse.
  expect_balanced(b, "rotating plate", 1e-6);
  expect_second_order(run(motion, p, 2e-7, 100000), b, "rotating plate");
}

TEST(PowerBalance, TiltingPlateLiftingAParticleOffItsAxis) {
  // Plate turning at 10 rad/s about the x axis (a seesaw): under the particle at y = 2 mm its
  // surface rises at ~2 cm/s, so v_s has a normal component that changes along the contact
  // (the dashpot and the spring both do work), and the particle rolls down the growing slope
  // (0.2 rad after 20 ms, below the friction angle atan 0.5).
  RigidMotion motion;
  motion.angular_velocity = Vec3(10.0, 0, 0);
  const Particle p = sphere(1, Vec3(0, 2e-3, kRadius - resting_overlap()), Vec3::Zero(), kRadius);
  const Balance b = run(motion, p, 1e-7, 200000);
  expect_balanced(b, "tilting plate", 1e-6);  // the figure, as above
  EXPECT_GT(b.lift_work, 0.5 * b.work);       // mostly lifting: the particle rides up ~0.4 mm
  expect_second_order(run(motion, p, 2e-7, 100000), b, "tilting plate");
}

}  // namespace
}  // namespace ppohdem::dem::test
