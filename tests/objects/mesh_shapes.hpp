#pragma once
// Meshes for the mesh-contact tests: flat rectangles split into many triangles (so that a face
// is several coplanar triangles), a V-notch, a three-face corner, a box.
#include <Eigen/Geometry>

#include "ppohdem/mesh/triangle_mesh.hpp"

namespace ppohdem::dem::test {

/// Appends the rectangle o + s u + t w, s, t in [0, 1], split into nu x nw cells of two
/// triangles each (diagonals alternating), counter-clockwise seen from the side of u x w.
/// Vertices are o + (i/nu) u + (j/nw) w computed the same way for every rectangle, so two
/// rectangles sharing a side with the same o and the same division weld there.
inline void add_rectangle(TriangleMesh& mesh, const Vec3& o, const Vec3& u, const Vec3& w, int nu, int nw) {
  const auto at = [&](int i, int j) {
    return Vec3(o + (static_cast<double>(i) / nu) * u + (static_cast<double>(j) / nw) * w);
  };
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nw; ++j) {
      const Vec3 p00 = at(i, j), p10 = at(i + 1, j), p01 = at(i, j + 1), p11 = at(i + 1, j + 1);
      Triangle a, b;
      if ((i + j) % 2 == 0) {
        a.v = {p00, p10, p11};
        b.v = {p00, p11, p01};
      } else {
        a.v = {p00, p10, p01};
        b.v = {p10, p11, p01};
      }
      mesh.triangles.push_back(a);
      mesh.triangles.push_back(b);
    }
  }
}

/// The mesh moved by x -> Q x + t.
inline TriangleMesh transformed(const TriangleMesh& mesh, const Eigen::Matrix3d& q, const Vec3& t) {
  TriangleMesh out = mesh;
  for (Triangle& tri : out.triangles) {
    for (Vec3& v : tri.v) v = q * v + t;
  }
  return out;
}

/// A 90-degree V-notch along x in [0, length]: face A {(x, s, s)}, face B {(x, -s, s)},
/// s in [0, depth], outward normals nA = (0, -1, 1)/sqrt(2) and nB = (0, 1, 1)/sqrt(2) (both into
/// the notch). Each face is cells x cells rectangles of two triangles; the crease welds.
inline TriangleMesh v_notch(double length, double depth, int cells) {
  TriangleMesh mesh;
  // Face A: u along x, w up the face; u x w = (L,0,0) x (0,d,d) = (0, -L d, L d): along nA.
  add_rectangle(mesh, Vec3::Zero(), Vec3(length, 0, 0), Vec3(0, depth, depth), cells, cells);
  // Face B: u up the face, w along x; (0,-d,d) x (L,0,0) = (0, d L, d L): along nB. Its crease
  // vertices are o + (j/n) (L,0,0), the same doubles as face A's.
  add_rectangle(mesh, Vec3::Zero(), Vec3(0, -depth, depth), Vec3(length, 0, 0), cells, cells);
  return mesh;
}

/// The concave corner of three faces: floor z = 0 (x, y in [0, a]), walls x = 0 and y = 0,
/// outward normals +z, +x, +y (into the corner's open side).
inline TriangleMesh three_face_corner(double a, int cells) {
  TriangleMesh mesh;
  add_rectangle(mesh, Vec3::Zero(), Vec3(a, 0, 0), Vec3(0, a, 0), cells, cells);  // floor, +z
  add_rectangle(mesh, Vec3::Zero(), Vec3(0, a, 0), Vec3(0, 0, a), cells, cells);  // x = 0, +x
  add_rectangle(mesh, Vec3::Zero(), Vec3(0, 0, a), Vec3(a, 0, 0), cells, cells);  // y = 0, +y
  return mesh;
}

/// The closed box [0, a]^3 with outward normals, each face cells x cells rectangles.
inline TriangleMesh box(double a, int cells) {
  TriangleMesh mesh;
  const Vec3 x(a, 0, 0), y(0, a, 0), z(0, 0, a);
  add_rectangle(mesh, Vec3::Zero(), y, x, cells, cells);  // z = 0, -z
  add_rectangle(mesh, z, x, y, cells, cells);             // z = a, +z
  add_rectangle(mesh, Vec3::Zero(), z, y, cells, cells);  // x = 0, -x
  add_rectangle(mesh, x, y, z, cells, cells);             // x = a, +x
  add_rectangle(mesh, Vec3::Zero(), x, z, cells, cells);  // y = 0, -y
  add_rectangle(mesh, y, z, x, cells, cells);             // y = a, +y
  return mesh;
}

}  // namespace ppohdem::dem::test
