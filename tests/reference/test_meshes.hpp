#pragma once
/// \file test_meshes.hpp
/// Meshes built in code for the SDF tests (no file reader involved). Every generator emits
/// triangles from an indexed vertex list, so shared vertices are bit-identical and closed meshes
/// are watertight; triangles are counter-clockwise seen from outside.
#include <cmath>
#include <numbers>
#include <vector>

#include "ppohdem/mesh/triangle_mesh.hpp"

namespace ppohdem::test {

/// Mesh from vertices and index triples.
inline TriangleMesh indexed_mesh(const std::vector<Vec3>& vertices, const std::vector<std::array<int, 3>>& faces) {
  TriangleMesh mesh;
  for (const auto& f : faces) {
    Triangle t;
    t.v = {vertices[static_cast<std::size_t>(f[0])], vertices[static_cast<std::size_t>(f[1])],
           vertices[static_cast<std::size_t>(f[2])]};
    mesh.triangles.push_back(t);
  }
  return mesh;
}

/// Axis-aligned box [lo, hi], 12 triangles.
inline TriangleMesh box_mesh(const Vec3& lo, const Vec3& hi) {
  std::vector<Vec3> v;
  for (int corner = 0; corner < 8; ++corner) {  // bit 0 -> x, bit 1 -> y, bit 2 -> z
    v.emplace_back((corner & 1) ? hi.x() : lo.x(), (corner & 2) ? hi.y() : lo.y(), (corner & 4) ? hi.z() : lo.z());
  }
  // Each face as a quad (p, q, r, s) counter-clockwise seen from outside -> (p, q, r), (p, r, s).
  const std::vector<std::array<int, 4>> quads = {
      {0, 2, 3, 1},  // z = lo (normal -z)
      {4, 5, 7, 6},  // z = hi (+z)
      {0, 1, 5, 4},  // y = lo (-y)
      {2, 6, 7, 3},  // y = hi (+y)
      {0, 4, 6, 2},  // x = lo (-x)
      {1, 3, 7, 5},  // x = hi (+x)
  };
  std::vector<std::array<int, 3>> faces;
  for (const auto& q : quads) {
    faces.push_back({q[0], q[1], q[2]});
    faces.push_back({q[0], q[2], q[3]});
  }
  return indexed_mesh(v, faces);
}

/// UV sphere: `longitudes` meridians, `bands` latitude bands, poles on the z axis through `centre`.
/// Triangles: 2 longitudes (bands - 1). Vertices lie on the sphere (the polyhedron is inscribed).
inline TriangleMesh uv_sphere(const Vec3& centre, double radius, int longitudes, int bands) {
  std::vector<Vec3> v;
  v.push_back(centre + Vec3(0, 0, radius));  // north pole, index 0
  for (int b = 1; b < bands; ++b) {
    const double theta = std::numbers::pi * b / bands;  // polar angle
    for (int l = 0; l < longitudes; ++l) {
      const double phi = 2.0 * std::numbers::pi * l / longitudes;
      v.push_back(centre + radius * Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)));
    }
  }
  v.push_back(centre - Vec3(0, 0, radius));  // south pole
  const int south = static_cast<int>(v.size()) - 1;
  auto ring = [&](int b, int l) { return 1 + (b - 1) * longitudes + (l % longitudes); };
  std::vector<std::array<int, 3>> faces;
  for (int l = 0; l < longitudes; ++l) {
    faces.push_back({0, ring(1, l), ring(1, l + 1)});
    faces.push_back({south, ring(bands - 1, l + 1), ring(bands - 1, l)});
    for (int b = 1; b + 1 < bands; ++b) {
      faces.push_back({ring(b, l), ring(b + 1, l), ring(b + 1, l + 1)});
      faces.push_back({ring(b, l), ring(b + 1, l + 1), ring(b, l + 1)});
    }
  }
  return indexed_mesh(v, faces);
}

/// Icosphere: an icosahedron subdivided `levels` times, vertices projected onto the sphere
/// (20 * 4^levels triangles).
inline TriangleMesh icosphere(const Vec3& centre, double radius, int levels) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> unit = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                            {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (Vec3& p : unit) p.normalize();
  std::vector<std::array<int, 3>> faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                           {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                           {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                           {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int level = 0; level < levels; ++level) {
    std::vector<std::array<int, 3>> finer;
    std::vector<std::pair<std::pair<int, int>, int>> midpoints;  // edge -> new vertex (small meshes: linear search is fine)
    auto midpoint = [&](int a, int b) {
      const std::pair<int, int> key = {std::min(a, b), std::max(a, b)};
      for (const auto& [edge, index] : midpoints) {
        if (edge == key) return index;
      }
      unit.push_back((unit[static_cast<std::size_t>(a)] + unit[static_cast<std::size_t>(b)]).normalized());
      midpoints.push_back({key, static_cast<int>(unit.size()) - 1});
      return static_cast<int>(unit.size()) - 1;
    };
    for (const auto& f : faces) {
      const int ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
      finer.push_back({f[0], ab, ca});
      finer.push_back({f[1], bc, ab});
      finer.push_back({f[2], ca, bc});
      finer.push_back({ab, bc, ca});
    }
    faces = finer;
  }
  std::vector<Vec3> v;
  for (const Vec3& p : unit) v.push_back(centre + radius * p);
  return indexed_mesh(v, faces);
}

/// A right prism over a counter-clockwise polygon (xy) from z0 to z1; caps fanned from polygon[fan_apex]
/// (the fan must stay inside the polygon, e.g. an L fanned from its reflex corner).
inline TriangleMesh prism(const std::vector<Eigen::Vector2d>& polygon, double z0, double z1, int fan_apex) {
  const int n = static_cast<int>(polygon.size());
  std::vector<Vec3> v;
  for (const auto& p : polygon) v.emplace_back(p.x(), p.y(), z0);  // 0..n-1 bottom
  for (const auto& p : polygon) v.emplace_back(p.x(), p.y(), z1);  // n..2n-1 top
  std::vector<std::array<int, 3>> faces;
  for (int s = 1; s + 1 < n; ++s) {
    const int b = (fan_apex + s) % n, c = (fan_apex + s + 1) % n;
    faces.push_back({n + fan_apex, n + b, n + c});  // top: counter-clockwise seen from +z
    faces.push_back({fan_apex, c, b});               // bottom: reversed
  }
  for (int e = 0; e < n; ++e) {  // side quad below edge e -> e+1; outward is to the right of it
    const int p = e, q = (e + 1) % n;
    faces.push_back({p, q, n + q});
    faces.push_back({p, n + q, n + p});
  }
  return indexed_mesh(v, faces);
}

/// The L-shaped solid ([0,2]x[0,1] u [0,1]x[0,2]) x [0,1], scaled by `s` and shifted by `offset`.
inline TriangleMesh l_shape(double s, const Vec3& offset) {
  const std::vector<Eigen::Vector2d> polygon = {{0, 0}, {2 * s, 0}, {2 * s, s}, {s, s}, {s, 2 * s}, {0, 2 * s}};
  TriangleMesh mesh = prism(polygon, 0.0, s, 3);
  for (Triangle& t : mesh.triangles) {
    for (Vec3& p : t.v) p += offset;
  }
  return mesh;
}

/// Applies x -> R x + shift to every vertex.
inline TriangleMesh transformed(TriangleMesh mesh, const Eigen::Matrix3d& rotation, const Vec3& shift) {
  for (Triangle& t : mesh.triangles) {
    for (Vec3& p : t.v) p = rotation * p + shift;
  }
  return mesh;
}

}  // namespace ppohdem::test
