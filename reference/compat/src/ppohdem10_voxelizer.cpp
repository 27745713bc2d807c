// The original DEM-Util pipeline (see ppohdem10_voxelizer.hpp): voxelise, pass 1, exact band,
// pass 2, all ranks simulated in one process.
#include "ppohdem/compat/ppohdem10_voxelizer.hpp"

#include <cmath>
#include <stdexcept>
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
void exact_band_of_rank(RankSlab& s, const Ppohdem10Grid& g, const std::vector<Ppohdem10Facet>& facets,
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

struct Ppohdem10VoxelizerStages::State {
  State(const TriangleMesh& placed_mesh, const VoxelizerInput& input, int rank_count)
      : g(ppohdem10_grid(input.voxels, input.length)), facets(ppohdem10_facets(placed_mesh)), n(input.voxels),
        nprocs(rank_count), value(n), calculated(n), vote_inside(n) {}
  Ppohdem10Grid g;
  std::vector<Ppohdem10Facet> facets;
  Index3 n;
  int nprocs;
  Ppohdem10Trace trace;
  NodeFlags value, calculated, vote_inside;
  std::vector<RankSlab> ranks;
  int done = 0;

  void expect(int stages, const char* stage, const char* before) const {
    if (done != stages) {
      throw std::logic_error(std::string(stage) + " needs " + before + " first (stages done: " +
                             std::to_string(done) + " of 4)");
    }
  }
};

Ppohdem10VoxelizerStages::Ppohdem10VoxelizerStages(const TriangleMesh& placed_mesh, const VoxelizerInput& input,
                                                   int nprocs) {
  check_arguments(input, nprocs);
  state_ = std::make_unique<State>(placed_mesh, input, nprocs);
  state_->trace.nodes = input.voxels;
  state_->trace.spacing_w = state_->g.w;
  state_->trace.sentinel = state_->g.lx * 10;
}

Ppohdem10VoxelizerStages::~Ppohdem10VoxelizerStages() = default;

void Ppohdem10VoxelizerStages::voxelize() {
  State& st = *state_;
  st.expect(0, "voxelize", "a fresh pipeline");
  const Index3& n = st.n;
  Ppohdem10Trace& trace = st.trace;
  // 1. z-ray voxelisation, column by column (each rank does its own columns; the result does
  //    not depend on the split).
  for (int j = 1; j <= n[1]; ++j) {
    for (int i = 1; i <= n[0]; ++i) {
      const Ppohdem10Column column = ppohdem10_zray_column(st.facets, st.g, i, j);
      if (column.crossings.size() % 2 == 1) ++trace.odd_crossing_columns;
      if (column.candidates > kPpohdem10MaxFacetCrossList) ++trace.overflowing_columns;
      for (const double c : column.crossings) {
        if (!std::isfinite(c)) {
          ++trace.nonfinite_crossing_columns;
          break;
        }
      }
      for (int k = 1; k <= n[2]; ++k) st.value(i, j, k) = column.inside[static_cast<std::size_t>(k)];
    }
  }
  trace.voxel_inside = st.value.gridspec_order();
  st.done = 1;
}

void Ppohdem10VoxelizerStages::pass1() {
  State& st = *state_;
  st.expect(1, "pass 1 (distancecalculate_MPI1)", "the voxelisation (makevoxel)");
  // 2. Pass 1. distance_3D starts at the sentinel everywhere, ghost planes included.
  st.ranks = make_ranks(st.n, st.nprocs, st.trace.sentinel);
  jacobi_pass(st.ranks, st.g, st.value, st.calculated);
  st.trace.pass1 = gather(st.ranks, st.n);
  st.done = 2;
}

void Ppohdem10VoxelizerStages::exact_band() {
  State& st = *state_;
  st.expect(2, "the exact band (distanceprecise)", "pass 1 (distancecalculate_MPI1)");
  // 3. Exact band.
  for (RankSlab& s : st.ranks) exact_band_of_rank(s, st.g, st.facets, st.value, st.calculated, st.vote_inside);
  const double hx = st.g.lx / st.n[0];
  const double hy = st.g.ly / st.n[1];
  const double hz = st.g.lz / st.n[2];
  st.trace.band_width = 2 * std::sqrt(hx * hx + hy * hy + hz * hz);
  st.trace.in_band = st.calculated.gridspec_order();
  st.trace.vote_inside = st.vote_inside.gridspec_order();
  st.done = 3;
}

void Ppohdem10VoxelizerStages::pass2() {
  State& st = *state_;
  st.expect(3, "pass 2 (distancecalculate_MPI2)", "the exact band (distanceprecise)");
  // 4. Pass 2 from the frozen band.
  jacobi_pass(st.ranks, st.g, st.value, st.calculated);
  st.trace.distance = gather(st.ranks, st.n);
  st.done = 4;
}

int Ppohdem10VoxelizerStages::stages_done() const { return state_->done; }

std::vector<double> Ppohdem10VoxelizerStages::distance() const {
  if (state_->done == 0) return std::vector<double>(state_->value.gridspec_order().size(), state_->trace.sentinel);
  return gather(state_->ranks, state_->n);
}

const Ppohdem10Trace& Ppohdem10VoxelizerStages::trace() const { return state_->trace; }

Ppohdem10Trace ppohdem10_distance_trace(const TriangleMesh& placed_mesh, const VoxelizerInput& input,
                                        int nprocs) {
  Ppohdem10VoxelizerStages stages(placed_mesh, input, nprocs);
  stages.voxelize();
  stages.pass1();
  stages.exact_band();
  stages.pass2();
  return stages.trace();
}

std::vector<double> ppohdem10_distance(const TriangleMesh& placed_mesh, const VoxelizerInput& input, int nprocs) {
  return ppohdem10_distance_trace(placed_mesh, input, nprocs).distance;
}

}  // namespace ppohdem::compat
