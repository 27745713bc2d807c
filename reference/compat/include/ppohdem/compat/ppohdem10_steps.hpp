#pragma once
/// \file ppohdem10_steps.hpp
/// The building blocks of ppohdem10_voxelizer.hpp, each a literal transcription of one routine
/// of the original (operand order kept so the doubles come out identical). Exposed so tests can
/// check each against an independent answer; users want ppohdem10_distance().
#include <array>
#include <cstdint>
#include <vector>

#include "ppohdem/mesh/triangle_mesh.hpp"

namespace ppohdem::compat {

/// Three doubles with no vector arithmetic attached, so every operation is spelled out.
struct Ppohdem10Point {
  double x = 0.0, y = 0.0, z = 0.0;
};

/// One facet as the original stores it: vertices v1, v2, v3 and its per-axis min/max.
struct Ppohdem10Facet {
  Ppohdem10Point v1, v2, v3;
  Ppohdem10Point min, max;
};

std::vector<Ppohdem10Facet> ppohdem10_facets(const TriangleMesh& mesh);

/// Node coordinates of the original's grid, 1-based like the Fortran (element 0 unused):
/// x[i] = (Lx / gridX) * (i - 1).
struct Ppohdem10Grid {
  Index3 n = {0, 0, 0};
  double lx = 0.0, ly = 0.0, lz = 0.0;
  std::vector<double> x, y, z;
  double w = 0.0;   ///< W = Lx / gridX
  double w2 = 0.0;  ///< W * W
};
Ppohdem10Grid ppohdem10_grid(const Index3& nodes, const Vec3& length);

/// ppohDEM_v_makecrosslist_MPI + makegridout_MPI for column (ix, jy) (1-based): the sorted
/// z-heights where the column crosses the facets it selects, and the nodes it marks inside
/// (`inside[k]` for k = 1..gridZ, element 0 unused).
struct Ppohdem10Column {
  std::vector<double> crossings;     ///< sorted ascending
  std::vector<std::uint8_t> inside;  ///< 1-based
  int candidates = 0;                ///< facets passing the strict bounding-box test
};
Ppohdem10Column ppohdem10_zray_column(const std::vector<Ppohdem10Facet>& facets, const Ppohdem10Grid& grid,
                                      int ix, int jy);

/// The closest point of the facet to p, Ericson's Voronoi-region test exactly as the original
/// codes it (no degenerate-triangle guard).
Ppohdem10Point ppohdem10_closest_point(const Ppohdem10Facet& facet, const Ppohdem10Point& p);
/// sqrt((a-b)x^2 + (a-b)y^2 + (a-b)z^2), distance_2points.
double ppohdem10_distance_2points(const Ppohdem10Point& a, const Ppohdem10Point& b);

/// check_point_inside_out_{x,y,z}: 1 if the ray parity along `axis` (0, 1, 2) says p is inside.
/// A facet counts if the three triple products u, v, w of the ray direction pq = (extent of the
/// grid along the axis) with the vertices are all > 0 (so only facets wound one way, and only
/// strictly inside ones, count); it is counted on the "P" side if u < p[axis] (the original
/// compares the triple product u, a volume, with a coordinate), else on the "Q" side; inside
/// means both counts odd.
int ppohdem10_axis_inside(const std::vector<Ppohdem10Facet>& facets, const Ppohdem10Grid& grid,
                          const Ppohdem10Point& p, int axis);

/// The eikonal update of one node from its value c and its six neighbours (ppohDEM's
/// distancecalculate): with dx = min(x+, x-, c) etc., the number of axes whose min is c itself
/// chooses the stencil:
///   3 -> c;  2 -> W + (the other axis' min);
///   1 -> ((a + b) + sqrt(2 W^2 - (a - b)^2)) / 2, or c if the root is negative;
///   0 -> (dx + dy + dz + sqrt(3 W^2 - 2 (dx^2+dy^2+dz^2 - dx dy - dy dz - dz dx))) / 3, or c.
/// (Sethian, "Level Set Methods and Fast Marching Methods", 1999, ch. 8, first-order upwind.)
double ppohdem10_eikonal_update(double c, double xp, double xm, double yp, double ym, double zp, double zm,
                                double w, double w2);

}  // namespace ppohdem::compat
