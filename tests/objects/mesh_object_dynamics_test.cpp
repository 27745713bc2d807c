// Exact contacts of mesh objects in an engine (docs/objects.md "Exact contacts for mesh objects"):
// a sphere at rest in a 90-degree V-notch and in a corner of three faces at the analytic
// contact heights whatever the grid's offset, rolling down a V-groove as the rigid-body answer,
// and conserving energy to the integrator's order with e = 1. The field's trilinear contact (the
// seed's method) is run on the same scenes for comparison (and its error asserted, so a silent
// switch of method is seen).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <map>
#include <numbers>
#include <random>
#include <tuple>

#include "../dem/dem_test_support.hpp"
#include "mesh_shapes.hpp"
#include "ppohdem/dem/checkpoint.hpp"
#include "ppohdem/dem/distance_field_object.hpp"
#include "ppohdem/sdf/fast/fast_sdf_builder.hpp"

namespace ppohdem::dem::test {
namespace {

using ppohdem::dem::reference::ReferenceEngine;

constexpr double kRadius = 1e-3;     // m
constexpr double kDensity = 2500.0;  // kg/m^3
constexpr double kStiffness = 10.0;  // N/m, linear law: overlap m g / k ~ 1% of R
constexpr double kGravity = 9.81;    // m/s^2
const double kMass = kDensity * 4.0 / 3.0 * std::numbers::pi * kRadius * kRadius * kRadius;

/// The mesh's object with its exact distance on a grid of spacing h covering [lo, hi], placed
/// so that `anchor` sits at `fraction` (per axis, in cells) from the node below it.
std::shared_ptr<DistanceFieldObject> object_on_grid(const TriangleMesh& mesh, const Vec3& lo, const Vec3& hi,
                                                    double h, const Vec3& anchor, const Vec3& fraction,
                                                    bool mesh_contacts) {
  GridSpec grid;
  grid.spacing = Vec3::Constant(h);
  for (int a = 0; a < 3; ++a) {
    grid.origin[a] = anchor[a] - (std::ceil((anchor[a] - lo[a]) / h) + fraction[a]) * h;
    grid.nodes[a] = static_cast<int>(std::ceil((hi[a] - grid.origin[a]) / h)) + 1;
  }
  auto object = std::make_shared<DistanceFieldObject>(sdf::fast::FastSdfBuilder().build(mesh, grid), RigidMotion{},
                                                      "notch");
  if (mesh_contacts) object->use_mesh_contacts(mesh);
  return object;
}

SimulationSetup one_sphere(const Vec3& at, const Vec3& gravity, double restitution, double friction, double dt) {
  Material m = peer_material(restitution, friction);
  m.density = kDensity;
  SimulationSetup s;
  s.dt = dt;
  s.gravity = gravity;
  s.material = m;
  s.law = LinearSpringDashpot::from_stiffness(kStiffness, restitution, friction);
  s.particles = {sphere(1, at, Vec3::Zero(), kRadius)};
  return s;
}

// The notched block of mesh_shapes.hpp: crease on the x axis, x in [0, length].
struct Notch {
  double length = 0.012, half_width = 0.004, depth = 0.002;
  int cells = 12;
  TriangleMesh mesh() const { return notched_block(length, half_width, depth, cells); }
  Vec3 lo() const { return Vec3(0.0, -half_width, -depth) - Vec3::Constant(3e-3); }
  Vec3 hi() const { return Vec3(length, half_width, half_width) + Vec3::Constant(3e-3); }
};

// Grid offsets of the crease (in cells): on a node, half-way in both directions, and others.
const Vec3 kOffsets[] = {Vec3(0, 0, 0), Vec3(0, 0.5, 0.5), Vec3(0.3, 0.25, 0.7), Vec3(0.5, 0.37, 0.11),
                         Vec3(0.0, 0.5, 0.0)};

// Settles a frictionless sphere (e = 0.3) dropped off-centre into the notch for 1 s; returns the
// final centre minus the analytic rest position and the final speed.
template <class Engine = ReferenceEngine>
std::pair<Vec3, double> settle_in_notch(const Vec3& offset, bool mesh_contacts, double h) {
  const Notch notch;
  // At rest each face pushes m g / sqrt(2) along its normal (45 degrees): overlap delta =
  // m g / (sqrt(2) k), centre at distance R - delta from both faces: z = sqrt(2) (R - delta).
  const double delta = kMass * kGravity / (std::sqrt(2.0) * kStiffness);
  const Vec3 rest(0.006, 0.0, std::sqrt(2.0) * (kRadius - delta));
  SimulationSetup s = one_sphere(rest + Vec3(0, 0.2 * kRadius, 0.3 * kRadius), Vec3(0, 0, -kGravity), 0.3, 0.0, 5e-5);
  s.boundaries = {object_on_grid(notch.mesh(), notch.lo(), notch.hi(), h, Vec3::Zero(), offset, mesh_contacts)};
  Engine engine(s);
  engine.advance(20000);  // 1 s = 300 contact durations: the transient decays by 0.3^600
  const Particle& p = engine.particles()[0];
  return {p.position - rest, p.velocity.norm()};
}

// The analytic rest position to 1e-12 m (1e-9 R): the transient has decayed below round-off,
// and the equilibrium of two linear springs is exact to the round-off of positions of 1e-2 m.
TEST(MeshObjectDynamics, VNotchRestsAtTheTwoContactHeightAtAnyGridOffset) {
  for (const Vec3& offset : kOffsets) {
    for (const double h : {1e-3, 0.5e-3}) {
      const auto [error, speed] = settle_in_notch(offset, true, h);
      EXPECT_LT(error.norm(), 1e-12) << "offset " << offset.transpose() << " h " << h << " error " << error.transpose();
      EXPECT_LT(speed, 1e-12);
    }
  }
  // The fast engine (also bitwise equal to the reference: FastEngineGivesTheReferenceBits).
  for (const Vec3& offset : {kOffsets[0], kOffsets[1]}) {
    const auto [error, speed] = settle_in_notch<fast::FastEngine>(offset, true, 1e-3);
    EXPECT_LT(error.norm(), 1e-12) << "fast engine, offset " << offset.transpose();
    EXPECT_LT(speed, 1e-12);
  }
}

// The seed's trilinear contact in the same notch (documented in docs/objects.md): its rest
// height depends on the grid's offset by a good fraction of h.
TEST(MeshObjectDynamics, FieldContactInTheVNotchIsOffByAFractionOfTheCell) {
  double worst = 0.0;
  for (const Vec3& offset : kOffsets) {
    for (const double h : {1e-3, 0.5e-3}) {
      const auto [error, speed] = settle_in_notch(offset, false, h);
      std::printf("field contact, h = %g m, crease offset (%g, %g) cells: rest error z %.3e m, y %.3e m, speed %.3e m/s\n",
                  h, offset.y(), offset.z(), error.z(), error.y(), speed);
      worst = std::max(worst, error.norm());
    }
  }
  EXPECT_GT(worst, 1e-5);  // the exact method is at 1e-12 m (above)
}

// A corner of three faces (a cube with a cubic notch removed) with gravity along -(1, 1, 1):
// three contacts of m g / sqrt(3) each, centre at (d, d, d), d = R - m g / (sqrt(3) k).
TEST(MeshObjectDynamics, CornerOfThreeFacesRestsAtTheAnalyticPosition) {
  const std::array<std::vector<double>, 3> lattice = {std::vector<double>{-3e-3, 0.0, 5e-3},
                                                      std::vector<double>{-3e-3, 0.0, 5e-3},
                                                      std::vector<double>{-3e-3, 0.0, 5e-3}};
  const TriangleMesh mesh = lattice_solid(lattice, [](int i, int j, int k) { return !(i == 1 && j == 1 && k == 1); });
  const double d = kRadius - kMass * kGravity / (std::sqrt(3.0) * kStiffness);
  for (const Vec3& offset : kOffsets) {
    SimulationSetup s = one_sphere(Vec3(1.3, 1.1, 1.2) * kRadius, -Vec3::Ones().normalized() * kGravity, 0.3, 0.0, 5e-5);
    s.boundaries = {object_on_grid(mesh, Vec3::Constant(-6e-3), Vec3::Constant(8e-3), 1e-3, Vec3::Zero(), offset, true)};
    ReferenceEngine engine(s);
    engine.advance(20000);
    const Particle& p = engine.particles()[0];
    EXPECT_LT((p.position - Vec3::Constant(d)).norm(), 1e-12) << "offset " << offset.transpose();
    EXPECT_EQ(engine.contact_counts().particle_boundary, 3u);
  }
}

// Rolling without slipping down a V-groove tilted by alpha: the contacts lie d / sqrt(2) below
// the centre (d = R - delta), so a = g sin(alpha) / (1 + I / (m d^2 / 2)), I = 2 m R^2 / 5.
// The tangential springs ride over the faces' triangles (1 mm long) under one feature id each.
TEST(MeshObjectDynamics, SphereRollsDownAGrooveAsARigidBody) {
  Notch notch;
  notch.length = 0.04;
  notch.cells = 40;
  const double alpha = 0.1;
  const Vec3 g = kGravity * Vec3(std::sin(alpha), 0, -std::cos(alpha));
  const double d = kRadius - kMass * kGravity * std::cos(alpha) / (std::sqrt(2.0) * kStiffness);
  const Vec3 start(0.005, 0.0, std::sqrt(2.0) * d);
  SimulationSetup s = one_sphere(start, g, 0.3, 0.5, 2.5e-5);
  s.boundaries = {object_on_grid(notch.mesh(), notch.lo(), notch.hi(), 1e-3, Vec3::Zero(), Vec3(0.3, 0.25, 0.7), true)};
  ReferenceEngine engine(s);
  const auto keys = [&] {
    std::vector<std::int64_t> k;
    for (const auto& r : engine.save_state().contacts) k.push_back(r.id_b);
    return k;
  };
  const std::vector<std::int64_t> first = keys();
  ASSERT_EQ(first.size(), 2u);
  const double seconds = 0.2;
  engine.advance(static_cast<long>(std::lround(seconds / s.dt)));
  const double a = kGravity * std::sin(alpha) / (1.0 + 0.4 * kRadius * kRadius / (0.5 * d * d));
  const Particle& p = engine.particles()[0];
  // The tangential springs start unloaded and then vibrate about the rolling solution, undamped
  // (no tangential dashpot), at omega_t ~ sqrt(2 k_t / (m / (1 + m r^2 / I))) ~ 1100 rad/s,
  // excited by the initial mismatch g sin(alpha) - a ~ 0.44 m/s^2: amplitudes ~ 4e-7 m in
  // position (3e-5 of the 1.1e-2 m travelled) and ~ 4e-4 m/s in velocity. The tolerances are
  // 3x and 1.5x those; the slip v - omega d / sqrt(2) (a sliding sphere: ~ v) within 1% of v.
  const double travel = 0.5 * a * seconds * seconds;
  EXPECT_NEAR(p.position.x() - start.x(), travel, 1e-4 * travel);
  EXPECT_NEAR(p.velocity.x(), a * seconds, 6e-4);
  EXPECT_NEAR(p.velocity.x() - p.angular_velocity.y() * d / std::sqrt(2.0), 0.0, 1e-2 * p.velocity.x());
  EXPECT_LT(std::abs(p.position.y()), 1e-12);
  EXPECT_EQ(keys(), first);  // the same two face features after crossing 11 triangles
}

// e = 1, frictionless: the energy (kinetic + gravitational + elastic) of a sphere bouncing in the
// notch is conserved to the integrator's order: the largest error over the run falls by 4 when
// dt halves (velocity Verlet, second order).
double largest_energy_error(double dt, bool mesh_contacts) {
  const Notch notch;
  SimulationSetup s = one_sphere(Vec3(0.006, 0.4 * kRadius, 2.5 * kRadius), Vec3(0, 0, -kGravity), 1.0, 0.0, dt);
  s.boundaries = {object_on_grid(notch.mesh(), notch.lo(), notch.hi(), 1e-3, Vec3::Zero(), Vec3(0.3, 0.25, 0.7),
                                 mesh_contacts)};
  ReferenceEngine engine(s);
  const double e0 = engine.energies().total();
  double worst = 0.0;
  const long steps = std::lround(0.1 / dt);
  for (long k = 0; k < steps; ++k) {
    engine.step();
    worst = std::max(worst, std::abs(engine.energies().total() - e0));
  }
  return worst / (kMass * kGravity * kRadius);
}

// The largest error over a run depends on where in a step each impact starts, so the order is
// the least-squares slope of log(error) against log(dt) over a factor 16 in dt (measured 2.17,
// docs/objects.md); the seed's trilinear contact does not converge at all (0.17 m g R at every
// dt: its force is not the gradient of its energy across the crease).
TEST(MeshObjectDynamics, EnergyIsConservedToSecondOrderWithRestitutionOne) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double steps[] = {4e-5, 2e-5, 1e-5, 5e-6, 2.5e-6};
  for (const double dt : steps) {
    const double error = largest_energy_error(dt, true);
    std::printf("mesh contact, e = 1, dt = %g s: largest energy error / (m g R) %.3e\n", dt, error);
    EXPECT_LT(error, 10.0 * dt / 1e-5 * dt / 1e-5 * 2.6e-5 + 1e-12);  // the trend of dt^2, 10x slack
    sx += std::log(dt);
    sy += std::log(error);
    sxx += std::log(dt) * std::log(dt);
    sxy += std::log(dt) * std::log(error);
  }
  const double n = std::size(steps);
  const double order = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  std::printf("order %.3f\n", order);
  EXPECT_GT(order, 1.8);
  EXPECT_LT(order, 2.3);
  for (const double dt : {2e-5, 1e-5}) {
    std::printf("field contact, e = 1, dt = %g s: largest energy error / (m g R) %.3e\n", dt,
                largest_energy_error(dt, false));
  }
}

}  // namespace
}  // namespace ppohdem::dem::test

namespace ppohdem::dem::test {
namespace {

// A heap of 1,100 frictional spheres in the notch: a row in the crease touching both faces and
// a row on each face (at their rest overlap), a lattice falling onto them. The fast engine gives
// the reference's bits (the same contacts added in the same order: dem_fast/fast_engine_test.cpp's
// rule), the same contact histories with their feature keys, and either restarts from the
// other's checkpoint with the same bits.
SimulationSetup heap_in_notch() {
  const double r = 0.4e-3, pitch = 2.05 * r;
  SimulationSetup s;
  s.dt = 2e-5;
  s.gravity = Vec3(0, 0, -kGravity);
  s.material = peer_material(0.5, 0.5);
  s.law = LinearSpringDashpot::from_stiffness(kStiffness, 0.5, 0.5);
  std::mt19937_64 rng(38);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::int64_t id = 0;
  const double gap = 0.999 * r;  // overlap 4e-7 m, about the rest overlap m g / k
  for (double x = r; x <= 12e-3 - r; x += pitch) {
    s.particles.push_back(sphere(id++, Vec3(x, 0, std::sqrt(2.0) * gap), Vec3::Zero(), r));
    const double up = 3.0 * r / std::sqrt(2.0);  // 3 R up each face from the crease
    s.particles.push_back(sphere(id++, Vec3(x, up, up) + gap * Vec3(0, -1, 1).normalized(), Vec3::Zero(), r));
    s.particles.push_back(sphere(id++, Vec3(x, -up, up) + gap * Vec3(0, 1, 1).normalized(), Vec3::Zero(), r));
  }
  for (double z = 3.0e-3; id < 1100; z += pitch) {
    for (double y = -2.4e-3; y <= 2.4e-3 && id < 1100; y += pitch) {
      for (double x = r; x <= 12e-3 - r && id < 1100; x += pitch) {
        s.particles.push_back(sphere(id++, Vec3(x, y, z), 0.05 * Vec3(u(rng), u(rng), u(rng)), r));
      }
    }
  }
  const Notch notch;
  s.boundaries = {object_on_grid(notch.mesh(), notch.lo(), notch.hi(), 1e-3, Vec3::Zero(), Vec3(0.3, 0.25, 0.7), true)};
  return s;
}

void expect_same_particles(const Particles& a, const Particles& b, const std::string& what) {
  ASSERT_EQ(a.size(), b.size());
  std::size_t differing = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const bool same = a[i].id == b[i].id && a[i].position == b[i].position && a[i].velocity == b[i].velocity &&
                      a[i].angular_velocity == b[i].angular_velocity && a[i].force == b[i].force &&
                      a[i].torque == b[i].torque;
    if (!same && differing++ == 0) ADD_FAILURE() << what << ": particle id " << a[i].id << " differs";
  }
  EXPECT_EQ(differing, 0u) << what;
}

std::vector<std::tuple<std::int64_t, std::int64_t>> boundary_keys(const EngineState& state) {
  std::vector<std::tuple<std::int64_t, std::int64_t>> keys;
  for (const auto& c : state.contacts) {
    if (c.kind == ContactHistoryRecord::Kind::kParticleBoundary) keys.emplace_back(c.id_a, c.id_b);
  }
  return keys;
}

TEST(MeshObjectDynamics, FastEngineGivesTheReferenceBits) {
  const SimulationSetup s = heap_in_notch();
  ASSERT_EQ(s.particles.size(), 1100u);  // the fast kernels run on several threads from 1,024
  ReferenceEngine reference(s);
  fast::FastEngine fast(s);
  std::size_t most_features = 0;
  for (int block = 0; block < 3; ++block) {
    reference.advance(40);
    fast.advance(40);
    const std::string when = "after " + std::to_string(reference.step_count()) + " steps";
    expect_same_particles(reference.particles(), fast.particles(), when);
    EXPECT_EQ(reference.contact_counts().particle_boundary, fast.contact_counts().particle_boundary) << when;
    const EngineState a = reference.save_state();
    EXPECT_EQ(boundary_keys(a), boundary_keys(fast.save_state())) << when;
    std::map<std::int64_t, std::size_t> per_particle;
    for (const auto& [particle, key] : boundary_keys(a)) most_features = std::max(most_features, ++per_particle[particle]);
  }
  EXPECT_GE(most_features, 2u);  // not vacuous: particles with two springs on the object
  EXPECT_GE(reference.contact_counts().particle_boundary, 50u);  // 14 x 2 + 28 at the start
  // Each engine restarts from the other's checkpoint, written to bytes and read back (the
  // feature keys travel in the contact records' id_b), and continues with the same bits.
  Checkpoint written;
  written.engine = reference.save_state();
  const Checkpoint read = decode_checkpoint(encode_checkpoint(written), "in memory");
  EXPECT_EQ(boundary_keys(read.engine), boundary_keys(written.engine));
  ReferenceEngine reference_restarted(s);
  fast::FastEngine fast_restarted(s);
  reference_restarted.restore_state(fast.save_state());
  fast_restarted.restore_state(read.engine);
  reference.advance(30);
  fast.advance(30);
  reference_restarted.advance(30);
  fast_restarted.advance(30);
  expect_same_particles(reference.particles(), fast_restarted.particles(), "fast from the reference's checkpoint");
  expect_same_particles(fast.particles(), reference_restarted.particles(), "reference from the fast checkpoint");
}

}  // namespace
}  // namespace ppohdem::dem::test
