// Closest point on a triangle: against brute-force minimisation over barycentric samples and
// against a second, independent formula (projection onto the plane, else the nearest edge).
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "ppohdem/sdf/reference/closest_point_triangle.hpp"

using ppohdem::Vec3;
using namespace ppohdem::sdf::reference;

namespace {

constexpr int kSamples = 64;  // lattice subdivisions per edge

/// min over the lattice a + (i/N)(b - a) + (j/N)(c - a), i + j <= N, of |x - p|.
/// Every point of the triangle is within (longest edge)/N of a lattice point.
double sampled_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= kSamples; ++i) {
    for (int j = 0; i + j <= kSamples; ++j) {
      const Vec3 x = a + (double(i) / kSamples) * (b - a) + (double(j) / kSamples) * (c - a);
      best = std::min(best, (x - p).norm());
    }
  }
  return best;
}

/// Independent formula: if the projection of p onto the plane has barycentric coordinates >= 0,
/// the distance is the distance to the plane; otherwise the minimum over the three edges.
double projection_or_edges_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const double area2 = n.squaredNorm();
  const double edges = std::min({(closest_point_on_segment(p, a, b) - p).norm(),
                                 (closest_point_on_segment(p, b, c) - p).norm(),
                                 (closest_point_on_segment(p, c, a) - p).norm()});
  if (area2 == 0.0) return edges;
  const Vec3 q = p - n * (n.dot(p - a) / area2);
  const double u = (c - b).cross(q - b).dot(n), v = (a - c).cross(q - c).dot(n), w = (b - a).cross(q - a).dot(n);
  if (u >= 0 && v >= 0 && w >= 0) return std::min(edges, (q - p).norm());
  return edges;
}

rc::Gen<Vec3> point_in_cube(double half) {
  return rc::gen::map(rc::gen::tuple(rc::gen::inRange(-1000, 1001), rc::gen::inRange(-1000, 1001), rc::gen::inRange(-1000, 1001)),
                      [half](const std::tuple<int, int, int>& t) -> Vec3 {
                        return Vec3(std::get<0>(t), std::get<1>(t), std::get<2>(t)) * (half / 1000.0);
                      });
}

void check_against_oracles(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const double d = std::sqrt(squared_distance_to_triangle(p, a, b, c));
  const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
  const double sampled = sampled_distance(p, a, b, c);
  // Round-off allowance: coordinates are O(1); the formulas take tens of operations.
  const double roundoff = 1e-12;
  // The closest point is not farther than any sample, and no sample is farther than the
  // lattice resolution from it.
  RC_ASSERT(d <= sampled + roundoff);
  RC_ASSERT(sampled <= d + longest / kSamples + roundoff);
  // The second formula is exact too: agreement to round-off. Near-slivers lose digits in the
  // plane projection of the second formula (division by a tiny area), hence the wider 1e-9.
  RC_ASSERT(std::abs(d - projection_or_edges_distance(p, a, b, c)) <= 1e-9);
}

}  // namespace

RC_GTEST_PROP(ClosestPointTriangle, MatchesBruteForceOnRandomTriangles, ()) {
  const Vec3 a = *point_in_cube(1.0), b = *point_in_cube(1.0), c = *point_in_cube(1.0);
  const Vec3 p = *point_in_cube(2.0);
  check_against_oracles(p, a, b, c);
}

RC_GTEST_PROP(ClosestPointTriangle, MatchesBruteForceOnSliversAndDegenerates, ()) {
  const Vec3 a = *point_in_cube(1.0), b = *point_in_cube(1.0);
  const Vec3 p = *point_in_cube(2.0);
  // c on the line through a, b (collinear: zero area), or lifted off it by a tiny amount.
  const double t = *rc::gen::inRange(-500, 1501) / 1000.0;
  const double lift = *rc::gen::element(0.0, 1e-300, 1e-15, 1e-12, 1e-9, 1e-6);
  const Vec3 off = a == b ? Vec3(0, 0, 1) : (b - a).unitOrthogonal();
  const Vec3 c = a + t * (b - a) + lift * off;
  check_against_oracles(p, a, b, c);
  check_against_oracles(p, a, a, c);  // two vertices equal
  check_against_oracles(p, a, a, a);  // a point
}

TEST(ClosestPointTriangle, HandComputedRegions) {
  const Vec3 a(0, 0, 0), b(2, 0, 0), c(0, 2, 0);
  // Face region: straight above (0.5, 0.5).
  EXPECT_EQ(closest_point_on_triangle(Vec3(0.5, 0.5, 3), a, b, c), Vec3(0.5, 0.5, 0));
  // Vertex regions.
  EXPECT_EQ(closest_point_on_triangle(Vec3(-1, -1, 1), a, b, c), a);
  EXPECT_EQ(closest_point_on_triangle(Vec3(3, -1, 0), a, b, c), b);
  EXPECT_EQ(closest_point_on_triangle(Vec3(-1, 3, 0), a, b, c), c);
  // Edge regions: ab (y < 0), ca (x < 0), bc (x + y > 2).
  EXPECT_EQ(closest_point_on_triangle(Vec3(1, -1, 0), a, b, c), Vec3(1, 0, 0));
  EXPECT_EQ(closest_point_on_triangle(Vec3(-1, 1, 0), a, b, c), Vec3(0, 1, 0));
  EXPECT_EQ(closest_point_on_triangle(Vec3(2, 2, 0), a, b, c), Vec3(1, 1, 0));
}

TEST(ClosestPointTriangle, DegenerateTriangleIsItsLongestEdge) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(3, 0, 0);  // collinear: the segment [0, 3] on x
  EXPECT_TRUE(is_degenerate_triangle(a, b, c));
  EXPECT_EQ(closest_point_on_triangle(Vec3(2, 1, 0), a, b, c), Vec3(2, 0, 0));
  EXPECT_EQ(closest_point_on_triangle(Vec3(5, 0, 0), a, b, c), c);
  EXPECT_FALSE(is_degenerate_triangle(a, b, Vec3(0, 1e-6, 0)));
}
