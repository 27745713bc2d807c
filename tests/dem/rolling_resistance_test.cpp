// Rolling resistance (core/include/ppohdem/dem/rolling_resistance.hpp, docs/dem.md "Rolling
// resistance"): analytic oracles run on every engine, the engines' bitwise agreement and
// checkpoint continuity with rolling springs, and the energy property of the contact rule.
//
// The oracles, for a sphere (mass m, radius R, I = (2/5) m R^2) on a plane, rolling without
// slip with lever arm rho = R - delta (the contact point sits in the middle of the overlap's
// foot, delta = the resting overlap), normal force F_n = m g cos(theta) on a slope theta:
//   along the slope   m dv/dt = m g sin(theta) - F_t
//   spin              I dw/dt = rho F_t - M,   M = mu_r R F_n (mobilised), v = w rho
//   =>  a = m g (rho sin(theta) - mu_r R cos(theta)) / (I / rho + m rho)
// which is -(5/7) mu_r g on the level (theta = 0, rho = R): Ai, Chen, Rotter & Ooi 2011,
// Powder Technol. 206:269, sec. 3.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <cstring>

#include "dem_test_support.hpp"
#include "ppohdem/dem/checkpoint.hpp"
#include "ppohdem/dem/contact_force.hpp"
#include "../reliability/reliability_scenes.hpp"

namespace ppohdem::dem::test {
namespace {

constexpr double kR = 5.0e-3;   // m
constexpr double kG = 9.81;     // m/s^2
constexpr double kDt = 5.0e-5;  // s: 58 % of 0.2 T_R = 8.65e-5 s for R = 5 mm

Material rolling_material(double mu_r) {
  Material m = peer_material(0.5, 0.5);  // E = 1e7 Pa, nu = 0.3, 2500 kg/m^3, e = 0.5, mu = 0.5
  m.rolling_friction = mu_r;
  return m;
}

/// Resting overlap on a plane under the normal load F_n: F_n = K delta^{3/2} (the wall has the
/// particle's material, so K = (4/3) E* sqrt(R) with E* = E / (2 (1 - nu^2))).
double resting_overlap(const Material& m, double f_n) {
  const double k = 4.0 / 3.0 * m.effective_young() * std::sqrt(kR);
  return std::pow(f_n / k, 2.0 / 3.0);
}

/// Acceleration down the slope (negative: decelerating) of the header's formula.
double rolling_acceleration(const Material& m, double theta, double delta) {
  const double mass = m.mass(kR);
  const double inertia = m.moment_of_inertia(kR);
  const double rho = kR - delta;
  return mass * kG * (rho * std::sin(theta) - m.rolling_friction * kR * std::cos(theta)) / (inertia / rho + mass * rho);
}

/// A sphere resting on a plane through the origin whose normal n = (sin theta, 0, cos theta) is
/// tilted so that the slope descends along +x, rolling down-slope at speed v0 without slip
/// (v + w x (-rho n) = 0, so w = n x v / rho).
SimulationSetup sphere_on_slope(RollingModel model, double mu_r, double theta, double v0) {
  SimulationSetup s;
  s.dt = kDt;
  s.gravity = Vec3(0, 0, -kG);
  s.material = rolling_material(mu_r);
  s.law = HertzMindlin::from_material(s.material);
  s.rolling = model;
  const Vec3 normal(std::sin(theta), 0.0, std::cos(theta));
  const Vec3 downhill(std::cos(theta), 0.0, -std::sin(theta));
  const double delta = resting_overlap(s.material, s.material.mass(kR) * kG * std::cos(theta));
  Particle p = sphere(1, (kR - delta) * normal, v0 * downhill, kR);
  p.angular_velocity = normal.cross(downhill) * (v0 / (kR - delta));
  s.particles = {p};
  s.boundaries = {std::make_shared<PlaneWall>(Vec3::Zero(), normal)};
  return s;
}

/// Distance travelled down the slope [m].
double downhill_distance(const Particles& p, double theta) {
  return p[0].position.dot(Vec3(std::cos(theta), 0.0, -std::sin(theta)));
}

template <class Engine>
class RollingResistance : public ::testing::Test {};
TYPED_TEST_SUITE(RollingResistance, EngineTypes);

// CDT on the level: the sphere decelerates at (5/7) mu_r g (with the lever arm R - delta) and
// stops after v0^2 / (2 a). Tolerance 1e-3 relative: the tangential spring (no dashpot)
// oscillates with deflection m a / k_t = 2.5e-7 m, 1e-4 of the distances, and takes up the
// static friction within a quarter of its 2.8 ms period (a displacement of a t^2 ~ 2e-7 m).
TYPED_TEST(RollingResistance, CdtSphereRollingOnALevelPlaneStopsAsAnalytic) {
  const double mu_r = 0.05, v0 = 0.05;
  const SimulationSetup setup = sphere_on_slope(RollingModel::kCdt, mu_r, 0.0, v0);
  const double delta = resting_overlap(setup.material, setup.material.mass(kR) * kG);
  const double a = -rolling_acceleration(setup.material, 0.0, delta);
  EXPECT_NEAR(a, 5.0 / 7.0 * mu_r * kG, 5.0 / 7.0 * mu_r * kG * 2.0 * delta / kR);  // (5/7) mu_r g
  const double stop_time = v0 / a, stop_distance = v0 * v0 / (2.0 * a);
  TypeParam engine(setup);
  const long half = std::lround(0.5 * stop_time / kDt);
  engine.advance(half);
  const double t = engine.time();
  EXPECT_NEAR(downhill_distance(engine.particles(), 0.0), v0 * t - 0.5 * a * t * t, 1e-3 * stop_distance);
  EXPECT_NEAR(engine.particles()[0].velocity.x(), v0 - a * t, 2e-2 * v0);  // the spring's oscillation: 1 %
  engine.advance(std::lround(stop_time / kDt));  // to 1.5 stop times
  EXPECT_NEAR(downhill_distance(engine.particles(), 0.0), stop_distance, 1e-3 * stop_distance);
  EXPECT_LT(std::abs(engine.particles()[0].velocity.x()), 2e-2 * v0);
  // Control: without rolling resistance the sphere rolls on (it would have gone 1.5 v0 t_s).
  SimulationSetup free = sphere_on_slope(RollingModel::kNone, 0.0, 0.0, v0);
  TypeParam rolling_on(free);
  rolling_on.advance(3 * half);
  EXPECT_GT(downhill_distance(rolling_on.particles(), 0.0), 1.4 * v0 * stop_time);
}

// EPSD2 at rest (Ai et al. 2011, sec. 4: the spring holds a particle at rest, which CDT's
// torque of fixed size cannot): on a slope with tan(theta) = mu_r / 2 the sphere, released at
// rest, stays where it is up to the elastic deflections of its springs. Static deflection of
// the centre: the tangential spring's F_t / k_t plus the rolling spring's rho M / k_r with
// M = rho F_t, k_r = k_t R^2, i.e. about 2 F_t / k_t; released from rest without damping
// along the slope the motion overshoots to twice that, so the bound is 5 F_t / k_t.
TYPED_TEST(RollingResistance, Epsd2HoldsASphereAtRestOnASlopeBelowMuR) {
  const double mu_r = 0.2, theta = std::atan(0.5 * mu_r);
  const SimulationSetup setup = sphere_on_slope(RollingModel::kEpsd2, mu_r, theta, 0.0);
  const Material& m = setup.material;
  const double f_n = m.mass(kR) * kG * std::cos(theta), f_t = m.mass(kR) * kG * std::sin(theta);
  const double k_t = 8.0 * m.effective_shear() * std::sqrt(kR * resting_overlap(m, f_n));
  const double start = downhill_distance(setup.particles, theta);
  TypeParam engine(setup);
  double farthest = 0.0;
  for (int k = 0; k < 100; ++k) {  // 0.5 s
    engine.advance(100);
    farthest = std::max(farthest, std::abs(downhill_distance(engine.particles(), theta) - start));
  }
  EXPECT_LT(farthest, 5.0 * f_t / k_t) << "free rolling would have gone " << 0.5 * (5.0 / 7.0) * kG * std::sin(theta) * 0.25 << " m";
  EXPECT_GT(farthest, 0.0);  // the springs do deflect
}

// Above the threshold (tan(theta) = 2 mu_r) both models mobilise M = mu_r R F_n and the sphere,
// rolling down at v0 from the start (so that w > 0 throughout: CDT's torque is constant and the
// motion linear, and EPSD2's spring is mobilised within one step), follows the header's
// acceleration; without rolling resistance it rolls at (5/7) g sin(theta) (control).
// Tolerance 1e-3 relative, as on the level.
TYPED_TEST(RollingResistance, BothModelsRollDownASlopeAboveMuRAsAnalytic) {
  for (const RollingModel model : {RollingModel::kNone, RollingModel::kCdt, RollingModel::kEpsd2}) {
    const double mu_r = model == RollingModel::kNone ? 0.0 : 0.05, theta = std::atan(0.1);
    const double v0 = 0.05;  // m/s
    const SimulationSetup setup = sphere_on_slope(model, mu_r, theta, v0);
    const double delta = resting_overlap(setup.material, setup.material.mass(kR) * kG * std::cos(theta));
    const double a = rolling_acceleration(setup.material, theta, delta);
    const double start = downhill_distance(setup.particles, theta);
    TypeParam engine(setup);
    engine.advance(4000);  // 0.2 s
    const double t = engine.time();
    const double expected = v0 * t + 0.5 * a * t * t;
    EXPECT_NEAR(downhill_distance(engine.particles(), theta) - start, expected, 1e-3 * expected)
        << (model == RollingModel::kCdt ? "cdt" : model == RollingModel::kEpsd2 ? "epsd2" : "none");
  }
}

// ---- both engines, bit for bit; checkpoints --------------------------------------------

bool same_bits(const Vec3& a, const Vec3& b) { return std::memcmp(a.data(), b.data(), sizeof(double) * 3) == 0; }
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// The reliability pile (walls, a moving wall, a spinning ball object) with rolling resistance.
SimulationSetup rolling_pile(RollingModel model) {
  SimulationSetup s = pile_setup();
  s.material.rolling_friction = 0.1;
  s.rolling = model;
  return s;
}

void expect_same_particles(const DemEngine& a, const DemEngine& b) {
  ASSERT_EQ(a.particles().size(), b.particles().size());
  for (std::size_t k = 0; k < a.particles().size(); ++k) {
    const Particle& p = a.particles()[k];
    const Particle& q = b.particles()[k];
    ASSERT_EQ(p.id, q.id);
    EXPECT_TRUE(same_bits(p.position, q.position) && same_bits(p.velocity, q.velocity) &&
                same_bits(p.angular_velocity, q.angular_velocity))
        << "particle " << p.id;
  }
}

/// Energies and loads of two engines: the same terms summed in another order (per particle
/// instead of per pair), so equal to round-off: bounds as in dem_fast's
/// FastEqualsReference (~n eps of the scale per evaluation, 400 evaluations).
void expect_same_sums(const DemEngine& a, const DemEngine& b) {
  const Energies ea = a.energies(), eb = b.energies();
  const double scale = ea.kinetic + ea.rotational + ea.elastic + ea.dissipated;
  EXPECT_NEAR(ea.elastic, eb.elastic, 1e-12 * scale);
  EXPECT_NEAR(ea.dissipated, eb.dissipated, 1e-10 * scale);
  EXPECT_NEAR(ea.boundary_work, eb.boundary_work, 1e-10 * scale);
  for (std::size_t w = 0; w < a.boundary_loads().size(); ++w) {
    const Vec3 d = a.boundary_loads()[w].moment_about_origin - b.boundary_loads()[w].moment_about_origin;
    EXPECT_LE(d.norm(), 1e-12 * (a.boundary_loads()[w].moment_about_origin.norm() + 1e-12)) << w;
  }
}

/// The same engine after the same steps: every sum in the same order, so the same bits.
void expect_same_energies(const DemEngine& a, const DemEngine& b) {
  const Energies ea = a.energies(), eb = b.energies();
  EXPECT_TRUE(same_bits(ea.elastic, eb.elastic) && same_bits(ea.dissipated, eb.dissipated) &&
              same_bits(ea.boundary_work, eb.boundary_work));
}

TEST(RollingResistanceEngines, FastEqualsReferenceBitwise) {
  for (const RollingModel model : {RollingModel::kCdt, RollingModel::kEpsd2}) {
    const SimulationSetup setup = rolling_pile(model);
    ppohdem::dem::reference::ReferenceEngine reference(setup);
    ppohdem::dem::fast::FastEngine fast(setup);
    reference.advance(400);
    fast.advance(400);
    expect_same_particles(reference, fast);
    expect_same_sums(reference, fast);
    EXPECT_GT(reference.contact_counts().particle_pairs, 5u);
    // Control: the rolling torque changes the trajectories.
    ppohdem::dem::reference::ReferenceEngine none(pile_setup());
    none.advance(400);
    EXPECT_FALSE(same_bits(none.particles()[0].angular_velocity, reference.particles()[0].angular_velocity));
  }
}

template <class Engine>
class RollingCheckpoint : public ::testing::Test {};
TYPED_TEST_SUITE(RollingCheckpoint, EngineTypes);

// The EPSD2 spring is part of the history: two halves through a checkpoint file equal one
// whole run bitwise, and dropping the rolling springs changes the result.
TYPED_TEST(RollingCheckpoint, TwoHalvesEqualOneWholeBitwise) {
  const SimulationSetup setup = rolling_pile(RollingModel::kEpsd2);
  TypeParam whole(setup);
  whole.advance(400);
  TypeParam first(setup);
  first.advance(200);
  Checkpoint c;
  c.engine = first.save_state();
  std::size_t rolling_springs = 0;
  for (const ContactHistoryRecord& r : c.engine.contacts) rolling_springs += r.spring.rolling.torque != Vec3::Zero();
  EXPECT_GE(rolling_springs, 5u);
  const EngineState saved = decode_checkpoint(encode_checkpoint(c), "memory").engine;
  TypeParam second(setup);
  second.restore_state(saved);
  second.advance(200);
  expect_same_particles(whole, second);
  expect_same_energies(whole, second);
  EngineState dropped = saved;
  for (ContactHistoryRecord& r : dropped.contacts) r.spring.rolling = RollingSpring{};
  TypeParam third(setup);
  third.restore_state(dropped);
  third.advance(200);
  bool any_differs = false;
  for (std::size_t k = 0; k < whole.particles().size(); ++k) {
    any_differs = any_differs || !same_bits(whole.particles()[k].angular_velocity, third.particles()[k].angular_velocity);
  }
  EXPECT_TRUE(any_differs);
}

// ---- the contact rule never adds energy -------------------------------------------------

// With a fixed contact plane, constant stiffness (linear law) and a normal force that does not
// drop (the limit mu_r R F_n never falls below the torque already held), each step's rolling
// dissipation is >= 0 for any rotation: D = k (1 - c) (th . t + c |t|^2) / 2 with c |t| >= |th|
// (th = S/k before, t the trial, c the slip factor). When F_n drops faster than the spring can
// follow while the bodies roll back, the trapezoid work of that step can exceed the stored
// energy (the integrator applied the old torque over the step), as for the tangential spring
// (contact_force.hpp): a remainder of order |S| |dth|, not a property of the model.
// CDT dissipates mu_r R |F_n| |w_t| dt.
RC_GTEST_PROP(RollingResistanceRule, NeverAddsEnergy, ()) {
  const Vec3 n = Vec3(*rc::gen::inRange(-100, 101), *rc::gen::inRange(-100, 101), 100.0).normalized();
  for (const RollingModel model : {RollingModel::kCdt, RollingModel::kEpsd2}) {
    const RollingParameters p{model, *rc::gen::inRange(1, 100) * 1e-2};
    const double r_eff = 1e-3, k_t = 1e3, dt = 1e-5;
    RollingSpring spring;
    double work = 0.0, dissipated = 0.0, scale = 0.0, f_n = 0.0;  // [J], [N]
    Vec3 previous = Vec3::Zero();
    for (int step = 0; step < 40; ++step) {
      f_n += *rc::gen::inRange(0, 100) * 1e-3;  // N, loading (see above)
      const Vec3 spin(*rc::gen::inRange(-100, 101), *rc::gen::inRange(-100, 101), *rc::gen::inRange(-100, 101));
      const Vec3 rotation = spin * dt;
      const double stored_before = spring.stored_energy();
      const RollingTorque m = rolling_torque(p, r_eff, f_n, k_t, n, spin, rotation, spring, dt);
      // >= 0 to the round-off of the step's energies (1e-12 of them; the terms cancel).
      const double step_scale = stored_before + m.elastic + std::abs(0.5 * (previous + m.on_i).dot(rotation)) +
                                std::abs(m.dissipated);
      RC_ASSERT(m.dissipated >= -1e-12 * step_scale);
      dissipated += m.dissipated;
      scale += std::abs(m.dissipated) + std::abs(m.elastic);
      work += -0.5 * (previous + m.on_i).dot(rotation);  // the torques' work on the contact
      previous = m.on_i;
    }
    RC_ASSERT(dissipated >= -1e-12 * scale);  // each step's round-off, as above
    // What the bodies put in is stored or dissipated, never more: E_r <= W.
    RC_ASSERT(spring.stored_energy() <= work + 1e-12 * std::abs(work) + 1e-300);
  }
}

}  // namespace
}  // namespace ppohdem::dem::test
