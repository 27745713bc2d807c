/// \file bench_sdf_main.cpp
/// ppohdem-bench-sdf: one SDF build or one comparison per process, so that ci/bench-sdf.sh can
/// put a time limit on each run and read each run's own peak memory.
///
///   ppohdem-bench-sdf run --method fast|exact|seed|cgal --mesh M.stl --n N [--threads T]
///                         [--precision double|float] [--band W] [--shared 1] [--out field.f64]
///       builds the field on benchmark_grid(mesh, N) and prints one line of key=value pairs:
///       seconds (the build only), nodes_per_second, peak_rss_bytes, field_bytes; for fast also
///       the work counters (exact/transferred nodes, candidate tests, distance evaluations per
///       node). --band W: the fast builder's band mode (exact within W h); --shared 1: its
///       shared-candidate scheme for the exact nodes.
///   ppohdem-bench-sdf compare --mesh M.stl --n N --candidate c.f64|c.vtk --oracle o.f64 [--band B]
///       prints max/RMS |error| in h over all nodes and over the band |oracle| < B h (default 3),
///       and sign mismatches (nodes with |oracle| > 1e-9 h whose sign differs).
///   ppohdem-bench-sdf box --mesh M.stl
///       prints the benchmark grid's box as `ppohdem voxelize --box` takes it (xmin ymin zmin
///       xmax ymax zmax, shortest round-trip text), so that `--cells N N N --box ...` is the
///       same grid, bit for bit (ci/bench-sdf-process.sh).
#include <chrono>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <string>

#include "bench_grid.hpp"
#include "ppohdem/io/vtk_structured_points.hpp"
#include "ppohdem/mesh/stl_io.hpp"
#include "ppohdem/sdf/reference/builders.hpp"
#include "ppohdem/sdf/fast/fast_sdf_builder.hpp"
#include "ppohdem/sdf/field_metrics.hpp"
#include "ppohdem/validation/cgal_signed_distance.hpp"

namespace {

using namespace ppohdem;

std::map<std::string, std::string> parse(int argc, char** argv, int first) {
  std::map<std::string, std::string> args;
  for (int a = first; a + 1 < argc; a += 2) {
    if (std::strncmp(argv[a], "--", 2) != 0) throw std::runtime_error(std::string("unexpected argument ") + argv[a]);
    args[argv[a] + 2] = argv[a + 1];
  }
  return args;
}

std::string need(const std::map<std::string, std::string>& args, const std::string& key) {
  const auto it = args.find(key);
  if (it == args.end()) throw std::runtime_error("missing --" + key);
  return it->second;
}

std::string get(const std::map<std::string, std::string>& args, const std::string& key, const std::string& fallback) {
  const auto it = args.find(key);
  return it == args.end() ? fallback : it->second;
}

int run(const std::map<std::string, std::string>& args) {
  const std::string method = need(args, "method");
  const TriangleMesh mesh = read_stl(need(args, "mesh"));
  const GridSpec grid = bench::benchmark_grid(mesh, std::stoi(need(args, "n")));
  const int threads = std::stoi(get(args, "threads", "2"));
  const bool single = get(args, "precision", "double") == "float";
  const double band = std::stod(get(args, "band", "0"));
  sdf::fast::FastSdfCounters counters;
  std::vector<double> values;
  std::size_t field_bytes = grid.node_count() * sizeof(double);
  const auto t0 = std::chrono::steady_clock::now();
  if (method == "fast") {
    sdf::fast::FastSdfOptions options;
    options.threads = threads;
    options.band_cells = band;
    options.shared_candidates = get(args, "shared", "0") == "1";
    options.counters = &counters;
    const sdf::fast::FastSdfBuilder builder(options);
    const SerialComm comm;
    if (single) {
      const std::vector<float> f = sdf::fast::build_sdf_distributed_float(builder, comm, mesh, grid);
      field_bytes = f.size() * sizeof(float);
      values.assign(f.begin(), f.end());  // after the clock stops would be fairer; see below
    } else {
      values = sdf::fast::build_sdf_distributed(builder, comm, mesh, grid).values;
    }
  } else if (method == "cgal") {
    values = validation::cgal_signed_distance(mesh, grid, threads).values;
  } else {
    values = sdf::reference::make_reference_sdf_builder(method)->build(mesh, grid).values;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // Peak memory before writing the output (the float run's double copy for the file is made
  // inside the timed region only to keep the code short; it is after the build proper).
  const std::size_t peak = peak_resident_bytes();
  const std::string out = get(args, "out", "");
  if (!out.empty()) bench::write_raw(out, values);
  const double nodes = static_cast<double>(grid.node_count());
  std::printf("method=%s n=%d threads=%d precision=%s band=%g triangles=%zu nodes=%zu seconds=%.6f "
              "nodes_per_second=%.6g peak_rss_bytes=%zu field_bytes=%zu exact_nodes=%zu transferred_nodes=%zu "
              "candidate_tests_per_node=%.4g distance_evaluations_per_node=%.4g\n",
              method.c_str(), grid.nodes[0], threads, single ? "float" : "double", band, mesh.size(),
              grid.node_count(), seconds, nodes / seconds, peak, field_bytes, counters.exact_nodes,
              counters.transferred_nodes, static_cast<double>(counters.candidate_tests) / nodes,
              static_cast<double>(counters.distance_evaluations) / nodes);
  return 0;
}

int compare(const std::map<std::string, std::string>& args) {
  const TriangleMesh mesh = read_stl(need(args, "mesh"));
  const GridSpec grid = bench::benchmark_grid(mesh, std::stoi(need(args, "n")));
  ScalarField candidate(grid), oracle(grid);
  const std::string candidate_path = need(args, "candidate");
  if (candidate_path.ends_with(".vtk")) {  // `ppohdem voxelize --out` on the same grid
    ScalarField read = read_vtk_structured_points(candidate_path);
    if (read.grid.nodes != grid.nodes) throw std::runtime_error(candidate_path + ": not the benchmark grid");
    candidate.values = std::move(read.values);
  } else {
    candidate.values = bench::read_raw(candidate_path, grid.node_count());
  }
  oracle.values = bench::read_raw(need(args, "oracle"), grid.node_count());
  const double band = std::stod(get(args, "band", "3"));
  const FieldComparison c = compare_fields(candidate, oracle, band, 1e-9);
  std::printf("max_all_h=%.6g rms_all_h=%.6g max_band_h=%.6g rms_band_h=%.6g band_nodes=%zu sign_checked=%zu "
              "sign_mismatches=%zu non_finite=%zu max_relative=%.6g\n",
              c.all.max_error_h, c.all.rms_error_h, c.band.max_error_h, c.band.rms_error_h, c.band.nodes,
              c.sign_checked_nodes, c.sign_mismatches, c.non_finite_candidate, c.max_relative_error);
  return 0;
}

int box(const std::map<std::string, std::string>& args) {
  const TriangleMesh mesh = read_stl(need(args, "mesh"));
  const auto [lo, hi] = bench::benchmark_box(mesh);
  std::printf("%.17g %.17g %.17g %.17g %.17g %.17g\n", lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc < 2) throw std::runtime_error("usage: ppohdem-bench-sdf run|compare|box --key value ...");
    const std::string mode = argv[1];
    const auto args = parse(argc, argv, 2);
    if (mode == "run") return run(args);
    if (mode == "compare") return compare(args);
    if (mode == "box") return box(args);
    throw std::runtime_error("unknown mode " + mode);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ppohdem-bench-sdf: error: %s\n", e.what());
    return 1;
  }
}
