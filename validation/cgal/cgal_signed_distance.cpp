// The CGAL signed-distance oracle. See cgal_signed_distance.hpp for what is computed.
//
// Two independent CGAL structures:
//   1. distance: AABB_tree of K::Triangle_3 built from the soup exactly as given (no welding,
//      degenerate triangles included: CGAL measures them as their edges);
//   2. side: a welded, closed Surface_mesh and its own AABB tree for Side_of_triangle_mesh.
// Both trees are built completely before the parallel loop (CGAL builds lazily otherwise).
#include "ppohdem/validation/cgal_signed_distance.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>

#include <array>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>
#include <vector>

#include "ppohdem/error.hpp"

#if defined(PPOHDEM_WITH_OPENMP)
#include <omp.h>
#endif

namespace ppohdem::validation {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;  // "Epick"
using Point = Kernel::Point_3;
using CgalTriangles = std::vector<Kernel::Triangle_3>;
using DistancePrimitive = CGAL::AABB_triangle_primitive<Kernel, CgalTriangles::const_iterator>;
using DistanceTree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, DistancePrimitive>>;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using SideOfMesh = CGAL::Side_of_triangle_mesh<SurfaceMesh, Kernel>;
using SideTree = SideOfMesh::AABB_tree;

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

Point to_point(const Vec3& v) { return Point(v.x(), v.y(), v.z()); }

void check_inputs(const TriangleMesh& mesh, const GridSpec& grid, int threads) {
  if (mesh.empty()) throw InputError("cgal_signed_distance: the mesh has no triangles");
  for (std::size_t t = 0; t < mesh.size(); ++t) {
    for (const Vec3& v : mesh.triangles[t].v) {
      if (!v.allFinite()) {
        throw InputError("cgal_signed_distance: triangle " + std::to_string(t) +
                         " has a non-finite vertex coordinate");
      }
    }
  }
  for (int a = 0; a < 3; ++a) {
    if (grid.nodes[a] < 1 || !std::isfinite(grid.spacing[a]) || !(grid.spacing[a] > 0.0) ||
        !std::isfinite(grid.origin[a])) {
      throw InputError("cgal_signed_distance: invalid grid on axis " + std::to_string(a) +
                       ": expected nodes >= 1, finite spacing > 0 and a finite origin");
    }
  }
  if (threads < 1) {
    throw InputError("cgal_signed_distance: threads must be >= 1, got " + std::to_string(threads));
  }
}

// Weld the soup into a Surface_mesh usable by Side_of_triangle_mesh, or nullopt (with a
// warning) if it is not a closed triangle mesh.
std::optional<SurfaceMesh> closed_sign_mesh(const TriangleMesh& mesh, OracleReport& report) {
  std::vector<Point> points;
  std::vector<std::array<std::size_t, 3>> polygons;
  points.reserve(3 * mesh.size());
  polygons.reserve(mesh.size());
  for (const Triangle& t : mesh.triangles) {
    const std::size_t first = points.size();
    for (const Vec3& v : t.v) points.push_back(to_point(v));
    polygons.push_back({first, first + 1, first + 2});
  }
  // Merges bit-identical points, drops polygons with repeated vertices and duplicate polygons.
  PMP::repair_polygon_soup(points, polygons);
  // Side_of_triangle_mesh counts ray crossings (parity), so orientation does not change the
  // answer; orienting is what lets the soup become a halfedge mesh. It returns false if it
  // had to duplicate vertices at non-manifold spots (then the mesh will not be closed).
  if (!PMP::orient_polygon_soup(points, polygons)) {
    report.warnings.push_back(
        "mesh is not an orientable 2-manifold after welding (non-manifold edges or vertices)");
  }
  if (!PMP::is_polygon_soup_a_polygon_mesh(polygons)) {
    report.warnings.push_back("welded soup is not a polygon mesh: no inside/outside");
    return std::nullopt;
  }
  SurfaceMesh sm;
  PMP::polygon_soup_to_polygon_mesh(points, polygons, sm);
  report.welded_vertices = sm.number_of_vertices();
  report.sign_mesh_faces = sm.number_of_faces();
  if (!CGAL::is_triangle_mesh(sm) || !CGAL::is_closed(sm)) {
    report.warnings.push_back("mesh is not closed (has boundary edges): no inside/outside");
    return std::nullopt;
  }
  return sm;
}

}  // namespace

namespace {

// The oracle at `count` points, point n at position(n): the grid and the point-list forms.
template <class Position>
std::vector<double> signed_distances(const TriangleMesh& mesh, long long count, Position position, int threads,
                                     OracleReport* report_out) {
  OracleReport report;
  report.input_triangles = mesh.size();
#if !defined(PPOHDEM_WITH_OPENMP)
  if (threads > 1) {
    report.warnings.push_back("built without OpenMP: running on 1 thread");
    threads = 1;
  }
#endif
  report.threads = threads;

  const auto build_start = Clock::now();
  CgalTriangles triangles;
  triangles.reserve(mesh.size());
  for (const Triangle& t : mesh.triangles) {
    triangles.emplace_back(to_point(t.v[0]), to_point(t.v[1]), to_point(t.v[2]));
  }
  DistanceTree distance_tree(triangles.cbegin(), triangles.cend());
  distance_tree.build();
  distance_tree.accelerate_distance_queries();
  const Vec3 first = count > 0 ? position(0) : Vec3::Zero();
  (void)distance_tree.squared_distance(to_point(first));

  const std::optional<SurfaceMesh> sign_mesh = closed_sign_mesh(mesh, report);
  report.sign_valid = sign_mesh.has_value();
  if (!report.sign_valid) report.warnings.push_back("returning the UNSIGNED distance");
  std::unique_ptr<SideTree> side_tree;
  if (sign_mesh) {
    side_tree = std::make_unique<SideTree>(faces(*sign_mesh).first, faces(*sign_mesh).second,
                                           *sign_mesh);
    side_tree->build();
    (void)SideOfMesh(*side_tree)(to_point(first));
  }
  report.build_seconds = seconds_since(build_start);

  std::vector<double> values(static_cast<std::size_t>(count));
  const long long node_count = count;
  std::size_t boundary_nodes = 0;
  const auto query_start = Clock::now();
#if defined(PPOHDEM_WITH_OPENMP)
#pragma omp parallel num_threads(threads) reduction(+ : boundary_nodes)
#endif
  {
    // One Side_of_triangle_mesh per thread (CGAL does not document it as thread-safe); they
    // share the prebuilt, read-only side tree.
    std::optional<SideOfMesh> side;
    if (side_tree) side.emplace(*side_tree);
#if defined(PPOHDEM_WITH_OPENMP)
#pragma omp for schedule(dynamic, 256)
#endif
    for (long long n = 0; n < node_count; ++n) {
      const Point p = to_point(position(n));
      const double distance = std::sqrt(distance_tree.squared_distance(p));  // [world units]
      double phi = distance;
      if (side) {
        switch ((*side)(p)) {
          case CGAL::ON_BOUNDED_SIDE: phi = -distance; break;
          case CGAL::ON_BOUNDARY: phi = 0.0; ++boundary_nodes; break;
          case CGAL::ON_UNBOUNDED_SIDE: break;
        }
      }
      values[static_cast<std::size_t>(n)] = phi;
    }
  }
  report.query_seconds = seconds_since(query_start);
  report.boundary_nodes = boundary_nodes;
  for (double v : values) report.inside_nodes += v < 0.0 ? 1 : 0;
  if (report_out) *report_out = std::move(report);
  return values;
}

}  // namespace

ScalarField cgal_signed_distance(const TriangleMesh& mesh, const GridSpec& grid, int threads,
                                 OracleReport* report_out) {
  check_inputs(mesh, grid, threads);
  const long long row = grid.nodes[0];
  const long long plane = row * grid.nodes[1];
  ScalarField field(grid);
  field.values = signed_distances(
      mesh, static_cast<long long>(grid.node_count()),
      [&](long long n) {
        return grid.position(static_cast<int>(n % row), static_cast<int>((n / row) % grid.nodes[1]),
                             static_cast<int>(n / plane));
      },
      threads, report_out);
  return field;
}

std::vector<double> cgal_signed_distance_at(const TriangleMesh& mesh, const std::vector<Vec3>& points, int threads,
                                            OracleReport* report) {
  GridSpec one_node;  // check_inputs checks the mesh and threads; the points are checked here
  check_inputs(mesh, one_node, threads);
  for (std::size_t n = 0; n < points.size(); ++n) {
    if (!points[n].allFinite()) {
      throw InputError("cgal_signed_distance_at: point " + std::to_string(n) + " has a non-finite coordinate");
    }
  }
  return signed_distances(
      mesh, static_cast<long long>(points.size()), [&](long long n) { return points[static_cast<std::size_t>(n)]; },
      threads, report);
}

ScalarField CgalOracleBuilder::build(const TriangleMesh& mesh, const GridSpec& grid,
                                     SdfReport* report) const {
  OracleReport oracle_report;
  ScalarField field = cgal_signed_distance(mesh, grid, threads_, &oracle_report);
  if (report) {
    report->warnings = oracle_report.warnings;
    report->inside_fraction = static_cast<double>(oracle_report.inside_nodes) /
                              static_cast<double>(field.values.size());
  }
  return field;
}

}  // namespace ppohdem::validation
