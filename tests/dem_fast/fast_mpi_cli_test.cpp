// The fast engine decomposed over MPI ranks (docs/dem.md "Domain decomposition"), through the
// command line as a user runs it: `mpirun -n P ppohdem simulate SCENE --engine fast` must write
// the same files, byte for byte (header lines aside), for P = 1, 2, 4 and 1 or 2 OpenMP
// threads, and the same final state as the REFERENCE engine on one rank (the independent
// oracle: a readable O(N^2)-free serial implementation with its own contact loop). A
// checkpoint written at one rank count restarts at another and continues bitwise.
// Label mpi; built only with PPOHDEM_ENABLE_MPI.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "../apps/cli_runner.hpp"
#include "../reliability/reliability_scenes.hpp"
#include "bed_scene.hpp"
#include "mpi_runner.hpp"
#include "ppohdem/dem/particle_csv.hpp"
#include "vtu_test_reader.hpp"

namespace fs = std::filesystem;
using ppohdem::test::body;
using ppohdem::test::CommandResult;
using ppohdem::test::run_mpi;
using ppohdem::test::replace_in_scene;
using ppohdem::test::write_bed;

namespace {

fs::path scratch(const std::string& name) { return ppohdem::test::scratch("dem_fast_mpi", name); }

/// Brick of x in the decomposition the program reports ("(a x b x c bricks)"), recomputed
/// here from its definition (bounding box of the initial centres cut into equal bricks).
struct Bricks {
  ppohdem::Vec3 lo, h;
  std::array<int, 3> dims{1, 1, 1};
  int of(const ppohdem::Vec3& x) const {
    std::array<int, 3> c{};
    for (int a = 0; a < 3; ++a) c[a] = std::clamp(static_cast<int>(std::floor((x[a] - lo[a]) / h[a])), 0, dims[a] - 1);
    return c[0] + dims[0] * (c[1] + dims[1] * c[2]);
  }
};
Bricks bricks_from(const std::string& output, const ppohdem::dem::Particles& initial) {
  Bricks b;
  const auto at = output.find("ranks (");
  EXPECT_NE(at, std::string::npos) << output;
  if (at == std::string::npos) return b;
  std::sscanf(output.c_str() + at, "ranks (%d x %d x %d", &b.dims[0], &b.dims[1], &b.dims[2]);
  ppohdem::Vec3 hi = initial.front().position;
  b.lo = hi;
  for (const auto& p : initial) {
    b.lo = b.lo.cwiseMin(p.position);
    hi = hi.cwiseMax(p.position);
  }
  for (int a = 0; a < 3; ++a) b.h[a] = (hi[a] - b.lo[a]) / b.dims[a];
  return b;
}

/// The scene with `[parallel] balance = "off"`: the equal bricks that Bricks recomputes.
void balance_off(const fs::path& scene) { std::ofstream(scene, std::ios::app) << "\n[parallel]\nbalance = \"off\"\n"; }

}  // namespace

// The bed: 15 x 15 x 19 = 4275 spheres, so that each of 4 ranks owns about kParallelMin = 1024
// particles or more and the OpenMP loops really run on 2 threads. The counts are odd so that
// the brick faces of 2 and 4 ranks (mid-planes of the box of centres) pass through lattice
// centres: those particles change owner at the first builds. With the load balance on (the
// default: bricks by bisection of the particle count) and off (equal bricks).
TEST(FastEngineMpi, FrictionalBedIsBitwiseIdenticalAcrossRanksAndThreads) {
  const long steps = 200, every = 100;
  const fs::path ref_dir = scratch("bed_reference");
  const fs::path ref_scene = write_bed(ref_dir, 15, 15, 19, steps, every);
  const CommandResult ref = ppohdem::test::run_ppohdem("simulate '" + ref_scene.string() + "' --engine reference --quiet");
  ASSERT_EQ(ref.exit_code, 0) << ref.output;
  const std::string ref_final = body(ref_dir / "out" / "final.csv");
  const auto initial = ppohdem::dem::read_particles_csv(ref_dir / "bed.csv");
  std::string first_energy, first_frame;
  for (const bool balance : {true, false}) {
  for (const int ranks : {1, 2, 4}) {
    for (const int threads : {1, 2}) {
      if (!balance && ranks == 1) continue;  // one rank has no bricks
      SCOPED_TRACE("ranks " + std::to_string(ranks) + ", threads " + std::to_string(threads) +
                   (balance ? ", balance rcb" : ", balance off"));
      const fs::path dir = scratch("bed_np" + std::to_string(ranks) + "_nt" + std::to_string(threads) +
                                   (balance ? "" : "_off"));
      const fs::path scene = write_bed(dir, 15, 15, 19, steps, every);
      if (!balance) balance_off(scene);
      const CommandResult run = run_mpi(ranks, threads, scene, "--engine fast --quiet");
      ASSERT_EQ(run.exit_code, 0) << run.output;
      // The state: bitwise the reference engine's (each particle sums its contacts in
      // partner-id order on every rank: no tolerance).
      EXPECT_EQ(body(dir / "out" / "final.csv"), ref_final);
      // Energies and frames: bitwise those of 1 rank, 1 thread (global sums in construction order).
      const std::string energy = body(dir / "out" / "energy.csv");
      const std::string frame = body(dir / "out" / "frame_000100.csv");
      if (first_energy.empty()) {
        first_energy = energy;
        first_frame = frame;
      }
      EXPECT_EQ(energy, first_energy);
      EXPECT_EQ(frame, first_frame);
      if (ranks == 4 && threads == 1 && !balance) {
        // The test is only worth something if particles changed owner and touching pairs
        // straddle a brick face: counted from the data, with the bricks' definition.
        const auto final = ppohdem::dem::read_particles_csv(dir / "out" / "final.csv");
        const Bricks b = bricks_from(run.output, initial);
        int moved = 0, straddling = 0;
        for (std::size_t i = 0; i < final.size(); ++i) {
          moved += b.of(final[i].position) != b.of(initial[i].position) ? 1 : 0;
          for (std::size_t j = i + 1; j < final.size(); ++j) {
            const double reach = final[i].radius + final[j].radius;
            if ((final[i].position - final[j].position).squaredNorm() < reach * reach &&
                b.of(final[i].position) != b.of(final[j].position)) {
              ++straddling;
            }
          }
        }
        EXPECT_GE(b.dims[0] * b.dims[1] * b.dims[2], 4);
        EXPECT_GE(moved, 10) << "no migration exercised";
        EXPECT_GE(straddling, 10) << "no contact across a brick face exercised";
      }
    }
  }
  }
}

// The same bed with the linear spring-dashpot law: its pairs go through the scalar contact
// law, not the four-lane Hertz-Mindlin one (which the tests above run), so a pair with a
// lower-id ghost (evaluated on both ranks; the owner adds the force and its own torque
// r_i x F in the sum pass) takes the scalar path's stores. Without this test, storing the
// wrong torque there failed no test. The reference engine's final state on 2 and 4 ranks,
// and contacts across a brick face counted as above. k_n = 1000 N/m keeps dt = 1e-5 s below
// the stability limit `simulate` prints (4.28e-5 s = 0.2 pi sqrt(m*/k_n)).
TEST(FastEngineMpi, LinearLawBedIsBitwiseTheReferencesAcrossRanks) {
  const long steps = 200, every = 100;
  auto linear = [](const fs::path& scene) {
    replace_in_scene(scene, "model = \"hertz-mindlin\"\n", "model = \"linear\"\nstiffness = 1000.0\n");
  };
  const fs::path ref_dir = scratch("linear_reference");
  const fs::path ref_scene = write_bed(ref_dir, 15, 15, 19, steps, every);
  linear(ref_scene);
  const CommandResult ref = ppohdem::test::run_ppohdem("simulate '" + ref_scene.string() + "' --engine reference --quiet");
  ASSERT_EQ(ref.exit_code, 0) << ref.output;
  const std::string ref_final = body(ref_dir / "out" / "final.csv");
  const auto initial = ppohdem::dem::read_particles_csv(ref_dir / "bed.csv");
  for (const int ranks : {2, 4}) {
    SCOPED_TRACE("ranks " + std::to_string(ranks));
    const fs::path dir = scratch("linear_np" + std::to_string(ranks));
    const fs::path scene = write_bed(dir, 15, 15, 19, steps, every);
    linear(scene);
    balance_off(scene);  // the equal bricks, which Bricks recomputes
    const CommandResult run = run_mpi(ranks, 1, scene, "--engine fast --quiet");
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_EQ(body(dir / "out" / "final.csv"), ref_final);
    const auto final = ppohdem::dem::read_particles_csv(dir / "out" / "final.csv");
    const Bricks b = bricks_from(run.output, initial);
    int straddling = 0;
    for (std::size_t i = 0; i < final.size(); ++i) {
      for (std::size_t j = i + 1; j < final.size(); ++j) {
        const double reach = final[i].radius + final[j].radius;
        if ((final[i].position - final[j].position).squaredNorm() < reach * reach &&
            b.of(final[i].position) != b.of(final[j].position)) {
          ++straddling;
        }
      }
    }
    EXPECT_GE(straddling, 3) << "no contact across a brick face exercised";
  }
}

/// The scene file with `energy_balance = false` added to its [simulation] table.
void untrack_energies(const fs::path& scene) {
  replace_in_scene(scene, "[simulation]\n", "[simulation]\nenergy_balance = false\n");
}

// The reliability pile: moving wall, a moving and spinning distance-field object (boundary
// loads, objects.csv), tangential histories on walls and object. With the energies tracked
// (gathered at every evaluation) and untracked (the motion energies and the loads gathered
// when asked, the run checks screening the motion with every rank's closing-kick screen).
TEST(FastEngineMpi, PileWithObjectIsBitwiseIdenticalAcrossRanks) {
  std::string tracked_objects;
  for (const bool tracked : {true, false}) {
  SCOPED_TRACE(tracked ? "energies tracked" : "energies untracked");
  const std::string mode = tracked ? "" : "_untracked";
  const long steps = 300, every = 100;
  const fs::path ref_dir = scratch("pile_reference" + mode);
  const fs::path ref_scene = ppohdem::dem::test::write_pile_scene(ref_dir, steps, every);
  if (!tracked) untrack_energies(ref_scene);
  const CommandResult ref = ppohdem::test::run_ppohdem("simulate '" + ref_scene.string() + "' --engine reference --quiet");
  ASSERT_EQ(ref.exit_code, 0) << ref.output;
  std::string first_energy, first_objects;
  for (const int ranks : {1, 2, 4}) {
    SCOPED_TRACE("ranks " + std::to_string(ranks));
    const fs::path dir = scratch("pile_np" + std::to_string(ranks) + mode);
    const fs::path scene = ppohdem::dem::test::write_pile_scene(dir, steps, every);
    if (!tracked) untrack_energies(scene);
    const CommandResult run = run_mpi(ranks, 1, scene, "--engine optimized --quiet");
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_EQ(body(dir / "out" / "final.csv"), body(ref_dir / "out" / "final.csv"));
    const std::string energy = body(dir / "out" / "energy.csv");
    const std::string objects = body(dir / "out" / "objects.csv");
    if (first_energy.empty()) {
      first_energy = energy;
      first_objects = objects;
    }
    EXPECT_EQ(energy, first_energy);
    EXPECT_EQ(objects, first_objects);
    // Not vacuous: the loads on the object and the motion energies are in the files, and
    // untracked the contact terms are not.
    EXPECT_NE(objects.find('\n'), std::string::npos);
    EXPECT_EQ(energy.find("nan") == std::string::npos, tracked) << energy.substr(0, 400);
  }
  // The loads do not depend on the tracking: the same records summed in the same order.
  if (tracked) {
    tracked_objects = first_objects;
  } else {
    EXPECT_EQ(first_objects, tracked_objects);
  }
  }
}

// VTK XML frames: one piece per rank (no gather) and a .pvtu index naming them, frames.pvd
// naming the frames; the pieces together hold every particle of the frame with the bits of
// the CSV frame (%.17g: exact), read by the independent reader of tests/support.
TEST(FastEngineMpi, VtuFramesHaveOnePiecePerRankWithTheCsvFramesBits) {
  const long steps = 200, every = 100;
  for (const int ranks : {1, 2}) {
    SCOPED_TRACE("ranks " + std::to_string(ranks));
    const fs::path dir = scratch("vtu_np" + std::to_string(ranks));
    const fs::path scene = ppohdem::dem::test::write_pile_scene(dir, steps, every);
    replace_in_scene(scene, "formats = [\"csv\", \"vtk\"]", "formats = [\"csv\", \"vtu\"]");
    const CommandResult run = run_mpi(ranks, 1, scene, "--engine optimized --quiet");
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const fs::path out = dir / "out";
    std::vector<std::string> frames;
    for (long step = 0; step <= steps; step += every) {
      char stem[32];
      std::snprintf(stem, sizeof stem, "frame_%06ld", step);
      std::vector<std::string> pieces{std::string(stem) + ".vtu"};
      if (ranks > 1) {
        frames.push_back(std::string(stem) + ".pvtu");
        pieces = ppohdem::test::listed_files(out / frames.back(), "Source");
        ASSERT_EQ(pieces.size(), static_cast<std::size_t>(ranks));
      } else {
        frames.push_back(pieces[0]);
      }
      std::map<std::int64_t, ppohdem::dem::Particle> by_id;
      std::size_t pieces_with_particles = 0;
      for (const std::string& piece : pieces) {
        const auto particles = ppohdem::test::particles_of(ppohdem::test::read_vtu(out / piece));
        pieces_with_particles += !particles.empty();
        for (const auto& p : particles) EXPECT_TRUE(by_id.emplace(p.id, p).second) << "id " << p.id << " in two pieces";
      }
      EXPECT_EQ(pieces_with_particles, pieces.size()) << "every rank owns particles here";
      const auto csv = ppohdem::dem::read_particles_csv(out / (std::string(stem) + ".csv"));
      ASSERT_EQ(by_id.size(), csv.size());
      for (const auto& p : csv) {
        const auto& q = by_id.at(p.id);
        EXPECT_TRUE(p.position == q.position && p.velocity == q.velocity && p.angular_velocity == q.angular_velocity &&
                    p.radius == q.radius) << "particle " << p.id << " at step " << step;
      }
    }
    EXPECT_EQ(ppohdem::test::listed_files(out / "frames.pvd", "file"), frames);
  }
}

// A motion that becomes non-finite mid-run stops every rank with the particle named, tracked
// (the checks see it in the gathered energies) and untracked (in every rank's screen of the
// motion, gathered with the evaluation's counts). Particle 2 starts 3 R from particle 1 (out of
// reach, and on the other rank: the brick face is at 1.5 R) moving at -3 R / dt, all powers of
// two, so the first drift puts it exactly on particle 1: the contact normal is 0/0 and the
// velocities after the closing kick are NaN.
TEST(FastEngineMpi, ANonFiniteMotionStopsEveryRankWithTheParticleNamed) {
  for (const bool tracked : {true, false}) {
    SCOPED_TRACE(tracked ? "energies tracked" : "energies untracked");
    const fs::path dir = scratch(std::string("nonfinite_") + (tracked ? "tracked" : "untracked"));
    std::ofstream(dir / "p.csv") << "id,x,y,z,vx,vy,vz,wx,wy,wz,radius\n"
                                 << "1,0,0,0,0,0,0,0,0,0,0.00048828125\n"        // R = 2^-11 m
                                 << "2,0.00146484375,0,0,-1536,0,0,0,0,0,0.00048828125\n";  // 3 R, -3 R / dt
    std::ofstream(dir / "s.toml") << "[simulation]\ndt = 9.5367431640625e-07\nsteps = 5\n"  // dt = 2^-20 s
                                  << "gravity = [0.0, 0.0, 0.0]\nenergy_balance = " << (tracked ? "true" : "false") << "\n"
                                  << "[material]\ndensity = 2500.0\nyoung = 1.0e7\npoisson = 0.3\nrestitution = 0.5\nfriction = 0.5\n"
                                  << "[contact]\nmodel = \"hertz-mindlin\"\n[particles]\nfile = \"p.csv\"\n"
                                  << "[output]\ndir = \"out\"\nevery = 0\n";
    const CommandResult run = run_mpi(2, 1, dir / "s.toml", "--engine fast --quiet");
    EXPECT_EQ(run.exit_code, 1) << run.output;
    EXPECT_NE(run.output.find("over 2 ranks (recursive bisection by particle count"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("run stopped at step 1"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("particle id 1: the velocity is not finite"), std::string::npos) << run.output;
    EXPECT_TRUE(fs::exists(dir / "out" / "failed_checkpoint.bin"));
    EXPECT_FALSE(fs::exists(dir / "out" / "final.csv"));
  }
}

// Checkpoint at 2 ranks, restart at 1 and at 4 ranks: the same files as the uninterrupted run
// (the checkpoint at step 200, a step with an energy row, so energy.csv gets the same rows).
TEST(FastEngineMpi, RestartAtAnotherRankCountContinuesBitwise) {
  const long steps = 300, every = 100;
  const fs::path whole_dir = scratch("restart_whole");
  const fs::path whole = ppohdem::dem::test::write_pile_scene(whole_dir, steps, every);
  const CommandResult w = run_mpi(2, 1, whole, "--engine fast --quiet");
  ASSERT_EQ(w.exit_code, 0) << w.output;
  for (const int ranks : {1, 4}) {
    SCOPED_TRACE("restart at " + std::to_string(ranks) + " ranks");
    const fs::path dir = scratch("restart_np" + std::to_string(ranks));
    const fs::path scene = ppohdem::dem::test::write_pile_scene(dir, steps, every);
    const CommandResult first = run_mpi(2, 1, scene, "--engine fast --quiet --steps 200 --checkpoint-every 200");
    ASSERT_EQ(first.exit_code, 0) << first.output;
    ASSERT_TRUE(fs::exists(dir / "out" / "checkpoint.bin"));
    const CommandResult second =
        run_mpi(ranks, 1, scene, "--engine fast --quiet --restart '" + (dir / "out" / "checkpoint.bin").string() + "'");
    ASSERT_EQ(second.exit_code, 0) << second.output;
    for (const char* file : {"final.csv", "energy.csv", "objects.csv", "frame_000300.csv"}) {
      EXPECT_EQ(body(dir / "out" / file), body(whole_dir / "out" / file)) << file;
    }
  }
}

// Rolling resistance (EPSD2: a spring in the history) through the decomposition: 1, 2 and 4
// ranks give the reference's final state, and a checkpoint at 2 ranks restarts at 4 with the
// same files as the uninterrupted run (the rolling springs are carried over and mirrored
// across brick faces, and restored at another rank count).
TEST(FastEngineMpi, RollingResistanceIsTheReferencesAcrossRanksAndRestarts) {
  const long steps = 300, every = 100;
  auto rolling_scene = [&](const fs::path& dir) {
    const fs::path scene = ppohdem::dem::test::write_pile_scene(dir, steps, every);
    replace_in_scene(scene, "model = \"hertz-mindlin\"", "model = \"hertz-mindlin\"\nrolling = \"epsd2\"");
    replace_in_scene(scene, "friction = 0.5\n", "friction = 0.5\nrolling_friction = 0.1\n");
    return scene;
  };
  const fs::path ref_dir = scratch("rolling_reference");
  const CommandResult ref =
      ppohdem::test::run_ppohdem("simulate '" + rolling_scene(ref_dir).string() + "' --engine reference --quiet");
  ASSERT_EQ(ref.exit_code, 0) << ref.output;
  // final.csv is the reference's bit for bit; the sums (energy.csv, objects.csv) are the
  // reference's to round-off (another order) and the same bits at every rank count.
  const fs::path one_dir = scratch("rolling_np1");
  for (const int ranks : {1, 2, 4}) {
    SCOPED_TRACE("ranks " + std::to_string(ranks));
    const fs::path dir = scratch("rolling_np" + std::to_string(ranks));
    const CommandResult run = run_mpi(ranks, 1, rolling_scene(dir), "--quiet");
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_EQ(body(dir / "out" / "final.csv"), body(ref_dir / "out" / "final.csv"));
    for (const char* file : {"energy.csv", "objects.csv"}) {
      EXPECT_EQ(body(dir / "out" / file), body(one_dir / "out" / file)) << file;
    }
  }
  const fs::path dir = scratch("rolling_restart");
  const fs::path scene = rolling_scene(dir);
  const CommandResult first = run_mpi(2, 1, scene, "--quiet --steps 200 --checkpoint-every 200");
  ASSERT_EQ(first.exit_code, 0) << first.output;
  const CommandResult second = run_mpi(4, 1, scene, "--quiet --restart '" + (dir / "out" / "checkpoint.bin").string() + "'");
  ASSERT_EQ(second.exit_code, 0) << second.output;
  EXPECT_EQ(body(dir / "out" / "final.csv"), body(ref_dir / "out" / "final.csv"));
  for (const char* file : {"energy.csv", "objects.csv"}) {
    EXPECT_EQ(body(dir / "out" / file), body(one_dir / "out" / file)) << file;
  }
  // Not vacuous: the rolling resistance changes the result.
  const fs::path plain_dir = scratch("rolling_none");
  const CommandResult plain = run_mpi(1, 1, ppohdem::dem::test::write_pile_scene(plain_dir, steps, every), "--quiet");
  ASSERT_EQ(plain.exit_code, 0) << plain.output;
  EXPECT_NE(body(plain_dir / "out" / "final.csv"), body(ref_dir / "out" / "final.csv"));
}

/// The numbers of `simulate`'s "load balance:" line.
struct LoadLine {
  long recuts = -1;
  double max_over_mean = 0.0, equal_bricks = 0.0, messages = 0.0, messages_max = 0.0, all_to_all = 0.0;
  int peers = -1;
  long global = -1;
};
LoadLine load_line(const std::string& output) {
  LoadLine l;
  const auto at = output.find("load balance: ");
  EXPECT_NE(at, std::string::npos) << output;
  if (at == std::string::npos) return l;
  const auto comma = output.find(", ", at);
  std::sscanf(output.c_str() + comma,
              ", %ld re-cuts; particles per rank max/mean %lf (equal bricks of the initial box: %lf); exchanges: %lf "
              "messages per rank per step (max %lf; as all-to-all exchanges: %lf), %d peers on rank 0, %ld global",
              &l.recuts, &l.max_over_mean, &l.equal_bricks, &l.messages, &l.messages_max, &l.all_to_all, &l.peers,
              &l.global);
  return l;
}

// A cloud of 16 x 8 x 8 frictional spheres drifting at 2 m/s along x (plus the bed's
// velocities of up to 0.3 m/s, so they collide) moves 6 mm in 300 steps: in the equal bricks
// (4 slabs of 8.4 mm across x) the leading slab ends with far more than its share. Balanced,
// the bricks are re-cut and the load stays within the threshold; the files are the same bits
// as one rank's either way. The equal-bricks figure of the balanced run (the same positions
// counted in the equal bricks) is the unbalanced run's own load, to the last digit: the list
// builds, and so the positions counted, do not depend on the bricks. The ranks send fewer
// messages than the same exchanges as all-to-all ones (2 (P - 1) each): the halo refresh of
// every step sends one message per peer (its size is known), not a count and a block to
// every rank; unbalanced, the 4 slabs have 1 or 2 peers, and the all-to-all figure is 6 per
// step or more.
TEST(FastEngineMpi, ADriftingCloudIsReCutAndStaysBitwise) {
  auto write_cloud = [](const fs::path& dir, const std::string& parallel) {
    const fs::path scene = write_bed(dir, 16, 8, 8, 300, 0);
    replace_in_scene(scene, "gravity = [0.0, 0.0, -9.81]", "gravity = [0.0, 0.0, 0.0]");
    auto ps = ppohdem::dem::read_particles_csv(dir / "bed.csv");
    for (auto& p : ps) p.velocity.x() += 2.0;
    ppohdem::dem::write_particles_csv(dir / "bed.csv", ps, "drifting cloud");
    std::ifstream in(scene);
    std::stringstream text;
    text << in.rdbuf();
    std::string toml = text.str();
    toml = toml.substr(0, toml.find("[[wall]]")) + toml.substr(toml.find("[output]"));  // no walls
    std::ofstream(scene) << toml << parallel;
    return scene;
  };
  const fs::path one_dir = scratch("drift_np1");
  const CommandResult one = run_mpi(1, 1, write_cloud(one_dir, ""), "--engine fast --quiet");
  ASSERT_EQ(one.exit_code, 0) << one.output;
  const fs::path off_dir = scratch("drift_off");
  const CommandResult off = run_mpi(4, 1, write_cloud(off_dir, "[parallel]\nbalance = \"off\"\n"), "--engine fast --quiet");
  ASSERT_EQ(off.exit_code, 0) << off.output;
  const fs::path rcb_dir = scratch("drift_rcb");
  const CommandResult rcb = run_mpi(4, 2, write_cloud(rcb_dir, "[parallel]\nbalance = \"rcb\"\n"), "--engine fast --quiet");
  ASSERT_EQ(rcb.exit_code, 0) << rcb.output;
  for (const char* file : {"final.csv", "energy.csv"}) {
    EXPECT_EQ(body(off_dir / "out" / file), body(one_dir / "out" / file)) << file;
    EXPECT_EQ(body(rcb_dir / "out" / file), body(one_dir / "out" / file)) << file;
  }
  const LoadLine unbalanced = load_line(off.output), balanced = load_line(rcb.output);
  EXPECT_EQ(unbalanced.recuts, 0);
  EXPECT_GT(unbalanced.max_over_mean, 1.4) << off.output;  // the leading slab: about 1.7
  EXPECT_EQ(balanced.equal_bricks, unbalanced.max_over_mean) << rcb.output;
  EXPECT_GE(balanced.recuts, 1) << rcb.output;
  // Within the threshold 1.05 (the load at the last build, after its re-cut if any).
  EXPECT_LE(balanced.max_over_mean, 1.05) << rcb.output;
  EXPECT_LT(balanced.messages_max, balanced.all_to_all) << rcb.output;
  EXPECT_GE(balanced.messages, 1.0) << rcb.output;  // not vacuous: the counter counts
  EXPECT_EQ(balanced.global, 0) << rcb.output;
  EXPECT_LE(unbalanced.peers, 2) << off.output;  // rank 0's slab: one neighbour
  EXPECT_GE(unbalanced.all_to_all, 6.0) << off.output;
  EXPECT_LT(unbalanced.messages_max, 0.5 * unbalanced.all_to_all) << off.output;
  EXPECT_EQ(unbalanced.global, 0) << off.output;
}

TEST(FastEngineMpi, ReferenceEngineOnSeveralRanksIsRefused) {
  const fs::path dir = scratch("refused");
  const fs::path scene = ppohdem::dem::test::write_pile_scene(dir, 10, 10);
  const CommandResult run = run_mpi(2, 1, scene, "--engine reference --quiet");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.output.find("runs on one rank only"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(dir / "out" / "final.csv"));
}
