// The original DEM-Util pipeline (see ppohdem10_voxelizer.hpp): voxelise, pass 1, exact band,
// pass 2, all ranks simulated in one process.
#include "ppohdem/compat/ppohdem10_voxelizer.hpp"

#include <cmath>
#include <string>

#include "ppohdem/error.hpp"
#include "ppohdem/io/distance_dat.hpp"
#include "ppohdem/compat/ppohdem10_steps.hpp"
#include "ppohdem10_ranks.hpp"

namespace ppohdem::compat {
namespace {

void check_arguments(const VoxelizerInput& input, int nprocs) {
  const Index3& n = input.voxels;
  if (n[0] < 3 || n[1] < 3 || n[2] < 3) {
    throw InputError("--compat ppohdem-1.0: expected at least 3 nodes per axis, found " + std::to_string(n[0]) +
                     " " + std::to_string(n[1]) + " " + std::to_string(n[2]));
  }
  if (n[0] > n[1]) {
    throw InputError("--compat ppohdem-1.0: expected gridX <= gridY (the original fills the face j = gridY with "
                     "j = gridX and would write outside its array), found gridX " +
                     std::to_string(n[0]) + " > gridY " + std::to_string(n[1]));
  }
  if (nprocs < 1 || nprocs > n[0]) {
    throw InputError("--compat ppohdem-1.0: expected 1 <= ranks <= gridX = " + std::to_string(n[0]) + ", found " +
                     std::to_string(nprocs));
  }
}

std::vector<RankSlab> make_ranks(const Index3& nodes, int nprocs, double fill) {
  std::vector<RankSlab> ranks;
  for (int r = 0; r < nprocs; ++r) {
    const DistanceDatSlab slab = distance_dat_slab(nodes[0], nprocs, r);
    ranks.emplace_back(r, nprocs, slab.first_plane + 1, slab.first_plane + slab.plane_count, nodes, fill);
  }
  return ranks;
}

// Each rank's own planes, in GridSpec order (0-based, x fastest).
std::vector<double> gather(const std::vector<RankSlab>& ranks, const Index3& n) {
  std::vector<double> out(static_cast<std::size_t>(n[0]) * static_cast<std::size_t>(n[1]) *
                          static_cast<std::size_t>(n[2]));
  for (const RankSlab& s : ranks)
    for (int k = 1; k <= n[2]; ++k)
      for (int j = 1; j <= n[1]; ++j)
        for (int i = s.first; i <= s.last; ++i)
          out[static_cast<std::size_t>(i - 1) +
              static_cast<std::size_t>(n[0]) * (static_cast<std::size_t>(j - 1) +
                                                static_cast<std::size_t>(n[1]) * static_cast<std::size_t>(k - 1))] =
              s.at(i, j, k);
  return out;
}

// ppohDEM_v_distanceprecise on one rank's own planes. Writes the band's signed exact distance
// and the sentinel everywhere else (tdistance_voxel_3D is copied over distance_3D whole).
void exact_band(RankSlab& s, const Ppohdem10Grid& g, const std::vector<Ppohdem10Facet>& facets,
                const NodeFlags& value, NodeFlags& calculated, NodeFlags& vote_inside) {
  const double sentinel = g.lx * 10.0;
  const double hx = g.lx / g.n[0];
  const double hy = g.ly / g.n[1];
  const double hz = g.lz / g.n[2];
  const double check_gap = 2 * std::sqrt(hx * hx + hy * hy + hz * hz);
  std::vector<double> result(s.planes_size(), sentinel);
  std::vector<double> facet_distance(facets.size());
  for (int k = 1; k <= g.n[2]; ++k) {
    for (int j = 1; j <= g.n[1]; ++j) {
      for (int i = s.first; i <= s.last; ++i) {
        if (!(s.at(i, j, k) < check_gap || value(i, j, k))) continue;
        const Ppohdem10Point p{g.x[static_cast<std::size_t>(i)], g.y[static_cast<std::size_t>(j)],
                               g.z[static_cast<std::size_t>(k)]};
        // The 2-of-3 vote, overruled by the voxelisation when it says inside.
        const int votes = ppohdem10_axis_inside(facets, g, p, 0) + ppohdem10_axis_inside(facets, g, p, 1) +
                          ppohdem10_axis_inside(facets, g, p, 2);
        const bool inside = votes >= 2 || value(i, j, k);
        vote_inside(i, j, k) = votes >= 2 ? 1 : 0;
        for (std::size_t m = 0; m < facets.size(); ++m) {
          facet_distance[m] = ppohdem10_distance_2points(p, ppohdem10_closest_point(facets[m], p));
        }
        // Running minimum in facet order; a voxel-inside node accepts ties (<=), others not.
        double& t = result[s.offset(i, j, k)];
        for (const double d : facet_distance) {
          if (value(i, j, k)) {
            if (d <= std::abs(t)) {
              t = -d;
              calculated(i, j, k) = 1;
            }
          } else if (d < std::abs(t)) {
            t = inside ? -d : d;
            calculated(i, j, k) = 1;
          }
        }
      }
    }
  }
  for (int k = 1; k <= g.n[2]; ++k)
    for (int j = 1; j <= g.n[1]; ++j)
      for (int i = s.first; i <= s.last; ++i) s.at(i, j, k) = result[s.offset(i, j, k)];
}

}  // namespace

Ppohdem10Trace ppohdem10_distance_trace(const TriangleMesh& placed_mesh, const VoxelizerInput& input,
                                        int nprocs) {
  check_arguments(input, nprocs);
  const Ppohdem10Grid g = ppohdem10_grid(input.voxels, input.length);
  const std::vector<Ppohdem10Facet> facets = ppohdem10_facets(placed_mesh);
  const Index3& n = input.voxels;

  Ppohdem10Trace trace;
  trace.nodes = n;
  trace.spacing_w = g.w;
  trace.sentinel = g.lx * 10;

  // 1. z-ray voxelisation, column by column (each rank does its own columns; the result does
  //    not depend on the split).
  NodeFlags value(n);
  for (int j = 1; j <= n[1]; ++j) {
    for (int i = 1; i <= n[0]; ++i) {
      const Ppohdem10Column column = ppohdem10_zray_column(facets, g, i, j);
      if (column.crossings.size() % 2 == 1) ++trace.odd_crossing_columns;
      if (column.candidates > kPpohdem10MaxFacetCrossList) ++trace.overflowing_columns;
      for (const double c : column.crossings) {
        if (!std::isfinite(c)) {
          ++trace.nonfinite_crossing_columns;
          break;
        }
      }
      for (int k = 1; k <= n[2]; ++k) value(i, j, k) = column.inside[static_cast<std::size_t>(k)];
    }
  }
  trace.voxel_inside = value.gridspec_order();

  // 2. Pass 1. distance_3D starts at the sentinel everywhere, ghost planes included.
  std::vector<RankSlab> ranks = make_ranks(n, nprocs, trace.sentinel);
  NodeFlags calculated(n);
  jacobi_pass(ranks, g, value, calculated);
  trace.pass1 = gather(ranks, n);

  // 3. Exact band.
  NodeFlags vote_inside(n);
  for (RankSlab& s : ranks) exact_band(s, g, facets, value, calculated, vote_inside);
  const double hx = g.lx / n[0];
  const double hy = g.ly / n[1];
  const double hz = g.lz / n[2];
  trace.band_width = 2 * std::sqrt(hx * hx + hy * hy + hz * hz);
  trace.in_band = calculated.gridspec_order();
  trace.vote_inside = vote_inside.gridspec_order();

  // 4. Pass 2 from the frozen band.
  jacobi_pass(ranks, g, value, calculated);
  trace.distance = gather(ranks, n);
  return trace;
}

std::vector<double> ppohdem10_distance(const TriangleMesh& placed_mesh, const VoxelizerInput& input, int nprocs) {
  return ppohdem10_distance_trace(placed_mesh, input, nprocs).distance;
}

}  // namespace ppohdem::compat
