// The chaotic tier's modes of `ppohdem validate` (port_check.hpp; docs/port-validation.md).
#include "port_check.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "ppohdem/dem/particle_csv.hpp"
#include "ppohdem/io/atomic_file.hpp"
#include "deterministic.hpp"
#include "engines.hpp"
#include "growth.hpp"
#include "plot.hpp"
#include "ppohdem/validation/check_registry.hpp"
#include "port_scenes.hpp"
#include "report.hpp"
#include "subprocess.hpp"

namespace ppohdem::port {
namespace fs = std::filesystem;
namespace {

std::vector<std::string> words(const std::string& s) {
  std::vector<std::string> w;
  std::istringstream in(s);
  for (std::string x; in >> x;) w.push_back(x);
  return w;
}

double children_cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_CHILDREN, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

std::string fmt(const char* format, double x) {
  char b[64];
  std::snprintf(b, sizeof b, format, x);
  return b;
}

std::vector<std::string> provenance_lines(const std::string& command) {
  std::vector<std::string> lines;
  for (const auto& [key, value] : validation::provenance_fields()) lines.push_back(key + ": " + value);
  lines.push_back("command: " + command);
  return lines;
}

/// Runs `seeds` members of an exported scene (one output folder each, under `dir`) and
/// returns their observables; each folder is deleted once read unless `keep`.
std::vector<Observables> run_members(const PortScene& scene, const fs::path& scene_file, const std::vector<long>& seeds,
                                     const fs::path& dir, const PortOptions& options, bool keep,
                                     std::vector<fs::path>* run_dirs = nullptr) {
  const std::string program = find_ppohdem_program();
  std::vector<std::vector<std::string>> commands;
  std::vector<std::string> logs;
  std::vector<fs::path> outs;
  fs::create_directories(dir);
  for (const long seed : seeds) {
    const fs::path out = dir / ("seed_" + std::to_string(seed));
    fs::remove_all(out);
    outs.push_back(out);
    commands.push_back({program, "simulate", scene_file.string(), "--engine", options.engine, "--quiet",
                        "--perturb-seed", std::to_string(seed), "--output-dir", out.string()});
    logs.push_back((dir / ("seed_" + std::to_string(seed) + ".log")).string());
    fs::remove(logs.back());
  }
  std::fprintf(stderr, "[port] %s: %zu runs of %ld steps (%d at a time)\n", scene.name.c_str(), seeds.size(),
               scene.steps, options.jobs);
  const auto status = run_programs(commands, logs, options.jobs, words(options.launcher));
  std::vector<Observables> result;
  for (std::size_t k = 0; k < seeds.size(); ++k) {
    if (status[k] != 0) {
      throw std::runtime_error("ppohdem simulate " + scene.name + " --perturb-seed " + std::to_string(seeds[k]) +
                               " exited " + std::to_string(status[k]) + ": see " + logs[k]);
    }
    result.push_back(run_observables(scene, outs[k]));
    if (!keep) {
      fs::remove_all(outs[k]);
      fs::remove(logs[k]);
    }
  }
  if (run_dirs) *run_dirs = outs;
  return result;
}

fs::path work_directory(const PortOptions& options) {
  const fs::path work = options.work_dir.empty()
                            ? fs::temp_directory_path() / ("ppohdem-port-" + std::to_string(::getpid()))
                            : fs::path(options.work_dir);
  fs::create_directories(work);
  return work;
}

PortScene scene_to_run(const std::string& name, const PortOptions& options) {
  return scaled(port_scene(name), options.scale);
}

std::vector<std::string> chosen_scenes(const PortOptions& options) {
  return options.scenes.empty() ? port_scene_names() : options.scenes;
}

/// The growth diagnostic's data from member folders (the first 40, in pairs) and a reference run
/// of kGrowthSeed, made here.
void make_growth(const PortScene& scene, const fs::path& scene_file, const std::vector<fs::path>& members,
                 const fs::path& dir, const fs::path& work, const PortOptions& options) {
  std::vector<fs::path> reference;
  run_members(scene, scene_file, {kGrowthSeed}, work / "runs" / (scene.name + "_growth"), options, true, &reference);
  const std::vector<fs::path> pairs(members.begin(), members.begin() + std::min<std::size_t>(members.size(), 40));
  save_growth(dir, scene.name, pairs, reference.front());
  fs::remove_all(reference.front());
}

int export_scenes(const PortOptions& options) {
  for (const auto& name : chosen_scenes(options)) {
    const fs::path file = export_scene(scene_to_run(name, options), options.export_scenes, options.source_dir,
                                       find_ppohdem_program());
    std::printf("wrote %s\n", file.string().c_str());
  }
  return 0;
}

/// Fraction of the triples of held-out seeds (the same seeds in every scene) that fail in at
/// least one scene: the false-positive rate of a whole port check.
double combined_false_positive_rate(const std::vector<Baseline>& baselines,
                                    const std::vector<std::vector<Observables>>& held_out) {
  const std::size_t n = held_out.front().size();
  std::size_t triples = 0, failed = 0;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j)
      for (std::size_t k = j + 1; k < n; ++k) {
        ++triples;
        bool fail = false;
        for (std::size_t s = 0; s < baselines.size(); ++s) {
          fail = fail || !judge(baselines[s], {held_out[s][i], held_out[s][j], held_out[s][k]}).pass;
        }
        failed += fail ? 1 : 0;
      }
  return triples > 0 ? static_cast<double>(failed) / static_cast<double>(triples) : 0.0;
}

/// --refit: the baseline's statistics again from its stored members, with options.rule; prints
/// the false-positive rates (the rule can be chosen without running anything).
int refit_baseline(const PortOptions& options, const std::string& command) {
  const fs::path dir = options.save_baseline;
  std::vector<Baseline> baselines;
  std::vector<std::vector<Observables>> held;
  for (const auto& name : chosen_scenes(options)) {
    const fs::path members = dir / (name + ".members.csv");
    if (!fs::exists(members)) continue;
    const Baseline old = read_baseline(dir / (name + ".baseline.csv"));
    Baseline b = fit_baseline(name, read_members(members, "fit"), options.rule);
    b.particle_count = old.particle_count;
    b.radius_sum = old.radius_sum;
    b.provenance = old.provenance;
    b.provenance.push_back("refit: " + command);
    held.push_back(read_members(members, "held-out"));
    const auto [rate, triples] = false_positive_rate(b, held.back());
    std::printf("%s: %zu PCs, false-positive rate %.2f %% of %zu held-out triples\n", name.c_str(),
                static_cast<std::size_t>(b.eigenvalues.size()), 100.0 * rate, triples);
    write_baseline(dir, b);
    baselines.push_back(std::move(b));
  }
  if (baselines.empty()) throw std::invalid_argument(dir.string() + ": no <scene>.members.csv to refit");
  if (baselines.size() > 1) {
    std::printf("whole check: false-positive rate %.2f %%\n", 100.0 * combined_false_positive_rate(baselines, held));
  }
  return 0;
}

int save_baseline(const PortOptions& options, const std::string& command) {
  if (options.refit) return refit_baseline(options, command);
  const auto t0 = std::chrono::steady_clock::now();
  const double cpu0 = children_cpu_seconds();
  const fs::path dir = options.save_baseline;
  fs::create_directories(dir);
  const fs::path work = work_directory(options);
  std::vector<Baseline> baselines;
  std::vector<std::vector<Observables>> held;
  std::ostringstream summary;
  if (options.growth_only) {  // only the growth diagnostic (into an existing baseline)
    for (const auto& name : chosen_scenes(options)) {
      const PortScene scene = scene_to_run(name, options);
      const fs::path scene_file = export_scene(scene, work / "scenes", options.source_dir, find_ppohdem_program());
      std::vector<long> seeds;
      for (int k = 1; k <= 40; ++k) seeds.push_back(k);
      std::vector<fs::path> dirs;
      run_members(scene, scene_file, seeds, work / "runs" / name, options, true, &dirs);
      make_growth(scene, scene_file, dirs, dir, work, options);
      for (const auto& d : dirs) fs::remove_all(d);
    }
    std::printf("wrote the growth diagnostic into %s\n", dir.string().c_str());
    if (options.work_dir.empty()) fs::remove_all(work);
    return 0;
  }
  if (options.members == 0) {  // only the deterministic tier's references (into an existing baseline)
    const auto runs = run_deterministic_scenes(work, options.source_dir, options.engine, options.launcher);
    for (std::size_t k = 0; k < runs.size(); ++k) save_deterministic_reference(dir, deterministic_scene_names()[k], runs[k]);
    std::printf("wrote the deterministic references into %s\n", dir.string().c_str());
    if (options.work_dir.empty()) fs::remove_all(work);
    return 0;
  }
  for (const auto& name : chosen_scenes(options)) {
    const PortScene scene = scene_to_run(name, options);
    const fs::path scene_file = export_scene(scene, work / "scenes", options.source_dir, find_ppohdem_program());
    std::vector<long> seeds;
    std::vector<bool> held_flags;
    for (int k = 1; k <= options.members + options.held_out; ++k) {
      seeds.push_back(k);
      held_flags.push_back(k > options.members);
    }
    const double scene_cpu0 = children_cpu_seconds();
    std::vector<fs::path> dirs;
    const auto members = run_members(scene, scene_file, seeds, work / "runs" / name, options, true, &dirs);
    make_growth(scene, scene_file, dirs, dir, work, options);
    for (const auto& d : dirs) fs::remove_all(d);
    const double scene_cpu = children_cpu_seconds() - scene_cpu0;
    std::vector<Observables> fit(members.begin(), members.begin() + options.members);
    held.emplace_back(members.begin() + options.members, members.end());
    Baseline b = fit_baseline(name, fit, options.rule);
    const auto particles = dem::read_particles_csv(scene_file.parent_path() / "particles.csv");
    b.particle_count = particles.size();
    for (const auto& p : particles) b.radius_sum += p.radius;
    b.provenance = provenance_lines(command);
    b.provenance.push_back("scene: " + scene.description);
    write_baseline(dir, b);
    write_members(dir, name, seeds, held_flags, members);
    summary << "| " << name << " | " << b.names.size() << " (+" << b.constant_names.size() << " constant) | "
            << b.eigenvalues.size() << " | " << options.members << " + " << options.held_out << " | "
            << fmt("%.0f", scene_cpu) << " s |";
    if (options.held_out >= 3) {
      const auto [rate, triples] = false_positive_rate(b, held.back());
      summary << " " << fmt("%.2f", 100.0 * rate) << " % of " << triples << " |";
    } else {
      summary << " - |";
    }
    summary << "\n";
    baselines.push_back(std::move(b));
  }
  const auto deterministic = run_deterministic_scenes(work, options.source_dir, options.engine, options.launcher);
  for (std::size_t k = 0; k < deterministic.size(); ++k) {
    save_deterministic_reference(dir, deterministic_scene_names()[k], deterministic[k]);
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  AtomicFileWriter readme(dir / "README.md");
  auto& o = readme.stream();
  o << "# Port-validation baseline\n\nThe reference ensembles of the chaotic tier (docs/port-validation.md): for "
       "each scene, every member's observables (`<scene>.members.csv`: seed, fit or held-out, values) and the "
       "statistics a port is judged against (`<scene>.baseline.csv`: observables, means, standard deviations, "
       "and the kept principal components of their correlation matrix: eigenvalue, loadings). "
       "`deterministic_<scene>.csv`: the deterministic tier's numbers (velocity and spin changes after 1 and 4 "
       "steps, energies, object loads) of the dense scenes.\n\n"
       "Regenerate (on a trusted machine):\n\n    "
    << command << "\n\n## Provenance\n\n";
  for (const auto& line : provenance_lines(command)) o << "- " << line << "\n";
  o << "- wall time " << fmt("%.0f", wall) << " s, CPU time of the simulations " << fmt("%.0f", children_cpu_seconds() - cpu0)
    << " s\n\n## Ensembles\n\nRule: a PC fails when its score is beyond " << options.rule.sigma << " sigma in at least "
    << options.rule.runs_needed << " of the 3 runs; a check fails when at least " << options.rule.min_failing_pcs
    << " PC(s) fail. PCs kept: the leading ones explaining " << 100.0 * options.rule.variance_kept
    << " % of the variance.\n\n| scene | observables | PCs kept | members (fit + held-out) | CPU | false-positive rate "
       "(held-out triples) |\n|---|---|---|---|---|---|\n"
    << summary.str();
  if (baselines.size() > 1 && options.held_out >= 3) {
    o << "\nWhole check (a triple of held-out seeds fails if any scene fails): false-positive rate "
      << fmt("%.2f", 100.0 * combined_false_positive_rate(baselines, held)) << " %.\n";
  }
  readme.commit();
  std::printf("wrote baseline %s (%.0f s)\n", dir.string().c_str(), wall);
  if (options.work_dir.empty()) fs::remove_all(work);
  return 0;
}

/// The baseline of the scene the runs in `dirs` hold (by particle count and sum of radii).
const Baseline& baseline_of_runs(const std::vector<Baseline>& baselines, const std::vector<std::string>& dirs) {
  const Baseline* found = nullptr;
  for (const auto& dir : dirs) {
    const RunFingerprint f = run_fingerprint(dir);
    const Baseline* match = nullptr;
    for (const auto& b : baselines) {
      if (b.particle_count == f.count && std::abs(b.radius_sum - f.radius_sum) <= 1e-9 * b.radius_sum) match = &b;
    }
    if (!match) {
      throw std::invalid_argument(dir + ": " + std::to_string(f.count) + " particles, radii summing to " +
                                  fmt("%.9g", f.radius_sum) + " m: not a scene of the baseline (export them with "
                                  "ppohdem validate --export-scenes DIR)");
    }
    if (found && found != match) throw std::invalid_argument("--external: the runs are of different scenes");
    found = match;
  }
  return *found;
}

struct SceneResult {
  const Baseline* baseline = nullptr;
  std::vector<std::string> runs;  // labels
  Verdict verdict;
  std::vector<GrowthRow> growth;  // empty: no growth diagnostic
  std::vector<Observables> observed;  // the runs' observables (the standardised table)
};

/// Each observable of each run as (value - mean) / stddev of the fit members: the rule scores
/// the PCs, this table says which observables a failing PC is made of. The runs' values go to
/// img/port_observables_<scene>.csv (one row per run), for studies beyond the check.
void write_standardised_table(std::ostream& o, const Baseline& b, const std::vector<std::string>& labels,
                              const std::vector<Observables>& runs, const fs::path& img) {
  if (runs.empty()) return;
  std::vector<std::vector<double>> values;
  for (const auto& run : runs) {
    values.emplace_back();
    for (const auto& name : b.names) {
      const auto it = std::find(run.names.begin(), run.names.end(), name);
      values.back().push_back(it == run.names.end() ? std::nan("") : run.values[static_cast<std::size_t>(it - run.names.begin())]);
    }
  }
  const std::string csv = "port_observables_" + b.scene + ".csv";
  validation::write_csv((img / csv).string(), b.names, values);
  o << "\nObservables standardised by the ensemble, (run - mean) / standard deviation of the "
    << b.fit_members << " fit members (beyond " << b.rule.sigma << " marked):\n\n| observable | mean | sd |";
  for (const auto& label : labels) o << " " << label << " |";
  o << "\n|---|---|---|";
  for (std::size_t c = 0; c < labels.size(); ++c) o << "---|";
  o << "\n";
  std::vector<Eigen::VectorXd> z;
  for (const auto& run : runs) z.push_back(standardised(b, run));
  for (std::size_t k = 0; k < b.names.size(); ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    o << "| " << b.names[k] << " | " << fmt("%.6g", b.mean(i)) << " | " << fmt("%.3g", b.stddev(i)) << " |";
    for (const auto& zr : z) o << " " << fmt("%+.2f", zr(i)) << (std::abs(zr(i)) > b.rule.sigma ? " **!**" : "") << " |";
    o << "\n";
  }
  o << "\nThe runs' values: [img/" << csv << "](img/" << csv << ").\n";
}

/// The oracle suite's analytic groups (Chung & Ooi), run in this process with the fast engine.
std::vector<validation::CheckRow> analytic_checks(const PortOptions& options, const fs::path& work, const fs::path& img) {
  validation::CheckContext ctx;
  ctx.quick = true;
  ctx.source_dir = options.source_dir;
  ctx.work_dir = (work / "analytic").string();
  ctx.img_dir = img.string();
  ctx.engines = {"fast"};
  fs::create_directories(ctx.work_dir);
  std::vector<validation::CheckRow> rows;
  for (const auto& g : validation::all_check_groups()) {
    if (g.name.rfind("Chung & Ooi", 0) != 0) continue;
    std::fprintf(stderr, "[port] deterministic tier: %s\n", g.name.c_str());
    for (auto& row : g.run(ctx)) {
      row.check = g.name + ": " + row.check;
      rows.push_back(std::move(row));
    }
  }
  return rows;
}

void write_report(const fs::path& out, const std::vector<SceneResult>& results, const PortOptions& options,
                  const std::string& command, double wall, double cpu, bool pass,
                  const std::vector<DeterministicRow>& deterministic,
                  const std::vector<validation::CheckRow>& analytic) {
  const fs::path img = out.parent_path() / "img";
  fs::create_directories(img);
  const fs::path work = work_directory(options);
  AtomicFileWriter w(out);
  auto& o = w.stream();
  o << "# Port validation report\n\n**Verdict: " << (pass ? "PASS" : "FAIL") << "** (deterministic tier and "
    << "ensemble consistency test, docs/port-validation.md)\n\n## Provenance\n\n";
  for (const auto& line : provenance_lines(command)) o << "- " << line << "\n";
  o << "- baseline: " << (options.against.empty() ? "(default)" : options.against) << "\n";
  o << "- runs: ppohdem simulate --engine " << options.engine
    << (options.launcher.empty() ? std::string(" (no launcher)") : " under '" + options.launcher + "'") << "\n";
  if (!options.scale.empty()) {
    o << "- known-bad change:";
    for (const auto& [k, v] : options.scale) o << " " << k << " x " << fmt("%.17g", v);
    o << "\n";
  }
  o << "- wall time " << fmt("%.1f", wall) << " s, CPU time of the simulations " << fmt("%.1f", cpu) << " s\n";
  if (!deterministic.empty() || !analytic.empty()) {
    o << "\n## Deterministic tier\n\n| scene | quantity | relative difference to the baseline | tolerance | |\n"
      << "|---|---|---|---|---|\n";
    for (const auto& d : deterministic) {
      o << "| " << d.scene << " | " << d.quantity << " | " << fmt("%.3g", d.measured) << " | "
        << fmt("%.0e", d.tolerance) << " | " << (d.passed() ? "pass" : "**FAIL**") << " |\n";
    }
    if (!analytic.empty()) {
      o << "\nAnalytic checks of the oracle suite (fast engine):\n\n| check | measured | expected | tolerance | |\n"
        << "|---|---|---|---|---|\n";
      for (const auto& a : analytic) {
        o << "| " << a.check << " | " << a.measured << " | " << a.expected << " | " << a.tolerance << " | "
          << (a.passed ? "pass" : "**FAIL**") << " |\n";
      }
    }
  }
  for (const auto& r : results) {
    const Baseline& b = *r.baseline;
    o << "\n## " << b.scene << ": " << (r.verdict.pass ? "PASS" : "FAIL") << "\n\n"
      << "Baseline of " << b.fit_members << " members; " << b.names.size() << " observables, " << b.eigenvalues.size()
      << " PCs. Rule: a PC fails beyond " << b.rule.sigma << " sigma in >= " << b.rule.runs_needed << " of "
      << r.runs.size() << " runs; the scene fails with >= " << b.rule.min_failing_pcs << " failing PC(s). Failing PCs:";
    if (r.verdict.failing_pcs.empty()) o << " none";
    for (const int k : r.verdict.failing_pcs) o << " " << k + 1;
    o << ".\n\n| PC | eigenvalue |";
    for (const auto& run : r.runs) o << " " << run << " |";
    o << "\n|---|---|";
    for (std::size_t k = 0; k < r.runs.size(); ++k) o << "---|";
    o << "\n";
    std::vector<std::vector<double>> rows;
    for (Eigen::Index k = 0; k < r.verdict.scores.rows(); ++k) {
      o << "| " << k + 1 << " | " << fmt("%.3g", b.eigenvalues(k)) << " |";
      std::vector<double> row{static_cast<double>(k + 1)};
      for (Eigen::Index c = 0; c < r.verdict.scores.cols(); ++c) {
        const double s = r.verdict.scores(k, c);
        o << " " << fmt("%+.2f", s) << (std::abs(s) > b.rule.sigma ? " **!**" : "") << " |";
        row.push_back(s);
      }
      o << "\n";
      rows.push_back(row);
    }
    std::vector<std::string> header{"pc"};
    for (std::size_t c = 0; c < r.runs.size(); ++c) header.push_back("run" + std::to_string(c + 1));
    const std::string csv = (work / ("scores_" + b.scene + ".csv")).string();
    validation::write_csv(csv, header, rows);
    validation::CheckContext ctx;
    ctx.source_dir = options.source_dir;
    ctx.img_dir = img.string();
    const std::string png = "port_scores_" + b.scene + ".png";
    const char* env = std::getenv("PPOHDEM_PYTHON");
    const std::string python = env ? env : "/usr/bin/python3";
    const std::string script = (fs::path(options.source_dir) / "validation" / "port" / "plot_port.py").string();
    const std::string cmd = validation::shell_quote(python) + " " + validation::shell_quote(script) + " scores " +
                            validation::shell_quote(csv) + " " + validation::shell_quote((img / png).string()) + " " +
                            fmt("%g", b.rule.sigma) + " " + validation::shell_quote(b.scene) + " 1>&2";
    if (std::system(cmd.c_str()) == 0) o << "\n![PC scores of " << b.scene << "](img/" << png << ")\n";
    else std::fprintf(stderr, "[port] warning: plot %s not made\n", png.c_str());
    write_standardised_table(o, b, r.runs, r.observed, img);
    if (!r.growth.empty()) {
      o << "\nGrowth diagnostic: RMS distance [m] between this machine's run of seed " << kGrowthSeed
        << " and the reference machine's (every 10th particle), and between pairs of reference members:\n\n"
        << "| step | port vs reference | members: min | median | max |\n|---|---|---|---|---|\n";
      std::vector<std::vector<double>> growth_rows_csv;
      for (const auto& g : r.growth) {
        o << "| " << g.step << " | " << fmt("%.3g", g.port) << " | " << fmt("%.3g", g.low) << " | "
          << fmt("%.3g", g.median) << " | " << fmt("%.3g", g.high) << " |\n";
        growth_rows_csv.push_back({static_cast<double>(g.step), g.port, g.low, g.median, g.high});
      }
      const std::string gcsv = (work / ("growth_" + b.scene + ".csv")).string();
      validation::write_csv(gcsv, {"step", "port", "low", "median", "high"}, growth_rows_csv);
      const std::string gpng = "port_growth_" + b.scene + ".png";
      const std::string gcmd = validation::shell_quote(python) + " " + validation::shell_quote(script) + " growth " +
                               validation::shell_quote(gcsv) + " " + validation::shell_quote((img / gpng).string()) +
                               " 0 " + validation::shell_quote(b.scene) + " 1>&2";
      if (std::system(gcmd.c_str()) == 0) o << "\n![growth diagnostic of " << b.scene << "](img/" << gpng << ")\n";
    }
  }
  w.commit();
}

int check_port(const PortOptions& options, const std::string& command) {
  const auto t0 = std::chrono::steady_clock::now();
  const double cpu0 = children_cpu_seconds();
  const fs::path baseline_dir =
      options.against.empty() ? fs::path(options.source_dir) / "fixtures" / "port-baseline" : fs::path(options.against);
  std::vector<Baseline> baselines;
  if (!fs::is_directory(baseline_dir)) throw std::invalid_argument(baseline_dir.string() + ": no baseline directory");
  for (const auto& e : fs::directory_iterator(baseline_dir)) {
    const std::string name = e.path().filename().string();
    if (name.size() > 13 && name.substr(name.size() - 13) == ".baseline.csv") baselines.push_back(read_baseline(e.path()));
  }
  if (baselines.empty()) throw std::invalid_argument(baseline_dir.string() + ": no <scene>.baseline.csv in it");
  std::sort(baselines.begin(), baselines.end(), [](const Baseline& a, const Baseline& b) { return a.scene > b.scene; });
  std::vector<SceneResult> results;
  const fs::path work = work_directory(options);
  std::vector<DeterministicRow> deterministic;
  std::vector<validation::CheckRow> analytic;
  const fs::path out = fs::absolute(options.out.empty() ? fs::path("port-validation-report.md") : fs::path(options.out));
  bool deterministic_pass = true;
  if (options.external.empty() && options.scale.empty() && options.scenes.empty()) {
    const auto runs = run_deterministic_scenes(work, options.source_dir, options.engine, options.launcher);
    for (std::size_t k = 0; k < runs.size(); ++k) {
      const std::string name = deterministic_scene_names()[k];
      if (!fs::exists(baseline_dir / ("deterministic_" + name + ".csv"))) continue;
      for (auto& row : compare_deterministic(baseline_dir, name, runs[k])) {
        std::printf("%-14s %-60s %.3g (tolerance %.0e) %s\n", row.scene.c_str(), row.quantity.c_str(), row.measured,
                    row.tolerance, row.passed() ? "pass" : "FAIL");
        deterministic_pass = deterministic_pass && row.passed();
        deterministic.push_back(row);
      }
    }
    fs::create_directories(out.parent_path() / "img");
    analytic = analytic_checks(options, work, out.parent_path() / "img");
    std::size_t failed = 0;
    for (const auto& a : analytic) failed += a.passed ? 0 : 1;
    std::printf("analytic checks (Chung & Ooi, fast engine): %zu rows, %zu failed\n", analytic.size(), failed);
    deterministic_pass = deterministic_pass && failed == 0;
  }
  if (!options.external.empty()) {
    if (static_cast<int>(options.external.size()) != options.runs) {
      throw std::invalid_argument("--external: expected " + std::to_string(options.runs) + " run folders, got " +
                                  std::to_string(options.external.size()));
    }
    const Baseline& b = baseline_of_runs(baselines, options.external);
    std::vector<Observables> runs;
    for (const auto& dir : options.external) runs.push_back(run_observables(port_scene(b.scene), dir));
    results.push_back({&b, options.external, judge(b, runs), {}, runs});
  } else {
    for (const auto& b : baselines) {
      if (!options.scenes.empty() && std::find(options.scenes.begin(), options.scenes.end(), b.scene) == options.scenes.end()) continue;
      const PortScene scene = scene_to_run(b.scene, options);
      const fs::path scene_file = export_scene(scene, work / "scenes", options.source_dir, find_ppohdem_program());
      std::vector<long> seeds;
      std::vector<std::string> labels;
      for (int k = 0; k < options.runs; ++k) {
        seeds.push_back(options.first_port_seed + k);
        labels.push_back("seed " + std::to_string(seeds.back()));
      }
      std::vector<fs::path> dirs;
      const auto runs = run_members(scene, scene_file, seeds, work / "runs" / b.scene, options, true, &dirs);
      std::vector<GrowthRow> growth;
      if (options.first_port_seed == kGrowthSeed) growth = growth_rows(baseline_dir, b.scene, dirs.front());
      for (const auto& d : dirs) fs::remove_all(d);
      results.push_back({&b, labels, judge(b, runs), growth, runs});
    }
  }
  if (results.empty()) throw std::invalid_argument("--scenes: none of them is in the baseline");
  bool pass = deterministic_pass;
  for (const auto& r : results) {
    std::printf("%-14s %s  (failing PCs:", r.baseline->scene.c_str(), r.verdict.pass ? "PASS" : "FAIL");
    if (r.verdict.failing_pcs.empty()) std::printf(" none");
    for (const int k : r.verdict.failing_pcs) std::printf(" %d", k + 1);
    std::printf("; largest |score| %.2f sigma)\n", r.verdict.scores.cwiseAbs().maxCoeff());
    pass = pass && r.verdict.pass;
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  write_report(out, results, options, command, wall, children_cpu_seconds() - cpu0, pass, deterministic, analytic);
  std::printf("port check: %s\nreport: %s\n", pass ? "PASS" : "FAIL", out.string().c_str());
  if (options.work_dir.empty()) fs::remove_all(work);
  return pass ? 0 : 1;
}

}  // namespace

int run_port_validation(const PortOptions& options, const std::string& command_line) {
  try {
    if (!options.export_scenes.empty()) return export_scenes(options);
    if (!options.save_baseline.empty()) return save_baseline(options, command_line);
    return check_port(options, command_line);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "ppohdem validate: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {  // a run that fails or cannot be read: the port fails
    std::fprintf(stderr, "ppohdem validate: error: %s\n", e.what());
    return 1;
  }
}

}  // namespace ppohdem::port
