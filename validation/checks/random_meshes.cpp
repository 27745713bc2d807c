#include "random_meshes.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "ppohdem/error.hpp"

namespace ppohdem::validation {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;

TriangleMesh convex_hull_mesh(const std::vector<Vec3>& points) {
  std::vector<Point> pts;
  pts.reserve(points.size());
  for (const Vec3& p : points) pts.emplace_back(p.x(), p.y(), p.z());
  CGAL::Surface_mesh<Point> hull;
  CGAL::convex_hull_3(pts.begin(), pts.end(), hull);
  if (hull.number_of_faces() < 4) throw InputError("convex_hull_mesh: degenerate (coplanar) point set");
  TriangleMesh mesh;
  mesh.name = "convex hull";
  for (auto f : hull.faces()) {
    Triangle t;
    int k = 0;
    for (auto v : CGAL::vertices_around_face(hull.halfedge(f), hull)) {
      if (k > 2) throw InputError("convex_hull_mesh: non-triangular face");
      const Point& p = hull.point(v);
      t.v[static_cast<std::size_t>(k++)] = Vec3(p.x(), p.y(), p.z());
    }
    mesh.triangles.push_back(t);  // CGAL orients hull faces outward (counter-clockwise)
  }
  return mesh;
}

namespace {
using Cell = std::array<int, 3>;
}

TriangleMesh cell_union_mesh(const std::vector<Cell>& cells, double h, const Vec3& origin) {
  const std::set<Cell> occupied(cells.begin(), cells.end());
  TriangleMesh mesh;
  mesh.name = "cell union";
  for (const Cell& c : occupied) {
    for (int axis = 0; axis < 3; ++axis) {
      for (int side = 0; side < 2; ++side) {
        Cell n = c;
        n[static_cast<std::size_t>(axis)] += side == 0 ? -1 : 1;
        if (occupied.count(n)) continue;  // interior face
        // The face at coordinate c[axis] + side, spanned by the two other axes u, w with
        // (u, w, axis) cyclic, so that u x w = +axis; the outward normal is +axis for side 1.
        const int u = (axis + 1) % 3, w = (axis + 2) % 3;
        auto corner = [&](int du, int dw) {
          Vec3 p(c[0], c[1], c[2]);
          p[axis] += side;
          p[u] += du;
          p[w] += dw;
          return Vec3(origin + h * p);
        };
        const Vec3 a = corner(0, 0), b = corner(1, 0), cc = corner(1, 1), d = corner(0, 1);
        Triangle t1, t2;
        if (side == 1) {
          t1.v = {a, b, cc};
          t2.v = {a, cc, d};
        } else {
          t1.v = {a, cc, b};
          t2.v = {a, d, cc};
        }
        mesh.triangles.push_back(t1);
        mesh.triangles.push_back(t2);
      }
    }
  }
  return mesh;
}

bool is_manifold_cell_union(const std::vector<Cell>& cells) {
  const std::set<Cell> occupied(cells.begin(), cells.end());
  auto has = [&](int x, int y, int z) { return occupied.count(Cell{x, y, z}) != 0; };
  int lo[3] = {1 << 30, 1 << 30, 1 << 30}, hi[3] = {-(1 << 30), -(1 << 30), -(1 << 30)};
  for (const Cell& c : occupied)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], c[static_cast<std::size_t>(a)]);
      hi[a] = std::max(hi[a], c[static_cast<std::size_t>(a)]);
    }
  // Every lattice vertex sees a 2x2x2 block of cells. Non-manifold edge: in some 2x2 slab
  // around an edge, exactly the two diagonal cells are occupied (or exactly two empty
  // diagonal ones). Non-manifold vertex: the occupied cells of the block (or the empty ones)
  // are not face-connected within the block.
  for (int x = lo[0]; x <= hi[0] + 1; ++x)
    for (int y = lo[1]; y <= hi[1] + 1; ++y)
      for (int z = lo[2]; z <= hi[2] + 1; ++z) {
        bool b[2][2][2];
        for (int i = 0; i < 2; ++i)
          for (int j = 0; j < 2; ++j)
            for (int k = 0; k < 2; ++k) b[i][j][k] = has(x - 1 + i, y - 1 + j, z - 1 + k);
        // Face-connectivity of occupied and of empty cells inside the block.
        for (int value = 0; value < 2; ++value) {
          int count = 0, first = -1;
          for (int idx = 0; idx < 8; ++idx)
            if (b[idx >> 2][(idx >> 1) & 1][idx & 1] == (value == 1)) {
              ++count;
              if (first < 0) first = idx;
            }
          if (count == 0) continue;
          int seen = 1 << first, frontier = 1 << first;
          while (frontier) {
            int next = 0;
            for (int idx = 0; idx < 8; ++idx) {
              if (!(frontier & (1 << idx))) continue;
              for (int bit : {4, 2, 1}) {
                const int nb = idx ^ bit;
                if (!(seen & (1 << nb)) && b[nb >> 2][(nb >> 1) & 1][nb & 1] == (value == 1)) {
                  seen |= 1 << nb;
                  next |= 1 << nb;
                }
              }
            }
            frontier = next;
          }
          if (__builtin_popcount(static_cast<unsigned>(seen)) != count) return false;
        }
      }
  return true;
}

double cell_union_outside_distance(const std::vector<Cell>& cells, double h, const Vec3& origin,
                                   const Vec3& x) {
  double best = std::numeric_limits<double>::infinity();
  for (const Cell& c : cells) {
    const Vec3 lo = origin + h * Vec3(c[0], c[1], c[2]);
    const Vec3 hi = lo + Vec3::Constant(h);
    const Vec3 d = (lo - x).cwiseMax(x - hi).cwiseMax(Vec3::Zero());
    best = std::min(best, d.norm());
  }
  return best;
}

}  // namespace ppohdem::validation
