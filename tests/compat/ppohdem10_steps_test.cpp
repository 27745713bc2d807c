// The building blocks of --compat ppohdem-1.0, each against an independent answer: analytic
// plane waves for the eikonal update, the reference closest-point routine, analytic boxes for
// the z-ray voxelisation and the axis votes (including the original's documented defects).
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>

#include "ppohdem/compat/ppohdem10_steps.hpp"
#include "ppohdem/sdf/reference/closest_point_triangle.hpp"

namespace ppohdem::compat {
namespace {
using sdf::reference::is_degenerate_triangle;  // the reference geometry the steps are checked against
using sdf::reference::squared_distance_to_triangle;

// Axis-aligned box [lo, hi] as 12 outward, counter-clockwise triangles. Every face is split
// along the diagonal from its lowest corner (in the two in-face coordinates) to its highest.
TriangleMesh box_mesh(const Vec3& lo, const Vec3& hi) {
  const Vec3 c[8] = {{lo.x(), lo.y(), lo.z()}, {hi.x(), lo.y(), lo.z()}, {hi.x(), hi.y(), lo.z()},
                     {lo.x(), hi.y(), lo.z()}, {lo.x(), lo.y(), hi.z()}, {hi.x(), lo.y(), hi.z()},
                     {hi.x(), hi.y(), hi.z()}, {lo.x(), hi.y(), hi.z()}};
  const int faces[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                            {3, 6, 2}, {3, 7, 6}, {0, 4, 7}, {0, 7, 3}, {1, 2, 6}, {1, 6, 5}};
  TriangleMesh mesh;
  for (const auto& f : faces) mesh.triangles.push_back(Triangle{{c[f[0]], c[f[1]], c[f[2]]}, Vec3::Zero()});
  return mesh;
}

TEST(Ppohdem10Eikonal, OneUpwindAxisAddsOneSpacing) {
  // d = x: upwind neighbour a - W along x; the other axes hold the sentinel, as does the node.
  const double w = 0.5789473684210527;
  const double a = 7.25;
  const double sentinel = 440.0;
  EXPECT_EQ(ppohdem10_eikonal_update(sentinel, a + w, a - w, sentinel, sentinel, sentinel, sentinel, w, w * w),
            a);
}

RC_GTEST_PROP(Ppohdem10Eikonal, ReproducesAnyPlaneWaveWithThreeUpwindAxes, ()) {
  // d(x) = n . x with n > 0 componentwise: the upwind neighbours are a - W n_i and the
  // three-axis quadratic sum_i (d - d_i)^2 = W^2 has the root d = a exactly (|n| = 1).
  const double nx = *rc::gen::inRange(50, 1000) / 1000.0;
  const double ny = *rc::gen::inRange(50, 1000) / 1000.0;
  const double nz = *rc::gen::inRange(50, 1000) / 1000.0;
  const double norm = std::sqrt(nx * nx + ny * ny + nz * nz);
  const Vec3 n(nx / norm, ny / norm, nz / norm);
  const double w = *rc::gen::inRange(1, 1000) / 100.0;
  const double a = *rc::gen::inRange(1000, 100000) / 100.0;
  const double got = ppohdem10_eikonal_update(1e6, a + w * n.x(), a - w * n.x(), a + w * n.y(), a - w * n.y(),
                                              a + w * n.z(), a - w * n.z(), w, w * w);
  // The root is a sum of terms of size a and W with a square root of W^2-sized terms: a few
  // ulps of max(a, W) each, hence 1e-12 relative.
  RC_ASSERT(std::abs(got - a) <= 1e-12 * std::max(a, w) * 10);
}

TEST(Ppohdem10Eikonal, TwoAxisUpdateKeepsTheNodeWhenTheRootIsComplex) {
  // |dy - dz| > sqrt(2) W: 2 W^2 - (dy - dz)^2 < 0 and the original keeps the old value.
  const double w = 1.0;
  EXPECT_EQ(ppohdem10_eikonal_update(100.0, 100.0, 100.0, 3.0, 200.0, 5.0, 200.0, w, w * w), 100.0);
  // With a real root: ((3 + 4) + sqrt(2 - 1)) / 2 = 4.
  EXPECT_EQ(ppohdem10_eikonal_update(100.0, 100.0, 100.0, 3.0, 200.0, 4.0, 200.0, w, w * w), 4.0);
}

RC_GTEST_PROP(Ppohdem10ClosestPoint, DistanceEqualsTheReferenceRoutine, ()) {
  auto coordinate = [] { return *rc::gen::inRange(-1000, 1000) / 100.0; };
  const Vec3 a(coordinate(), coordinate(), coordinate());
  const Vec3 b(coordinate(), coordinate(), coordinate());
  const Vec3 c(coordinate(), coordinate(), coordinate());
  RC_PRE(!is_degenerate_triangle(a, b, c) && (b - a).cross(c - a).norm() > 1e-3);
  const Vec3 p(coordinate(), coordinate(), coordinate());
  TriangleMesh mesh;
  mesh.triangles.push_back(Triangle{{a, b, c}, Vec3::Zero()});
  const Ppohdem10Facet f = ppohdem10_facets(mesh).front();
  const Ppohdem10Point q{p.x(), p.y(), p.z()};
  const double got = ppohdem10_distance_2points(q, ppohdem10_closest_point(f, q));
  const double want = std::sqrt(squared_distance_to_triangle(p, a, b, c));
  // Same Voronoi regions, different operation order and clamping: agreement to rounding of
  // coordinates of size 10, i.e. ~1e-13 absolute; 1e-9 leaves room for thin triangles.
  RC_ASSERT(std::abs(got - want) <= 1e-9);
}

TEST(Ppohdem10ZRay, ColumnsMarkTheBoxInteriorInGenericPosition) {
  // Box corners chosen so that no grid column lies on a facet edge or diagonal.
  const Vec3 lo(2.13, 3.07, 1.91), hi(6.71, 5.83, 7.37);
  const auto facets = ppohdem10_facets(box_mesh(lo, hi));
  const Ppohdem10Grid grid = ppohdem10_grid({20, 20, 20}, Vec3(10.0, 10.0, 10.0));
  int inside_nodes = 0;
  for (int j = 1; j <= 20; ++j) {
    for (int i = 1; i <= 20; ++i) {
      const Ppohdem10Column column = ppohdem10_zray_column(facets, grid, i, j);
      for (int k = 1; k <= 20; ++k) {
        const double x = grid.x[static_cast<std::size_t>(i)];
        const double y = grid.y[static_cast<std::size_t>(j)];
        const double z = grid.z[static_cast<std::size_t>(k)];
        const bool expected = x > lo.x() && x < hi.x() && y > lo.y() && y < hi.y() && z > lo.z() && z < hi.z();
        EXPECT_EQ(column.inside[static_cast<std::size_t>(k)] == 1, expected) << i << " " << j << " " << k;
        inside_nodes += expected ? 1 : 0;
      }
    }
  }
  EXPECT_EQ(inside_nodes, 9 * 5 * 11);  // x in {2.5..6.5}, y in {3.5..5.5}, z in {2..7}
}

TEST(Ppohdem10ZRay, ColumnThroughAFaceDiagonalIsLost) {
  // The original's defect (docs/compat.md): a column through the diagonal shared by the two
  // triangles of the top and bottom faces fails every strict edge test of both, so it finds no
  // crossing and its inside nodes are taken as outside. Box [0.5, 2.5]^3, nodes at integers:
  // column (x, y) = (1, 1) lies on the diagonal from (0.5, 0.5) to (2.5, 2.5).
  const auto facets = ppohdem10_facets(box_mesh(Vec3(0.5, 0.5, 0.5), Vec3(2.5, 2.5, 2.5)));
  const Ppohdem10Grid grid = ppohdem10_grid({10, 10, 10}, Vec3(10.0, 10.0, 10.0));
  const Ppohdem10Column on_diagonal = ppohdem10_zray_column(facets, grid, 2, 2);  // x = y = 1
  EXPECT_TRUE(on_diagonal.crossings.empty());
  EXPECT_EQ(on_diagonal.inside[2] + on_diagonal.inside[3], 0);  // z = 1, 2 are inside the box
  const Ppohdem10Column off_diagonal = ppohdem10_zray_column(facets, grid, 3, 2);  // x = 2, y = 1
  EXPECT_EQ(off_diagonal.crossings.size(), 2u);
  EXPECT_EQ(off_diagonal.inside[2] + off_diagonal.inside[3], 2);
}

RC_GTEST_PROP(Ppohdem10AxisVote, NeverSaysInsideForAConvexMesh, ()) {
  // A line through a point inside a convex closed mesh crosses exactly two facets, wound
  // oppositely as seen along the line; only one of them has all three triple products > 0, so
  // one side count is 0 and "both counts odd" cannot hold. The 2-of-3 vote is therefore never
  // "inside" here (and on the cube and sphere samples: 0 of 4,056 and 2,268 band nodes).
  const Vec3 lo(2.13, 3.07, 1.91), hi(6.71, 5.83, 7.37);
  const auto facets = ppohdem10_facets(box_mesh(lo, hi));
  const Ppohdem10Grid grid = ppohdem10_grid({20, 20, 20}, Vec3(10.0, 10.0, 10.0));
  const double tx = *rc::gen::inRange(1, 999) / 1000.0;
  const double ty = *rc::gen::inRange(1, 999) / 1000.0;
  const double tz = *rc::gen::inRange(1, 999) / 1000.0;
  const Ppohdem10Point p{lo.x() + tx * (hi.x() - lo.x()), lo.y() + ty * (hi.y() - lo.y()),
                         lo.z() + tz * (hi.z() - lo.z())};
  for (int axis = 0; axis < 3; ++axis) RC_ASSERT(ppohdem10_axis_inside(facets, grid, p, axis) == 0);
}

}  // namespace
}  // namespace ppohdem::compat
