// The kill test (issue 10, item 3): `ppohdem simulate --checkpoint-every` is SIGKILLed at
// random moments, several times in a row, each time restarted from its last checkpoint.
// After every kill each output file on disk must be complete and parseable (frames, final
// and energy/objects logs, checkpoint); temp files of the killed process may remain but are
// removed by the next run. The last restart runs to the end and must reach the state of an
// uninterrupted run (data of final.csv, energy.csv, objects.csv, and the engine state of the
// final checkpoint, bitwise). Seed: PPOHDEM_KILL_SEED=<n> reproduces the kill times.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <thread>
#include <vector>

#include "ppohdem/dem/checkpoint.hpp"
#include "ppohdem/dem/particle_csv.hpp"
#include "reliability_scenes.hpp"

namespace ppohdem::dem::test {
namespace {

namespace fs = std::filesystem;
constexpr long kSteps = 2000;
constexpr long kFrameEvery = 20;
constexpr long kCheckpointEvery = 100;
constexpr int kKills = 5;         // kills to aim for
constexpr int kMaxAttempts = 12;  // a restart may finish before its kill time

/// Starts `ppohdem <arguments>` in `dir` (output appended to dir/run.log); returns its pid.
pid_t spawn(const fs::path& dir, std::vector<std::string> arguments) {
  arguments.insert(arguments.begin(), "ppohdem");
  std::vector<char*> argv;
  for (std::string& a : arguments) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::fflush(nullptr);  // or the child would print the parent's buffered lines again
  const pid_t pid = ::fork();
  if (pid == 0) {
    if (::chdir(dir.c_str()) != 0) ::_exit(127);
    std::FILE* log = std::freopen("run.log", "a", stdout);
    if (log == nullptr || ::dup2(::fileno(stdout), 2) < 0) ::_exit(127);
    ::execv(PPOHDEM_EXE, argv.data());
    ::_exit(127);
  }
  return pid;
}

/// `ppohdem simulate pile.toml --quiet --checkpoint-every N [--restart out/checkpoint.bin]`.
pid_t start_run(const fs::path& dir, bool restart) {
  // The reference engine, as when this test was written: the fast one (the default) can end a
  // restart before its kill time on a loaded machine, and fewer kills land.
  std::vector<std::string> arguments{"simulate", "pile.toml", "--quiet", "--engine", "reference",
                                     "--checkpoint-every", std::to_string(kCheckpointEvery)};
  if (restart) {
    arguments.push_back("--restart");
    arguments.push_back("out/checkpoint.bin");
  }
  return spawn(dir, arguments);
}

int wait_for(pid_t pid) {
  int status = 0;
  ::waitpid(pid, &status, 0);
  return status;
}

std::string slurp(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> data_rows(const fs::path& file) {
  std::istringstream in(slurp(file));
  std::vector<std::string> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] != '#') rows.push_back(line);
  }
  return rows;
}

bool is_temp(const fs::path& p) { return p.filename().string().find(".tmp.") != std::string::npos; }

/// Every output file is complete: CSV frames parse with all 48 particles, the logs have a
/// header and full rows, VTK frames end with their last block, the checkpoint decodes.
/// Returns the number of files checked; temp files are counted in `temps`.
std::size_t check_outputs(const fs::path& out, std::size_t& temps) {
  std::size_t checked = 0;
  if (!fs::exists(out)) return 0;
  for (const auto& entry : fs::recursive_directory_iterator(out)) {
    if (!entry.is_regular_file()) continue;
    const fs::path p = entry.path();
    const std::string name = p.filename().string();
    SCOPED_TRACE(p.string());
    if (is_temp(p)) {
      ++temps;
      continue;
    }
    ++checked;
    if (name == "energy.csv" || name == "objects.csv") {
      const auto rows = data_rows(p);
      EXPECT_GE(rows.size(), 2u);  // the column line and step 0
      const std::size_t columns = name == "energy.csv" ? 8 : 20;
      for (const std::string& row : rows) {
        EXPECT_EQ(static_cast<std::size_t>(std::count(row.begin(), row.end(), ',')), columns - 1) << row;
      }
      EXPECT_EQ(slurp(p).back(), '\n');
    } else if (p.extension() == ".csv") {
      EXPECT_EQ(read_particles_csv(p).size(), 48u);
    } else if (p.extension() == ".vtk") {
      const std::string text = slurp(p);
      const auto last = text.rfind("VECTORS angular_velocity double\n");
      if (last == std::string::npos) {
        ADD_FAILURE() << "no angular_velocity block";
        continue;
      }
      EXPECT_EQ(std::count(text.begin() + static_cast<std::ptrdiff_t>(last), text.end(), '\n'), 49);
    } else if (name == "checkpoint.bin") {
      EXPECT_NO_THROW(read_checkpoint(p));
    } else {
      ADD_FAILURE() << "unexpected file " << name;
    }
  }
  return checked;
}

TEST(KillTest, OutputsSurviveSigkillAndTheLastCheckpointRestartsExactly) {
  const char* seed_env = std::getenv("PPOHDEM_KILL_SEED");
  const unsigned seed = seed_env ? static_cast<unsigned>(std::strtoul(seed_env, nullptr, 10))
                                 : static_cast<unsigned>(std::random_device{}());
  std::printf("kill test seed: PPOHDEM_KILL_SEED=%u\n", seed);
  std::mt19937 random(seed);
  const fs::path base = fs::temp_directory_path() / ("ppohdem_kill_" + std::to_string(::getpid()));
  fs::remove_all(base);
  const fs::path whole = base / "whole", killed = base / "killed";
  write_pile_scene(whole, kSteps, kFrameEvery, "", 0.0);
  write_pile_scene(killed, kSteps, kFrameEvery, "", 0.0);

  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  const int status = wait_for(start_run(whole, false));
  const double duration = std::chrono::duration<double>(clock::now() - t0).count();
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << slurp(whole / "run.log");
  // Start-up before the first step (MPI_Init, reading the scene and the ball, step 0's
  // outputs) [s]: a run of 0 steps of the same scene in a scratch directory.
  const fs::path scratch = base / "startup";
  write_pile_scene(scratch, kSteps, kFrameEvery, "", 0.0);
  const auto t1 = clock::now();
  wait_for(spawn(scratch, {"simulate", "pile.toml", "--quiet", "--steps", "0"}));
  const double startup = std::min(std::chrono::duration<double>(clock::now() - t1).count(), 0.8 * duration);
  std::printf("uninterrupted run: %.2f s, of which start-up ~%.2f s\n", duration, startup);

  std::uniform_real_distribution<double> when(0.0, 1.0);
  // Stepping time of one checkpoint interval in the uninterrupted run [s].
  const double interval = (duration - startup) * static_cast<double>(kCheckpointEvery) / static_cast<double>(kSteps);
  int kills = 0;
  long last_step = 0;
  for (int k = 0; k < kMaxAttempts && kills < kKills && last_step < kSteps; ++k) {
    const bool restart = fs::exists(killed / "out" / "checkpoint.bin");
    const pid_t pid = start_run(killed, restart);
    // Wait until this run is stepping (a checkpoint beyond the last one appeared), then kill
    // it at a random moment of the next checkpoint interval: the kill falls anywhere in the
    // cycle of steps, frame writes and checkpoint writes, independently of the machine's load.
    const auto started = clock::now();
    int s = 0;
    bool exited = false;
    while (!exited) {
      if (::waitpid(pid, &s, WNOHANG) == pid) {
        exited = true;
        break;
      }
      try {
        if (read_checkpoint(killed / "out" / "checkpoint.bin").engine.step > last_step) break;
      } catch (const InputError&) {
        // not written yet (a checkpoint on disk is always complete: atomic rename)
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    const double delay = when(random) * interval;
    std::this_thread::sleep_for(std::chrono::duration<double>(delay));
    if (!exited) {
      ::kill(pid, SIGKILL);
      s = wait_for(pid);
    }
    const double alive = std::chrono::duration<double>(clock::now() - started).count();
    if (WIFSIGNALED(s)) ++kills;
    std::size_t temps = 0;
    const std::size_t files = check_outputs(killed / "out", temps);
    long step = -1;
    if (fs::exists(killed / "out" / "checkpoint.bin")) step = read_checkpoint(killed / "out" / "checkpoint.bin").engine.step;
    std::printf("kill %d after %.2f s, %.3f s after a new checkpoint (%s): %zu files complete, %zu temp files, "
                "last checkpoint step %ld\n",
                k + 1, alive, delay, WIFSIGNALED(s) ? "killed" : "had finished", files, temps, step);
    EXPECT_GE(step, last_step);  // checkpoints only move forward
    last_step = std::max(last_step, step);
    if (HasFailure()) break;
  }
  // Each kill comes at most ~2 checkpoint intervals after the previous one's checkpoint, so
  // 5 kills cannot reach the end (2000 steps = 20 intervals): all must hit a running process.
  EXPECT_EQ(kills, kKills);
  const int end = wait_for(start_run(killed, fs::exists(killed / "out" / "checkpoint.bin")));
  ASSERT_TRUE(WIFEXITED(end) && WEXITSTATUS(end) == 0) << slurp(killed / "run.log");
  std::size_t temps = 0;
  check_outputs(killed / "out", temps);
  EXPECT_EQ(temps, 0u) << "temp files of killed runs must be removed by the next run";

  for (const char* file : {"final.csv", "energy.csv", "objects.csv"}) {
    EXPECT_EQ(data_rows(whole / "out" / file), data_rows(killed / "out" / file)) << file;
  }
  const Checkpoint a = read_checkpoint(whole / "out" / "checkpoint.bin");
  const Checkpoint b = read_checkpoint(killed / "out" / "checkpoint.bin");
  EXPECT_EQ(a.engine.step, kSteps);
  Checkpoint x, y;
  x.engine = a.engine;
  y.engine = b.engine;
  EXPECT_TRUE(encode_checkpoint(x) == encode_checkpoint(y)) << "final engine states differ";
  EXPECT_EQ(a.run.energy_rows, b.run.energy_rows);
  if (!HasFailure()) fs::remove_all(base);
}

}  // namespace
}  // namespace ppohdem::dem::test
