#pragma once
/// \file run.hpp
/// Drive an engine through a scene and write its outputs (output_writers.hpp):
///   <dir>/final.csv always; <dir>/energy.csv with a row at step 0, every `every` steps (or
///   every steps/100 if every = 0) and at the end; frames at step 0 and every `every` steps
///   in the formats asked for. Progress on stderr (at most every 10% or 5 s) if asked.
/// Steps are counted from the start of the scene (a restarted run continues the count), and
/// the run ends at step scene.steps.
/// Checkpoints (checkpoint.hpp): with checkpoint_every = N > 0, <dir>/checkpoint.bin is
///   replaced atomically at every step that is a multiple of N and at the last step, after
///   that step's outputs; with several ranks (comm) it is a manifest written after every
///   rank's part (checkpoint.hpp "Parts"). A restart (RunOptions::restart) restores the engine, checks that the
///   objects are where the checkpoint saw them, and continues energy.csv, objects.csv and the
///   frame numbering, so a run to the same end step gives the same files (up to the header
///   line) as an uninterrupted one. Stale temp files of killed runs in <dir> are removed.
/// Insertion ([[insert]], insertion_run.hpp): the events due at a step run right after it (step
///   0's before the initial outputs), so that step's outputs and checkpoint include them.
/// Diagnostics (run_diagnostics.hpp) after every step; a failed check writes the logs and
///   <dir>/failed_checkpoint.bin and throws RunFailure.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <ostream>
#include <string>

#include "ppohdem/comm/comm.hpp"
#include "ppohdem/dem/checkpoint.hpp"
#include "ppohdem/dem/engine.hpp"
#include "ppohdem/dem/run_diagnostics.hpp"
#include "ppohdem/dem/scene.hpp"

namespace ppohdem::dem {

struct RunSummary {
  long steps = 0;
  double wall_seconds = 0.0;  ///< time loop only [s]
  double gather_seconds = 0.0;  ///< the final particles gathered (several ranks: each rank's part of final.csv) [s]
  double write_seconds = 0.0;   ///< final.csv written (rank 0) [s]
  /// Point-to-point messages this rank sent for the files written in parts (CSV, legacy VTK
  /// and POV-Ray frames, final.csv): not the steps' (Comm::messages_sent counts both).
  std::uint64_t output_messages = 0;
  std::uintmax_t write_bytes = 0;  ///< size of final.csv (rank 0) [B]
  std::size_t checkpoints = 0;        ///< checkpoints written by the time loop
  double checkpoint_seconds = 0.0;    ///< their time (rank 0, part of wall_seconds) [s]
  Energies initial;
  Energies final;
  std::size_t escaped = 0;
  std::size_t frames = 0;
  CheckMargins margins;  ///< largest overlap and energy growth seen (run_diagnostics.hpp)
  std::int64_t inserted = 0;       ///< particles inserted by [[insert]] (insertion_run.hpp)
  std::int64_t insert_failed = 0;  ///< particles [[insert]] asked for but found no place for
  /// Wall time of the [[insert]] events (rank 0): step 0's before the time loop, the later
  /// ones part of wall_seconds [s]
  double insert_seconds = 0.0;
  /// Kinetic, rotational and gravitational energy of the particles inserted after step 0 [J]
  Energies inserted_energy;
};

struct RunOptions {
  long checkpoint_every = 0;  ///< steps between checkpoints; 0 = none
  /// Continue from this checkpoint (read_checkpoint) instead of step 0.
  std::shared_ptr<const Checkpoint> restart;
  /// Several ranks restarting from a checkpoint's parts (read_checkpoint_share): this rank's
  /// share of the engine state, restored by DemEngine::restore_state_share; `restart` then
  /// holds the manifest's other fields. nullptr: `restart` holds the whole state.
  std::shared_ptr<const EngineStateShare> restart_share;
  std::string scene_name;  ///< recorded in checkpoints (information)
  /// Several ranks (an engine decomposed over them, e.g. fast::FastOptions::comm): every rank
  /// calls run_scene; the engine's queries are collective and global, rank 0 alone writes the
  /// files and the progress lines, and the objects' outside-grid counts are summed over ranks.
  /// nullptr: one rank.
  const Comm* comm = nullptr;
  /// The scene's stability limit (time_step_limit of the setup WITH its particles), for a
  /// caller that frees scene.setup.particles once the engine holds them; empty: computed from
  /// scene.setup.
  std::optional<TimeStepLimit> time_step_limit;
  /// Called with the engine's step count before the first step and after every step (after
  /// its checks, logs and checkpoint): for a caller that times or tunes blocks of steps
  /// (`ppohdem simulate --alternate-threads`). Empty: not called.
  std::function<void(long steps_done)> at_step_boundary;
};

/// File names in the output directory.
inline constexpr const char* kCheckpointFile = "checkpoint.bin";
inline constexpr const char* kFailedCheckpointFile = "failed_checkpoint.bin";

/// Removes "<name>.tmp.<pid>.<n>" files (io/atomic_file.hpp) in `dir` whose process is gone;
/// returns how many.
std::size_t remove_stale_temp_files(const std::filesystem::path& dir);

/// `header` is the run header written at the top of every output (provenance + engine).
/// Creates output.dir if needed. `log` receives a one-line summary at the end.
RunSummary run_scene(DemEngine& engine, const Scene& scene, const std::string& header,
                     std::ostream& log, const RunOptions& options = {});

}  // namespace ppohdem::dem
