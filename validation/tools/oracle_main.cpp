// ppohdem-oracle: the CGAL signed distance of an STL mesh on a node grid, written as legacy
// VTK STRUCTURED_POINTS.
//
//   ppohdem-oracle --mesh M.stl --cells NX NY NZ --box XMIN YMIN ZMIN XMAX YMAX ZMAX
//                  --out F.vtk [--threads 2]
//
// Node (i, j, k) sits at min + (i, j, k) .* (max - min) ./ (N - 1) (GridSpec::spanning, the
// same grid as `ppohdem voxelize --cells --box`), so the two files compare node by node.
#include <CLI/CLI.hpp>

#include <array>
#include <chrono>
#include <cstdio>
#include <exception>
#include <string>

#include "ppohdem/error.hpp"
#include "ppohdem/io/vtk_structured_points.hpp"
#include "ppohdem/mesh/stl_io.hpp"
#include "ppohdem/validation/cgal_signed_distance.hpp"

int main(int argc, char** argv) {
  CLI::App app{"ppohdem-oracle: CGAL signed distance field of an STL mesh (validation oracle)"};
  std::string mesh_path;
  std::string out_path;
  std::array<int, 3> cells{};
  std::array<double, 6> box{};
  int threads = 1;
  app.add_option("--mesh", mesh_path, "STL file (ASCII or binary)")->required();
  app.add_option("--cells", cells, "node counts NX NY NZ (each >= 2)")->required();
  app.add_option("--box", box, "XMIN YMIN ZMIN XMAX YMAX ZMAX: first and last node [world units]")
      ->required();
  app.add_option("--out", out_path, "output legacy VTK file")->required();
  app.add_option("--threads", threads, "OpenMP threads")->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);

  try {
    using namespace ppohdem;
    const auto start = std::chrono::steady_clock::now();
    const TriangleMesh mesh = read_stl(mesh_path);
    const GridSpec grid = GridSpec::spanning(Vec3(box[0], box[1], box[2]),
                                             Vec3(box[3], box[4], box[5]),
                                             Index3{cells[0], cells[1], cells[2]});
    validation::OracleReport report;
    const ScalarField field = validation::cgal_signed_distance(mesh, grid, threads, &report);
    write_vtk_structured_points(out_path, field, "distance",
                                report.sign_valid ? "CGAL oracle signed distance"
                                                  : "CGAL oracle UNSIGNED distance (open mesh)");
    const double total =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("%s: %zu triangles, %d x %d x %d nodes, %d thread(s)\n", mesh_path.c_str(),
                report.input_triangles, grid.nodes[0], grid.nodes[1], grid.nodes[2],
                report.threads);
    std::printf("sign: %s; inside nodes %zu; on-surface nodes %zu\n",
                report.sign_valid ? "valid (closed mesh)" : "NOT available (unsigned)",
                report.inside_nodes, report.boundary_nodes);
    std::printf("seconds: build %.3f, query %.3f, total %.3f\n", report.build_seconds,
                report.query_seconds, total);
    for (const std::string& w : report.warnings) std::printf("warning: %s\n", w.c_str());
    std::printf("wrote %s\n", out_path.c_str());
  } catch (const ppohdem::InputError& e) {
    std::fprintf(stderr, "ppohdem-oracle: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ppohdem-oracle: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
