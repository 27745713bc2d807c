// Contact-law options users port from LIGGGHTS (issue 38, item 3; contact_law.hpp,
// contact_force.hpp, pair_laws.hpp): the hooke law (k_n per contact), the linear law with
// several materials and the tangential dashpot, each against an analytic two-body answer or an
// independent integration of the two-body equations, typed over both engines; the engines
// agree bit for bit; the energy balance closes with the dashpot.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "dem_test_support.hpp"
#include "ppohdem/dem/contact_force.hpp"
#include "ppohdem/dem/pair_laws.hpp"
#include "ppohdem/dem/particle_generator.hpp"
#include "ppohdem/dem/scene.hpp"
#include "ppohdem/error.hpp"
#include "ppohdem/units.hpp"

namespace ppohdem::dem::test {
namespace {

// Random vectors drawn in a fixed order: the order in which a call's arguments are evaluated is
// unspecified (GCC takes the last first, Clang the first), so Vec3(u(rng), u(rng), u(rng))
// gave the two compilers different scenes. These draw as GCC did, keeping the scenes.
template <class D, class R>
Vec3 draw3(D& u, R& rng) {
  const double z = u(rng);
  const double y = u(rng);
  const double x = u(rng);
  return Vec3(x, y, z);
}
template <class D, class R>
Vec3 draw2(D& u, R& rng, double z) {
  const double y = u(rng);
  const double x = u(rng);
  return Vec3(x, y, z);
}

template <class Engine>
class ContactOptions : public ::testing::Test {};
TYPED_TEST_SUITE(ContactOptions, EngineTypes);

constexpr double kRadius = 0.5e-3;  // m
constexpr double kSpeed = 0.1;      // m/s
constexpr double kPi = units::kPi;

/// The peer material's numbers worked out by hand (python, double precision) for the
/// LIGGGHTS formula k_n = (16/15) sqrt(R*) E* (15 m* v_c^2 / (16 sqrt(R*) E*))^{1/5} with
/// rho = 2500 kg/m^3, E = 1e7 Pa, nu = 0.3, R = 0.5 mm, v_c = 0.1 m/s:
///   m = rho (4/3) pi R^3 = 1.3089969389957471e-06 kg, E* = E / (2 (1 - nu^2)) = 5494505.4945 Pa
///   pair (m* = m/2, R* = R/2):   k_n = 217.13188318879304 N/m
///   wall (m* = m,   R* = R):     k_n = 329.11039246685425 N/m  (2^{3/5} = 1.5157 times)
constexpr double kHookePair = 217.13188318879304;  // N/m
constexpr double kHookeWall = 329.11039246685425;  // N/m

/// gamma_n = 2 sqrt(m* k) (-ln e) / sqrt(pi^2 + ln^2 e) [kg/s] (Schwager & Poeschel 2005).
double gamma_for(double m_eff, double k, double e) {
  const double l = std::log(e);
  return 2.0 * std::sqrt(m_eff * k) * (-l) / std::sqrt(kPi * kPi + l * l);
}
/// Duration pi / omega_d of the damped linear oscillator [s].
double linear_duration(double m_eff, double k, double e) {
  const double g = gamma_for(m_eff, k, e) / (2.0 * m_eff);
  return kPi / std::sqrt(k / m_eff - g * g);
}

LinearSpringDashpot hooke_of(const Material& m, double v_c = kSpeed) {
  return LinearSpringDashpot::hooke(m.effective_young(), v_c, m.restitution, m.friction);
}

TEST(HookeLaw, StiffnessIsLiggghtsFormulaWorkedOutByHand) {
  const Material m = peer_material(0.5, 0.3);
  const auto law = hooke_of(m);
  const double mass = m.mass(kRadius);
  const PairProperties pair{mass / 2.0, kRadius / 2.0}, wall{mass, kRadius};
  // 1e-14: the same formula in another association order (a few ulps).
  EXPECT_NEAR(law.stiffness(pair) / kHookePair, 1.0, 1e-14);
  EXPECT_NEAR(law.stiffness(wall) / kHookeWall, 1.0, 1e-14);
  EXPECT_NEAR(law.stiffness(wall) / law.stiffness(pair), std::pow(2.0, 0.6), 1e-14);
  // The equivalent power form (16/15)^{4/5} E*^{4/5} R*^{2/5} m*^{1/5} v_c^{2/5}.
  const double power_form = std::pow(16.0 / 15.0, 0.8) * std::pow(m.effective_young(), 0.8) *
                            std::pow(kRadius / 2.0, 0.4) * std::pow(mass / 2.0, 0.2) * std::pow(kSpeed, 0.4);
  EXPECT_NEAR(law.stiffness(pair) / power_form, 1.0, 1e-14);
  EXPECT_EQ(law.tangential_stiffness(1e-6, pair), law.stiffness(pair));  // LIGGGHTS: k_t = k_n
  EXPECT_NEAR(law.damping_coefficient(pair) / gamma_for(mass / 2.0, kHookePair, 0.5), 1.0, 1e-14);
  EXPECT_EQ(law.tangential_damping_coefficient(1e-6, pair), law.damping_coefficient(pair));
  // The linear spring of k_n stores the Hertz energy at the Hertz overlap of a v_c impact.
  const double delta = std::pow(15.0 * (mass / 2.0) * kSpeed * kSpeed /
                                    (16.0 * m.effective_young() * std::sqrt(kRadius / 2.0)), 0.4);
  EXPECT_NEAR(law.elastic_energy(delta, pair) / (0.5 * (mass / 2.0) * kSpeed * kSpeed), 1.0, 1e-13);
}

/// Runs a head-on contact, recording the deepest overlap as well.
template <class Engine>
ImpactMeasurement impact_with_depth(Engine& engine, double& deepest, bool wall) {
  deepest = 0.0;
  auto gap = [&](const Particles& p) {
    const double g = wall ? p[0].position.z() - p[0].radius : pair_gap(p);
    deepest = std::max(deepest, -g);
    return g;
  };
  auto speed = [&](const Particles& p) { return wall ? p[0].velocity.z() : pair_separation_speed(p); };
  return measure_impact(engine, gap, speed, 400000);
}

TYPED_TEST(ContactOptions, HookeHeadOnMatchesDampedOscillatorAndHertzOverlap) {
  const double mass = peer_material(1.0, 0.0).mass(kRadius);
  for (const double e : {1.0, 0.5}) {
    const Material m = peer_material(e, 0.0);
    const double t_c = linear_duration(mass / 2.0, kHookePair, e);
    TypeParam engine(head_on_setup(hooke_of(m), m, kRadius, kSpeed, t_c / 2000.0));
    double deepest = 0.0;
    const auto r = impact_with_depth(engine, deepest, false);
    // 1e-3: the linear law's error budget at 2000 steps per contact (impact_test.cpp).
    EXPECT_NEAR(r.rebound_velocity / kSpeed, e, 1e-3 * e) << "e = " << e;
    EXPECT_NEAR(r.duration / t_c, 1.0, 1e-3) << "e = " << e;
    if (e == 1.0) {
      // Elastic at v = v_c: the Hertz maximum overlap (15 m* v^2 / (16 E* sqrt(R*)))^{2/5}
      // = 5.49025502550162e-06 m (worked out by hand); sampling the peak every step errs by
      // ~(pi/2000)^2/2 ~ 1e-6 relative.
      EXPECT_NEAR(deepest / 5.49025502550162e-06, 1.0, 1e-5);
    }
  }
}

/// A sphere of material m dropping onto the wall z = 0 (no gravity) with velocity v.
SimulationSetup sphere_on_wall(const ContactLaw& law, const Material& m, const Vec3& v, double dt) {
  SimulationSetup s;
  s.dt = dt;
  s.material = m;
  s.law = law;
  s.particles = {sphere(1, Vec3(0, 0, 1.02 * kRadius), v, kRadius)};
  s.boundaries = {std::make_shared<PlaneWall>(Vec3::Zero(), Vec3::UnitZ())};
  return s;
}

TYPED_TEST(ContactOptions, HookeAgainstWallUsesRAndMOfTheSphere) {
  // LIGGGHTS' wall contact: R* = R, m* = m, so k_n is 2^{3/5} times the pair's: the
  // duration is that of kHookeWall with m* = m.
  const Material m = peer_material(0.7, 0.0);
  const double mass = m.mass(kRadius);
  const double t_c = linear_duration(mass, kHookeWall, 0.7);
  TypeParam engine(sphere_on_wall(hooke_of(m), m, Vec3(0, 0, -kSpeed), t_c / 2000.0));
  double deepest = 0.0;
  const auto r = impact_with_depth(engine, deepest, true);
  EXPECT_NEAR(r.duration / t_c, 1.0, 1e-3);  // the pair stiffness would give 1.23
  EXPECT_NEAR(r.rebound_velocity / kSpeed, 0.7, 0.7e-3);
}

TYPED_TEST(ContactOptions, LinearTwoMaterialsUseOneStiffnessAndThePairRestitution) {
  // Material 0 (e = 0.9, 2500 kg/m^3) meets material 1 (e = 0.6, 7800 kg/m^3): one k_n, the
  // pair's e by the mixing rule min(0.9, 0.6) or, when given, the [[material_pair]] value.
  const double k_n = 500.0;  // N/m
  const Material a = peer_material(0.9, 0.0);
  Material b = peer_material(0.6, 0.0);
  b.density = 7800.0;
  const double m_eff = a.mass(kRadius) * b.mass(kRadius) / (a.mass(kRadius) + b.mass(kRadius));
  for (const double explicit_e : {0.0, 0.75}) {
    const double e = explicit_e > 0.0 ? explicit_e : 0.6;
    const double t_c = linear_duration(m_eff, k_n, e);
    SimulationSetup s = head_on_setup(LinearSpringDashpot::from_stiffness(k_n, a.restitution, 0.0), a, kRadius,
                                      kSpeed, t_c / 2000.0);
    s.more_materials = {b};
    s.particles[1].material = 1;
    if (explicit_e > 0.0) s.material_pairs = {{0, 1, explicit_e, std::nullopt}};
    TypeParam engine(s);
    const auto r = measure_impact(engine, pair_gap, pair_separation_speed, 400000);
    EXPECT_NEAR(r.rebound_velocity / kSpeed, e, 1e-3 * e) << "explicit " << explicit_e;
    EXPECT_NEAR(r.duration / t_c, 1.0, 1e-3) << "explicit " << explicit_e;
  }
}

TYPED_TEST(ContactOptions, HookeTwoMaterialsCombineEStar) {
  // E*_ab = 1 / ((1 - nu_a^2)/E_a + (1 - nu_b^2)/E_b) enters hooke's k_n (as LIGGGHTS' Yeff):
  // E_a = 1e7, nu_a = 0.3, E_b = 4e7, nu_b = 0.25: E* = 1/(0.91e-7 + 0.9375/4e7)
  // = 8.7384e6 Pa (by hand); k_n from the formula with it.
  const Material a = peer_material(0.8, 0.0);
  Material b = peer_material(0.8, 0.0);
  b.young = 4.0e7;
  b.poisson = 0.25;
  const double e_star = 1.0 / (0.91 / 1.0e7 + 0.9375 / 4.0e7);
  const double m_eff = a.mass(kRadius) / 2.0, r_eff = kRadius / 2.0;
  const double k = 16.0 / 15.0 * std::sqrt(r_eff) * e_star *
                   std::pow(15.0 * m_eff * kSpeed * kSpeed / (16.0 * std::sqrt(r_eff) * e_star), 0.2);
  const double t_c = linear_duration(m_eff, k, 0.8);
  SimulationSetup s = head_on_setup(hooke_of(a), a, kRadius, kSpeed, t_c / 2000.0);
  s.more_materials = {b};
  s.particles[1].material = 1;
  TypeParam engine(s);
  const auto r = measure_impact(engine, pair_gap, pair_separation_speed, 400000);
  EXPECT_NEAR(r.duration / t_c, 1.0, 1e-3);  // E* of material a alone: 20 % longer
  EXPECT_NEAR(r.rebound_velocity / kSpeed, 0.8, 0.8e-3);
}

/// Rebound of a sphere after an oblique impact on the wall z = 0: tangential velocity and
/// spin about y [m/s], [rad/s].
struct Rebound {
  double vx = 0.0, vz = 0.0, wy = 0.0;
};

/// The two-body problem (sphere on a fixed plane, motion in the x-z plane) integrated directly
/// with RK4 at a step far below the engine's, written from the model's definition
/// (contact_law.hpp, contact_force.hpp):
///   delta = R - z, F_n = f_n(delta, -v_z) (the law's normal force; 0 out of contact)
///   u = v_x - w_y z (contact-point slip velocity; the lever arm is the centre height z)
///   xi' = u, F_t = -k_t(delta) xi - gamma_t(delta) u, |F_t| <= mu max(F_n, 0); when capped the
///   spring carries the capped force, xi = -F_t / k_t (applied after each step)
///   m v_x' = F_t, m v_z' = F_n, I w_y' = -z F_t,  I = (2/5) m R^2.
template <class Fn, class Kt, class Gt>
Rebound two_body_rebound(double mass, double mu, const Vec3& v0, Fn f_n, Kt k_t, Gt gamma_t, double h) {
  struct State {
    double z, vz, vx, wy, xi;
  };
  const double inertia = 0.4 * mass * kRadius * kRadius;
  auto forces = [&](const State& s, double& fn, double& ft) {
    const double delta = kRadius - s.z;
    if (delta <= 0.0) {
      fn = ft = 0.0;
      return;
    }
    fn = f_n(delta, -s.vz);
    const double u = s.vx - s.wy * s.z;
    ft = -k_t(delta) * s.xi - gamma_t(delta) * u;
    const double cap = mu * std::max(fn, 0.0);
    if (std::abs(ft) > cap) ft = std::copysign(cap, ft);
  };
  auto rate = [&](const State& s) {
    double fn, ft;
    forces(s, fn, ft);
    const bool touching = kRadius - s.z > 0.0;
    return State{s.vz, fn / mass, ft / mass, -s.z * ft / inertia, touching ? s.vx - s.wy * s.z : 0.0};
  };
  auto add = [](const State& a, const State& b, double f) {
    return State{a.z + f * b.z, a.vz + f * b.vz, a.vx + f * b.vx, a.wy + f * b.wy, a.xi + f * b.xi};
  };
  State s{kRadius, v0.z(), v0.x(), 0.0, 0.0};  // starts at first touch
  for (long step = 0; step < 100000000; ++step) {
    const State k1 = rate(s), k2 = rate(add(s, k1, h / 2)), k3 = rate(add(s, k2, h / 2)), k4 = rate(add(s, k3, h));
    s = State{s.z + h / 6 * (k1.z + 2 * k2.z + 2 * k3.z + k4.z), s.vz + h / 6 * (k1.vz + 2 * k2.vz + 2 * k3.vz + k4.vz),
              s.vx + h / 6 * (k1.vx + 2 * k2.vx + 2 * k3.vx + k4.vx), s.wy + h / 6 * (k1.wy + 2 * k2.wy + 2 * k3.wy + k4.wy),
              s.xi + h / 6 * (k1.xi + 2 * k2.xi + 2 * k3.xi + k4.xi)};
    const double delta = kRadius - s.z;
    if (delta <= 0.0) {
      if (s.vz > 0.0) return {s.vx, s.vz, s.wy};  // separated
      continue;
    }
    double fn, ft;
    forces(s, fn, ft);
    const double k = k_t(delta);
    const double trial = -k * s.xi - gamma_t(delta) * (s.vx - s.wy * s.z);
    if (std::abs(trial) > mu * std::max(fn, 0.0)) s.xi = k > 0.0 ? -ft / k : 0.0;  // slip
  }
  ADD_FAILURE() << "the two-body contact did not end";
  return {};
}

template <class Engine>
Rebound engine_rebound(const SimulationSetup& s) {
  Engine engine(s);
  auto gap = [](const Particles& p) { return p[0].position.z() - p[0].radius; };
  auto speed = [](const Particles& p) { return p[0].velocity.z(); };
  measure_impact(engine, gap, speed, 1000000);
  const Particle& p = engine.particles()[0];
  return {p.velocity.x(), p.velocity.z(), p.angular_velocity.y()};
}

TYPED_TEST(ContactOptions, TangentialDashpotObliqueImpactMatchesTwoBodyIntegration) {
  // Hooke on a wall, 30 degrees from the normal, mu = 10 (sticking but near the end, where
  // F_n -> 0 caps the force), e = 0.5, the dashpot on (hooke's default) and off.
  Material m = peer_material(0.5, 10.0);
  const double mass = m.mass(kRadius);
  const double k_n = kHookeWall, g_n = gamma_for(mass, k_n, 0.5);  // by hand (above)
  const double t_c = linear_duration(mass, k_n, 0.5);
  const Vec3 v0 = kSpeed * Vec3(std::sin(kPi / 6), 0, -std::cos(kPi / 6));
  Rebound with[2], without[2];
  for (const bool damping : {true, false}) {
    auto law = hooke_of(m);  // v_c = 0.1 m/s: k_n = kHookeWall
    law.set_tangential_damping(damping);
    const Rebound expected = two_body_rebound(
        mass, m.friction, v0, [&](double d, double dd) { return k_n * d + g_n * dd; },
        [&](double) { return k_n; }, [&](double) { return damping ? g_n : 0.0; }, t_c / 200000.0);
    const Rebound got = engine_rebound<TypeParam>(sphere_on_wall(law, m, v0, t_c / 5000.0));
    (damping ? with : without)[0] = expected;
    (damping ? with : without)[1] = got;
    // 2e-3 of the impact speed: at 5000 steps per contact the contact's onset and end are
    // resolved to a step (the dashpot force jumps there: gamma v dt / (m v) ~ 4e-4), and
    // Verlet's O(dt^2) error is ~1e-6.
    EXPECT_NEAR(got.vx, expected.vx, 2e-3 * kSpeed) << "damping " << damping;
    EXPECT_NEAR(got.vz, expected.vz, 2e-3 * kSpeed) << "damping " << damping;
    EXPECT_NEAR(got.wy * kRadius, expected.wy * kRadius, 2e-3 * kSpeed) << "damping " << damping;
  }
  // Not vacuous: the dashpot changes the tangential rebound by far more than the tolerance.
  EXPECT_GT(std::abs(with[0].vx - without[0].vx), 10 * 2e-3 * kSpeed);
  std::printf("v_x' with dashpot: engine %.6f, integration %.6f; without: %.6f, %.6f m/s\n", with[1].vx,
              with[0].vx, without[1].vx, without[0].vx);
}

TYPED_TEST(ContactOptions, TangentialDashpotOnHertzMatchesTwoBodyIntegration) {
  // Hertz-Mindlin with the dashpot gamma_t = eta delta^{1/4}: the scalar path (the AVX
  // four-contact path is off with the dashpot), mu = 10, 45 degrees, e = 0.5.
  Material m = peer_material(0.5, 10.0);
  auto law = HertzMindlin::from_material(m);
  law.set_tangential_damping(true);
  const double mass = m.mass(kRadius);
  // Wall: E* = E/(2(1 - nu^2)), G* = G/(2(2 - nu)), R* = R, m* = m (material.hpp).
  const double e_star = m.young / (2.0 * (1.0 - m.poisson * m.poisson));
  const double g_star = m.young / (2.0 * (1.0 + m.poisson)) / (2.0 * (2.0 - m.poisson));
  const double big_k = 4.0 / 3.0 * e_star * std::sqrt(kRadius);
  const double eta = law.damping_ratio() * std::sqrt(mass * big_k);  // alpha(e): hertz_damping_test
  const Vec3 v0 = kSpeed * Vec3(std::sqrt(0.5), 0, -std::sqrt(0.5));
  const double t_c = hertz_elastic_duration(mass, kRadius, e_star, kSpeed);
  const Rebound expected = two_body_rebound(
      mass, m.friction, v0,
      [&](double d, double dd) { return std::max(0.0, big_k * d * std::sqrt(d) + eta * std::sqrt(std::sqrt(d)) * dd); },
      [&](double d) { return 8.0 * g_star * std::sqrt(kRadius * d); },
      [&](double d) { return eta * std::sqrt(std::sqrt(d)); }, t_c / 200000.0);
  const Rebound got = engine_rebound<TypeParam>(sphere_on_wall(law, m, v0, t_c / 5000.0));
  // 2e-3 of the speed: as above (the Hertz force starts at 0, so the onset errs less).
  EXPECT_NEAR(got.vx, expected.vx, 2e-3 * kSpeed);
  EXPECT_NEAR(got.vz, expected.vz, 2e-3 * kSpeed);
  EXPECT_NEAR(got.wy * kRadius, expected.wy * kRadius, 2e-3 * kSpeed);
}

TYPED_TEST(ContactOptions, GrossSlidingWithDashpotIsTheCoulombImpulse) {
  // mu = 0.1 at 60 degrees from the normal: the contact point slides throughout, so Coulomb
  // caps the TOTAL tangential force at mu F_n and v_x' = v_x - mu (1 + e) v_n (the Hertz force
  // is clamped at F_n >= 0, so its impulse is m (1 + e) v_n), whatever the dashpot.
  for (const bool damping : {false, true}) {
    Material m = peer_material(0.5, 0.1);
    auto law = HertzMindlin::from_material(m);
    law.set_tangential_damping(damping);
    const Vec3 v0 = kSpeed * Vec3(std::sin(kPi / 3), 0, -std::cos(kPi / 3));
    const Rebound got = engine_rebound<TypeParam>(sphere_on_wall(law, m, v0, 1e-7));
    const double expected = v0.x() - 0.1 * (got.vz - v0.z());  // tangential impulse = mu x normal
    // 1 % of the tangential impulse: the first steps of a Hertz contact stick (k_t, F_n -> 0 at
    // delta -> 0), Chung & Ooi's test 4 sees the same 0.5 %.
    EXPECT_NEAR((v0.x() - got.vx) / (v0.x() - expected), 1.0, 0.01) << "damping " << damping;
  }
}

TEST(TangentialDashpot, ContactForceIsEqualAndOppositeForBothOrders) {
  // The mirror rule of both engines (contact_force.hpp): evaluating a contact as (j, i) gives
  // -F bit for bit, sticking and sliding, with the dashpot (as without: invariants_test).
  const Material m = peer_material(0.5, 0.4);
  std::mt19937_64 rng(38);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int sliding = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    auto law = trial % 2 ? hooke_of(m) : LinearSpringDashpot::from_stiffness(300.0, 0.5, 0.4);
    law.set_tangential_damping(true);
    ContactKinematics k;
    k.normal = draw2(u, rng, 1.0).normalized();
    k.overlap = (1.0 + u(rng)) * 1e-6;
    k.relative_velocity = 0.1 * draw3(u, rng);
    k.relative_displacement = k.relative_velocity * 1e-7;
    k.relative_displacement_previous_arms = k.relative_displacement;
    k.pair = {m.mass(kRadius) / 2.0, kRadius / 2.0};
    ContactKinematics mirrored = k;
    mirrored.normal = -k.normal;
    mirrored.relative_velocity = -k.relative_velocity;
    mirrored.relative_displacement = -k.relative_displacement;
    mirrored.relative_displacement_previous_arms = -k.relative_displacement_previous_arms;
    TangentialSpring a, b;
    a.displacement = 1e-6 * draw3(u, rng);
    a.stiffness = law.tangential_stiffness(k.overlap, k.pair);
    b = a.mirrored();
    const auto f_ij = frictional_contact_force(law, k, a, 1e-7);
    const auto f_ji = frictional_contact_force(law, mirrored, b, 1e-7);
    ASSERT_EQ(f_ij.on_i, Vec3(-f_ji.on_i)) << trial;
    ASSERT_EQ(a.displacement, Vec3(-b.displacement)) << trial;
    ASSERT_EQ(f_ij.dissipated, f_ji.dissipated) << trial;
    const double f_n = f_ij.on_i.dot(k.normal);
    if ((f_ij.on_i - f_n * k.normal).norm() >= 0.4 * f_n * (1.0 - 1e-12)) ++sliding;
  }
  EXPECT_GT(sliding, 100);  // both branches were exercised
  EXPECT_LT(sliding, 1900);
}

/// Six spheres converging with spin (no gravity, no walls): many oblique contacts.
SimulationSetup cluster(const ContactLaw& law, const Material& m, double dt) {
  SimulationSetup s;
  s.dt = dt;
  s.material = m;
  s.law = law;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 6; ++k) {
    const Vec3 x = 1.4 * kRadius * Vec3(k % 2 ? 1.0 : -1.0, (k / 2) % 2 ? 1.0 : -1.0, k >= 4 ? 1.5 : -0.5) +
                   0.05 * kRadius * draw3(u, rng);
    s.particles.push_back(sphere(k + 1, x, -0.8 * x.normalized() + 0.2 * draw3(u, rng), kRadius));
    s.particles.back().angular_velocity = 100.0 * draw3(u, rng);
  }
  return s;
}

TEST(TangentialDashpot, EnergyBalanceClosesAtSecondOrder) {
  // The dashpot's dissipation gamma_t |v_t|^2 dt is booked like the normal dashpot's (the
  // predicted velocity; contact_force.hpp), so the balance error stays the O(dt^2) error of
  // the normal force: halving dt divides it by about 4 (a first-order booking error would
  // halve it only). Measured with the dashpot at dt = 1e-7 s (~1,000 steps per contact):
  // hooke 2.9e-6 -> 6.7e-7, Hertz 2.0e-6 -> 5.0e-7; without it 2.6e-6 and 1.7e-6 (bound 5e-6).
  Material m = peer_material(0.5, 0.5);
  auto hooke = hooke_of(m, 1.0);
  hooke.set_tangential_damping(true);
  auto hertz = HertzMindlin::from_material(m);
  hertz.set_tangential_damping(true);
  for (const ContactLaw& law : {ContactLaw(hooke), ContactLaw(hertz)}) {
    auto error_at = [&](double dt, double& dissipated) {
      reference::ReferenceEngine engine(cluster(law, m, dt));
      const double e0 = engine.energies().total();
      engine.advance(std::lround(1.0e-3 / dt));
      dissipated = engine.energies().dissipated / e0;
      return std::abs(engine.energies().total() - e0) / e0;
    };
    double d1 = 0.0, d2 = 0.0;
    const double coarse = error_at(1.0e-7, d1), fine = error_at(0.5e-7, d2);
    const char* name = law.index() ? "hertz" : "hooke";
    std::printf("%s: balance error %.3g -> %.3g (dissipated %.3f of E0)\n", name, coarse, fine, d1);
    EXPECT_GT(d1, 0.05) << name;  // collided (not vacuous)
    EXPECT_LT(coarse, 5e-6) << name;
    EXPECT_LT(fine, coarse / 3.0) << name;
  }
}

/// The mixed random scene of multi_material_test, with hooke, three materials and walls of
/// two kinds, the tangential dashpot on.
SimulationSetup mixed_hooke_scene(const ContactLaw& law) {
  const double r = 0.5e-3, width = 10.0 * 2.0 * r;
  SimulationSetup s;
  s.material = peer_material(0.5, 0.5);
  s.law = law;
  Material hard = peer_material(0.8, 0.3);
  hard.young = 1.0e8;
  hard.poisson = 0.22;
  Material heavy = peer_material(0.4, 0.6);
  heavy.density = 6000.0;
  heavy.young = 3.0e8;
  s.more_materials = {hard, heavy};
  s.material_pairs = {{0, 2, std::nullopt, 0.0}, {1, 2, 0.3, std::nullopt}};
  GeneratorSpec g;
  g.kind = GeneratorKind::kLattice;
  g.box_min = Vec3::Zero();
  g.box_max = Vec3(width, width, 2.0 * width);
  g.count = 600;
  g.radius = r;
  g.radius_max = 1.02 * r;
  g.jitter = 0.05;
  g.seed = 5;
  s.particles = generate_particles(g, "test");
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (Particle& q : s.particles) {
    q.velocity = 0.3 * draw3(u, rng);
    q.angular_velocity = 300.0 * draw3(u, rng);
    q.material = static_cast<std::uint16_t>(rng() % 3);
  }
  s.gravity = Vec3(0, 0, -9.81);
  s.boundaries.push_back(std::make_shared<PlaneWall>(Vec3::Zero(), Vec3(0, 0, 1)));
  s.boundaries.push_back(std::make_shared<PlaneWall>(Vec3::Zero(), Vec3(1, 0, 0)));
  s.boundaries.push_back(std::make_shared<PlaneWall>(Vec3(width, 0, 0), Vec3(-1, 0, 0)));
  s.boundary_materials = {1, -1, 2};
  s.dt = 0.5 * time_step_limit(s).limit;
  s.source = "mixed_hooke_scene";
  return s;
}

std::size_t differing(const Particles& a, const Particles& b) {
  std::size_t n = a.size() == b.size() ? 0 : 1;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    n += !(a[i].id == b[i].id && a[i].position == b[i].position && a[i].velocity == b[i].velocity &&
           a[i].angular_velocity == b[i].angular_velocity && a[i].force == b[i].force && a[i].torque == b[i].torque);
  }
  return n;
}

TEST(ContactOptionsEngines, ReferenceAndFastAgreeBitwise) {
  // hooke with three materials (pair E*, mixing and explicit pairs) and linear with three
  // materials, both with the dashpot; Hertz-Mindlin with it on one material (the fast
  // engine's AVX path must step aside for the scalar law).
  Material m = peer_material(0.5, 0.5);
  auto hooke = hooke_of(m, 0.3);
  hooke.set_tangential_damping(true);  // the factory leaves it off; a scene's default is on
  auto linear = LinearSpringDashpot::from_stiffness(400.0, 0.5, 0.5);
  linear.set_tangential_damping(true);
  auto hertz = HertzMindlin::from_material(m);
  hertz.set_tangential_damping(true);
  const char* names[] = {"hooke", "linear", "hertz"};
  int which = 0;
  for (const ContactLaw& law : {ContactLaw(hooke), ContactLaw(linear), ContactLaw(hertz)}) {
    const char* name = names[which++];
    SimulationSetup s = mixed_hooke_scene(law);
    if (std::holds_alternative<HertzMindlin>(law)) {
      s.more_materials.clear();
      s.material_pairs.clear();
      s.boundary_materials.clear();
      for (Particle& p : s.particles) p.material = 0;
      s.dt = 0.5 * time_step_limit(s).limit;
    }
    reference::ReferenceEngine reference(s);
    fast::FastEngine fast(s);
    for (int block = 0; block < 3; ++block) {
      reference.advance(100);
      fast.advance(100);
      EXPECT_EQ(differing(reference.particles(), fast.particles()), 0u) << name << " step " << reference.step_count();
    }
    EXPECT_GT(fast.contact_counts().particle_pairs, 50u) << name;
    EXPECT_GT(fast.contact_counts().particle_boundary, 5u) << name;
    // The dashpot shows in the dissipation: not the run without it.
    ContactLaw off = law;
    std::visit([](auto& l) { l.set_tangential_damping(false); }, off);
    SimulationSetup s_off = s;
    s_off.law = off;
    reference::ReferenceEngine without(s_off);
    without.advance(300);
    EXPECT_GT(differing(reference.particles(), without.particles()), 100u) << name;
  }
}


/// A scene's law from TOML text with the given [contact] lines (and materials).
SimulationSetup scene_with(const std::string& contact, const std::string& materials =
                                                           "[material]\ndensity = 2500.0\nyoung = 1e7\npoisson = 0.3\n"
                                                           "restitution = 0.5\nfriction = 0.4\n") {
  const std::string text = "[simulation]\ndt = 1e-7\nsteps = 1\n[contact]\n" + contact + materials +
                           "[particles]\ngenerator = \"lattice\"\nbox_min = [0, 0, 0]\nbox_max = [0.01, 0.01, 0.01]\n"
                           "count = 4\nradius = 0.001\n";
  return read_scene_text(text, "scene.toml", ".").setup;
}

std::string scene_error(const std::string& contact, const std::string& materials = "") {
  try {
    if (materials.empty()) scene_with(contact);
    else scene_with(contact, materials);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ContactOptionsScene, ReadsHookeKeysAndTheDashpotDefaults) {
  const SimulationSetup hooke = scene_with("model = \"hooke\"\ncharacteristic_velocity = 0.5\n");
  const LinearSpringDashpot law = std::get<LinearSpringDashpot>(hooke.law);
  EXPECT_TRUE(law.per_contact_stiffness());
  EXPECT_EQ(law.effective_young(), 1e7 / (2.0 * (1.0 - 0.09)));
  EXPECT_EQ(law.characteristic_velocity(), 0.5);
  EXPECT_EQ(law.restitution(), 0.5);
  EXPECT_EQ(law.friction(), 0.4);
  EXPECT_TRUE(law.tangential_damping());  // LIGGGHTS' default for hooke
  const PairProperties pair{1e-6, 1e-3};
  EXPECT_EQ(law.tangential_stiffness(0.0, pair), law.stiffness(pair));  // ratio 1 by default
  const LinearSpringDashpot ratio = std::get<LinearSpringDashpot>(
      scene_with("model = \"hooke\"\ncharacteristic_velocity = 0.5\ntangential_stiffness_ratio = 0.25\n"
                 "tangential_damping = false\n").law);
  EXPECT_EQ(ratio.tangential_stiffness(0.0, pair), 0.25 * ratio.stiffness(pair));
  EXPECT_FALSE(ratio.tangential_damping());
  // Off by default for the other laws (their scenes are unchanged), on when asked.
  EXPECT_FALSE(std::get<LinearSpringDashpot>(scene_with("model = \"linear\"\nstiffness = 100.0\n").law).tangential_damping());
  EXPECT_FALSE(std::get<HertzMindlin>(scene_with("model = \"hertz-mindlin\"\n").law).tangential_damping());
  EXPECT_TRUE(std::get<HertzMindlin>(scene_with("model = \"hertz-mindlin\"\ntangential_damping = true\n").law)
                  .tangential_damping());
  // The linear law with two materials is read (the pair table in ContactOptions tests).
  const std::string two =
      "[[material]]\nname = \"a\"\ndensity = 2500.0\nrestitution = 0.5\n"
      "[[material]]\nname = \"b\"\ndensity = 7800.0\nrestitution = 0.9\n";
  EXPECT_EQ(scene_with("model = \"linear\"\nstiffness = 100.0\n", two).material_count(), 2u);
}

TEST(ContactOptionsScene, InputErrorsNameTheKey) {
  EXPECT_NE(scene_error("model = \"hooke\"\n").find("characteristic_velocity"), std::string::npos);
  EXPECT_NE(scene_error("model = \"hooke\"\ncharacteristic_velocity = -1.0\n").find("must be > 0 m/s"), std::string::npos);
  EXPECT_NE(scene_error("model = \"hooke\"\ncharacteristic_velocity = 1.0\nstiffness = 5.0\n")
                .find("stiffness does not apply to model = \"hooke\""),
            std::string::npos);
  EXPECT_NE(scene_error("model = \"linear\"\nstiffness = 5.0\ncharacteristic_velocity = 1.0\n")
                .find("applies to model = \"hooke\" only"),
            std::string::npos);
  EXPECT_NE(scene_error("model = \"hertz-mindlin\"\ntangential_damping = 1\n").find("tangential_damping"),
            std::string::npos);
  EXPECT_NE(scene_error("model = \"hook\"\n").find("\"linear\" or \"hooke\""), std::string::npos);
  // hooke needs E and nu.
  EXPECT_NE(scene_error("model = \"hooke\"\ncharacteristic_velocity = 1.0\n",
                        "[material]\ndensity = 2500.0\nrestitution = 0.5\n")
                .find("young must be > 0"),
            std::string::npos);
  for (const std::string& e : {scene_error("model = \"hooke\"\n")}) EXPECT_NE(e.find("scene.toml"), std::string::npos) << e;
}

}  // namespace
}  // namespace ppohdem::dem::test
