// The original's z-ray voxelisation: ppohDEM_v_makecrosslist_MPI and ppohDEM_v_makegridout_MPI,
// transcribed expression by expression (see ppohdem10_steps.hpp).
#include <algorithm>
#include <cmath>

#include "ppohdem/compat/ppohdem10_steps.hpp"

namespace ppohdem::compat {

std::vector<Ppohdem10Facet> ppohdem10_facets(const TriangleMesh& mesh) {
  std::vector<Ppohdem10Facet> facets;
  facets.reserve(mesh.size());
  for (const Triangle& t : mesh.triangles) {
    Ppohdem10Facet f;
    f.v1 = {t.v[0].x(), t.v[0].y(), t.v[0].z()};
    f.v2 = {t.v[1].x(), t.v[1].y(), t.v[1].z()};
    f.v3 = {t.v[2].x(), t.v[2].y(), t.v[2].z()};
    // ppohDEM_v_inivar: min/max found per axis with `if (min > v) min = v` over v1, v2, v3 and
    // then placed by the same formula as the vertices, so they equal the placed extremes.
    f.min = {std::min({f.v1.x, f.v2.x, f.v3.x}), std::min({f.v1.y, f.v2.y, f.v3.y}),
             std::min({f.v1.z, f.v2.z, f.v3.z})};
    f.max = {std::max({f.v1.x, f.v2.x, f.v3.x}), std::max({f.v1.y, f.v2.y, f.v3.y}),
             std::max({f.v1.z, f.v2.z, f.v3.z})};
    facets.push_back(f);
  }
  return facets;
}

Ppohdem10Grid ppohdem10_grid(const Index3& nodes, const Vec3& length) {
  Ppohdem10Grid g;
  g.n = nodes;
  g.lx = length.x();
  g.ly = length.y();
  g.lz = length.z();
  auto axis = [](double l, int n) {
    std::vector<double> c(static_cast<std::size_t>(n) + 1, 0.0);
    for (int i = 1; i <= n; ++i) c[static_cast<std::size_t>(i)] = (l / n) * (i - 1);
    return c;
  };
  g.x = axis(g.lx, nodes[0]);
  g.y = axis(g.ly, nodes[1]);
  g.z = axis(g.lz, nodes[2]);
  g.w = g.lx / nodes[0];
  g.w2 = g.w * g.w;
  return g;
}

namespace {

// One of the three edge tests of makecrosslist: the line through edge (a, b) predicts y at the
// third vertex c and at the column's x; the column passes if both predictions lie on the same
// side (strictly) of c.y and of the column's y. A vertical edge (a.x == b.x) makes the slope
// +-inf or NaN, as in the Fortran (which then signals IEEE_DIVIDE_BY_ZERO).
bool same_side_as_vertex(const Ppohdem10Point& a, const Ppohdem10Point& b, const Ppohdem10Point& c, double gx,
                         double gy) {
  const double slope = (b.y - a.y) / (b.x - a.x);
  const double y_at_c = a.y + slope * (c.x - a.x);
  const double y_at_column = a.y + slope * (gx - a.x);
  return (y_at_c > c.y && y_at_column > gy) || (y_at_c < c.y && y_at_column < gy);
}

// Plane a x + b y + c z + d = 0 through the facet, coefficients in the original's form.
double crossing_height(const Ppohdem10Facet& f, double gx, double gy) {
  const Ppohdem10Point& p1 = f.v1;
  const Ppohdem10Point& p2 = f.v2;
  const Ppohdem10Point& p3 = f.v3;
  const double a = p1.y * (p2.z - p3.z) + p2.y * (p3.z - p1.z) + p3.y * (p1.z - p2.z);
  const double b = p1.z * (p2.x - p3.x) + p2.z * (p3.x - p1.x) + p3.z * (p1.x - p2.x);
  const double c = p1.x * (p2.y - p3.y) + p2.x * (p3.y - p1.y) + p3.x * (p1.y - p2.y);
  const double d = -(p1.x * (p2.y * p3.z - p3.y * p2.z)) - p2.x * (p3.y * p1.z - p1.y * p3.z) -
                   p3.x * (p1.y * p2.z - p2.y * p1.z);
  return (-d - a * gx - b * gy) / c;
}

}  // namespace

Ppohdem10Column ppohdem10_zray_column(const std::vector<Ppohdem10Facet>& facets, const Ppohdem10Grid& grid,
                                      int ix, int jy) {
  const double gx = grid.x[static_cast<std::size_t>(ix)];
  const double gy = grid.y[static_cast<std::size_t>(jy)];
  Ppohdem10Column column;
  // makecrosslist step 1: strict bounding-box test (a column through a facet's extreme x or y
  // selects nothing there), in facet order.
  std::vector<const Ppohdem10Facet*> candidates;
  for (const Ppohdem10Facet& f : facets) {
    if (gx < f.max.x && gx > f.min.x && gy < f.max.y && gy > f.min.y) candidates.push_back(&f);
  }
  column.candidates = static_cast<int>(candidates.size());
  // Step 2: the three edge tests, (v2, v3 | v1), then (v3, v1 | v2), then (v1, v2 | v3).
  for (const Ppohdem10Facet* f : candidates) {
    if (same_side_as_vertex(f->v2, f->v3, f->v1, gx, gy) && same_side_as_vertex(f->v3, f->v1, f->v2, gx, gy) &&
        same_side_as_vertex(f->v1, f->v2, f->v3, gx, gy)) {
      column.crossings.push_back(crossing_height(*f, gx, gy));
    }
  }
  // makegridout: sort (ppohDEM_qsort, ascending; only the values matter), then nodes strictly
  // between crossings 1-2, 3-4, ... are inside. An unpaired last crossing marks nothing (see
  // Ppohdem10Trace::odd_crossing_columns).
  // NaN (a facet parallel to z) has no place in the original's order; it goes last here so the
  // sort stays well defined, and the caller counts such columns.
  std::sort(column.crossings.begin(), column.crossings.end(),
            [](double a, double b) { return a < b || (!std::isnan(a) && std::isnan(b)); });
  column.inside.assign(static_cast<std::size_t>(grid.n[2]) + 1, 0);
  for (std::size_t pair = 0; pair + 1 < column.crossings.size(); pair += 2) {
    const double low = column.crossings[pair];
    const double high = column.crossings[pair + 1];
    for (int k = 1; k <= grid.n[2]; ++k) {
      const double gz = grid.z[static_cast<std::size_t>(k)];
      if (gz > low && gz < high) column.inside[static_cast<std::size_t>(k)] = 1;
    }
  }
  return column;
}

}  // namespace ppohdem::compat
