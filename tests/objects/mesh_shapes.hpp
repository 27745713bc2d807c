#pragma once
// Meshes for the mesh-contact tests: flat rectangles split into many triangles (so that a face
// is several coplanar triangles), a V-notch, a three-face corner, a box.
#include <Eigen/Geometry>
#include <array>
#include <utility>
#include <vector>

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

namespace ppohdem::dem::test {

/// A closed prism along x in [0, length]: the polygon `yz` (counter-clockwise seen from +x,
/// the first vertex a corner every other vertex can be seen from) extruded, each side face
/// split into `cells` rectangles along x (two triangles each), the end caps fanned from the
/// first vertex. Every vertex is (j length / cells, y_k, z_k): shared vertices weld.
inline TriangleMesh prism(const std::vector<Eigen::Vector2d>& yz, double length, int cells) {
  TriangleMesh mesh;
  const auto at = [&](std::size_t k, int j) {
    return Vec3(j * length / cells, yz[k % yz.size()].x(), yz[k % yz.size()].y());
  };
  for (std::size_t k = 0; k < yz.size(); ++k) {
    for (int j = 0; j < cells; ++j) {
      Triangle a, b;
      a.v = {at(k, j), at(k + 1, j), at(k + 1, j + 1)};
      b.v = {at(k, j), at(k + 1, j + 1), at(k, j + 1)};
      mesh.triangles.push_back(a);
      mesh.triangles.push_back(b);
    }
  }
  for (std::size_t k = 1; k + 1 < yz.size(); ++k) {
    Triangle near, far;
    near.v = {at(0, 0), at(k + 1, 0), at(k, 0)};          // x = 0, normal -x
    far.v = {at(0, cells), at(k, cells), at(k + 1, cells)};  // x = length, normal +x
    mesh.triangles.push_back(near);
    mesh.triangles.push_back(far);
  }
  return mesh;
}

/// A block with a 90-degree V-notch along x cut in its top: crease on the x axis, notch faces
/// nA = (0, -1, 1)/sqrt(2) on y > 0 and nB = (0, 1, 1)/sqrt(2) on y < 0 up to the rims at
/// |y| = z = half_width, block bottom at z = -depth.
inline TriangleMesh notched_block(double length, double half_width, double depth, int cells) {
  const double w = half_width;
  return prism({{0, 0}, {-w, w}, {-w, -depth}, {w, -depth}, {w, w}}, length, cells);
}

/// The closed surface of a union of cells of the lattice bx x by x bz (breakpoints ascending):
/// cell (i, j, k) is solid if solid(i, j, k). Two triangles per exposed cell face, outward.
template <class Solid>
TriangleMesh lattice_solid(const std::array<std::vector<double>, 3>& b, Solid solid) {
  TriangleMesh mesh;
  const int n[3] = {static_cast<int>(b[0].size()) - 1, static_cast<int>(b[1].size()) - 1,
                    static_cast<int>(b[2].size()) - 1};
  const auto filled = [&](int c[3]) {
    for (int a = 0; a < 3; ++a) {
      if (c[a] < 0 || c[a] >= n[a]) return false;
    }
    return static_cast<bool>(solid(c[0], c[1], c[2]));
  };
  for (int i = 0; i < n[0]; ++i) {
    for (int j = 0; j < n[1]; ++j) {
      for (int k = 0; k < n[2]; ++k) {
        int c[3] = {i, j, k};
        if (!filled(c)) continue;
        for (int a = 0; a < 3; ++a) {
          for (int s = -1; s <= 1; s += 2) {
            int m[3] = {i, j, k};
            m[a] += s;
            if (filled(m)) continue;
            const int bb = (a + 1) % 3, cc = (a + 2) % 3;  // e_b x e_c = e_a
            const auto corner = [&](int db, int dc) {
              Vec3 p;
              p[a] = b[a][c[a] + (s > 0 ? 1 : 0)];
              p[bb] = b[bb][c[bb] + db];
              p[cc] = b[cc][c[cc] + dc];
              return p;
            };
            std::array<Vec3, 4> q = {corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)};
            if (s < 0) std::swap(q[1], q[3]);
            Triangle t1, t2;
            t1.v = {q[0], q[1], q[2]};
            t2.v = {q[0], q[2], q[3]};
            mesh.triangles.push_back(t1);
            mesh.triangles.push_back(t2);
          }
        }
      }
    }
  }
  return mesh;
}

}  // namespace ppohdem::dem::test
