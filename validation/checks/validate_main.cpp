// ppohdem-validate: runs every oracle check group (check_registry.hpp), prints one table,
// writes the Markdown report with provenance and plots, exits 1 if any check failed.
//   ppohdem-validate [--quick|--full] [--live] [--out FILE] [--engines a,b] [--only TEXT]
// Normally started as `ppohdem validate ...` (apps/cmd_validate.cpp execs this program).
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "engines.hpp"
#include "ppohdem/build_info.hpp"
#include "ppohdem/io/atomic_file.hpp"
#include "ppohdem/provenance.hpp"
#include "ppohdem/validation/check_registry.hpp"
#include "port_check.hpp"
#include "report.hpp"

namespace fs = std::filesystem;
using namespace ppohdem::validation;

int main(int argc, char** argv) {
  CLI::App app{"ppohdem-validate: run the oracle suite and write the validation report"};
  bool full = false, quick = false, live = false, list_only = false;
  std::string out, only, work_dir;
  std::string source_dir = PPOHDEM_SOURCE_DIR;
  std::vector<std::string> engines;
  auto* q = app.add_flag("--quick", quick, "the CI subset (default): a few minutes");
  app.add_flag("--full", full, "also the long studies (under an hour on 2 cores)")->excludes(q);
  app.add_flag("--live", live, "rerun peer codes (YADE) instead of their stored outputs");
  app.add_option("--out", out, "report file (default ./validation-report.md, or ./port-validation-report.md "
                               "with --port/--against); plots go to img/ beside it");
  app.add_option("--engines", engines, "DEM engines to exercise (default: every engine built)")
      ->delimiter(',');
  app.add_option("--only", only, "run only the groups whose name contains this text");
  app.add_option("--source-dir", source_dir, "checkout root (fixtures/, validation/)")
      ->capture_default_str();
  app.add_option("--work-dir", work_dir, "scratch directory (default: a temporary directory)");
  app.add_flag("--list", list_only, "list the check groups and exit");
  // Port validation of chaotic runs (validation/port, docs/port-validation.md).
  ppohdem::port::PortOptions port;
  app.add_flag("--port", port.port, "check this build against the shipped ensemble baseline (fixtures/port-baseline)");
  app.add_option("--save-baseline", port.save_baseline, "make a new ensemble baseline in DIR (a trusted machine)");
  app.add_option("--against", port.against, "check this build (or --external runs) against the baseline in DIR");
  app.add_option("--export-scenes", port.export_scenes, "write the chaotic tier's scenes (TOML, CSV) into DIR");
  app.add_option("--external", port.external, "with --port: judge these 3 output folders instead of running ppohdem")
      ->expected(1, 3);
  app.add_option("--scenes", port.scenes, "port scenes (settling_bed, seed_sample, small_bed; default: the baseline's)")
      ->delimiter(',');
  app.add_option("--members", port.members, "--save-baseline: fit members")->capture_default_str();
  app.add_option("--held-out", port.held_out, "--save-baseline: held-out members (false-positive rate)")
      ->capture_default_str();
  app.add_option("--jobs", port.jobs, "simulations run at once")->capture_default_str();
  app.add_option("--launcher", port.launcher, "words before each ppohdem simulate, e.g. 'mpirun -n 2'");
  app.add_option("--engine", port.engine, "engine of the port's runs")->capture_default_str();
  app.add_option("--first-seed", port.first_port_seed, "perturbation seed of the port's first run")
      ->capture_default_str();
  std::vector<std::string> scale_args;
  app.add_option("--scale-parameter", scale_args,
                 "a known-bad change: NAME=FACTOR (friction, restitution, young, dt, gravity)")
      ->delimiter(',');
  app.add_flag("--growth", port.growth_only, "--save-baseline DIR: only the growth diagnostic's data (40 members)");
  app.add_flag("--refit", port.refit, "--save-baseline DIR: refit DIR's stored members with --sigma/--min-failing-pcs");
  app.add_option("--sigma", port.rule.sigma, "--save-baseline: a PC fails beyond this many sigma")->capture_default_str();
  app.add_option("--min-failing-pcs", port.rule.min_failing_pcs, "--save-baseline: failing PCs that fail a check")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  if (port.any()) {
    for (const auto& arg : scale_args) {  // NAME=FACTOR
      const auto eq = arg.find('=');
      char* end = nullptr;
      const double factor = eq == std::string::npos ? 0.0 : std::strtod(arg.c_str() + eq + 1, &end);
      if (eq == std::string::npos || end == arg.c_str() + eq + 1 || *end != '\0' || !(factor > 0.0)) {
        std::fprintf(stderr, "ppohdem validate: error: --scale-parameter: expected NAME=FACTOR (a factor > 0), got '%s'\n",
                     arg.c_str());
        return 2;
      }
      port.scale[arg.substr(0, eq)] = factor;
    }
    port.source_dir = fs::absolute(source_dir).string();
    port.work_dir = work_dir;
    port.out = out;
    std::string command = "ppohdem validate";
    for (int i = 1; i < argc; ++i) command.append(" ").append(argv[i]);
    return ppohdem::port::run_port_validation(port, command);
  }

  try {
    const auto& groups = all_check_groups();
    if (list_only) {
      for (const auto& g : groups) std::printf("%-50s %s\n", g.name.c_str(), g.in_quick ? "quick" : "full");
      return 0;
    }
    const auto available = engine_names();
    if (engines.empty()) engines = available;
    for (const auto& e : engines) {
      if (!has_engine(e)) {
        std::string known;
        for (const auto& a : available) known.append(" ").append(a);
        std::fprintf(stderr, "ppohdem-validate: error: --engines: unknown engine '%s' (built:%s)\n",
                     e.c_str(), known.c_str());
        return 2;
      }
    }
    // In the working directory: a run never modifies the checkout unless --out points there.
    if (out.empty()) out = "validation-report.md";
    const fs::path out_path = fs::absolute(out);
    const fs::path img_dir = out_path.parent_path() / "img";
    fs::create_directories(img_dir);
    fs::path work = work_dir.empty() ? fs::temp_directory_path() /
                                           ("ppohdem-validate-" + std::to_string(::getpid()))
                                     : fs::path(work_dir);
    fs::create_directories(work);

    CheckContext ctx;
    ctx.quick = !full;
    ctx.live = live;
    ctx.source_dir = fs::absolute(source_dir).string();
    ctx.work_dir = work.string();
    ctx.img_dir = img_dir.string();
    ctx.engines = engines;

    std::vector<GroupResult> results;
    const auto t_start = std::chrono::steady_clock::now();
    for (const auto& g : groups) {
      if (!only.empty() && g.name.find(only) == std::string::npos) continue;
      if (ctx.quick && !g.in_quick) continue;
      std::fprintf(stderr, "[validate] %s ...\n", g.name.c_str());
      const auto t0 = std::chrono::steady_clock::now();
      GroupResult r;
      r.group = &g;
      try {
        r.rows = g.run(ctx);
      } catch (const std::exception& e) {
        CheckRow row;
        row.check = "group ran to completion";
        row.engine = "-";
        row.measured = std::string("exception: ") + e.what();
        row.expected = "no exception";
        row.tolerance = "-";
        row.tolerance_source = "a check that cannot run is a failure";
        row.passed = false;
        r.rows.push_back(row);
      }
      if (r.rows.empty()) {
        CheckRow row;
        row.check = "group produced rows";
        row.engine = "-";
        row.measured = "0 rows";
        row.expected = ">= 1 row";
        row.tolerance = "-";
        row.tolerance_source = "an empty group proves nothing";
        r.rows.push_back(row);
      }
      r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::size_t failed = 0;
      for (const auto& row : r.rows) failed += row.passed ? 0 : 1;
      std::fprintf(stderr, "[validate] %s: %zu rows, %zu failed, %.1f s\n", g.name.c_str(),
                   r.rows.size(), failed, r.seconds);
      results.push_back(std::move(r));
    }
    const double total_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();

    std::size_t n_rows = 0, n_failed = 0;
    for (const auto& r : results)
      for (const auto& row : r.rows) {
        ++n_rows;
        n_failed += row.passed ? 0 : 1;
      }
    print_table(std::cout, results);
    std::printf("\n%zu checks, %zu failed (%s mode, %.0f s)\n", n_rows, n_failed,
                ctx.quick ? "quick" : "full", total_seconds);
    ReportInfo info;
    info.mode = ctx.quick ? "quick" : "full";
    info.live = live;
    info.engines = engines;
    info.total_seconds = total_seconds;
    info.command = "ppohdem validate";
    for (int i = 1; i < argc; ++i) info.command.append(" ").append(argv[i]);
    {
      ppohdem::AtomicFileWriter writer(out_path);
      write_markdown_report(writer.stream(), info, results, out_path.parent_path());
      writer.commit();
    }
    std::printf("report: %s\n", out_path.string().c_str());
    if (work_dir.empty() && n_failed == 0) fs::remove_all(work);
    else std::printf("scratch files (CSV, property-test logs): %s\n", work.string().c_str());
    return n_failed == 0 ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ppohdem-validate: error: %s\n", e.what());
    return 2;
  }
}
