// Scene and particle-file input: the issue's example runs, bad input is refused clearly.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <utility>

#include "dem_test_support.hpp"
#include "ppohdem/dem/fast/fast_engine.hpp"
#include "ppohdem/dem/particle_csv.hpp"
#include "ppohdem/dem/run.hpp"
#include "ppohdem/dem/scene.hpp"
#include "ppohdem/error.hpp"
#include "test_paths.hpp"

namespace ppohdem::dem::test {
namespace {

namespace fs = std::filesystem;

fs::path write(const fs::path& file, const std::string& text) {
  std::ofstream(file) << text;
  return file;
}

template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

const char* kHeader = "id,x,y,z,vx,vy,vz,wx,wy,wz,radius\n";

/// The text of a fixture file.
std::string fixture_text(const std::string& name) {
  std::ifstream in(ppohdem::test::fixture(name));
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(ParticleCsv, RejectsNegativeRadiusNamingTheLine) {
  const auto f = write(ppohdem::test::scratch_dir() / "p.csv",
                       std::string(kHeader) + "1,0,0,0,0,0,0,0,0,0,1e-3\n2,1,0,0,0,0,0,0,0,0,-1e-3\n");
  const std::string msg = error_of([&] { read_particles_csv(f); });
  EXPECT_NE(msg.find("p.csv:3"), std::string::npos) << msg;
  EXPECT_NE(msg.find("radius"), std::string::npos) << msg;
}

TEST(ParticleCsv, RejectsNaNNamingTheLine) {
  const auto f = write(ppohdem::test::scratch_dir() / "p.csv",
                       std::string("# comment\n") + kHeader + "1,0,nan,0,0,0,0,0,0,0,1e-3\n");
  const std::string msg = error_of([&] { read_particles_csv(f); });
  EXPECT_NE(msg.find("p.csv:3"), std::string::npos) << msg;
  EXPECT_NE(msg.find("finite"), std::string::npos) << msg;
}

TEST(ParticleCsv, WriteThenReadRoundTripsExactly) {
  Particles p = {sphere(7, Vec3(0.1, 1.0 / 3.0, -2e-9), Vec3(1e-300, 2, 3), 0.123456789012345)};
  p[0].angular_velocity = Vec3(-4, 5, 6.0 / 7.0);
  const auto f = ppohdem::test::scratch_dir() / "q.csv";
  write_particles_csv(f, p, "header");
  const Particles q = read_particles_csv(f);
  ASSERT_EQ(q.size(), 1u);
  EXPECT_EQ(q[0].id, 7);
  EXPECT_EQ(q[0].position, p[0].position);  // %.17g round-trips doubles exactly
  EXPECT_EQ(q[0].velocity, p[0].velocity);
  EXPECT_EQ(q[0].angular_velocity, p[0].angular_velocity);
  EXPECT_EQ(q[0].radius, p[0].radius);
}

TEST(Scene, IssueExampleRunsAsWrittenAndGivesRestitution) {
  const fs::path dir = ppohdem::test::scratch_dir();
  fs::copy(ppohdem::test::fixture("scenes/two_spheres.toml"), dir / "two_spheres.toml");
  fs::copy(ppohdem::test::fixture("scenes/two_spheres.csv"), dir / "two_spheres.csv");
  Scene scene = read_scene(dir / "two_spheres.toml");
  scene.output.progress = false;
  ppohdem::dem::reference::ReferenceEngine engine(scene.setup);
  std::ostringstream log;
  const RunSummary s = run_scene(engine, scene, "test header", log);
  EXPECT_EQ(s.steps, 40000);
  EXPECT_TRUE(fs::exists(dir / "out" / "final.csv"));
  EXPECT_TRUE(fs::exists(dir / "out" / "energy.csv"));
  EXPECT_TRUE(fs::exists(dir / "out" / "frame_040000.vtk"));
  EXPECT_TRUE(fs::exists(dir / "out" / "frame_040000.pov"));
  const Particles final_state = read_particles_csv(dir / "out" / "final.csv");
  // Head-on at 0.1 m/s relative; the scene's e = 0.5 must be the measured one (1%).
  const double rebound = final_state[1].velocity.x() - final_state[0].velocity.x();
  EXPECT_NEAR(rebound / 0.1, 0.5, 0.005);
}

TEST(Scene, UnknownKeyIsAnErrorNamingTheKey) {
  const fs::path dir = ppohdem::test::scratch_dir();
  std::string scene = fixture_text("scenes/two_spheres.toml");
  scene.replace(scene.find("poisson"), 7, "poison");
  write(dir / "s.toml", scene);
  const std::string msg = error_of([&] { read_scene(dir / "s.toml"); });
  EXPECT_NE(msg.find("unknown key 'poison'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("s.toml:"), std::string::npos) << msg;
}

// [parallel] (docs/dem.md "Load balance"): the defaults, both values of balance and the
// threshold are read; a wrong value names the key, the file and the line.
TEST(Scene, ParallelBalanceKeysAreReadAndCheckedNamingTheLine) {
  const fs::path dir = ppohdem::test::scratch_dir();
  const std::string base = fixture_text("scenes/two_spheres.toml");
  fs::copy_file(ppohdem::test::fixture("scenes/two_spheres.csv"), dir / "two_spheres.csv");
  write(dir / "default.toml", base);
  const Scene plain = read_scene(dir / "default.toml");
  EXPECT_TRUE(plain.parallel.balance);
  EXPECT_EQ(plain.parallel.balance_threshold, 1.05);
  write(dir / "off.toml", base + "\n[parallel]\nbalance = \"off\"\nbalance_threshold = 1.2\n");
  const Scene off = read_scene(dir / "off.toml");
  EXPECT_FALSE(off.parallel.balance);
  EXPECT_EQ(off.parallel.balance_threshold, 1.2);
  write(dir / "rcb.toml", base + "\n[parallel]\nbalance = \"rcb\"\n");
  EXPECT_TRUE(read_scene(dir / "rcb.toml").parallel.balance);
  const auto lines = static_cast<int>(std::count(base.begin(), base.end(), '\n'));
  const std::string at = "bad.toml:" + std::to_string(lines + 3);  // the line of the bad key
  write(dir / "bad.toml", base + "\n[parallel]\nbalance = \"zoltan\"\n");
  std::string msg = error_of([&] { read_scene(dir / "bad.toml"); });
  EXPECT_NE(msg.find("[parallel] balance: expected \"rcb\" or \"off\", found \"zoltan\""), std::string::npos) << msg;
  EXPECT_NE(msg.find(at), std::string::npos) << msg;
  write(dir / "bad.toml", base + "\n[parallel]\nbalance_threshold = 0.9\n");
  msg = error_of([&] { read_scene(dir / "bad.toml"); });
  EXPECT_NE(msg.find("balance_threshold: expected a number >= 1"), std::string::npos) << msg;
  EXPECT_NE(msg.find(at), std::string::npos) << msg;
  write(dir / "bad.toml", base + "\n[parallel]\nbalanse = \"rcb\"\n");
  msg = error_of([&] { read_scene(dir / "bad.toml"); });
  EXPECT_NE(msg.find("unknown key 'balanse'"), std::string::npos) << msg;
}

// [output] formats: "vtu" is read; an unknown name is an error naming the file, the line and
// the names expected.
TEST(Scene, OutputFormatsReadVtuAndNameTheExpectedOnes) {
  const fs::path dir = ppohdem::test::scratch_dir();
  fs::copy(ppohdem::test::fixture("scenes/two_spheres.csv"), dir / "two_spheres.csv", fs::copy_options::overwrite_existing);
  const std::string scene = fixture_text("scenes/two_spheres.toml");
  const std::string line = "formats = [\"csv\", \"vtk\", \"pov\"]";
  const auto at = scene.find(line);
  ASSERT_NE(at, std::string::npos);
  write(dir / "vtu.toml", std::string(scene).replace(at, line.size(), "formats = [\"csv\", \"vtu\"]"));
  const Scene s = read_scene(dir / "vtu.toml");
  EXPECT_TRUE(s.output.vtu);
  EXPECT_TRUE(s.output.csv);
  EXPECT_FALSE(s.output.vtk);
  write(dir / "bad.toml", std::string(scene).replace(at, line.size(), "formats = [\"vtp\"]"));
  const std::string msg = error_of([&] { read_scene(dir / "bad.toml"); });
  EXPECT_NE(msg.find("bad.toml:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("\"vtu\""), std::string::npos) << msg;
  EXPECT_NE(msg.find("found vtp"), std::string::npos) << msg;
}

// [simulation] energy_balance = false through the whole run: the key is read, the run ends
// with the same final state as the tracked run, and energy.csv carries nan in the three
// contact columns (and finite kinetic energies). A non-boolean value names the key.
TEST(Scene, EnergyBalanceOffRunsTheSameMotionWithNanContactEnergies) {
  const fs::path dir = ppohdem::test::scratch_dir();
  const std::string tracked = fixture_text("scenes/two_spheres.toml");
  std::string untracked = tracked;
  untracked.insert(untracked.find("[simulation]") + 12, "\nenergy_balance = false");
  untracked.replace(untracked.find("dir = \"out\""), 11, "dir = \"off\"");
  fs::copy(ppohdem::test::fixture("scenes/two_spheres.csv"), dir / "two_spheres.csv");
  write(dir / "on.toml", tracked);
  write(dir / "off.toml", untracked);
  Scene on = read_scene(dir / "on.toml");
  Scene off = read_scene(dir / "off.toml");
  EXPECT_TRUE(on.setup.energy_balance);
  ASSERT_FALSE(off.setup.energy_balance);
  on.output.progress = off.output.progress = false;
  on.output.every = off.output.every = 0;
  std::ostringstream log;
  ppohdem::dem::reference::ReferenceEngine engine_on(on.setup);
  ppohdem::dem::reference::ReferenceEngine engine_off(off.setup);
  run_scene(engine_on, on, "test header", log);
  const RunSummary s = run_scene(engine_off, off, "test header", log);
  EXPECT_TRUE(std::isnan(s.final.dissipated));
  const Particles a = read_particles_csv(dir / "out" / "final.csv");
  const Particles b = read_particles_csv(dir / "off" / "final.csv");
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].position, b[i].position);
    EXPECT_EQ(a[i].velocity, b[i].velocity);
  }
  std::ifstream csv(dir / "off" / "energy.csv");
  std::string line, last;
  while (std::getline(csv, line)) {
    if (!line.empty() && line[0] != '#') last = line;
  }
  EXPECT_NE(last.find(",nan,nan,nan"), std::string::npos) << last;
  std::string bad = tracked;  // a copy
  bad.insert(bad.find("[simulation]") + 12, "\nenergy_balance = \"no\"");
  write(dir / "bad.toml", bad);
  const std::string msg = error_of([&] { read_scene(dir / "bad.toml"); });
  EXPECT_NE(msg.find("energy_balance"), std::string::npos) << msg;
}

SimulationSetup two_soft_spheres(double gap_fraction, double dt) {
  const Material m = peer_material(0.5, 0.0);
  SimulationSetup s = head_on_setup(HertzMindlin::from_material(m), m, 0.5e-3, 0.1, dt);
  s.particles[0].position.x() = -0.5e-3 * (1.0 + gap_fraction);
  s.particles[1].position.x() = 0.5e-3 * (1.0 + gap_fraction);
  s.source = "scene.toml";
  return s;
}

TEST(SetupValidation, RejectsInitialOverlapAboveOnePercentUnlessAllowed) {
  // Overlap 2% of the radius (gap fraction -0.01 on each side): refused, then allowed.
  SimulationSetup s = two_soft_spheres(-0.01, 1e-7);
  const std::string msg = error_of([&] { ppohdem::dem::reference::ReferenceEngine e(s); });
  EXPECT_NE(msg.find("overlap"), std::string::npos) << msg;
  s.allow_initial_overlap = true;
  EXPECT_NO_THROW(ppohdem::dem::reference::ReferenceEngine e(s));
  // 0.8% is within the 1% allowance.
  EXPECT_NO_THROW(ppohdem::dem::reference::ReferenceEngine e(two_soft_spheres(-0.004, 1e-7)));
}

TEST(SetupValidation, RejectsTimeStepAboveRayleighLimitGivingTheLimit) {
  // T_R = pi R sqrt(rho/G) / (0.1631 nu + 0.8766), G = E / (2 (1 + nu)): for R = 0.5 mm,
  // 2500 kg/m^3, E = 1e7 Pa, nu = 0.3: T_R = 4.327e-5 s, limit 0.2 T_R = 8.654e-6 s.
  const double g = 1.0e7 / 2.6;
  const double t_r = 3.14159265358979 * 0.5e-3 * std::sqrt(2500.0 / g) / (0.1631 * 0.3 + 0.8766);
  EXPECT_NEAR(rayleigh_time(0.5e-3, peer_material(0.5, 0.0)), t_r, 1e-15);
  SimulationSetup s = two_soft_spheres(0.1, 1.0e-5);
  const std::string msg = error_of([&] { ppohdem::dem::reference::ReferenceEngine e(s); });
  EXPECT_NE(msg.find("8.654e-06 s"), std::string::npos) << msg;
  EXPECT_NE(msg.find("--force"), std::string::npos) << msg;
  s.force_time_step = true;
  EXPECT_NO_THROW(ppohdem::dem::reference::ReferenceEngine e(s));
}

TEST(SetupValidation, RejectsNegativeRadius) {
  SimulationSetup s = two_soft_spheres(0.1, 1e-7);
  s.particles[1].radius = -1e-3;
  const std::string msg = error_of([&] { ppohdem::dem::reference::ReferenceEngine e(s); });
  EXPECT_NE(msg.find("radius must be > 0"), std::string::npos) << msg;
}

/// Frictionless Hertz spheres over the floor z = 0, time step `dt` [s] accepted above the
/// stability limit (so that a particle can cross the plane within one step).
SimulationSetup floor_scene(double dt, Particles particles) {
  const Material m = peer_material(0.5, 0.0);
  SimulationSetup s;
  s.dt = dt;
  s.force_time_step = true;
  s.material = m;
  s.law = HertzMindlin::from_material(m);
  s.particles = std::move(particles);
  s.boundaries = {std::make_shared<PlaneWall>(Vec3::Zero(), Vec3::UnitZ())};
  return s;
}

TEST(Boundaries, ParticleLeavingTheBoxIsCountedOnce) {
  // A particle crossing a wall plane in one step (dt forced far above the limit).
  const SimulationSetup s = floor_scene(1.0e-3, {sphere(1, Vec3(0, 0, 0.6e-3), Vec3(0, 0, -10.0), 0.5e-3),
                                                 sphere(2, Vec3(0.01, 0, 0.6e-3), Vec3::Zero(), 0.5e-3)});
  ppohdem::dem::reference::ReferenceEngine engine(s);
  engine.advance(5);
  EXPECT_EQ(engine.escaped_count(), 1u);
}

TEST(Boundaries, FastEngineSeesAWallThatWasFarAtTheListBuild) {
  // The fast engine skips a fixed wall for a particle that was farther than R + skin from it
  // at the last list build (near_boundaries). Particle 1 starts 20 radii above the floor and
  // hits it (and bounces); particle 3 is thrown through it (0.6 mm per step from 10.15 mm: one
  // step ends 0.55 mm above the plane, out of contact, the next 0.05 mm below it). Both must
  // touch the floor at the same steps as in the reference, which checks every wall at every
  // step, and particle 3 must be counted as escaped; particle 2 rests on the floor throughout.
  SimulationSetup s = floor_scene(2.0e-5, {sphere(1, Vec3(0, 0, 10.0e-3), Vec3(0, 0, -3.0), 0.5e-3),
                                           sphere(2, Vec3(0.01, 0, 0.499e-3), Vec3::Zero(), 0.5e-3),
                                           sphere(3, Vec3(0.02, 0, 10.15e-3), Vec3(0, 0, -30.0), 0.5e-3)});
  s.gravity = Vec3(0, 0, -9.81);
  ppohdem::dem::reference::ReferenceEngine reference(s);
  ppohdem::dem::fast::FastEngine fast(s);
  std::size_t most_touching = 0;
  for (int step = 0; step < 400; ++step) {
    reference.step();
    fast.step();
    ASSERT_EQ(fast.escaped_count(), reference.escaped_count()) << "step " << step;
    ASSERT_EQ(fast.contact_counts().particle_boundary, reference.contact_counts().particle_boundary) << "step " << step;
    most_touching = std::max(most_touching, fast.contact_counts().particle_boundary);
  }
  // Not vacuous: particle 1 touched the floor while particle 2 rested on it, particle 3 went through.
  EXPECT_GE(most_touching, 2u);
  EXPECT_EQ(fast.escaped_count(), 1u);
  const Particles a = reference.particles();
  const Particles b = fast.particles();
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].position, b[i].position) << "particle " << a[i].id;
    EXPECT_EQ(a[i].velocity, b[i].velocity) << "particle " << a[i].id;
  }
}

}  // namespace
}  // namespace ppohdem::dem::test
