#pragma once
/// \file cgal_signed_distance.hpp
/// The independent oracle for signed distance fields: CGAL computes the distance and the
/// side, sharing no code with ppohdem's builders.
///
///   phi(x) = s(x) * sqrt( min_t |x - closest_t(x)|^2 )   [world units]
///   s(x)   = +1 outside, -1 inside, 0 on the surface (CGAL::Side_of_triangle_mesh)
///
/// Distance: CGAL::AABB_tree over the triangle soup as given (AABB_triangle_primitive over a
/// std::vector<Triangle_3>, Epick kernel = CGAL::Exact_predicates_inexact_constructions_kernel),
/// query tree.squared_distance(x) with accelerate_distance_queries().
/// Side: the soup is welded and made a CGAL::Surface_mesh (Polygon_mesh_processing::
/// repair_polygon_soup, orient_polygon_soup, polygon_soup_to_polygon_mesh); if it is closed,
/// CGAL::Side_of_triangle_mesh (ray parity with exact predicates) gives the side; points it
/// reports ON_BOUNDARY get phi = 0 exactly.
/// If the welded mesh is not closed no side exists: the UNSIGNED distance is returned,
/// report->sign_valid is false and a warning says why.
///
/// Accuracy: predicates are exact; constructions (closest point, squared distance) are in
/// double, so the distance carries an absolute error of a few ulps of the coordinates'
/// magnitude (see docs/sdf-accuracy.md, "The CGAL oracle").
#include <cstddef>
#include <string>
#include <vector>

#include "ppohdem/grid/scalar_field.hpp"
#include "ppohdem/mesh/triangle_mesh.hpp"
#include "ppohdem/sdf/signed_distance.hpp"

namespace ppohdem::validation {

struct OracleReport {
  bool sign_valid = true;              ///< false: the mesh is not closed, phi is unsigned
  std::vector<std::string> warnings;   ///< human-readable, one problem each
  std::size_t input_triangles = 0;     ///< triangles in the soup (all used for distance)
  std::size_t welded_vertices = 0;     ///< distinct vertices of the sign mesh after repair
  std::size_t sign_mesh_faces = 0;     ///< faces of the sign mesh after repair
  std::size_t boundary_nodes = 0;      ///< nodes CGAL reports ON_BOUNDARY (phi = 0)
  std::size_t inside_nodes = 0;        ///< nodes with phi < 0
  int threads = 1;                     ///< threads actually used
  double build_seconds = 0.0;          ///< building the trees and the sign mesh [s]
  double query_seconds = 0.0;          ///< the node loop [s]
};

/// Signed distance of `mesh` at every node of `grid` (x-fastest), computed by CGAL.
/// `threads` >= 1 (OpenMP if built with it; otherwise 1 is used and a warning added).
/// The result does not depend on `threads` (each node is computed independently).
/// Throws InputError on an empty mesh, a non-finite vertex, an invalid grid or threads < 1.
ScalarField cgal_signed_distance(const TriangleMesh& mesh, const GridSpec& grid, int threads = 1,
                                 OracleReport* report = nullptr);

/// The same at arbitrary points (the Python module's pd.oracles.signed_distance): phi at
/// points[n]; report->inside_nodes counts the points with phi < 0. Throws InputError also on a
/// non-finite point.
std::vector<double> cgal_signed_distance_at(const TriangleMesh& mesh, const std::vector<Vec3>& points,
                                            int threads = 1, OracleReport* report = nullptr);

/// The oracle behind the SdfBuilder interface (method name "cgal"), so contract tests can
/// run it like any builder. Oracle warnings are copied into SdfReport::warnings.
class CgalOracleBuilder final : public SdfBuilder {
 public:
  explicit CgalOracleBuilder(int threads = 1) : threads_(threads) {}
  std::string name() const override { return "cgal"; }
  ScalarField build(const TriangleMesh& mesh, const GridSpec& grid,
                    SdfReport* report = nullptr) const override;

 private:
  int threads_;
};

}  // namespace ppohdem::validation
