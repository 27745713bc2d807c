// Checkpoint/restart of the engines (issue 10, item 2): a run of 2N steps and a run of N
// steps + save_state + checkpoint file + restore_state into a NEW engine + N steps end in
// bitwise the same state: particles (every double), energies, contact histories with their
// keys, boundary loads and contact counts. The oracle is the uninterrupted run. The scene
// (reliability_scenes.hpp) has particle-pair and particle-wall friction histories, a moving
// wall and a moving, rotating object; a control shows that dropping the histories at the
// restart changes the result, so the comparison does see them.
#include <gtest/gtest.h>

#include <cstring>

#include "../dem/dem_test_support.hpp"
#include "ppohdem/dem/checkpoint.hpp"
#include "reliability_scenes.hpp"

namespace ppohdem::dem::test {
namespace {

constexpr long kHalf = 200;  // N: the ball touches the pile after ~120 steps

/// Bitwise equality of doubles (== would accept -0.0 for 0.0).
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool same_bits(const Vec3& a, const Vec3& b) {
  return same_bits(a.x(), b.x()) && same_bits(a.y(), b.y()) && same_bits(a.z(), b.z());
}

void expect_identical(const EngineState& a, const EngineState& b) {
  EXPECT_EQ(a.step, b.step);
  ASSERT_EQ(a.particles.size(), b.particles.size());
  for (std::size_t i = 0; i < a.particles.size(); ++i) {
    const Particle& p = a.particles[i];
    const Particle& q = b.particles[i];
    EXPECT_EQ(p.id, q.id);
    EXPECT_TRUE(same_bits(p.position, q.position) && same_bits(p.velocity, q.velocity) &&
                same_bits(p.angular_velocity, q.angular_velocity) && same_bits(p.force, q.force) &&
                same_bits(p.torque, q.torque) && same_bits(p.radius, q.radius))
        << "particle id " << p.id;
  }
  const Energies& e = a.accumulators;
  const Energies& f = b.accumulators;
  const auto energy = [](const char* name, double x, double y) {
    EXPECT_TRUE(same_bits(x, y)) << name << ": " << x << " vs " << y << " (difference " << x - y << " J)";
  };
  energy("kinetic", e.kinetic, f.kinetic);
  energy("rotational", e.rotational, f.rotational);
  energy("gravitational", e.gravitational, f.gravitational);
  energy("elastic", e.elastic, f.elastic);
  energy("dissipated", e.dissipated, f.dissipated);
  energy("boundary_work", e.boundary_work, f.boundary_work);
  ASSERT_EQ(a.contacts.size(), b.contacts.size());
  for (std::size_t c = 0; c < a.contacts.size(); ++c) {
    const ContactHistoryRecord& r = a.contacts[c];
    const ContactHistoryRecord& s = b.contacts[c];
    EXPECT_TRUE(r.kind == s.kind && r.id_a == s.id_a && r.id_b == s.id_b) << "contact " << c;
    EXPECT_TRUE(same_bits(r.spring.displacement, s.spring.displacement) &&
                same_bits(r.spring.stiffness, s.spring.stiffness) &&
                same_bits(r.spring.branch_i, s.spring.branch_i) && same_bits(r.spring.branch_j, s.spring.branch_j) &&
                same_bits(r.spring.surface_velocity, s.spring.surface_velocity))
        << "contact (" << r.id_a << ", " << r.id_b << ")";
  }
  EXPECT_EQ(a.escaped_ids, b.escaped_ids);
  ASSERT_EQ(a.boundary_loads.size(), b.boundary_loads.size());
  for (std::size_t w = 0; w < a.boundary_loads.size(); ++w) {
    EXPECT_TRUE(same_bits(a.boundary_loads[w].force, b.boundary_loads[w].force) &&
                same_bits(a.boundary_loads[w].moment_about_origin, b.boundary_loads[w].moment_about_origin))
        << "boundary " << w;
  }
  EXPECT_EQ(a.contact_counts.particle_pairs, b.contact_counts.particle_pairs);
  EXPECT_EQ(a.contact_counts.particle_boundary, b.contact_counts.particle_boundary);
  EXPECT_TRUE(same_bits(a.boundary_power, b.boundary_power));
}

/// save_state, or a skip for an engine that declares it has no checkpoints (engine.hpp).
template <class Engine>
std::optional<EngineState> save_or_skip(const Engine& engine) {
  try {
    return engine.save_state();
  } catch (const InputError& e) {
    if (std::string(e.what()).find("does not support checkpoints") == std::string::npos) throw;
    return std::nullopt;
  }
}

/// Through the file format: encode to bytes and decode again.
EngineState through_file(const EngineState& state) {
  Checkpoint c;
  c.engine = state;
  return decode_checkpoint(encode_checkpoint(c), "memory").engine;
}

template <class Engine>
class CheckpointRestart : public ::testing::Test {};
TYPED_TEST_SUITE(CheckpointRestart, EngineTypes);

TYPED_TEST(CheckpointRestart, TwoHalvesEqualOneWholeBitwise) {
  const SimulationSetup setup = pile_setup();
  TypeParam whole(setup);
  whole.advance(2 * kHalf);

  TypeParam first(setup);
  first.advance(kHalf);
  const auto saved = save_or_skip(first);
  if (!saved) GTEST_SKIP() << first.name() << " declares no checkpoint support";
  // The checkpoint must hold what the comparison is about: histories of both kinds, the
  // object among the touched boundaries, energy already dissipated.
  std::size_t pairs = 0, walls = 0, ball = 0;
  for (const ContactHistoryRecord& r : saved->contacts) {
    if (r.kind == ContactHistoryRecord::Kind::kParticlePair) ++pairs;
    else if (r.id_b == kBallBoundary) ++ball;
    else ++walls;
  }
  EXPECT_GE(pairs, 5u);
  EXPECT_GE(walls, 2u);
  EXPECT_GT(ball, 0u) << "the ball must touch the pile before the checkpoint";
  EXPECT_GT(saved->accumulators.dissipated, 0.0);

  TypeParam second(setup);  // a fresh engine, as after a restart in a new process
  second.restore_state(through_file(*saved));
  expect_identical(second.save_state(), *saved);  // restore + save is the identity
  second.advance(kHalf);
  expect_identical(second.save_state(), whole.save_state());
  EXPECT_NE(whole.boundary_loads().at(kBallBoundary).force.norm(), 0.0);
}

// Control: the same restart without the contact histories ends elsewhere, so the bitwise
// comparison above would notice a checkpoint that forgot them.
TYPED_TEST(CheckpointRestart, DroppingTheHistoriesChangesTheResult) {
  const SimulationSetup setup = pile_setup();
  TypeParam whole(setup);
  whole.advance(2 * kHalf);
  TypeParam first(setup);
  first.advance(kHalf);
  auto saved = save_or_skip(first);
  if (!saved) GTEST_SKIP() << first.name() << " declares no checkpoint support";
  saved->contacts.clear();
  TypeParam second(setup);
  second.restore_state(*saved);
  second.advance(kHalf);
  const Particles& p = second.particles();
  const Particles& q = whole.particles();
  double largest = 0.0;  // largest position difference [m]
  for (std::size_t i = 0; i < p.size(); ++i) largest = std::max(largest, (p[i].position - q[i].position).norm());
  EXPECT_GT(largest, 1e-9);  // 1 nm: far above round-off (1e-19 m) of positions ~1e-3 m
}

TYPED_TEST(CheckpointRestart, RestoreRefusesTheStateOfAnotherScene) {
  const SimulationSetup setup = pile_setup();
  TypeParam engine(setup);
  const auto saved = save_or_skip(engine);
  if (!saved) GTEST_SKIP() << engine.name() << " declares no checkpoint support";
  SimulationSetup other_dt = setup;
  other_dt.dt = 0.5 * setup.dt;
  TypeParam a(other_dt);
  EXPECT_THROW(a.restore_state(*saved), InputError);
  SimulationSetup fewer = setup;
  fewer.particles.pop_back();
  TypeParam b(fewer);
  EXPECT_THROW(b.restore_state(*saved), InputError);
  SimulationSetup no_walls = setup;
  no_walls.boundaries.clear();
  TypeParam c(no_walls);
  EXPECT_THROW(c.restore_state(*saved), InputError);
}

}  // namespace
}  // namespace ppohdem::dem::test
