// The original's exact band: the closest point of ppohDEM_v_distanceprecise and the axis
// ray-parity tests check_point_inside_out_{x,y,z}, transcribed expression by expression.
#include <cmath>

#include "ppohdem/compat/ppohdem10_steps.hpp"

namespace ppohdem::compat {
namespace {

using P = Ppohdem10Point;

// vector_3d_ab: b - a.
P from_to(const P& a, const P& b) { return {b.x - a.x, b.y - a.y, b.z - a.z}; }

// Inner_product: accumulated from 0.0 in x, y, z order.
double inner(const P& a, const P& b) {
  double ip = 0.0;
  ip = ip + (a.x * b.x);
  ip = ip + (a.y * b.y);
  ip = ip + (a.z * b.z);
  return ip;
}

// Outer_product: a x b.
P outer(const P& a, const P& b) {
  return {(a.y * b.z) - (a.z * b.y), (a.z * b.x) - (a.x * b.z), (a.x * b.y) - (a.y * b.x)};
}

}  // namespace

P ppohdem10_closest_point(const Ppohdem10Facet& f, const P& grid) {
  // Ericson, Real-Time Collision Detection (2005) 5.1.5, with a = v1, b = v2, c = v3.
  const P ab = from_to(f.v1, f.v2);
  const P ac = from_to(f.v1, f.v3);
  const P ap = from_to(f.v1, grid);
  const double d1 = inner(ab, ap);
  const double d2 = inner(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return f.v1;

  const P bp = from_to(f.v2, grid);
  const double d3 = inner(ab, bp);
  const double d4 = inner(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return f.v2;

  const double vc = (d1 * d4) - (d3 * d2);
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double v = d1 / (d1 - d3);
    return {f.v1.x + (v * ab.x), f.v1.y + (v * ab.y), f.v1.z + (v * ab.z)};
  }

  const P cp = {grid.x - f.v3.x, grid.y - f.v3.y, grid.z - f.v3.z};
  const double d5 = inner(ab, cp);
  const double d6 = inner(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return f.v3;

  const double vb = (d5 * d2) - (d1 * d6);
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double w = d2 / (d2 - d6);
    return {f.v1.x + (w * ac.x), f.v1.y + (w * ac.y), f.v1.z + (w * ac.z)};
  }

  const double va = (d3 * d6) - (d5 * d4);
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {f.v2.x + (w * (f.v3.x - f.v2.x)), f.v2.y + (w * (f.v3.y - f.v2.y)), f.v2.z + (w * (f.v3.z - f.v2.z))};
  }

  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom;
  const double w = vc * denom;
  return {f.v1.x + (ab.x * v) + (ac.x * w), f.v1.y + (ab.y * v) + (ac.y * w), f.v1.z + (ab.z * v) + (ac.z * w)};
}

double ppohdem10_distance_2points(const P& a, const P& b) {
  const double dx = a.x - b.x;
  const double dy = a.y - b.y;
  const double dz = a.z - b.z;
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

int ppohdem10_axis_inside(const std::vector<Ppohdem10Facet>& facets, const Ppohdem10Grid& grid, const P& p,
                          int axis) {
  // The ray direction: the grid's extent along the axis (last node minus first node).
  P pq{0.0, 0.0, 0.0};
  double coordinate = 0.0;
  const std::size_t nx = static_cast<std::size_t>(grid.n[0]);
  const std::size_t ny = static_cast<std::size_t>(grid.n[1]);
  const std::size_t nz = static_cast<std::size_t>(grid.n[2]);
  if (axis == 0) {
    pq.x = grid.x[nx] - grid.x[1];
    coordinate = p.x;
  } else if (axis == 1) {
    pq.y = grid.y[ny] - grid.y[1];
    coordinate = p.y;
  } else {
    pq.z = grid.z[nz] - grid.z[1];
    coordinate = p.z;
  }
  int count_p = 0;
  int count_q = 0;
  for (const Ppohdem10Facet& f : facets) {
    const P pa = from_to(p, f.v1);
    const P pb = from_to(p, f.v2);
    const P pc = from_to(p, f.v3);
    const double u = inner(pb, outer(pq, pc));
    const double v = inner(pc, outer(pq, pa));
    const double w = inner(pa, outer(pq, pb));
    if (u > 0.0 && v > 0.0 && w > 0.0) {
      // The original compares the triple product u [m^3] with the node's coordinate [m].
      if (u < coordinate) {
        ++count_p;
      } else {
        ++count_q;
      }
    }
  }
  return (count_p % 2 == 1 && count_q % 2 == 1) ? 1 : 0;
}

}  // namespace ppohdem::compat
