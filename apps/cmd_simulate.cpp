// `ppohdem simulate`: run a DEM scene.
//
//   ppohdem simulate SCENE.toml [--engine fast|reference|optimized] [--force] [--quiet]
//       Reads the TOML scene (ppohdem/dem/scene.hpp), runs it with the chosen engine (default
//       fast, the same bits as the reference; `--engine reference` runs the lecture code) and
//       writes final.csv, energy.csv and frames into the scene's [output] dir.
//   ppohdem simulate input_params_update.dat [--data-length L] [--steps N | --time-finish T]
//       The seed's sample_main01 (dem/legacy_scene.hpp), recognised by the first label
//       `Lx_Ly_Lz:` or forced with --legacy; run in the directory holding the distance files.
//   ppohdem simulate --compat ppohdem-1.0 input_params_update.dat [--initial STATE] [--steps N]
//       The original program number for number (cmd_simulate_compat.cpp, docs/compat.md §2).
// --steps / --time-finish override the end of any scene (short test runs).
//   --checkpoint-every N   write <dir>/checkpoint.bin every N steps and at the end
//   --restart FILE         continue from a checkpoint to the scene's (or --steps') end step
//   --perturb-seed K       move every particle coordinate by one ulp, seeded (dem/perturb.hpp)
//   --output-dir DIR       write the outputs to DIR instead of the scene's [output] dir
//   --phases A,B,...       report the wall time of the steps (first, A], (A, B], ..., (last, end]
//   --alternate-threads 1,2 [--alternate-every K]   switch the OpenMP thread count every K
//       steps (default 500; order 1 2 2 1 1 2 ...) and report each count's particle-steps per second: a
//       speed-up measured in one process, over the same phases of the run (the results do not
//       depend on the thread count; docs/performance.md)
// A run of at least kHugePagesFromSteps steps with at least kHugePagesFromParticles particles a
// thread asks for huge pages for its heap (ppohdem/heap_pages.hpp); the environment variable
// PPOHDEM_HUGE_PAGES=on|off|auto overrides.
// Under `mpirun -n P` (P > 1) the fast engine decomposes the domain over the P ranks
// (docs/dem.md "Domain decomposition"): the same files, byte for byte, as one rank (header
// line aside), written by rank 0; checkpoints are written per rank (a manifest and one part per
// rank, docs/formats.md "Checkpoints") and restart at any rank count. The reference engine runs
// on one rank only.
// (docs/reliability.md; a run that fails a check exits 1 with a diagnosis).
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <vector>

#ifdef PPOHDEM_WITH_OPENMP
#include <omp.h>
#endif

#include "commands.hpp"
#include "phase_timing.hpp"
#include "ppohdem/dem/engine.hpp"
#include "ppohdem/dem/fast/fast_engine.hpp"
#include "ppohdem/dem/legacy_scene.hpp"
#include "ppohdem/dem/perturb.hpp"
#include "ppohdem/dem/run.hpp"
#include "ppohdem/dem/scene.hpp"
#include "ppohdem/error.hpp"
#include "ppohdem/heap_pages.hpp"
#include "ppohdem/mesh/mesh_stats.hpp"
#include "ppohdem/provenance.hpp"
#include "ppohdem/dem/reference/reference_engine.hpp"

namespace ppohdem::app {

// apps/cmd_simulate_compat.cpp: `--compat ppohdem-1.0` (the original sample, number for number).
void run_simulate_compat(const std::string& mode, const std::string& params_file,
                         const std::optional<std::string>& initial, std::optional<long> steps, bool quiet);
namespace {

/// A run asks for huge pages by default from these many steps and particles a thread (per
/// rank): a 2 MiB page's first touch costs about 3 ms on these VMs, repaid in a few hundred
/// steps, and the TLB misses they save are those of a state larger than the TLB reaches in
/// small pages (5,000 particles a thread gained nothing; docs/performance.md "Huge pages for
/// long runs").
constexpr long kHugePagesFromSteps = 1000;
constexpr std::size_t kHugePagesFromParticles = 10000;

/// The OpenMP threads a run starts with (1 without OpenMP).
int run_threads() {
#ifdef PPOHDEM_WITH_OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

struct SimulateOptions {
  std::string input;
  std::string engine = "fast";
  bool force = false;
  bool quiet = false;
  bool legacy = false;
  std::optional<long> steps;          // overrides the scene's step count
  std::optional<double> time_finish;  // [s], overrides it as round(T / dt) steps
  std::optional<double> data_length;  // legacy: L of the distance data [m]
  std::string compat;                 // "ppohdem-1.0": the original program (cmd_simulate_compat.cpp)
  std::optional<std::string> initial; // compat: initial state file
  long checkpoint_every = 0;          // steps between checkpoints (0: none)
  std::string restart;                // checkpoint file to continue from
  const Comm* comm = nullptr;         // the ranks this program runs on (mpirun)
  std::vector<int> alternate_threads; // OpenMP thread counts to switch between (empty: none)
  long alternate_every = 500;         // steps per block of one thread count
  std::optional<std::uint64_t> perturb_seed;  // move every coordinate by one ulp (dem/perturb.hpp)
  std::string output_dir;             // overrides the scene's [output] dir
  std::vector<long> phases;           // step numbers ending the timed phases (phase_timing.hpp)
  bool no_object_skip = false;        // fast engine: evaluate every particle against every object
};

/// `--alternate-threads`: the run switches the OpenMP thread count at every K-th step boundary
/// and adds each block's wall time to its count. The counts then share the machine's state of
/// the moment (a shared VM's speed drifts between minutes) and every phase of the run
/// (free fall, impact, settling), which separate runs do not. The order goes back and forth
/// (A B B A A B ...: block b of round b / k takes count b % k, reversed in odd rounds), so that
/// a cost that grows or shrinks along the run falls on every count alike (strict turns A B A B
/// bias one count: docs/performance.md).
class ThreadAlternation {
 public:
  ThreadAlternation(std::vector<int> counts, long every, long last_step)
      : counts_(std::move(counts)), every_(every), last_step_(last_step), seconds_(counts_.size(), 0.0),
        steps_(counts_.size(), 0) {}

  void at_step_boundary(long done) {
    const auto now = std::chrono::steady_clock::now();
    if (started_) {
      if (done - block_first_ < every_ && done < last_step_) return;
      seconds_[current_] += std::chrono::duration<double>(now - block_start_).count();
      steps_[current_] += done - block_first_;
      ++block_;
      const std::size_t k = counts_.size(), round = block_ / k, place = block_ % k;
      current_ = round % 2 == 0 ? place : k - 1 - place;
    }
    started_ = true;
#ifdef PPOHDEM_WITH_OPENMP
    omp_set_num_threads(counts_[current_]);
#endif
    block_first_ = done;
    block_start_ = std::chrono::steady_clock::now();
  }

  /// One line per thread count: steps, seconds, particle-steps per second, ratio to the first.
  void report(std::size_t particles) const {
    const double first_rate = rate(0, particles);
    for (std::size_t k = 0; k < counts_.size(); ++k) {
      if (steps_[k] == 0 || first_rate == 0.0) {
        std::printf("alternate threads: %d thread(s) %ld steps: no ratio (the run is shorter than %zu blocks of %ld "
                    "steps)\n", counts_[k], steps_[k], counts_.size(), every_);
        continue;
      }
      std::printf("alternate threads: %d thread(s) %ld steps in %.3f s, %.4g particle-steps/s, %.3fx %d thread(s)\n",
                  counts_[k], steps_[k], seconds_[k], rate(k, particles), rate(k, particles) / first_rate, counts_[0]);
    }
  }

 private:
  double rate(std::size_t k, std::size_t particles) const {
    return seconds_[k] > 0.0 ? static_cast<double>(steps_[k]) * static_cast<double>(particles) / seconds_[k] : 0.0;
  }
  std::vector<int> counts_;
  long every_, last_step_;
  std::vector<double> seconds_;
  std::vector<long> steps_;
  std::size_t current_ = 0;  // index into counts_ of the running block
  std::size_t block_ = 0;    // blocks started before the running one
  bool started_ = false;
  long block_first_ = 0;
  std::chrono::steady_clock::time_point block_start_;
};

const std::map<std::string, dem::EngineFactory>& engines() {
  static const std::map<std::string, dem::EngineFactory> table{
      {"reference", &dem::reference::ReferenceEngine::make},
      {"fast", &dem::fast::FastEngine::make},
      {"optimized", &dem::fast::FastEngine::make}};
  return table;
}

/// Wall time of reading the scene and its particle file [s] (run_input).
struct ReadTiming {
  double seconds = 0.0;
};

void run_scene_file(const SimulateOptions& options, dem::Scene scene, ReadTiming read = {}) {
  if (options.steps) scene.steps = *options.steps;
  if (options.time_finish) {
    if (!(*options.time_finish >= 0.0)) throw InputError("--time-finish: expected a time >= 0 s");
    scene.steps = std::lround(*options.time_finish / scene.setup.dt);
  }
  if (scene.steps < 0) throw InputError("--steps: expected >= 0");
  scene.setup.force_time_step = options.force;
  if (options.quiet) scene.output.progress = false;
  if (!options.output_dir.empty()) scene.output.dir = options.output_dir;
  if (options.perturb_seed) {  // an ensemble member (docs/port-validation.md)
    if (!options.restart.empty()) throw InputError("--perturb-seed applies to a fresh start, not to --restart");
    dem::perturb_positions_by_one_ulp(scene.setup.particles, *options.perturb_seed);
  }
  const auto factory = engines().find(options.engine);
  if (factory == engines().end()) {
    throw InputError("--engine: expected 'reference', 'fast' or 'optimized', got '" + options.engine + "'");
  }
  const int ranks = options.comm->size();
  const bool root = options.comm->rank() == 0;
  if (ranks > 1 && factory->second != &dem::fast::FastEngine::make) {
    throw InputError("--engine " + options.engine + " runs on one rank only (this run has " + std::to_string(ranks) +
                     " MPI ranks): use --engine fast (alias optimized), which decomposes the domain, or run "
                     "without mpirun");
  }
  if (!root) scene.output.progress = false;
  const dem::TimeStepLimit limit = dem::time_step_limit(scene.setup);
  const auto setup_start = std::chrono::steady_clock::now();
  std::unique_ptr<dem::DemEngine> engine;  // validates (dt, overlaps, ...)
  if (ranks > 1 || (options.no_object_skip && factory->second == &dem::fast::FastEngine::make)) {
    dem::fast::FastOptions fast_options;
    if (ranks > 1) fast_options.comm = options.comm;
    fast_options.skip_far_objects = !options.no_object_skip;
    fast_options.balance = scene.parallel.balance ? dem::fast::FastOptions::Balance::kBisection
                                                  : dem::fast::FastOptions::Balance::kOff;
    fast_options.balance_threshold = scene.parallel.balance_threshold;
    engine = std::make_unique<dem::fast::FastEngine>(scene.setup, fast_options);
  } else {
    engine = factory->second(scene.setup);
  }
  // The engine holds the particles now; the scene's copy (or this rank's share) is not read
  // again (run_scene uses the materials, boundaries and outputs): free it (about 140 bytes per
  // particle), after counting them (no gather of the engine's).
  const std::size_t particle_count = scene.setup.particle_total();
  dem::Particles().swap(scene.setup.particles);
  const double setup_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - setup_start).count();
  std::string header = provenance_line(ranks) + "; engine " + engine->name();
  if (options.perturb_seed) header += "; perturb-seed " + std::to_string(*options.perturb_seed);
  if (root) std::fprintf(stderr, "%s\n", header.c_str());
  if (root && ranks > 1) {
    const auto grid = dynamic_cast<const dem::fast::FastEngine&>(*engine).rank_grid();
    if (scene.parallel.balance) {
      std::fprintf(stderr, "simulate: domain decomposed over %d ranks (recursive bisection by particle count, "
                   "re-cut when max/mean > %g)\n", ranks, scene.parallel.balance_threshold);
    } else {
      std::fprintf(stderr, "simulate: domain decomposed over %d ranks (%d x %d x %d bricks)\n", ranks, grid[0],
                   grid[1], grid[2]);
    }
  }
  if (root) std::fprintf(stderr, "simulate: %zu particles, %zu boundaries, dt %g s (limit %g s: %s), %ld steps\n",
               particle_count, scene.setup.boundaries.size(), scene.setup.dt,
               limit.limit, limit.reason.c_str(), scene.steps);
  // An open object mesh: as `voxelize` says, its inside comes from the winding number
  // (docs/objects.md "Exact contacts for mesh objects"), and users should know.
  for (std::size_t k = 0; root && k < scene.objects.size(); ++k) {
    const TriangleMesh* mesh = scene.objects[k].object->display_mesh();
    if (mesh == nullptr) continue;
    const MeshStats stats = compute_mesh_stats(*mesh);
    if (stats.watertight()) continue;
    std::fprintf(stderr,
                 "warning: object %zu (%s): mesh is not watertight (%zu boundary edges, %zu non-manifold edges, %zu "
                 "inconsistently oriented edges): inside and outside come from the generalized winding number\n",
                 k, scene.objects[k].object->name().c_str(), stats.boundary_edges, stats.non_manifold_edges,
                 stats.inconsistent_edges);
  }
  if (root && scene.setup.dt > limit.limit) {
    std::fprintf(stderr, "warning: dt is above the stability limit (--force)\n");
  }
  dem::RunOptions run_options;
  if (options.checkpoint_every < 0) throw InputError("--checkpoint-every: expected >= 0 steps");
  run_options.checkpoint_every = options.checkpoint_every;
  run_options.scene_name = options.input;
  if (ranks > 1) run_options.comm = options.comm;
  run_options.time_step_limit = limit;  // of the setup with its particles (freed above)
  if (!options.restart.empty()) {
    if (ranks > 1) {  // each rank reads its parts only (docs/formats.md "Checkpoints")
      dem::CheckpointShareRead mine = dem::read_checkpoint_share(options.restart, *options.comm);
      run_options.restart = std::make_shared<const dem::Checkpoint>(std::move(mine.checkpoint));
      if (mine.share) run_options.restart_share = std::make_shared<const dem::EngineStateShare>(std::move(*mine.share));
    } else {
      run_options.restart = std::make_shared<const dem::Checkpoint>(dem::read_checkpoint(options.restart));
    }
  }
  std::optional<ThreadAlternation> alternation;
  if (!options.alternate_threads.empty()) {
    if (options.alternate_every < 1) throw InputError("--alternate-every: expected >= 1 step");
    for (const int count : options.alternate_threads) {
      if (count < 1) throw InputError("--alternate-threads: expected thread counts >= 1, got " + std::to_string(count));
    }
    if (factory->second != &dem::fast::FastEngine::make) {
      throw InputError("--alternate-threads: the " + options.engine + " engine runs on one thread; use --engine fast");
    }
#ifndef PPOHDEM_WITH_OPENMP
    throw InputError("--alternate-threads: this build has no OpenMP");
#endif
    alternation.emplace(options.alternate_threads, options.alternate_every, scene.steps);
  }
  std::optional<PhaseTiming> phases;
  if (!options.phases.empty()) {
    const long first_step = run_options.restart ? run_options.restart->engine.step : 0;
    phases.emplace(options.phases, first_step, scene.steps);
  }
  // Huge pages for the heap of a run long enough to repay their first touches, with a state
  // per thread beyond the TLB's reach in small pages; asked before the first step and again
  // whenever the heap has grown (docs/performance.md "Huge pages for long runs").
  const long steps_to_run = scene.steps - (run_options.restart ? run_options.restart->engine.step : 0);
  const std::size_t particles_a_thread = particle_count / static_cast<std::size_t>(ranks * run_threads());
  const HugePages huge_pages = huge_pages_setting();
  const bool heap_in_huge_pages =
      huge_pages == HugePages::kOn || (huge_pages == HugePages::kAuto && steps_to_run >= kHugePagesFromSteps &&
                                       particles_a_thread >= kHugePagesFromParticles);
  double huge_pages_seconds = 0.0;  // the first request, for the heap as set up (not in the steps' time)
  if (heap_in_huge_pages) {
    const auto started = std::chrono::steady_clock::now();
    back_heap_with_huge_pages();
    huge_pages_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  }
  if (alternation || phases || heap_in_huge_pages) {
    run_options.at_step_boundary = [&alternation, &phases, heap_in_huge_pages](long done) {
      if (phases) phases->at_step_boundary(done);  // first: its clock excludes the thread switch
      if (heap_in_huge_pages) back_heap_with_huge_pages();
      if (alternation) alternation->at_step_boundary(done);
    };
  }
  const std::uint64_t messages_before = options.comm->messages_sent();
  // The first step of the run (run_scene restores a checkpoint itself).
  const long steps_before = run_options.restart ? run_options.restart->engine.step : engine->step_count();
  const long exchanges_before = ranks > 1 ? dynamic_cast<const dem::fast::FastEngine&>(*engine).load_report().exchanges : 0;
  const dem::RunSummary s = dem::run_scene(*engine, scene, header, std::cerr, run_options);
  // Particles per rank and the exchanges' messages (docs/dem.md "Load balance").
  std::optional<dem::fast::LoadReport> load;
  double messages_mean = 0.0, messages_max = 0.0;  // per rank per step
  double all_to_all = 0.0;  // what the same exchanges would send as all-to-all ones (2 (P - 1) each)
  if (ranks > 1) {
    load = dynamic_cast<const dem::fast::FastEngine&>(*engine).load_report();  // collective
    const double steps_run = static_cast<double>(std::max(engine->step_count() - steps_before, 1L));
    // The steps' messages: not those of the files written in parts (RunSummary::output_messages).
    const double mine = static_cast<double>(options.comm->messages_sent() - messages_before - s.output_messages) / steps_run;
    messages_mean = options.comm->sum_over_ranks(mine) / ranks;
    messages_max = options.comm->max_over_ranks(mine);
    const long exchanges = load->exchanges - exchanges_before;
    all_to_all = 2.0 * (ranks - 1) * static_cast<double>(exchanges) / steps_run;
  }
  std::vector<std::size_t> outside;  // samples outside each object's grid, all ranks
  for (const dem::SceneObject& o : scene.objects) {
    outside.push_back(static_cast<std::size_t>(
        std::llround(options.comm->sum_over_ranks(static_cast<double>(o.object->outside_grid_count())))));
  }
  if (!root) return;  // rank 0 reports
  // Particles inserted after step 0 brought energy in ([[insert]]): counted as input.
  const double e0 = s.initial.total() + s.inserted_energy.total();
  const double e1 = s.final.total();
  std::printf("engine %s\n", engine->name().c_str());
  std::printf("steps %ld, time %.6g s, wall %.3f s\n", s.steps, engine->time(), s.wall_seconds);
  std::printf("energy [J]: kinetic %.6e rotational %.6e gravitational %.6e elastic %.6e "
              "dissipated %.6e boundary_work %.6e\n",
              s.final.kinetic, s.final.rotational, s.final.gravitational, s.final.elastic,
              s.final.dissipated, s.final.boundary_work);
  if (scene.setup.energy_balance) {
    std::printf("energy balance: total %.9e -> %.9e J (relative change %.2e)%s\n", e0, e1,
                e0 != 0.0 ? (e1 - e0) / std::abs(e0) : e1 - e0,
                s.inserted > 0 ? " (initial + the energy of the particles inserted after step 0)" : "");
  } else {
    std::printf("energy balance: not tracked ([simulation] energy_balance = false)\n");
  }
  const dem::ContactCounts c = engine->contact_counts();
  std::printf("contacts: %zu particle-particle, %zu particle-wall; escaped particles: %zu\n",
              c.particle_pairs, c.particle_boundary, s.escaped);
  for (std::size_t k = 0; k < scene.objects.size(); ++k) {
    std::printf("%s: %zu samples outside its grid\n", scene.objects[k].object->describe().c_str(), outside[k]);
  }
  // Unequal cores cap what several threads can give (fast_engine.hpp, ThreadSpeeds).
  if (const auto* fast_engine = dynamic_cast<const dem::fast::FastEngine*>(engine.get())) {
    const dem::fast::ThreadSpeeds& speeds = fast_engine->thread_speeds();
    if (speeds.intervals > 0) {
      std::printf("threads%s: the slowest ran at %.3f of the fastest's speed (force kernel, mean over %zu "
                  "intervals between list builds; %.0f %% of the time below 0.9)\n",
                  ranks > 1 ? " of rank 0" : "", speeds.mean_ratio(), speeds.intervals,
                  100.0 * speeds.fraction_below_0_9());
    }
  }
  if (scene.setup.energy_balance) {
    std::printf("checks: largest overlap %.3g %% of the radius (limit %.3g %%), largest energy growth "
                "%.3g %% (limit %.3g %%)\n", 100.0 * s.margins.overlap, 100.0 * scene.checks.max_overlap,
                100.0 * s.margins.energy_growth, 100.0 * scene.checks.max_energy_growth);
  } else {
    std::printf("checks: largest overlap %.3g %% of the radius (limit %.3g %%), energy check off\n",
                100.0 * s.margins.overlap, 100.0 * scene.checks.max_overlap);
  }
  std::printf("wrote %s (final.csv, energy.csv, %zu frames)\n", scene.output.dir.string().c_str(),
              s.frames);
  // Where a large run's time goes besides the steps (docs/performance.md "A million particles").
  std::printf("timing: read %.3f s, setup %.3f s, steps %.3f s, gather %.3f s, write %.3f s (%.1f MB, %.0f MB/s)\n",
              read.seconds, setup_seconds, s.wall_seconds, s.gather_seconds, s.write_seconds,
              static_cast<double>(s.write_bytes) / 1e6,
              s.write_seconds > 0.0 ? static_cast<double>(s.write_bytes) / 1e6 / s.write_seconds : 0.0);
  if (s.inserted + s.insert_failed > 0) {
    std::printf("timing: insertions %.3f s (step 0's before the steps, later ones part of the steps' time)\n",
                s.insert_seconds);
  }
  if (s.checkpoints > 0) {
    std::printf("timing: %zu checkpoints in %.3f s (part of the steps' time)\n", s.checkpoints, s.checkpoint_seconds);
  }
  if (heap_in_huge_pages) {
    const std::string why = huge_pages == HugePages::kOn ? "on" : "auto: a run of >= " + std::to_string(kHugePagesFromSteps) + " steps and >= " +
                                 std::to_string(kHugePagesFromParticles) + " particles a thread";
    std::printf("memory: %.0f MiB of the heap asked for in huge pages (PPOHDEM_HUGE_PAGES %s), %.3f s before the steps\n",
                static_cast<double>(heap_bytes_asked_for_huge_pages()) / (1 << 20), why.c_str(), huge_pages_seconds);
  }
  if (load) {
    std::printf("load balance: %s, %ld re-cuts; particles per rank max/mean %.3f (equal bricks of the initial "
                "box: %.3f); exchanges: %.2f messages per rank per step (max %.2f; as all-to-all exchanges: %.2f), %zu "
                "peers on rank 0, %ld global migrations; ghosts per rank %.1f (max %.0f); interior particles per "
                "rank %.1f (min %.0f), %ld halo refreshes overlapped on rank 0\n",
                scene.parallel.balance ? "rcb" : "off", load->recuts, load->max_over_mean,
                load->equal_bricks_max_over_mean, messages_mean, messages_max, all_to_all, load->peers,
                load->global_exchanges, load->ghosts_mean, load->ghosts_max, load->interior_mean, load->interior_min,
                load->overlapped_refreshes);
  }
  if (alternation) alternation->report(particle_count);
  if (phases) phases->report(particle_count);
}

// A legacy ppohDEM input_params_update.dat starts (after blank lines) with the label
// `Lx_Ly_Lz:` (users' guide List 2.2); a TOML scene cannot (it would be a syntax error).
bool looks_like_legacy_input(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos) continue;
    return line.compare(first, 9, "Lx_Ly_Lz:") == 0;
  }
  return false;
}

void run_input(const SimulateOptions& options) {
  if (!options.compat.empty()) {
    if (options.comm->size() > 1) throw InputError("--compat runs on one rank only (run it without mpirun)");
    run_simulate_compat(options.compat, options.input, options.initial, options.steps, options.quiet);
    return;
  }
  if (options.initial) throw InputError("--initial applies to --compat ppohdem-1.0 only");
  const auto read_start = std::chrono::steady_clock::now();
  auto read_time = [&] {
    return ReadTiming{std::chrono::duration<double>(std::chrono::steady_clock::now() - read_start).count()};
  };
  if (options.legacy || looks_like_legacy_input(options.input)) {
    dem::LegacySceneOptions legacy;
    legacy.data_length = options.data_length;
    dem::Scene scene = dem::read_legacy_scene(options.input, legacy);
    run_scene_file(options, std::move(scene), read_time());
    return;
  }
  if (options.data_length) throw InputError("--data-length applies to legacy inputs only");
  // Several ranks: each reads and keeps a share of the particle file (docs/dem.md "Reading on
  // every rank"); the fast engine places the shares.
  dem::Scene scene = dem::read_scene(options.input, options.comm->size() > 1 ? options.comm : nullptr);
  run_scene_file(options, std::move(scene), read_time());
}

}  // namespace

void register_simulate(CLI::App& app, const Comm& comm) {
  auto options = std::make_shared<SimulateOptions>();
  options->comm = &comm;
  CLI::App* cmd = app.add_subcommand("simulate", "run a DEM scene (TOML) and write its outputs");
  cmd->add_option("scene", options->input, "scene file (TOML)")->required();
  cmd->add_option("--engine", options->engine, "engine: fast (default; alias optimized) or reference (the lecture code, serial)")->capture_default_str();
  cmd->add_flag("--force", options->force, "run even if dt is above the stability limit");
  cmd->add_flag("--quiet", options->quiet, "no progress lines on stderr");
  cmd->add_flag("--legacy", options->legacy, "read the input as a legacy input_params_update.dat");
  cmd->add_option("--steps", options->steps, "run this many steps instead of the scene's");
  cmd->add_option("--time-finish", options->time_finish, "run to this time [s] instead of the scene's end");
  cmd->add_option("--checkpoint-every", options->checkpoint_every,
                  "write <output dir>/checkpoint.bin every N steps and at the end");
  cmd->add_option("--restart", options->restart, "continue from this checkpoint file");
  cmd->add_option("--alternate-threads", options->alternate_threads,
                  "fast engine: switch between these OpenMP thread counts (e.g. 1,2) every --alternate-every "
                  "steps and report each count's particle-steps per second")
      ->delimiter(',');
  cmd->add_option("--alternate-every", options->alternate_every, "steps per block of --alternate-threads")
      ->capture_default_str();
  cmd->add_option("--perturb-seed", options->perturb_seed,
                  "move every particle coordinate by one ulp, up or down as seed K draws it (ensemble member K; "
                  "docs/port-validation.md)");
  cmd->add_option("--phases", options->phases,
                  "report the wall time of each phase of the run, the phases ending at these steps (e.g. "
                  "500,2500,6000) and at the last step")
      ->delimiter(',');
  cmd->add_flag("--no-object-skip", options->no_object_skip,
                "fast engine: evaluate every particle against every object, also far ones (a diagnostic: "
                "the same results, slower; docs/objects.md \"Far objects cost nothing\")");
  cmd->add_option("--output-dir", options->output_dir, "write the outputs here instead of the scene's [output] dir");
  cmd->add_option("--data-length", options->data_length,
                  "legacy: length L [m] of the distance data (default: from input_constants_voxelizer.dat)");
  cmd->add_option("--compat", options->compat,
                  "ppohdem-1.0: run input_params_update.dat as the original program does, number for number "
                  "(docs/compat.md); run where distance_NNNN.dat and object_mesh.stl are");
  cmd->add_option("--initial", options->initial,
                  "compat: initial state, the original's full-precision dump (e.g. state_step000000.dat)");
  cmd->callback([options] { run_input(*options); });
}

}  // namespace ppohdem::app
