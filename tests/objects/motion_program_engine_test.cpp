// Motion programs in the engine (issue 38, item 1):
//  - power balance across switches: the work W of a plate driven by a program of four
//    segments (translate, rotate, vibrate, translate + rotate) equals the change of the
//    particle's energy plus the dissipation, W = d(K + K_rot + U_g + U_el) + D, to the
//    integrator's order, and W equals the time integral of the plate's power computed
//    independently from its loads and the program's kinematics (as power_balance_test.cpp);
//  - contact histories carry through a switch: a particle held on a moving plate by static
//    friction under a sideways load does not notice a switch between two equal translations,
//    while dropping the histories at the switch does move it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "../dem/dem_test_support.hpp"
#include "object_fields.hpp"
#include "ppohdem/dem/distance_field_object.hpp"
#include "ppohdem/units.hpp"

namespace ppohdem::dem::test {
namespace {

using ppohdem::dem::reference::ReferenceEngine;

constexpr double kRadius = 0.5e-3;  // m
constexpr double kG = 9.81;         // m/s^2

/// Static Hertz overlap under gravity: m g = K delta^(3/2), K = (4/3) E* sqrt(R).
double resting_overlap(const Material& m) {
  const double k = 4.0 / 3.0 * m.effective_young() * std::sqrt(kRadius);
  return std::pow(m.mass(kRadius) * kG / k, 2.0 / 3.0);
}

/// The plate z < 0 of power_balance_test.cpp (phi = z: exact under trilinear interpolation).
std::shared_ptr<DistanceFieldObject> plate(MotionProgram program) {
  const GridSpec grid{Vec3(-14e-3, -14e-3, -1e-3), Vec3::Constant(0.5e-3), {57, 57, 9}};
  return std::make_shared<DistanceFieldObject>(half_space_field(grid, Vec3::Zero(), Vec3::UnitZ()),
                                               std::move(program), "plate");
}

/// Switches at 5, 10 and 15 ms; every segment moves the contact point (and the vibration lifts
/// the plate at up to 2 g, so the particle hops).
MotionProgram four_segment_program() {
  std::vector<MotionSegment> s(4);
  s[0].start = 0.0;
  s[0].translation = {MotionProfile::linear, Vec3(0.02, 0, 0.05)};  // rise and slide [m/s]
  s[1].start = 5e-3;
  s[1].rotation = {MotionProfile::linear, Vec3(0, 0, 10.0)};  // turn about z [rad/s] ...
  s[1].point = Vec3(2e-3, 0, 0);                              // ... 2 mm from the particle
  s[2].start = 10e-3;
  s[2].translation = {MotionProfile::sine, Vec3(0, 1e-4, 5e-5), 2 * units::kPi * 100.0, 0.3};  // 100 Hz
  s[3].start = 15e-3;
  s[3].translation = {MotionProfile::linear, Vec3(0.01, 0, 0)};
  s[3].rotation = {MotionProfile::linear, Vec3(0, 0, -5.0)};
  return MotionProgram(s, Vec3::Zero());
}

struct Balance {
  double work = 0.0;             // boundary_work [J]
  double work_from_loads = 0.0;  // the plate's power from its loads, integrated [J]
  double energy_change = 0.0;    // d(K + K_rot + U_grav + U_el) + D [J]
};

double relative_error(const Balance& b) { return (b.energy_change - b.work) / b.work; }

Balance run_program(double dt, long steps) {
  const Material m = peer_material(0.5, 0.5);  // e = 0.5, mu = 0.5: dashpots and slip dissipate
  const HertzMindlin law = HertzMindlin::from_material(m);
  SimulationSetup s;
  s.dt = dt;
  s.gravity = Vec3(0, 0, -kG);
  s.material = m;
  s.law = law;
  s.particles = {sphere(1, Vec3(0, 0, kRadius - resting_overlap(m)), Vec3::Zero(), kRadius)};
  const auto object = plate(four_segment_program());
  const MotionProgram& program = object->program();
  s.boundaries = {object};
  ReferenceEngine engine(s);
  const Energies e0 = engine.energies();
  // The plate's power on the particle from its loads (F on the plate, M_0 about the origin):
  // the material velocity field is u(x) = u(0) + Omega x x, so P = -(F . u(0) + M_0 . Omega);
  // and its dashpot share, from the geometry and the Hertz law: F_d = -F . n - F_el(delta),
  // power F_d (u(p) . n) at the foot p of the centre (power_balance_test.cpp).
  struct Power {
    double total = 0.0;
    double dashpot = 0.0;
  };
  const auto power = [&] {
    const double t = engine.time();
    const BoundaryLoad load = engine.boundary_loads().at(0);
    Power p;
    p.total = -(load.force.dot(program.point_velocity(Vec3::Zero(), t)) +
                load.moment_about_origin.dot(program.angular_velocity_at(t)));
    const RigidTransform pose = program.pose_at(t);
    const Vec3 n = pose.rotate(Vec3::UnitZ());
    const Vec3 x = engine.particles()[0].position;
    const double gap = (x - pose.apply(Vec3::Zero())).dot(n);
    if (gap < kRadius) {
      const double f_el = law.elastic_force(kRadius - gap, PairProperties{m.mass(kRadius), kRadius});
      p.dashpot = (-load.force.dot(n) - f_el) * program.point_velocity(x - gap * n, t).dot(n);
    }
    return p;
  };
  Power previous = power();
  Balance b;
  for (long n = 0; n < steps; ++n) {
    engine.step();
    const Power now = power();
    b.work_from_loads += now.dashpot * dt + 0.5 * ((previous.total - previous.dashpot) + (now.total - now.dashpot)) * dt;
    previous = now;
  }
  EXPECT_EQ(object->outside_grid_count(), 0u);
  const Energies e1 = engine.energies();
  b.work = e1.boundary_work - e0.boundary_work;
  b.energy_change = (e1.kinetic - e0.kinetic) + (e1.rotational - e0.rotational) + (e1.gravitational - e0.gravitational) +
                    (e1.elastic - e0.elastic) + (e1.dissipated - e0.dissipated);
  return b;
}

TEST(MotionProgramEngine, PowerBalanceHoldsAcrossSwitches) {
  // 20 ms through three switches at dt = 1e-7 s, the bound 1e-6 relative (the single
  // motions of power_balance_test.cpp measure 6e-10..8e-8 there); and the order check: the
  // error must shrink ~4x when dt halves, as for single motions. A switch makes the surface
  // velocity jump under a loaded contact; the engine's rule (contact_force.hpp "Moving
  // boundaries") leaves an O(dt^2) term per switch, so the order stays two.
  const Balance fine = run_program(1e-7, 200000);
  const Balance coarse = run_program(2e-7, 100000);
  for (const auto& [b, what] : {std::pair(fine, "dt = 1e-7 s"), std::pair(coarse, "dt = 2e-7 s")}) {
    std::printf("%s: W %.9e J, from loads %.9e J, d(energy) + D %.9e J (relative %.2e)\n", what, b.work,
                b.work_from_loads, b.energy_change, relative_error(b));
  }
  ASSERT_GT(fine.work, 0.0);
  // The loads' integral: the same contact forces summed and dotted another way; round-off of
  // the reaction sums and of the reconstructed overlap, as power_balance_test.cpp: 1e-12.
  EXPECT_NEAR(fine.work_from_loads, fine.work, 1e-12 * std::abs(fine.work));
  EXPECT_NEAR(fine.energy_change, fine.work, 1e-6 * std::abs(fine.work));
  const double ratio = relative_error(coarse) / relative_error(fine);
  std::printf("error ratio dt / (dt/2) = %.3f\n", ratio);
  EXPECT_GT(ratio, 3.5);  // 2 for a first-order relapse
  EXPECT_LT(ratio, 4.5);
}

/// A particle resting on a plate sliding at 2 cm/s, pushed sideways by a tilted gravity
/// (g_x = 2 m/s^2 < mu g_z: static friction holds it, its spring stretched by m g_x / k_t).
/// `switch_time` > 0: the same translation as two segments, switching then; `drop_histories`:
/// the histories are removed at the switch (the control).
Vec3 held_particle_position(double switch_time, bool drop_histories) {
  const Material m = peer_material(0.5, 0.5);
  SimulationSetup s;
  s.dt = 1e-7;
  s.gravity = Vec3(2.0, 0, -kG);
  s.material = m;
  s.law = HertzMindlin::from_material(m);
  s.particles = {sphere(1, Vec3(0, 0, kRadius - resting_overlap(m)), Vec3(0.02, 0, 0), kRadius)};
  std::vector<MotionSegment> segments(switch_time > 0 ? 2 : 1);
  for (std::size_t k = 0; k < segments.size(); ++k) {
    segments[k].start = k == 0 ? 0.0 : switch_time;
    segments[k].translation = {MotionProfile::linear, Vec3(0.02, 0, 0)};
  }
  s.boundaries = {plate(MotionProgram(segments, Vec3::Zero()))};
  ReferenceEngine engine(s);
  constexpr long kSwitchStep = 20000, kSteps = 40000;  // the switch at 2 ms of 4 ms
  engine.advance(kSwitchStep);
  if (drop_histories) {
    EngineState state = engine.save_state();
    EXPECT_EQ(state.contacts.size(), 1u);  // the particle-plate contact
    state.contacts.clear();
    engine.restore_state(state);
  }
  engine.advance(kSteps - kSwitchStep);
  return engine.particles()[0].position;
}

TEST(MotionProgramEngine, ContactHistoriesCarryThroughASwitch) {
  const Vec3 single = held_particle_position(0.0, false);
  const Vec3 switched = held_particle_position(2e-3, false);
  const Vec3 dropped = held_particle_position(2e-3, true);
  std::printf("switch moved the particle by %.3e m; dropping the histories by %.3e m\n", (switched - single).norm(),
              (dropped - single).norm());
  // The second segment's pose is P_1 composed with v s: the plate's position differs from v t by
  // round-off (~1e-19 m at 1e-4 m); bound 1e-13 m. Dropping the stretched spring lets the
  // particle slip by ~m g_x / k_t before it sticks again (measured in the line above).
  EXPECT_LT((switched - single).norm(), 1e-13);
  EXPECT_GT((dropped - single).norm(), 1e3 * 1e-13);
}

}  // namespace
}  // namespace ppohdem::dem::test
