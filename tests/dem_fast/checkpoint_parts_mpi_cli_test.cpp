// Checkpoints written per rank (ppohdem/dem/checkpoint.hpp "Parts"; docs/formats.md
// "Checkpoints"), through `mpirun -n P ppohdem simulate --checkpoint-every N` as a user runs
// it: at P = 2 and 4 ranks every rank writes its own part and rank 0 a manifest holding no
// particle, and a restart from it at 1, 2, 3 and 4 ranks x 1 and 2 threads, and with the
// reference engine, ends in the same files, bit for bit, as the uninterrupted run (the
// oracle); so does a single-file checkpoint restarted at 2 and 3 ranks. Label mpi; built only
// with PPOHDEM_ENABLE_MPI.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <tuple>
#include <algorithm>
#include <string>
#include <vector>

#include "../apps/cli_runner.hpp"
#include "bed_scene.hpp"
#include "forged_part.hpp"
#include "mpi_runner.hpp"
#include "ppohdem/dem/checkpoint.hpp"

namespace fs = std::filesystem;
using ppohdem::test::body;
using ppohdem::test::bytes_of;
using ppohdem::test::forge_part;
using ppohdem::test::CommandResult;
using ppohdem::test::run_mpi;
using ppohdem::test::write_bed;

namespace {

fs::path scratch(const std::string& name) { return ppohdem::test::scratch("checkpoint_parts_mpi", name); }

// The bed of fast_mpi_cli_test.cpp: 4275 frictional spheres (each of 4 ranks owns about
// kParallelMin particles or more, so 2 threads really run), colliding with each other and the
// walls before the checkpoint at step 100 (pair and wall histories in the parts).
constexpr int kNx = 15, kNy = 15, kNz = 19;
constexpr long kSteps = 200, kEvery = 100;

}  // namespace

TEST(CheckpointPartsMpi, WrittenPerRankRestartAtAnyRankAndThreadCountBitwise) {
  const fs::path whole_dir = scratch("whole");
  const CommandResult whole = run_mpi(1, 1, write_bed(whole_dir, kNx, kNy, kNz, kSteps, kEvery), "--quiet");
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  for (const int writers : {2, 4}) {
    const fs::path dir = scratch("written_at_" + std::to_string(writers));
    const fs::path scene = write_bed(dir, kNx, kNy, kNz, kSteps, kEvery);
    const CommandResult first = run_mpi(writers, 1, scene, "--quiet --steps 100 --checkpoint-every 100");
    ASSERT_EQ(first.exit_code, 0) << first.output;
    // The manifest names one part per rank and holds no particle itself; the parts hold all.
    const fs::path manifest = dir / "out" / "checkpoint.bin";
    const ppohdem::dem::Checkpoint m = ppohdem::dem::decode_checkpoint(bytes_of(manifest), manifest.string());
    ASSERT_EQ(m.parts.size(), static_cast<std::size_t>(writers));
    EXPECT_TRUE(m.engine.particles.empty());
    std::uint64_t particles = 0, contacts = 0;
    for (int r = 0; r < writers; ++r) {
      const auto& entry = m.parts[static_cast<std::size_t>(r)];
      EXPECT_EQ(entry.file, "checkpoint.bin.parts/step_0000000100.rank_" + std::to_string(r) + "_of_" +
                                std::to_string(writers) + ".bin");
      EXPECT_TRUE(fs::is_regular_file(dir / "out" / entry.file)) << entry.file;
      EXPECT_GT(entry.particles, 0u) << "every rank owns a share";
      particles += entry.particles;
      contacts += entry.contacts;
    }
    EXPECT_EQ(particles, static_cast<std::uint64_t>(kNx * kNy * kNz));
    EXPECT_GT(contacts, 0u) << "not vacuous: contact histories are carried in the parts";
    for (const int ranks : {1, 2, 3, 4}) {
      for (const int threads : {1, 2}) {
        SCOPED_TRACE("written at " + std::to_string(writers) + " ranks, restarted at " + std::to_string(ranks) +
                     " ranks x " + std::to_string(threads) + " threads");
        fs::remove(dir / "out" / "final.csv");
        const CommandResult second = run_mpi(ranks, threads, scene, "--quiet --restart '" + manifest.string() + "'");
        ASSERT_EQ(second.exit_code, 0) << second.output;
        for (const char* file : {"final.csv", "energy.csv", "frame_000200.csv"}) {
          EXPECT_EQ(body(dir / "out" / file), body(whole_dir / "out" / file)) << file;
        }
      }
    }
  }
}

// A single-file checkpoint (one rank, the fast and the reference engine's) restarts at 2 and 3
// ranks: every rank reads the whole state and keeps what it owns (FastEngine::restore_state,
// the whole-state path), and the run ends in the uninterrupted run's files, bit for bit.
TEST(CheckpointPartsMpi, SingleFileRestartsAtSeveralRanksBitwise) {
  const fs::path whole_dir = scratch("single_whole");
  const CommandResult whole = run_mpi(1, 1, write_bed(whole_dir, kNx, kNy, kNz, kSteps, kEvery), "--quiet");
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  for (const char* engine : {"fast", "reference"}) {
    const fs::path dir = scratch(std::string("single_") + engine);
    const fs::path scene = write_bed(dir, kNx, kNy, kNz, kSteps, kEvery);
    const CommandResult first =
        run_mpi(1, 1, scene, std::string("--engine ") + engine + " --quiet --steps 100 --checkpoint-every 100");
    ASSERT_EQ(first.exit_code, 0) << first.output;
    const fs::path checkpoint = dir / "out" / "checkpoint.bin";
    ASSERT_TRUE(ppohdem::dem::decode_checkpoint(bytes_of(checkpoint), checkpoint.string()).parts.empty());
    for (const int ranks : {2, 3}) {
      SCOPED_TRACE(std::string(engine) + " checkpoint, restarted at " + std::to_string(ranks) + " ranks");
      fs::remove(dir / "out" / "final.csv");
      const CommandResult second = run_mpi(ranks, 1, scene, "--quiet --restart '" + checkpoint.string() + "'");
      ASSERT_EQ(second.exit_code, 0) << second.output;
      for (const char* file : {"final.csv", "energy.csv", "frame_000200.csv"}) {
        EXPECT_EQ(body(dir / "out" / file), body(whole_dir / "out" / file)) << file;
      }
    }
  }
}

// The reference engine (one rank, the lecture code) reads a checkpoint written per rank and
// continues to the uninterrupted reference run's final state, bit for bit.
TEST(CheckpointPartsMpi, ReferenceEngineRestartsFromParts) {
  const fs::path whole_dir = scratch("reference_whole");
  const CommandResult whole =
      run_mpi(1, 1, write_bed(whole_dir, kNx, kNy, kNz, kSteps, kEvery), "--engine reference --quiet");
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  const fs::path dir = scratch("reference_restart");
  const fs::path scene = write_bed(dir, kNx, kNy, kNz, kSteps, kEvery);
  const CommandResult first = run_mpi(4, 1, scene, "--quiet --steps 100 --checkpoint-every 100");
  ASSERT_EQ(first.exit_code, 0) << first.output;
  const CommandResult second =
      run_mpi(1, 1, scene, "--engine reference --quiet --restart '" + (dir / "out" / "checkpoint.bin").string() + "'");
  ASSERT_EQ(second.exit_code, 0) << second.output;
  EXPECT_EQ(body(dir / "out" / "final.csv"), body(whole_dir / "out" / "final.csv"));
}

// A damaged checkpoint written per rank is refused with the file and what was expected.
TEST(CheckpointPartsMpi, MissingOrForeignPartsAreRefused) {
  const fs::path dir = scratch("damaged");
  const fs::path scene = write_bed(dir, kNx, kNy, kNz, kSteps, kEvery);
  const CommandResult first = run_mpi(2, 1, scene, "--quiet --steps 100 --checkpoint-every 100");
  ASSERT_EQ(first.exit_code, 0) << first.output;
  const fs::path manifest = dir / "out" / "checkpoint.bin";
  const fs::path part1 = dir / "out" / "checkpoint.bin.parts" / "step_0000000100.rank_1_of_2.bin";
  const std::string restart = "--quiet --restart '" + manifest.string() + "'";
  // At 1 rank the parts are merged; at 2 and 3 ranks each rank reads its own (rank 2 none),
  // and every rank must refuse alike, naming the part (none left waiting: the test ends).
  const int rank_counts[] = {1, 2, 3};
  {  // a truncated part
    const std::vector<std::uint8_t> good = bytes_of(part1);
    std::ofstream(part1, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(good.data()), 1000);
    for (const int ranks : rank_counts) {
      const CommandResult r = run_mpi(ranks, 1, scene, restart);
      EXPECT_NE(r.exit_code, 0) << ranks << " ranks";
      EXPECT_NE(r.output.find(part1.string() + ": checkpoint part is truncated: the header announces " +
                              std::to_string(good.size()) + " bytes, the file has 1000"),
                std::string::npos)
          << ranks << " ranks: " << r.output;
    }
    std::ofstream(part1, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(good.data()),
                                                                    static_cast<std::streamsize>(good.size()));
  }
  {  // a part of another checkpoint: another run's part 1 (another step) under this name
    const fs::path other = scratch("damaged_other");
    const CommandResult o = run_mpi(2, 1, write_bed(other, kNx, kNy, kNz, kSteps, kEvery),
                                    "--quiet --steps 60 --checkpoint-every 60");
    ASSERT_EQ(o.exit_code, 0) << o.output;
    const std::vector<std::uint8_t> good = bytes_of(part1);
    fs::copy_file(other / "out" / "checkpoint.bin.parts" / "step_0000000060.rank_1_of_2.bin", part1,
                  fs::copy_options::overwrite_existing);
    for (const int ranks : rank_counts) {
      const CommandResult r = run_mpi(ranks, 1, scene, restart);
      EXPECT_NE(r.exit_code, 0) << ranks << " ranks";
      EXPECT_NE(r.output.find("checkpoint part: its CRC-32 differs from the one the manifest " + manifest.string() +
                              " lists (a part of another checkpoint?)"),
                std::string::npos)
          << ranks << " ranks: " << r.output;
    }
    std::ofstream(part1, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(good.data()),
                                                                    static_cast<std::streamsize>(good.size()));
  }
  {  // a missing part
    fs::remove(part1);
    for (const int ranks : rank_counts) {
      const CommandResult r = run_mpi(ranks, 1, scene, restart);
      EXPECT_NE(r.exit_code, 0) << ranks << " ranks";
      EXPECT_NE(r.output.find(manifest.string() + ": checkpoint: part 1 of 2, " + part1.string() + ", does not exist"),
                std::string::npos)
          << ranks << " ranks: " << r.output;
    }
  }
}

// Parts that frame and checksum well but whose contents do not fit the scene: the restore's
// checks refuse them with the same words whether one rank merges the parts or 2 and 3 ranks
// each place their own (restore_state against restore_state_share).
TEST(CheckpointPartsMpi, ForgedPartsAreRefusedAtEveryRankCount) {
  namespace dem = ppohdem::dem;
  const fs::path dir = scratch("forged");
  const fs::path scene = write_bed(dir, kNx, kNy, kNz, kSteps, kEvery);
  const CommandResult first = run_mpi(2, 1, scene, "--quiet --steps 100 --checkpoint-every 100");
  ASSERT_EQ(first.exit_code, 0) << first.output;
  const fs::path manifest = dir / "out" / "checkpoint.bin";
  const fs::path parts = dir / "out" / "checkpoint.bin.parts";
  const std::string restart = "--quiet --restart '" + manifest.string() + "'";
  // The good checkpoint, kept to start each case from.
  const fs::path good = scratch("forged_good");
  fs::copy(dir / "out", good, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  auto reset = [&] {
    fs::copy(good / "checkpoint.bin", manifest, fs::copy_options::overwrite_existing);
    fs::copy(good / "checkpoint.bin.parts", parts, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  };
  auto refused_with = [&](const std::string& words) {
    for (const int ranks : {1, 2, 3}) {
      const CommandResult r = run_mpi(ranks, 1, scene, restart);
      EXPECT_NE(r.exit_code, 0) << ranks << " ranks";
      EXPECT_NE(r.output.find(words), std::string::npos) << ranks << " ranks: " << r.output;
    }
  };
  std::int64_t unknown = 0;
  {  // a pair history naming a particle id the checkpoint does not hold
    forge_part(manifest, 0, [&](dem::CheckpointPart& p) {
      for (dem::ContactHistoryRecord& c : p.contacts) {
        if (c.kind != dem::ContactHistoryRecord::Kind::kParticlePair) continue;
        c.id_b = unknown = 1000000;
        return;
      }
      FAIL() << "no pair history in part 0";
    });
    refused_with("restore_state: contact names unknown particle id " + std::to_string(unknown));
    reset();
  }
  {  // a pair history between particles far apart (the first particle and the one farthest from it)
    forge_part(manifest, 0, [&](dem::CheckpointPart& p) {
      std::size_t far = 0;
      for (std::size_t i = 0; i < p.particles.size(); ++i) {
        if ((p.particles[i].position - p.particles[0].position).norm() > (p.particles[far].position - p.particles[0].position).norm()) far = i;
      }
      for (dem::ContactHistoryRecord& c : p.contacts) {
        if (c.kind != dem::ContactHistoryRecord::Kind::kParticlePair) continue;
        c.id_a = std::min(p.particles[0].id, p.particles[far].id);
        c.id_b = std::max(p.particles[0].id, p.particles[far].id);
        break;
      }
      std::sort(p.contacts.begin(), p.contacts.end(), [](const auto& a, const auto& b) {
        return std::tuple(a.kind, a.id_a, a.id_b) < std::tuple(b.kind, b.id_a, b.id_b);
      });
    });
    refused_with("restore_state: a contact history joins particles that are not neighbours");
    reset();
  }
  std::uint64_t twice = 0;
  {  // a construction index in both parts (part 1's first particle claims part 0's first index)
    dem::Checkpoint m = dem::decode_checkpoint(bytes_of(manifest), manifest.string());
    const fs::path file0 = manifest.parent_path() / m.parts.at(0).file;
    twice = dem::decode_checkpoint_part(bytes_of(file0), file0.string()).order.at(0);
    forge_part(manifest, 1, [&](dem::CheckpointPart& p) { p.order.at(0) = twice; });
    refused_with("construction index " + std::to_string(twice) + " appears in two parts");
    reset();
  }
  {  // a particle of another size than the scene's
    std::int64_t id = 0;
    std::uint64_t index = 0;
    forge_part(manifest, 1, [&](dem::CheckpointPart& p) {
      p.particles.at(3).radius *= 1.01;
      id = p.particles[3].id;
      index = p.order[3];
    });
    refused_with("restore_state: particle " + std::to_string(index) + " (id " + std::to_string(id) +
                 ") does not match the scene");
    reset();
  }
  // The good checkpoint still restarts at 3 ranks (the cases above left nothing behind).
  const CommandResult r = run_mpi(3, 1, scene, restart);
  EXPECT_EQ(r.exit_code, 0) << r.output;
}
