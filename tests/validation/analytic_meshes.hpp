#pragma once
// Meshes built in code whose exact signed distance is known in closed form (or bounded), so the
// oracle tests depend on neither the STL reader nor any fixture.
#include <array>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "ppohdem/mesh/triangle_mesh.hpp"

namespace ppohdem::test {

inline void add_triangle(TriangleMesh& mesh, const Vec3& a, const Vec3& b, const Vec3& c) {
  Triangle t;
  t.v = {a, b, c};
  mesh.triangles.push_back(t);
}

/// Axis-aligned box [lo, hi], 12 triangles, counter-clockwise seen from outside.
/// Corner b (0..7) is (b&1 ? hi.x : lo.x, b&2 ? hi.y : lo.y, b&4 ? hi.z : lo.z).
/// `skip_plus_x` leaves out the two +x triangles (an open box).
inline TriangleMesh box_mesh(const Vec3& lo, const Vec3& hi, bool skip_plus_x = false) {
  auto corner = [&](int b) {
    return Vec3((b & 1) ? hi.x() : lo.x(), (b & 2) ? hi.y() : lo.y(), (b & 4) ? hi.z() : lo.z());
  };
  // Quads (a, b, c, d) -> triangles (a, b, c), (a, c, d); orders checked by hand to give
  // outward area vectors: -x, +x, -y, +y, -z, +z.
  const int quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  TriangleMesh mesh;
  for (int f = 0; f < 6; ++f) {
    if (skip_plus_x && f == 1) continue;
    const auto& q = quads[f];
    add_triangle(mesh, corner(q[0]), corner(q[1]), corner(q[2]));
    add_triangle(mesh, corner(q[0]), corner(q[2]), corner(q[3]));
  }
  return mesh;
}

/// Exact signed distance of the box [lo, hi]: with q = |p - centre| - half_extent per axis,
///   phi = |max(q, 0)| + min(max_a q_a, 0)
/// (Quilez, "distance functions", box SDF).
inline double box_sdf(const Vec3& lo, const Vec3& hi, const Vec3& p) {
  const Vec3 centre = 0.5 * (lo + hi);
  const Vec3 half = 0.5 * (hi - lo);
  const Vec3 q = (p - centre).cwiseAbs() - half;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

/// Icosphere: the icosahedron subdivided `subdivisions` times (each triangle into 4, new
/// vertices pushed onto the sphere), 20 * 4^subdivisions triangles, every vertex at distance
/// `radius` from `centre` (up to rounding). Shared vertices are bit-identical.
inline TriangleMesh icosphere(const Vec3& centre, double radius, int subdivisions) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> unit = {{-1, t, 0}, {1, t, 0},  {-1, -t, 0}, {1, -t, 0},
                            {0, -1, t}, {0, 1, t},  {0, -1, -t}, {0, 1, -t},
                            {t, 0, -1}, {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (Vec3& v : unit) v.normalize();
  std::vector<std::array<int, 3>> faces = {
      {0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<int, int>, int> midpoint;
    auto middle = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      unit.push_back((unit[static_cast<std::size_t>(a)] + unit[static_cast<std::size_t>(b)])
                         .normalized());
      const int index = static_cast<int>(unit.size()) - 1;
      midpoint.emplace(key, index);
      return index;
    };
    std::vector<std::array<int, 3>> finer;
    for (const auto& f : faces) {
      const int ab = middle(f[0], f[1]), bc = middle(f[1], f[2]), ca = middle(f[2], f[0]);
      finer.push_back({f[0], ab, ca});
      finer.push_back({f[1], bc, ab});
      finer.push_back({f[2], ca, bc});
      finer.push_back({ab, bc, ca});
    }
    faces = std::move(finer);
  }
  TriangleMesh mesh;
  for (const auto& f : faces) {
    auto at = [&](int i) { return Vec3(centre + radius * unit[static_cast<std::size_t>(i)]); };
    add_triangle(mesh, at(f[0]), at(f[1]), at(f[2]));
  }
  return mesh;
}

/// The sagitta bound for a mesh inscribed in the sphere (centre, radius):
///   delta = radius - min_t dist(centre, plane(t))   [world units].
/// Every mesh point lies in the shell [radius - delta, radius] (a triangle's points are no
/// farther than its vertices, no nearer than its plane), the mesh is star-shaped about the
/// centre, so along every ray from the centre the mesh and the sphere are within delta; hence
/// |phi_mesh(p) - (|p - centre| - radius)| <= delta at every p (inside, outside and between).
inline double inscribed_chord_error(const TriangleMesh& mesh, const Vec3& centre, double radius) {
  double nearest_plane = radius;
  for (const Triangle& t : mesh.triangles) {
    const Vec3 n = t.area_vector().normalized();
    nearest_plane = std::min(nearest_plane, std::abs(n.dot(t.v[0] - centre)));
  }
  return radius - nearest_plane;
}

}  // namespace ppohdem::test
