// ppohdem-sdf-study: speed and accuracy of every SDF method against the CGAL oracle, in one
// process on one machine, printed as a markdown table (docs/sdf-accuracy.md is made with it).
//
//   ppohdem-sdf-study --mesh fixtures/meshes/bunny_closed.stl --nodes 32 64 --methods exact seed
//
// Grid: a cube of N nodes per axis centred on the mesh's bounding box, side 1.2 x the largest
// extent (so a 10 % margin on the longest axis). Errors are in units of the spacing h (and the
// seed method's observed convergence order is computed from the world-unit max error).
#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "ppohdem/error.hpp"
#include "ppohdem/mesh/mesh_stats.hpp"
#include "ppohdem/mesh/stl_io.hpp"
#include "ppohdem/provenance.hpp"
#include "ppohdem/sdf/reference/builders.hpp"
#include "ppohdem/sdf/field_metrics.hpp"
#include "ppohdem/validation/cgal_signed_distance.hpp"

namespace {
using namespace ppohdem;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

GridSpec study_grid(const BoundingBox& box, int n) {
  const double side = 1.2 * box.extent().maxCoeff();
  const Vec3 half = Vec3::Constant(0.5 * side);
  return GridSpec::spanning(box.centre() - half, box.centre() + half, {n, n, n});
}

struct Row {
  std::string method, mesh;
  int n = 0;
  double seconds = 0;
  FieldComparison cmp;
  double lipschitz = 0;
  bool signed_oracle = true;
};

void print_header() {
  std::printf("| method | mesh | N^3 | seconds | max err band (h) | RMS band (h) | max err all (h) | RMS all (h) | "
              "sign mismatches | Lipschitz | max rel. err |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
}

void print_row(const Row& r) {
  char signs[64];
  if (r.signed_oracle) {
    std::snprintf(signs, sizeof signs, "%zu / %zu", r.cmp.sign_mismatches, r.cmp.sign_checked_nodes);
  } else {
    std::snprintf(signs, sizeof signs, "n/a (open mesh)");
  }
  std::printf("| %s | %s | %d | %.3f | %.3g | %.3g | %.3g | %.3g | %s | %.12f | %.3g |\n", r.method.c_str(),
              r.mesh.c_str(), r.n, r.seconds, r.cmp.band.max_error_h, r.cmp.band.rms_error_h,
              r.cmp.all.max_error_h, r.cmp.all.rms_error_h, signs, r.lipschitz, r.cmp.max_relative_error);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ppohdem-sdf-study: SDF methods vs the CGAL oracle (markdown table on stdout)"};
  std::vector<std::string> meshes;
  std::vector<int> resolutions{32};
  std::vector<std::string> methods{"exact", "seed"};
  int threads = 2;
  double band = 2.0;
  app.add_option("--mesh", meshes, "STL meshes")->required();
  app.add_option("--nodes", resolutions, "nodes per axis (one run each)");
  app.add_option("--methods", methods, "methods to run (exact, seed)");
  app.add_option("--oracle-threads", threads, "threads for the CGAL oracle");
  app.add_option("--band", band, "narrow band half-width in h");
  CLI11_PARSE(app, argc, argv);

  try {
    std::printf("<!-- %s -->\n", provenance_line(1, 1).c_str());
    print_header();
    std::map<std::string, std::vector<Row>> seed_rows;
    for (const auto& mesh_path : meshes) {
      const TriangleMesh mesh = read_stl(mesh_path);
      const MeshStats stats = compute_mesh_stats(mesh);
      const std::string name = std::filesystem::path(mesh_path).filename().string();
      for (int n : resolutions) {
        const GridSpec grid = study_grid(stats.box, n);
        validation::OracleReport oracle_report;
        const auto t_oracle = Clock::now();
        const ScalarField oracle = validation::cgal_signed_distance(mesh, grid, threads, &oracle_report);
        Row oracle_row{"cgal oracle (" + std::to_string(threads) + " thr)", name, n, seconds_since(t_oracle), {}, 0, true};
        oracle_row.cmp = compare_fields(oracle, oracle, band);
        oracle_row.lipschitz = lipschitz_ratio(oracle);
        oracle_row.signed_oracle = oracle_report.sign_valid;
        print_row(oracle_row);
        for (const auto& method : methods) {
          auto builder = sdf::reference::make_reference_sdf_builder(method);
          SdfReport report;
          const auto t0 = Clock::now();
          ScalarField field = builder->build(mesh, grid, &report);
          Row row{method, name, n, seconds_since(t0), {}, 0, oracle_report.sign_valid};
          row.lipschitz = lipschitz_ratio(field);
          if (!oracle_report.sign_valid) {
            // Open mesh: the oracle is unsigned, so compare magnitudes only.
            for (double& v : field.values) v = std::abs(v);
          }
          row.cmp = compare_fields(field, oracle, band);
          print_row(row);
          if (method == "seed") seed_rows[name].push_back(row);
        }
      }
    }
    // Observed convergence order of the seed method's max error in world units,
    // p = log(e_coarse / e_fine) / log(h_coarse / h_fine), between successive resolutions.
    for (const auto& [name, rows] : seed_rows) {
      for (std::size_t i = 1; i < rows.size(); ++i) {
        const double e0 = rows[i - 1].cmp.all.max_error_h * rows[i - 1].cmp.h;
        const double e1 = rows[i].cmp.all.max_error_h * rows[i].cmp.h;
        const double r0 = rows[i - 1].cmp.all.rms_error_h * rows[i - 1].cmp.h;
        const double r1 = rows[i].cmp.all.rms_error_h * rows[i].cmp.h;
        const double ratio = rows[i - 1].cmp.h / rows[i].cmp.h;
        std::printf("\nseed method, %s, N %d -> %d: observed order (max error) %.2f, (RMS error) %.2f\n", name.c_str(),
                    rows[i - 1].n, rows[i].n, std::log(e0 / e1) / std::log(ratio), std::log(r0 / r1) / std::log(ratio));
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ppohdem-sdf-study: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
