// `ppohdem simulate` as a user runs it (issue 10, items 2 and 4):
//  - --checkpoint-every / --restart: 2N steps == N steps + restart to 2N, for final.csv,
//    energy.csv, objects.csv and the final checkpoint's engine state (bitwise);
//  - damaged checkpoints are refused with exit status 2 and a clear message;
//  - deliberately broken scenes stop with status 1 and a diagnosis naming the step, the
//    particle and the likely cause, and leave failed_checkpoint.bin for inspection.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "../apps/cli_runner.hpp"
#include "ppohdem/dem/checkpoint.hpp"
#include "reliability_scenes.hpp"

namespace ppohdem::dem::test {
namespace {

namespace fs = std::filesystem;
using ppohdem::test::run_ppohdem;

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("ppohdem_rel_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string slurp(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The file without its comment lines (the run header carries the date and command).
std::string data_lines(const fs::path& file) {
  std::istringstream in(slurp(file));
  std::string line, out;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] != '#') out += line + '\n';
  }
  return out;
}

bool same_state_bits(const EngineState& a, const EngineState& b) {
  // The encoded payload of the engine state alone: every field, every bit.
  Checkpoint x, y;
  x.engine = a;
  y.engine = b;
  return encode_checkpoint(x) == encode_checkpoint(y);
}

TEST(RestartCli, TwoHalvesEqualOneWhole) {
  const fs::path a = fresh_dir("whole"), b = fresh_dir("halves");
  write_pile_scene(a, 400, 50);
  write_pile_scene(b, 400, 50);
  const auto whole = run_ppohdem("simulate pile.toml --quiet --checkpoint-every 200", a.string());
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  const auto half = run_ppohdem("simulate pile.toml --quiet --steps 200 --checkpoint-every 200", b.string());
  ASSERT_EQ(half.exit_code, 0) << half.output;
  ASSERT_EQ(read_checkpoint(b / "out" / "checkpoint.bin").engine.step, 200);
  const auto rest = run_ppohdem("simulate pile.toml --quiet --restart out/checkpoint.bin --checkpoint-every 200",
                                b.string());
  ASSERT_EQ(rest.exit_code, 0) << rest.output;
  EXPECT_NE(rest.output.find("restarted at step 200"), std::string::npos) << rest.output;
  for (const char* file : {"final.csv", "energy.csv", "objects.csv", "frame_000400.csv", "frame_000250.csv"}) {
    EXPECT_EQ(data_lines(a / "out" / file), data_lines(b / "out" / file)) << file;
    EXPECT_FALSE(data_lines(a / "out" / file).empty()) << file;
  }
  const Checkpoint end_a = read_checkpoint(a / "out" / "checkpoint.bin");
  const Checkpoint end_b = read_checkpoint(b / "out" / "checkpoint.bin");
  EXPECT_EQ(end_a.engine.step, 400);
  EXPECT_TRUE(same_state_bits(end_a.engine, end_b.engine));
  EXPECT_GT(end_a.engine.contacts.size(), 20u);  // the comparison includes histories
  EXPECT_EQ(end_a.run.energy_rows, end_b.run.energy_rows);
  EXPECT_EQ(end_a.run.frames, end_b.run.frames);
  EXPECT_EQ(end_a.run.frames, 9u);  // steps 0, 50, ..., 400
  fs::remove_all(a);
  fs::remove_all(b);
}

TEST(RestartCli, DamagedCheckpointsAreRefused) {
  const fs::path d = fresh_dir("damaged");
  write_pile_scene(d, 20, 0);
  ASSERT_EQ(run_ppohdem("simulate pile.toml --quiet --checkpoint-every 10", d.string()).exit_code, 0);
  const std::string good = slurp(d / "out" / "checkpoint.bin");
  auto refused = [&](const std::string& bytes, const std::string& expected) {
    std::ofstream(d / "bad.bin", std::ios::binary) << bytes;
    const auto r = run_ppohdem("simulate pile.toml --quiet --restart bad.bin", d.string());
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(expected), std::string::npos) << r.output;
  };
  std::string flipped = good;
  flipped[good.size() / 2] = static_cast<char>(flipped[good.size() / 2] ^ 1);
  refused(flipped, "bad.bin: checkpoint data is corrupted (CRC-32 mismatch");
  refused(good.substr(0, good.size() - 100), "bad.bin: checkpoint is truncated");
  refused("frame data\n", "bad.bin: not a ppohdem checkpoint");
  // The checkpoint of another scene (fewer steps is fine; other particles are not).
  const fs::path e = fresh_dir("other");
  write_pile_scene(e, 20, 0, "");
  {
    std::ofstream(e / "pile.csv") << "id,x,y,z,vx,vy,vz,wx,wy,wz,radius\n1,0.004,0.004,0.002,0,0,0,0,0,0,0.001\n";
  }
  fs::copy_file(d / "out" / "checkpoint.bin", e / "c.bin");
  const auto r = run_ppohdem("simulate pile.toml --quiet --restart c.bin", e.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("48 particles, the scene has 1"), std::string::npos) << r.output;
  fs::remove_all(d);
  fs::remove_all(e);
}

// ---- diagnoses ------------------------------------------------------------------------

struct Failure {
  ppohdem::test::CommandResult result;
  fs::path dir;
};

/// Runs a scene of one or two spheres (glass-like soft material of the pile, R = 1 mm) given
/// by a particle CSV body and extra TOML, expecting it to fail.
Failure run_broken(const std::string& name, const std::string& particles, const std::string& toml,
                   const std::string& flags = "") {
  const fs::path dir = fresh_dir(name);
  std::ofstream(dir / "p.csv") << "id,x,y,z,vx,vy,vz,wx,wy,wz,radius\n" << particles;
  std::ofstream(dir / "s.toml") << toml
                                << "[material]\ndensity = 2500.0\nyoung = 1.0e7\npoisson = 0.3\n"
                                   "restitution = 0.9\nfriction = 0.0\n"
                                   "[output]\ndir = \"out\"\nprogress = false\n";
  return {run_ppohdem("simulate s.toml --quiet " + flags, dir.string()), dir};
}

/// The step number in "run stopped at step K".
long stopped_step(const std::string& output) {
  std::smatch m;
  if (!std::regex_search(output, m, std::regex("run stopped at step ([0-9]+)"))) return -1;
  return std::stol(m[1].str());
}

void expect_inspectable(const Failure& f, long step) {
  EXPECT_EQ(f.result.exit_code, 1) << f.result.output;
  EXPECT_EQ(stopped_step(f.result.output), step) << f.result.output;
  const Checkpoint c = read_checkpoint(f.dir / "out" / "failed_checkpoint.bin");
  EXPECT_EQ(c.engine.step, step);
  EXPECT_FALSE(fs::exists(f.dir / "out" / "final.csv"));
  EXPECT_EQ(slurp(f.dir / "out" / "energy.csv").find("nan"), std::string::npos);
  fs::remove_all(f.dir);
}

constexpr const char* kHertz = "[contact]\nmodel = \"hertz-mindlin\"\n[particles]\nfile = \"p.csv\"\n";

TEST(RunDiagnosticsCli, NonFiniteForceOfCoincidentParticles) {
  // Two centres at the same point: the contact normal d/|d| is 0/0 in the first evaluation.
  const auto f = run_broken("nonfinite", "1,0,0,0,0,0,0,0,0,0,0.001\n2,0,0,0,0,0,0,0,0,0,0.001\n",
                            std::string("[simulation]\ndt = 1e-6\nsteps = 10\n") + kHertz +
                                "allow_overlap = true\n");
  EXPECT_NE(f.result.output.find("particle id 1: the contact force is not finite"), std::string::npos)
      << f.result.output;
  EXPECT_NE(f.result.output.find("two particles placed at the same point"), std::string::npos);
  expect_inspectable(f, 0);
}

TEST(RunDiagnosticsCli, OverlapOfTooSoftAContact) {
  // Head-on at 3 m/s: an elastic Hertz impact overlaps by delta = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5)
  // = 0.167 R > 0.1 R (m* = 5.24e-6 kg, E* = 5.49e6 Pa, R* = 0.5 mm); dt = 1e-6 s is 6% of
  // the limit, so it is the stiffness, not dt. The gap of 0.1 mm closes after ~33 steps and
  // 10% overlap is reached ~33 steps later.
  const auto f = run_broken("soft", "1,-0.00105,0,0,1.5,0,0,0,0,0,0.001\n2,0.00105,0,0,-1.5,0,0,0,0,0,0.001\n",
                            std::string("[simulation]\ndt = 1e-6\nsteps = 1000\n") + kHertz);
  EXPECT_NE(f.result.output.find("particle id 1 and particle id 2 overlap"), std::string::npos) << f.result.output;
  EXPECT_NE(f.result.output.find("too soft for the impact speed"), std::string::npos) << f.result.output;
  const long step = stopped_step(f.result.output);
  EXPECT_GT(step, 50);  // not before the overlap can reach 10% (>= 33 + 33 steps minus slack)
  EXPECT_LT(step, 80);
  expect_inspectable(f, step);
}

TEST(RunDiagnosticsCli, OverlapOfATooLargeTimeStep) {
  // 0.5 m/s: the elastic overlap is only 0.04 R, but dt = 5e-4 s (29 x the limit, --force)
  // moves the spheres 2.5e-4 m = 0.25 R towards each other per step: 0.2 R after step 1.
  const auto f = run_broken("bigdt", "1,-0.001025,0,0,0.25,0,0,0,0,0,0.001\n2,0.001025,0,0,-0.25,0,0,0,0,0,0.001\n",
                            std::string("[simulation]\ndt = 5e-4\nsteps = 100\n") + kHertz, "--force");
  EXPECT_NE(f.result.output.find("dt too large"), std::string::npos) << f.result.output;
  // 5e-4 s / (0.2 T_R), T_R = pi R sqrt(rho/G) / (0.1631 nu + 0.8766) = 8.654e-5 s for R = 1 mm
  // (docs/dem.md: 4.327e-5 s at R = 0.5 mm): 2889 %.
  EXPECT_NE(f.result.output.find("2889 % of the stability limit 1.731e-05 s"), std::string::npos) << f.result.output;
  expect_inspectable(f, 1);
}

TEST(RunDiagnosticsCli, EnergyGrowthOfAnUnstableSpring) {
  // A sphere resting on a floor on a linear spring k = 1e4 N/m: Verlet is unstable for
  // dt > 2 / omega = 2 sqrt(m/k) = 6.5e-5 s; dt = 1e-4 s (--force) makes every contact
  // throw it higher: the energy grows without input while the overlaps stay far below 10%.
  const auto f = run_broken("energy", "1,0,0,0.001,0,0,0,0,0,0,0.001\n",
                            "[simulation]\ndt = 1e-4\nsteps = 2000\ngravity = [0.0, 0.0, -9.81]\n"
                            "[contact]\nmodel = \"linear\"\nstiffness = 1e4\n[particles]\nfile = \"p.csv\"\n"
                            "[[wall]]\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\n",
                            "--force");
  EXPECT_NE(f.result.output.find("the energy grew without input"), std::string::npos) << f.result.output;
  EXPECT_NE(f.result.output.find("fastest particle id 1"), std::string::npos) << f.result.output;
  const long step = stopped_step(f.result.output);
  EXPECT_GE(step, 1);
  EXPECT_LT(step, 20);
  expect_inspectable(f, step);
}

TEST(RunDiagnosticsCli, ParticleThroughAWall) {
  // 200 m/s towards the floor from 0.5 mm above contact: 2 mm per step of 1e-5 s, the centre
  // is below the floor after step 1.
  const auto f = run_broken("escape", "7,0,0,0.0015,0,0,-200,0,0,0,0.001\n",
                            std::string("[simulation]\ndt = 1e-5\nsteps = 100\n") + kHertz +
                                "[[wall]]\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\n");
  EXPECT_NE(f.result.output.find("particle id 7 left the domain"), std::string::npos) << f.result.output;
  EXPECT_NE(f.result.output.find("dt too large for this speed"), std::string::npos) << f.result.output;
  expect_inspectable(f, 1);
}

TEST(RunDiagnosticsCli, ParticleThroughAWallFastUntracked) {
  // The same escape in the fast engine without energy tracking, which counts the escapes only
  // when asked (FastEngine::escaped_count): the run checks still see it at step 1.
  const auto f = run_broken("escape_fast", "7,0,0,0.0015,0,0,-200,0,0,0,0.001\n",
                            std::string("[simulation]\ndt = 1e-5\nsteps = 100\nenergy_balance = false\n") +
                                kHertz + "[[wall]]\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\n",
                            "--engine fast");
  EXPECT_NE(f.result.output.find("particle id 7 left the domain"), std::string::npos) << f.result.output;
  EXPECT_EQ(f.result.exit_code, 1) << f.result.output;
  EXPECT_EQ(stopped_step(f.result.output), 1) << f.result.output;
  EXPECT_EQ(read_checkpoint(f.dir / "out" / "failed_checkpoint.bin").engine.step, 1);
  fs::remove_all(f.dir);
}

TEST(RunDiagnosticsCli, ParticleOutOfTheDomainBox) {
  // 1 m/s along x from 0.5 mm inside the box [0, 0.01]^3: out after 0.5 mm / (1 m/s * 1e-5 s)
  // = 50 steps (the centre is exactly on the face at step 50, outside at 51).
  const auto f = run_broken("box", "3,0.0095,0.005,0.005,1,0,0,0,0,0,0.001\n",
                            std::string("[simulation]\ndt = 1e-5\nsteps = 100\n") + kHertz +
                                "[checks]\ndomain_min = [0.0, 0.0, 0.0]\ndomain_max = [0.01, 0.01, 0.01]\n");
  EXPECT_NE(f.result.output.find("particle id 3 left the domain"), std::string::npos) << f.result.output;
  EXPECT_NE(f.result.output.find("left the box"), std::string::npos) << f.result.output;
  const long step = stopped_step(f.result.output);
  EXPECT_GE(step, 50);
  EXPECT_LE(step, 51);
  expect_inspectable(f, step);
}

TEST(RunDiagnosticsCli, ChecksCanBeRelaxedAndAreValidated) {
  // The wall case with stop_on_escape = false runs to the end (the engine's warning only).
  const fs::path dir = fresh_dir("relaxed");
  std::ofstream(dir / "p.csv") << "id,x,y,z,vx,vy,vz,wx,wy,wz,radius\n7,0,0,0.0015,0,0,-200,0,0,0,0.001\n";
  const std::string body = std::string("[simulation]\ndt = 1e-5\nsteps = 10\n") + kHertz +
                           "[[wall]]\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\n"
                           "[material]\ndensity = 2500.0\nyoung = 1.0e7\npoisson = 0.3\n"
                           "restitution = 0.9\nfriction = 0.0\n[output]\ndir = \"out\"\nprogress = false\n";
  std::ofstream(dir / "s.toml") << body << "[checks]\nstop_on_escape = false\n";
  const auto r = run_ppohdem("simulate s.toml --quiet", dir.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("escaped particles: 1"), std::string::npos) << r.output;
  std::ofstream(dir / "s.toml") << body << "[checks]\nmax_overlap = -0.1\n";
  const auto bad = run_ppohdem("simulate s.toml --quiet", dir.string());
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("[checks] max_overlap: expected > 0"), std::string::npos) << bad.output;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace ppohdem::dem::test
