// The fast engine against its oracle, the reference engine (STYLE habits 9-11): the same scene
// gives the same trajectories BIT FOR BIT (the fast engine sums each particle's contacts in the
// reference's order and evaluates each contact as the exact negation of the reference's, see
// ppohdem/dem/fast/fast_engine.hpp), for any thread count, across neighbour-list rebuilds
// (history carried by id) and across checkpoints. The engine-neutral contract tests (impacts,
// Chung & Ooi) run for both engines in tests/dem (EngineTypes).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "ppohdem/dem/cell_grid.hpp"
#include "ppohdem/dem/distance_field_object.hpp"
#include "ppohdem/dem/fast/fast_engine.hpp"
#include "ppohdem/dem/particle_generator.hpp"
#include "ppohdem/dem/run_diagnostics.hpp"
#include "ppohdem/dem/reference/reference_engine.hpp"
#include "../../core/src/dem/fast/fast_state.hpp"  // balance_split (internal)

#ifdef PPOHDEM_WITH_OPENMP
#include <omp.h>
#endif

namespace ppohdem::dem::test {
namespace {

using ppohdem::dem::fast::FastEngine;
using ppohdem::dem::reference::ReferenceEngine;

constexpr double kR = 0.5e-3;  // particle radius [m] (d = 1 mm, the standard scene)

Material glass_like(double friction) {
  Material m;
  m.density = 2500.0;  // kg/m^3
  m.young = 1.0e7;     // Pa
  m.poisson = 0.3;
  m.restitution = 0.5;
  m.friction = friction;
  return m;
}

enum class SceneKind {
  kHertzFrictionWalls,          // Hertz-Mindlin, mu = 0.5, a walled box, gravity
  kLinearFrictionWallsObject,   // linear, mu = 0.3, box with a moving lid, a spinning sphere object
  kHertzFrictionlessFree,       // Hertz, mu = 0, no boundaries, no gravity
};

/// About 1,400 spheres on a jittered lattice (so the loops run on every thread: the kernels
/// go parallel from 1,024 particles) with random velocities of up to 0.3 m/s per component and
/// random spins, so that contacts form and break from the first steps and the neighbour list
/// is rebuilt every ~10-20 steps. The box is `shape` times the width (14 diameters) per axis:
/// twice as tall as wide unless said.
SimulationSetup scene(SceneKind kind, const Vec3& shape = Vec3(1.0, 1.0, 2.0)) {
  const double width = 14.0 * 2.0 * kR;  // [m]
  SimulationSetup s;
  s.material = glass_like(kind == SceneKind::kHertzFrictionlessFree ? 0.0 : (kind == SceneKind::kHertzFrictionWalls ? 0.5 : 0.3));
  if (kind == SceneKind::kLinearFrictionWallsObject) {
    s.law = LinearSpringDashpot::from_stiffness(50.0, s.material.restitution, s.material.friction);  // k_n [N/m]
  } else {
    s.law = HertzMindlin::from_material(s.material);
  }
  s.dt = 0.2 * rayleigh_time(kR, s.material);
  if (kind != SceneKind::kHertzFrictionlessFree) s.gravity = Vec3(0.0, 0.0, -9.81);
  GeneratorSpec g;
  g.kind = GeneratorKind::kLattice;
  g.box_min = Vec3::Zero();
  g.box_max = width * shape;
  g.count = 1500;
  g.radius = kR;
  g.jitter = 0.05;
  g.seed = 7;
  Particles p = generate_particles(g, "test");
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (Particle& q : p) {
    q.velocity = 0.3 * Vec3(u(rng), u(rng), u(rng));            // [m/s]
    q.angular_velocity = 300.0 * Vec3(u(rng), u(rng), u(rng));   // [rad/s]
  }
  if (kind != SceneKind::kHertzFrictionlessFree) {
    s.boundaries.push_back(std::make_shared<PlaneWall>(Vec3::Zero(), Vec3(0, 0, 1)));
    s.boundaries.push_back(std::make_shared<PlaneWall>(Vec3::Zero(), Vec3(1, 0, 0)));
    s.boundaries.push_back(std::make_shared<PlaneWall>(Vec3(width * shape.x(), 0, 0), Vec3(-1, 0, 0)));
    s.boundaries.push_back(std::make_shared<PlaneWall>(Vec3::Zero(), Vec3(0, 1, 0)));
    s.boundaries.push_back(std::make_shared<PlaneWall>(Vec3(0, width * shape.y(), 0), Vec3(0, -1, 0)));
  }
  if (kind == SceneKind::kLinearFrictionWallsObject) {
    // A lid coming down at 0.5 m/s from just above the top layer, and a sphere of radius
    // 3 R spinning at 200 rad/s about z in the middle of the lattice (particles it would
    // overlap are removed), given by its exact distance on a grid of spacing R/2.
    double top = 0.0;
    for (const Particle& q : p) top = std::max(top, q.position.z() + q.radius);
    s.boundaries.push_back(std::make_shared<PlaneWall>(Vec3(0, 0, top + 0.1 * kR), Vec3(0, 0, -1), Vec3(0, 0, -0.5)));
    const Vec3 centre(0.5 * width, 0.5 * width, 0.5 * top);
    const double r_object = 3.0 * kR;
    std::erase_if(p, [&](const Particle& q) { return (q.position - centre).norm() < r_object + q.radius + 0.05 * kR; });
    GridSpec grid;
    grid.spacing = Vec3::Constant(0.5 * kR);
    grid.nodes = {29, 29, 29};
    grid.origin = centre - Vec3::Constant(14.0 * 0.5 * kR);
    ScalarField phi(grid);
    for (int k = 0; k < 29; ++k)
      for (int j = 0; j < 29; ++j)
        for (int i = 0; i < 29; ++i) phi.values[grid.index(i, j, k)] = (grid.position(i, j, k) - centre).norm() - r_object;
    RigidMotion motion;
    motion.angular_velocity = Vec3(0, 0, 200.0);  // [rad/s]
    motion.centroid = centre;
    s.boundaries.push_back(std::make_shared<DistanceFieldObject>(std::move(phi), motion, "sphere"));
  }
  s.particles = p;
  s.source = "fast_engine_test";
  return s;
}

/// Asserts bitwise equality of every particle's state (construction order in both).
void expect_same_bits(const Particles& a, const Particles& b, const std::string& what) {
  ASSERT_EQ(a.size(), b.size());
  std::size_t differing = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].id, b[i].id);
    const bool same = a[i].position == b[i].position && a[i].velocity == b[i].velocity &&
                      a[i].angular_velocity == b[i].angular_velocity && a[i].force == b[i].force &&
                      a[i].torque == b[i].torque;
    if (!same && differing++ == 0) {
      ADD_FAILURE() << what << ": particle id " << a[i].id << " differs, position difference "
                    << (a[i].position - b[i].position).norm() << " m";
    }
  }
  EXPECT_EQ(differing, 0u) << what;
}

class FastAgainstReference : public ::testing::TestWithParam<SceneKind> {};

TEST_P(FastAgainstReference, TrajectoriesAreBitwiseTheSame) {
  const SimulationSetup setup = scene(GetParam());
  ReferenceEngine reference(setup);
  FastEngine fast(setup);
  expect_same_bits(reference.particles(), fast.particles(), "initial forces");
  for (int block = 0; block < 4; ++block) {
    reference.advance(100);
    fast.advance(100);
    expect_same_bits(reference.particles(), fast.particles(), "after " + std::to_string(reference.step_count()) + " steps");
    EXPECT_EQ(reference.contact_counts().particle_pairs, fast.contact_counts().particle_pairs);
    EXPECT_EQ(reference.contact_counts().particle_boundary, fast.contact_counts().particle_boundary);
    EXPECT_EQ(reference.escaped_count(), fast.escaped_count());
  }
  // Not vacuous: many contacts, and the list was rebuilt often (histories carried over).
  EXPECT_GT(fast.contact_counts().particle_pairs, 50u);  // measured 120-230 at the end
  EXPECT_GT(fast.neighbour_list_builds(), 10);
  if (!setup.boundaries.empty()) {
    EXPECT_GT(fast.contact_counts().particle_boundary, 20u);
  }

  // Energies and loads are sums over particles in a different order (per particle, then in
  // storage order, instead of one running sum over pairs): they differ by round-off only.
  // A sum of n terms in two orders differs by at most ~n eps sum|terms|; here n ~ 1e4 terms
  // per evaluation (contacts), eps = 2.2e-16 -> 2e-12 of the scale per evaluation, and the
  // cumulative dissipated energy adds 400 such evaluations whose errors do not all align:
  // bound 1e-10 of the scale (the kinetic energy of the start).
  const Energies er = reference.energies();
  const Energies ef = fast.energies();
  const double scale = er.kinetic + er.rotational + er.elastic + er.dissipated;
  EXPECT_NEAR(ef.kinetic, er.kinetic, 1e-12 * scale);  // same bits summed in another order
  EXPECT_NEAR(ef.rotational, er.rotational, 1e-12 * scale);
  EXPECT_NEAR(ef.elastic, er.elastic, 1e-12 * scale);
  EXPECT_NEAR(ef.dissipated, er.dissipated, 1e-10 * scale);
  EXPECT_NEAR(ef.boundary_work, er.boundary_work, 1e-10 * scale);
  const auto lr = reference.boundary_loads();
  const auto lf = fast.boundary_loads();
  ASSERT_EQ(lr.size(), lf.size());
  double weight = 0.0;  // [N], the scale of the loads
  for (const Particle& p : reference.particles()) weight += setup.material.mass(p.radius) * 9.81;
  for (std::size_t b = 0; b < lr.size(); ++b) {
    // Sum of <= 1500 contact forces in another order: <= 1500 eps of the total, 1e-12 W.
    EXPECT_LE((lr[b].force - lf[b].force).norm(), 1e-12 * weight) << "boundary " << b;
    EXPECT_LE((lr[b].moment_about_origin - lf[b].moment_about_origin).norm(), 1e-12 * weight * 0.03) << "boundary " << b;
  }
}

// [simulation] energy_balance = false: no contact energy book-keeping. The energies only
// follow the motion, never steer it, so both engines' trajectories must be the very bits of
// the tracked run (and of each other); the three contact terms are NaN, the motion terms the
// same bits as with tracking.
TEST_P(FastAgainstReference, UntrackedEnergiesLeaveTheTrajectoriesBitwiseUnchanged) {
  SimulationSetup tracked = scene(GetParam());
  SimulationSetup untracked = tracked;
  untracked.energy_balance = false;
  FastEngine fast(tracked);
  FastEngine fast_untracked(untracked);
  ReferenceEngine reference_untracked(untracked);
  for (int block = 0; block < 2; ++block) {
    fast.advance(100);
    fast_untracked.advance(100);
    reference_untracked.advance(100);
    const std::string when = "after " + std::to_string(fast.step_count()) + " steps";
    expect_same_bits(fast.particles(), fast_untracked.particles(), "fast, untracked, " + when);
    expect_same_bits(fast.particles(), reference_untracked.particles(), "reference, untracked, " + when);
  }
  EXPECT_GT(fast.contact_counts().particle_pairs, 50u);  // not vacuous: contacts evaluated
  for (const Energies& e : {fast_untracked.energies(), reference_untracked.energies()}) {
    EXPECT_TRUE(std::isnan(e.elastic));
    EXPECT_TRUE(std::isnan(e.dissipated));
    EXPECT_TRUE(std::isnan(e.boundary_work));
    EXPECT_EQ(e.kinetic, fast.energies().kinetic);
    EXPECT_EQ(e.rotational, fast.energies().rotational);
    EXPECT_EQ(e.gravitational, fast.energies().gravitational);
  }
  EXPECT_TRUE(std::isfinite(fast.energies().dissipated));
  if (GetParam() != SceneKind::kHertzFrictionlessFree) {
    EXPECT_GT(fast.energies().dissipated, 0.0);
  }
}

// Untracked on one rank, the fast engine sums no energies, loads or escapes at every step
// (FastEngine::Impl::lazy_sums): asked, it gives the tracked engine's values bit for bit (the
// same terms in the same order), and its screen of the motion (motion_finite, from the closing
// kick) fails as soon as one velocity or angular velocity is not finite, so the run checks
// still stop such a run.
TEST(FastEngineUntracked, SumsWhenAskedAndScreensTheMotion) {
  const SimulationSetup tracked = scene(SceneKind::kLinearFrictionWallsObject);  // walls, lid, object
  SimulationSetup untracked = tracked;
  untracked.energy_balance = false;
  FastEngine fast(tracked);
  FastEngine lazy(untracked);
  for (int block = 0; block < 2; ++block) {
    fast.advance(75);
    lazy.advance(75);
    const std::vector<BoundaryLoad> want = fast.boundary_loads();
    const std::vector<BoundaryLoad> got = lazy.boundary_loads();
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t b = 0; b < want.size(); ++b) {
      for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(got[b].force[c], want[b].force[c]) << "boundary " << b;
        EXPECT_EQ(got[b].moment_about_origin[c], want[b].moment_about_origin[c]) << "boundary " << b;
      }
    }
    EXPECT_NE(want[0].force.z(), 0.0);  // not vacuous: the floor carries the bed
    EXPECT_EQ(lazy.energies().kinetic, fast.energies().kinetic);
    EXPECT_EQ(lazy.escaped_count(), fast.escaped_count());
    EXPECT_TRUE(lazy.motion_finite());
  }
  // A checkpoint (saved from the lazy engine: its loads summed when asked) restores the same run.
  const EngineState state = lazy.save_state();
  ASSERT_EQ(state.boundary_loads.size(), fast.boundary_loads().size());
  EXPECT_EQ(state.boundary_loads[0].force.z(), fast.boundary_loads()[0].force.z());
  // One non-finite component of a velocity or a spin enters the state; after one step the
  // screen fails and the run checks name the particle.
  for (const bool spin : {false, true}) {
    EngineState broken = state;
    Vec3& value = spin ? broken.particles[7].angular_velocity : broken.particles[7].velocity;
    value.y() = std::numeric_limits<double>::quiet_NaN();
    FastEngine engine(untracked);
    engine.restore_state(broken);
    RunDiagnostics checks(untracked, RunChecks{}, engine.energies());
    engine.step();
    EXPECT_FALSE(engine.motion_finite()) << (spin ? "spin" : "velocity");
    const std::optional<std::string> diagnosis = checks.check(engine);
    ASSERT_TRUE(diagnosis.has_value()) << (spin ? "spin" : "velocity");
    EXPECT_NE(diagnosis->find("is not finite"), std::string::npos) << *diagnosis;
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, FastAgainstReference,
                         ::testing::Values(SceneKind::kHertzFrictionWalls, SceneKind::kLinearFrictionWallsObject,
                                           SceneKind::kHertzFrictionlessFree),
                         [](const auto& test_info) {
                           switch (test_info.param) {
                             case SceneKind::kHertzFrictionWalls: return std::string("HertzFrictionWalls");
                             case SceneKind::kLinearFrictionWallsObject: return std::string("LinearFrictionWallsObject");
                             default: return std::string("HertzFrictionlessFree");
                           }
                         });

// The four-lane contact law (FastOptions::vector_contacts, on by default where the CPU has AVX)
// against one contact at a time through the whole engine: the same bits in every particle and
// in the energies (the same terms summed in the same order), with and without energy tracking.
// Untracked, the four-lane law also adds the particles' own sums, counts the pairs and offers
// the deepest contact (OwnSums): the counts and the deepest contact must match as well.
TEST(FastEngine, VectorContactsGiveTheBitsOfOneAtATime) {
  for (const bool tracked : {true, false}) {
    SimulationSetup setup = scene(SceneKind::kHertzFrictionWalls);
    setup.energy_balance = tracked;
    fast::FastOptions one_at_a_time;
    one_at_a_time.vector_contacts = false;
    FastEngine vector(setup);
    FastEngine scalar(setup, one_at_a_time);
    for (int block = 0; block < 3; ++block) {
      vector.advance(100);
      scalar.advance(100);
      expect_same_bits(scalar.particles(), vector.particles(), "after " + std::to_string(vector.step_count()) + " steps");
      const Energies a = scalar.energies();
      const Energies b = vector.energies();
      if (tracked) {
        EXPECT_EQ(a.elastic, b.elastic);
        EXPECT_EQ(a.dissipated, b.dissipated);
        EXPECT_EQ(a.boundary_work, b.boundary_work);
      }
      EXPECT_EQ(a.kinetic, b.kinetic);
      EXPECT_EQ(vector.contact_counts().particle_pairs, scalar.contact_counts().particle_pairs);
      ASSERT_TRUE(vector.largest_overlap().has_value());
      EXPECT_EQ(vector.largest_overlap()->ratio, scalar.largest_overlap()->ratio);
      EXPECT_EQ(vector.largest_overlap()->overlap, scalar.largest_overlap()->overlap);
      EXPECT_EQ(vector.largest_overlap()->id_a, scalar.largest_overlap()->id_a);
      EXPECT_EQ(vector.largest_overlap()->id_b, scalar.largest_overlap()->id_b);
      EXPECT_EQ(vector.largest_overlap()->boundary, scalar.largest_overlap()->boundary);
    }
    EXPECT_GT(vector.contact_counts().particle_pairs, 50u);  // not vacuous
  }
}

// A particle none of whose pair slots can touch (its smallest gap at the list build above twice
// the largest displacement since) is not screened: the same bits as screening every slot, and
// as the reference engine, with contacts forming and breaking and lists rebuilt.
TEST(FastEngine, SlotsThatCannotTouchAreSkippedWithTheSameBits) {
  for (const SceneKind kind : {SceneKind::kHertzFrictionWalls, SceneKind::kLinearFrictionWallsObject}) {
    SCOPED_TRACE(kind == SceneKind::kHertzFrictionWalls ? "Hertz, walls" : "linear, walls, object");
    const SimulationSetup setup = scene(kind);
    fast::FastOptions screen_all;
    screen_all.skip_apart_slots = false;
    FastEngine skipping(setup);
    FastEngine screening(setup, screen_all);
    ReferenceEngine reference(setup);
    for (int block = 0; block < 3; ++block) {
      skipping.advance(100);
      screening.advance(100);
      reference.advance(100);
      const std::string when = "after " + std::to_string(skipping.step_count()) + " steps";
      expect_same_bits(screening.particles(), skipping.particles(), when + ", skip on/off");
      expect_same_bits(reference.particles(), skipping.particles(), when + ", reference");
      EXPECT_EQ(skipping.energies().dissipated, screening.energies().dissipated) << when;
      EXPECT_EQ(skipping.contact_counts().particle_pairs, screening.contact_counts().particle_pairs) << when;
    }
    // Not vacuous: slots were skipped, none when told not to, and contacts formed.
    EXPECT_GT(skipping.skipped_screens(), 1000u);
    EXPECT_EQ(screening.skipped_screens(), 0u);
    EXPECT_GT(skipping.contact_counts().particle_pairs, 50u);
    EXPECT_GT(skipping.neighbour_list_builds(), 5);
  }
}

// The kernel's thread ranges: cut by estimated work, then corrected by the ranges' measured
// times. Without neighbour lists every particle weighs the same (8), so the cuts are exact
// fractions of n: even at first; with range 0 measured twice as slow as range 1, the shares
// that would have equalised the times are (1/3, 2/3) and the damped new shares half-way
// there, (5/12, 7/12); a range that stays far slower is held at 1/2 of an even share.
TEST(FastEngine, ThreadRangesFollowTheMeasuredTimes) {
  fast::FastState s;
  s.owned = 1200;
  fast::balance_split(s, 2);
  EXPECT_EQ(s.split, (std::vector<std::size_t>{0, 600, 1200}));
  s.range_seconds = {1.0, 1.0};  // balanced: the cut stays
  fast::balance_split(s, 2);
  EXPECT_EQ(s.split[1], 600u);
  s.range_seconds = {2.0, 1.0};
  fast::balance_split(s, 2);
  EXPECT_EQ(s.split[1], 500u);  // 1200 * 5/12
  EXPECT_NEAR(s.range_share[0], 5.0 / 12.0, 1e-15);
  EXPECT_EQ(s.range_seconds, (std::vector<double>{0.0, 0.0}));  // a new interval
  fast::balance_split(s, 2);  // no times measured: the even cut again
  EXPECT_EQ(s.split[1], 600u);
  s.range_seconds = {1000.0, 1.0};  // half-way towards ~0: a share just above 1/4
  fast::balance_split(s, 2);
  EXPECT_GT(s.range_share[0], 0.25);
  EXPECT_LT(s.range_share[0], 0.251);
  s.range_seconds = {1000.0, 1.0};  // again: held at the floor 1/4 (1/2 of an even share)
  fast::balance_split(s, 2);
  EXPECT_EQ(s.split[1], 300u);
}

// The threads' speeds against each other (a diagnostic, fast_engine.hpp ThreadSpeeds), by hand:
// shares (1/2, 1/2) in (1 s, 2 s) are speeds 1/2 and 1/4 per second, ratio 1/2 over an interval
// of 2 s; (1/4, 3/4) in (1 s, 1 s): ratio 1/3 over 1 s; (0.4, 0.6) in (2 s, 3 s): equal speeds
// 0.2, ratio 1 over 3 s. Mean (1/2 * 2 + 1/3 * 1 + 1 * 3) / 6 = 13/18; below 0.9: 3 s of 6.
// Then balance_split records each interval it cuts after, and one thread records none.
TEST(FastEngine, ThreadSpeedsAreTheSlowestRangesSpeedOverTheFastests) {
  fast::ThreadSpeeds speeds;
  EXPECT_EQ(speeds.mean_ratio(), 1.0);  // no interval yet
  speeds.record({0.5, 0.5}, {1.0, 2.0});
  EXPECT_NEAR(speeds.mean_ratio(), 0.5, 1e-15);
  speeds.record({0.25, 0.75}, {1.0, 1.0});
  EXPECT_NEAR(speeds.mean_ratio(), 4.0 / 9.0, 1e-15);
  speeds.record({0.4, 0.6}, {2.0, 3.0});
  speeds.record({1.0}, {1.0});            // one range
  speeds.record({0.5, 0.5}, {1.0, 0.0});  // a range without time
  speeds.record({0.5, 0.5}, {1.0});       // sizes differ
  EXPECT_EQ(speeds.intervals, 3u);
  EXPECT_NEAR(speeds.seconds, 6.0, 1e-15);
  EXPECT_NEAR(speeds.mean_ratio(), 13.0 / 18.0, 1e-15);
  EXPECT_NEAR(speeds.fraction_below_0_9(), 0.5, 1e-15);

  fast::FastState s;
  s.owned = 1200;
  fast::balance_split(s, 2);  // the first cut: no interval before it
  EXPECT_EQ(s.thread_speeds.intervals, 0u);
  s.range_seconds = {2.0, 1.0};  // even shares, range 0 took twice as long: ratio 1/2
  fast::balance_split(s, 2);
  EXPECT_EQ(s.thread_speeds.intervals, 1u);
  EXPECT_NEAR(s.thread_speeds.mean_ratio(), 0.5, 1e-15);
#ifdef PPOHDEM_WITH_OPENMP
  const SimulationSetup setup = scene(SceneKind::kHertzFrictionWalls);  // 1,500 particles: the kernel on every thread
  const int before = omp_get_max_threads();
  auto run = [&](int threads) {
    omp_set_num_threads(threads);
    FastEngine engine(setup);
    engine.advance(300);
    return std::pair(engine.neighbour_list_builds(), engine.thread_speeds());
  };
  const auto [builds_one, one] = run(1);
  const auto [builds_two, two] = run(2);
  omp_set_num_threads(before);
  EXPECT_EQ(one.intervals, 0u);
  ASSERT_GT(builds_two, 1);  // else no interval was measured
  EXPECT_GE(two.intervals, 1u);
  EXPECT_LE(two.intervals, static_cast<std::size_t>(builds_two));  // at most one per list build
  EXPECT_GT(two.mean_ratio(), 0.0);
  EXPECT_LE(two.mean_ratio(), 1.0);
#endif
}

TEST(FastEngine, FinalStateIsBitwiseTheSameForOneAndTwoThreads) {
#ifndef PPOHDEM_WITH_OPENMP
  GTEST_SKIP() << "built without OpenMP (PPOHDEM_ENABLE_OPENMP=OFF)";
#else
  const SimulationSetup setup = scene(SceneKind::kLinearFrictionWallsObject);
  const int before = omp_get_max_threads();
  auto run = [&](int threads) {
    omp_set_num_threads(threads);
    FastEngine engine(setup);
    engine.advance(300);
    return std::pair(engine.particles(), engine.energies());
  };
  const auto one = run(1);
  const auto two = run(2);
  omp_set_num_threads(before);
  expect_same_bits(one.first, two.first, "1 vs 2 threads");
  // Energies are summed exactly and rounded once (exact_sum.hpp): the same bits too.
  EXPECT_EQ(one.second.elastic, two.second.elastic);
  EXPECT_EQ(one.second.dissipated, two.second.dissipated);
  EXPECT_EQ(one.second.boundary_work, two.second.boundary_work);
#endif
}

// The fast engine sorts its cells with the longest axis varying slowest (cell_grid.hpp,
// with_longest_axis_slowest), so in a box longer in x or in y than in z the cell order and the
// neighbour search's rows (along the fastest axis) differ from the reference's x, y, z order.
// Boxes long in x (order y, z, x) and long in y (x, z, y): the reference's bits, on 1 and on 2
// threads.
TEST(FastEngine, CellsOrderedAcrossTheLongestAxisKeepTheReferencesBits) {
  for (const Vec3& shape : {Vec3(4.0, 1.0, 0.5), Vec3(1.0, 4.0, 0.5)}) {
    const SimulationSetup setup = scene(SceneKind::kHertzFrictionWalls, shape);
    // Not vacuous: these centres' grid has a slowest axis other than z.
    std::vector<Vec3> centres;
    for (const Particle& p : setup.particles) centres.push_back(p.position);
    const CellGrid grid = with_longest_axis_slowest(cell_grid_for(centres, 2.0 * kR));
    const std::size_t longest = shape.x() > shape.y() ? 0 : 1;
    ASSERT_EQ(grid.order[2], longest);
    ASSERT_EQ(grid.order[0], longest == 0 ? 1u : 0u);
    ReferenceEngine reference(setup);
    reference.advance(300);
    std::vector<int> thread_counts = {1};
#ifdef PPOHDEM_WITH_OPENMP
    thread_counts.push_back(2);
    const int before = omp_get_max_threads();
#endif
    for (int threads : thread_counts) {
#ifdef PPOHDEM_WITH_OPENMP
      omp_set_num_threads(threads);
#endif
      FastEngine fast(setup);
      fast.advance(300);
      const std::string what = "box " + std::to_string(shape.x()) + " x " + std::to_string(shape.y()) + ", " + std::to_string(threads) + " thread(s)";
      expect_same_bits(reference.particles(), fast.particles(), what);
      EXPECT_GT(fast.contact_counts().particle_pairs, 50u) << what;
      EXPECT_GT(fast.neighbour_list_builds(), 10) << what;
    }
#ifdef PPOHDEM_WITH_OPENMP
    omp_set_num_threads(before);
#endif
  }
}

TEST(FastEngine, ThreadCountChangedMidRunContinuesBitwise) {
#ifndef PPOHDEM_WITH_OPENMP
  GTEST_SKIP() << "built without OpenMP (PPOHDEM_ENABLE_OPENMP=OFF)";
#else
  // The tangential springs live in per-thread pools (fast_state.hpp): a change of the thread
  // count between steps re-lays them out. 1500 frictional particles (above kParallelMin, so
  // the loops really run on 2 threads) with contacts beginning and ending all the time: the
  // run switched 2 -> 1 -> 2 threads between list builds must equal a 1-thread run bit for bit.
  const SimulationSetup setup = scene(SceneKind::kHertzFrictionWalls);
  const int before = omp_get_max_threads();
  omp_set_num_threads(1);
  FastEngine steady(setup);
  steady.advance(300);
  omp_set_num_threads(2);
  FastEngine switched(setup);
  switched.advance(97);
  omp_set_num_threads(1);
  switched.advance(101);
  omp_set_num_threads(2);
  switched.advance(102);
  omp_set_num_threads(before);
  ASSERT_GT(steady.contact_counts().particle_pairs, 100u) << "the scene must have frictional contacts";
  expect_same_bits(steady.particles(), switched.particles(), "1 thread vs 2 -> 1 -> 2 threads");
  EXPECT_EQ(steady.energies().dissipated, switched.energies().dissipated);
#endif
}

/// A fast oblique collision among 1,200 resting spheres far apart (more than kParallelMin, so
/// the list builds run on every thread): the pair separates at about 40 m/s, so it moves apart by
/// more than the skin (0.2 R = 0.1 mm) within one step, and its history (the tangential spring
/// has stored energy) leaves the neighbour list at a build without the kernel seeing the
/// contact end: the "lost" history path of the list build (FastEngine::Impl::install_history).
/// Such an impact is far too fast for dt (a few steps per contact): the energy balance drifts by
/// a few per cent in both engines alike, so the test compares the engines, not the balance.
SimulationSetup lost_history_scene() {
  SimulationSetup s;
  s.material = glass_like(0.5);
  s.material.restitution = 1.0;  // no dashpot: the normal force stays positive to the last touching step
  s.law = HertzMindlin::from_material(s.material);
  s.dt = 0.2 * rayleigh_time(kR, s.material);
  Particles p;
  for (int k = 0; k < 1200; ++k) {  // a 10 x 10 x 12 lattice at spacing 4 R
    Particle q;
    q.id = k + 1;
    q.radius = kR;
    q.position = 4.0 * kR * Vec3(k % 10, (k / 10) % 10, k / 100);
    p.push_back(q);
  }
  // The pair, beside the lattice: B at rest, A coming at 40 m/s along x with an offset of R/2
  // in y (oblique: tangential slip), first touching after about 2 steps.
  Particle a, b;
  a.id = 5001;
  b.id = 5002;
  a.radius = b.radius = kR;
  b.position = Vec3(60.0 * kR, 0.0, 0.0);
  a.position = b.position - Vec3(2.0 * kR + 40.0 * s.dt * 2.0, 0.5 * kR, 0.0);
  a.velocity = Vec3(40.0, 0.0, 0.0);  // [m/s]
  p.push_back(a);
  p.push_back(b);
  s.particles = p;
  s.source = "fast_engine_test (lost history)";
  return s;
}

TEST(FastEngine, AHistoryLostAtAListBuildIsBookedOnceOnAnyThreadCount) {
  const SimulationSetup setup = lost_history_scene();
  ReferenceEngine reference(setup);
  FastEngine fast(setup);
  // The contact lasts a few tens of steps at this speed; 200 steps take the pair well apart.
  double most_stored = 0.0;  // the largest elastic energy seen [J]
  for (int step = 0; step < 200; ++step) {
    reference.step();
    fast.step();
    most_stored = std::max(most_stored, fast.energies().elastic);
  }
  const Energies r = reference.energies();
  const Energies f = fast.energies();
  ASSERT_GT(most_stored, 0.0) << "the pair must collide";
  EXPECT_EQ(f.elastic, 0.0) << "the pair is apart: nothing stored";
  EXPECT_EQ(r.elastic, 0.0);
  // The trajectories are the reference's bit for bit (its ending contact frees the spring at the
  // kernel, the fast engine's at the build: the forces do not depend on which).
  expect_same_bits(reference.particles(), fast.particles(), "fast vs reference, lost history");
  // The lost spring's stored energy is dissipated in both engines (the reference books it when
  // its kernel sees the contact end, the fast engine at the build): the totals agree to
  // round-off. Bound: 1e-12 of the energy in play (the sums' round-off is about 1e-16 of it per
  // operation); a spring dropped without booking misses its stored energy, 5.6e-6 J against
  // about 1e-3 J in play (a negative control that skipped the booking failed both checks).
  const double in_play = r.kinetic;  // [J]
  EXPECT_NEAR(f.dissipated, r.dissipated, 1e-12 * in_play);
  EXPECT_NEAR(f.total(), r.total(), 1e-12 * in_play);
#ifdef PPOHDEM_WITH_OPENMP
  // The same bits on 1 and 2 threads (the build's merge runs in blocks per thread).
  const int before = omp_get_max_threads();
  auto run = [&](int threads) {
    omp_set_num_threads(threads);
    FastEngine engine(setup);
    engine.advance(200);
    return engine.energies();
  };
  const Energies one = run(1);
  const Energies two = run(2);
  omp_set_num_threads(before);
  EXPECT_EQ(one.dissipated, two.dissipated);
  EXPECT_EQ(one.kinetic, two.kinetic);
#endif
}

TEST(FastEngine, KineticEnergySumsAreTheReferencesBitwiseOnTwoThreads) {
#ifndef PPOHDEM_WITH_OPENMP
  GTEST_SKIP() << "built without OpenMP (PPOHDEM_ENABLE_OPENMP=OFF)";
#else
  // Both engines sum over particles exactly and round once (exact_sum.hpp); the fast engine
  // sums on its threads. With 2 threads (1500 particles: above the 1,024 below which the loops
  // run on one thread) its kinetic, rotational and gravitational energies and its boundary
  // loads (the same terms, record by record) must be the reference's bits.
  const SimulationSetup setup = scene(SceneKind::kHertzFrictionWalls);
  ASSERT_GT(setup.particles.size(), 1024u) << "the sums would run on one thread";
  ReferenceEngine reference(setup);
  reference.advance(200);
  const int before = omp_get_max_threads();
  omp_set_num_threads(1);
  FastEngine one(setup);
  one.advance(200);
  omp_set_num_threads(2);
  FastEngine two(setup);
  two.advance(200);
  omp_set_num_threads(before);
  const Energies er = reference.energies();
  const Energies ef = two.energies();
  EXPECT_EQ(ef.kinetic, er.kinetic);
  EXPECT_EQ(ef.rotational, er.rotational);
  EXPECT_EQ(ef.gravitational, er.gravitational);
  EXPECT_GT(er.kinetic, 0.0);
  const auto l1 = one.boundary_loads();
  const auto l2 = two.boundary_loads();
  const auto lr = reference.boundary_loads();
  ASSERT_EQ(l1.size(), l2.size());
  ASSERT_EQ(lr.size(), l2.size());
  for (std::size_t b = 0; b < l1.size(); ++b) {
    EXPECT_EQ(l1[b].force, l2[b].force) << "boundary " << b;
    EXPECT_EQ(l1[b].moment_about_origin, l2[b].moment_about_origin) << "boundary " << b;
    EXPECT_EQ(lr[b].force, l2[b].force) << "boundary " << b << " against the reference";
    EXPECT_EQ(lr[b].moment_about_origin, l2[b].moment_about_origin) << "boundary " << b << " against the reference";
  }
  EXPECT_GT(two.contact_counts().particle_boundary, 20u);  // the loads are not all zero
#endif
}

// More ranges than two: the force kernel cuts its first pass and its sum pass differently, and
// the sum pass reads each particle's new boundary records from the block of the first-pass
// range it fell in (force_kernel.cpp), so with 3 and 4 threads (ranges of ~375-500 particles
// here, more threads than this machine's cores) a sum range meets several blocks. A
// frictionless walled box runs the kernel without a sum pass, whose records are merged right
// after the first pass. Oracles: the reference's trajectories and contact counts, and the
// boundary loads of one thread (the loads are summed from the merged records table in storage
// order, the same bits on any count).
TEST(FastEngine, ThreeAndFourThreadsKeepTheReferencesBitsAndOneThreadsLoads) {
#ifndef PPOHDEM_WITH_OPENMP
  GTEST_SKIP() << "built without OpenMP (PPOHDEM_ENABLE_OPENMP=OFF)";
#else
  const int before = omp_get_max_threads();
  SimulationSetup frictionless_walls = scene(SceneKind::kHertzFrictionWalls);
  frictionless_walls.material.friction = 0.0;
  frictionless_walls.law = HertzMindlin::from_material(frictionless_walls.material);
  const std::vector<std::pair<std::string, SimulationSetup>> setups = {
      {"Hertz-Mindlin, walls", scene(SceneKind::kHertzFrictionWalls)},
      {"linear, walls and an object", scene(SceneKind::kLinearFrictionWallsObject)},
      {"Hertz frictionless, walls", frictionless_walls}};
  for (const auto& [name, setup] : setups) {
    ReferenceEngine reference(setup);
    reference.advance(200);
    omp_set_num_threads(1);
    FastEngine one(setup);
    one.advance(200);
    const auto loads_one = one.boundary_loads();
    for (const int threads : {3, 4}) {
      omp_set_num_threads(threads);
      FastEngine fast(setup);
      fast.advance(200);
      const std::string what = name + ", " + std::to_string(threads) + " threads";
      expect_same_bits(reference.particles(), fast.particles(), what);
      EXPECT_EQ(reference.contact_counts().particle_pairs, fast.contact_counts().particle_pairs) << what;
      EXPECT_EQ(reference.contact_counts().particle_boundary, fast.contact_counts().particle_boundary) << what;
      EXPECT_GT(fast.contact_counts().particle_boundary, 20u) << what;  // records to read
      const auto loads = fast.boundary_loads();
      // EXPECT, not ASSERT: a return here would leave the thread count changed for later tests.
      EXPECT_EQ(loads.size(), loads_one.size()) << what;
      for (std::size_t b = 0; b < std::min(loads.size(), loads_one.size()); ++b) {
        EXPECT_EQ(loads[b].force, loads_one[b].force) << what << ", boundary " << b;
        EXPECT_EQ(loads[b].moment_about_origin, loads_one[b].moment_about_origin) << what << ", boundary " << b;
      }
    }
  }
  omp_set_num_threads(before);
#endif
}

TEST(FastEngine, RestartFromItsCheckpointIsBitwise) {
  const SimulationSetup setup = scene(SceneKind::kLinearFrictionWallsObject);
  FastEngine straight(setup);
  straight.advance(150);
  const EngineState saved = straight.save_state();
  EXPECT_FALSE(saved.contacts.empty());  // histories are part of the checkpoint
  FastEngine restarted(setup);
  restarted.restore_state(saved);
  straight.advance(150);
  restarted.advance(150);
  expect_same_bits(straight.particles(), restarted.particles(), "restart");
  EXPECT_EQ(straight.energies().dissipated, restarted.energies().dissipated);
  EXPECT_EQ(straight.energies().elastic, restarted.energies().elastic);
  EXPECT_EQ(straight.energies().boundary_work, restarted.energies().boundary_work);  // P(n) saved
}

TEST(FastEngine, ContinuesAReferenceCheckpointBitwise) {
  // The checkpoint is engine-neutral (histories keyed by ids): the reference's state restored
  // into the fast engine continues exactly as the reference does.
  const SimulationSetup setup = scene(SceneKind::kHertzFrictionWalls);
  ReferenceEngine reference(setup);
  reference.advance(120);
  FastEngine fast(setup);
  fast.restore_state(reference.save_state());
  reference.advance(120);
  fast.advance(120);
  expect_same_bits(reference.particles(), fast.particles(), "reference checkpoint continued");
}

TEST(FastEngine, CheckpointEqualsTheReferencesCheckpoint) {
  // Same scene, same step: the contact histories of both engines are the same records. With
  // the energies untracked the fast kernel does not keep the pairs' branch vectors (only the
  // energy terms read them) and save_state writes them from the positions: the same bits as
  // the reference's stored ones, with the four-lane law and with one contact at a time.
  for (const bool tracked : {true, false}) {
    for (const bool vector_contacts : {true, false}) {
      SimulationSetup setup = scene(SceneKind::kHertzFrictionWalls);
      setup.energy_balance = tracked;
      fast::FastOptions options;
      options.vector_contacts = vector_contacts;
      ReferenceEngine reference(setup);
      FastEngine fast(setup, options);
      reference.advance(200);
      fast.advance(200);
      const EngineState a = reference.save_state();
      const EngineState b = fast.save_state();
      const std::string mode = std::string(tracked ? "tracked" : "untracked") + (vector_contacts ? ", four lanes" : ", one at a time");
      ASSERT_EQ(a.contacts.size(), b.contacts.size()) << mode;
      std::size_t pairs = 0;
      for (std::size_t c = 0; c < a.contacts.size(); ++c) {
        EXPECT_EQ(a.contacts[c].id_a, b.contacts[c].id_a) << mode;
        EXPECT_EQ(a.contacts[c].id_b, b.contacts[c].id_b) << mode;
        EXPECT_EQ(a.contacts[c].spring.displacement, b.contacts[c].spring.displacement) << mode;
        EXPECT_EQ(a.contacts[c].spring.stiffness, b.contacts[c].spring.stiffness) << mode;
        EXPECT_EQ(a.contacts[c].spring.branch_i, b.contacts[c].spring.branch_i) << mode;
        EXPECT_EQ(a.contacts[c].spring.branch_j, b.contacts[c].spring.branch_j) << mode;
        if (a.contacts[c].kind == ContactHistoryRecord::Kind::kParticlePair) ++pairs;
      }
      EXPECT_GT(pairs, 50u) << mode;  // not vacuous: pair histories compared
      EXPECT_EQ(a.escaped_ids, b.escaped_ids) << mode;
    }
  }
}

TEST(FastEngine, RefusesACheckpointOfAnotherScene) {
  SimulationSetup setup = scene(SceneKind::kHertzFrictionlessFree);
  FastEngine engine(setup);
  EngineState state = engine.save_state();
  state.dt *= 2.0;
  EXPECT_THROW(engine.restore_state(state), InputError);
}

}  // namespace
}  // namespace ppohdem::dem::test
