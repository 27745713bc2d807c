/// \file closest_point_triangle.cpp
/// Ericson, Real-Time Collision Detection (2005), section 5.1.5, with an edge fallback for
/// degenerate triangles. See the header for the formulas.
#include "ppohdem/sdf/reference/closest_point_triangle.hpp"

#include <algorithm>
#include <limits>

namespace ppohdem::sdf::reference {

Vec3 closest_point_on_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  // Minimise |a + t (b - a) - p|^2 over t in [0, 1]: t = (p - a).(b - a) / |b - a|^2, clamped.
  const Vec3 ab = b - a;
  const double length_squared = ab.squaredNorm();
  if (length_squared == 0.0) return a;
  const double t = std::clamp((p - a).dot(ab) / length_squared, 0.0, 1.0);
  return a + t * ab;
}

bool is_degenerate_triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
  // |ab x ac| = |ab| |ac| sin(angle at a). Comparing against the product of the two SHORTER
  // edges measures the smallest angle; 64 eps leaves room for the rounding of the cross product.
  const double ab2 = (b - a).squaredNorm();
  const double ac2 = (c - a).squaredNorm();
  const double bc2 = (c - b).squaredNorm();
  const double longest2 = std::max({ab2, ac2, bc2});
  if (longest2 == 0.0) return true;
  const double two_shorter = ab2 * ac2 * bc2 / longest2;
  const double tolerance = 64.0 * std::numeric_limits<double>::epsilon();
  return (b - a).cross(c - a).squaredNorm() <= tolerance * tolerance * two_shorter;
}

namespace {

Vec3 closest_point_on_edges(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 on_ab = closest_point_on_segment(p, a, b);
  const Vec3 on_bc = closest_point_on_segment(p, b, c);
  const Vec3 on_ca = closest_point_on_segment(p, c, a);
  Vec3 best = on_ab;
  if ((on_bc - p).squaredNorm() < (best - p).squaredNorm()) best = on_bc;
  if ((on_ca - p).squaredNorm() < (best - p).squaredNorm()) best = on_ca;
  return best;
}

/// Smallest angle below ~1e-4 rad (sin^2 < 1e-8): Ericson's barycentric coordinates lose more
/// than half of their digits, so the edges are checked as well.
bool is_thin_triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double ab2 = (b - a).squaredNorm();
  const double ac2 = (c - a).squaredNorm();
  const double bc2 = (c - b).squaredNorm();
  const double two_shorter = ab2 * ac2 * bc2 / std::max({ab2, ac2, bc2});
  return (b - a).cross(c - a).squaredNorm() < 1e-8 * two_shorter;
}

}  // namespace

Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  if (is_degenerate_triangle(a, b, c)) return closest_point_on_edges(p, a, b, c);

  const Vec3 ab = b - a;
  const Vec3 ac = c - a;

  // Vertex region of a.
  const Vec3 ap = p - a;
  const double d1 = ab.dot(ap);
  const double d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;

  // Vertex region of b.
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp);
  const double d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;

  // Edge region of ab: project onto ab.
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + (d1 / (d1 - d3)) * ab;

  // Vertex region of c.
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp);
  const double d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;

  // Edge region of ac: project onto ac.
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + (d2 / (d2 - d6)) * ac;

  // Edge region of bc: project onto bc.
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  }

  // Face region: barycentric (1 - v - w, v, w). On a near-sliver the products above cancel and
  // v, w carry relative errors ~ eps / sin^2(smallest angle); clamping keeps the point on the
  // triangle (never closer than the truth), and comparing with the edges keeps the answer within
  // the sliver's width of the truth. The point is in the plane, so its in-plane error changes
  // the distance only to second order for points off the surface.
  const double sum = va + vb + vc;
  if (!(sum > 0.0)) return closest_point_on_edges(p, a, b, c);
  const double v = std::clamp(vb / sum, 0.0, 1.0);
  const double w = std::clamp(vc / sum, 0.0, 1.0 - v);
  const Vec3 on_face = a + v * ab + w * ac;
  if (!is_thin_triangle(a, b, c)) return on_face;
  const Vec3 on_edges = closest_point_on_edges(p, a, b, c);
  return (on_edges - p).squaredNorm() < (on_face - p).squaredNorm() ? on_edges : on_face;
}

double squared_distance_to_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  return (closest_point_on_triangle(p, a, b, c) - p).squaredNorm();
}

}  // namespace ppohdem::sdf::reference
