// The original's eikonal passes with its MPI slab decomposition, simulated rank by rank in one
// process: ppohDEM_v_distancecalculate_MPI (Jacobi sweeps, ghost-plane exchange, boundary
// extrapolation), transcribed expression by expression.
#include "ppohdem10_ranks.hpp"

#include <cmath>

#include "ppohdem/compat/ppohdem10_steps.hpp"

namespace ppohdem::compat {

namespace {
// float_min of the original: a if a < b, else b.
double float_min(double a, double b) { return a < b ? a : b; }
}  // namespace

double ppohdem10_eikonal_update(double c, double xp, double xm, double yp, double ym, double zp, double zm,
                                double w, double w2) {
  double dx = float_min(xp, xm);
  double dy = float_min(yp, ym);
  double dz = float_min(zp, zm);
  dx = float_min(dx, c);
  dy = float_min(dy, c);
  dz = float_min(dz, c);
  const int on_x = dx == c ? 1 : 0;
  const int on_y = dy == c ? 1 : 0;
  const int on_z = dz == c ? 1 : 0;
  const int fixed_axes = on_x + on_y + on_z;
  if (fixed_axes == 3) return c;
  if (fixed_axes == 2) {
    if (on_x == 0) return w + dx;
    if (on_y == 0) return w + dy;
    return w + dz;
  }
  if (fixed_axes == 1) {
    double a = 0.0;
    double b = 0.0;
    if (on_x == 1) {
      a = dy;
      b = dz;
    } else if (on_y == 1) {
      a = dz;
      b = dx;
    } else {
      a = dx;
      b = dy;
    }
    const double delta2 = 2 * w2 - (a - b) * (a - b);
    return delta2 >= 0 ? ((a + b) + std::sqrt(delta2)) / 2.0 : c;
  }
  const double delta3 = 3 * w2 - 2 * (dx * dx + dy * dy + dz * dz - dx * dy - dy * dz - dz * dx);
  return delta3 >= 0 ? (dx + dy + dz + std::sqrt(delta3)) / 3.0 : c;
}

RankSlab::RankSlab(int rank_, int nprocs_, int first_, int last_, const Index3& nodes, double fill)
    : rank(rank_), nprocs(nprocs_), first(first_), last(last_), ny(nodes[1]), nz(nodes[2]), nx(nodes[0]) {
  stride_j_ = static_cast<std::size_t>(last - first + 3);
  stride_k_ = stride_j_ * static_cast<std::size_t>(ny);
  planes_.assign(stride_k_ * static_cast<std::size_t>(nz), fill);
  // The loop range of the sweeps: rank 0 starts at i = 2; otherwise the last rank stops at
  // gridX - 1. With one rank the first branch wins, so the sweeps run over i = 2..gridX and
  // i = gridX reads the never-written ghost plane gridX + 1 (the sentinel).
  if (rank == 0) {
    sweep_first = 2;
    sweep_last = last;
  } else if (rank == nprocs - 1) {
    sweep_first = first;
    sweep_last = last - 1;
  } else {
    sweep_first = first;
    sweep_last = last;
  }
}

void exchange_ghost_planes(std::vector<RankSlab>& ranks) {
  // Each sweep starts with: every rank but 0 sends its first plane down, every rank but the
  // last receives it as ghost plane last + 1; then the same upwards into ghost plane first - 1.
  // Both sends read own planes only, so the order of the ranks does not matter.
  for (std::size_t r = 0; r < ranks.size(); ++r) {
    RankSlab& me = ranks[r];
    for (int k = 1; k <= me.nz; ++k) {
      for (int j = 1; j <= me.ny; ++j) {
        if (r + 1 < ranks.size()) me.at(me.last + 1, j, k) = ranks[r + 1].at(me.last + 1, j, k);
        if (r > 0) me.at(me.first - 1, j, k) = ranks[r - 1].at(me.first - 1, j, k);
      }
    }
  }
}

namespace {

// One Jacobi sweep on one rank: new values from the old ones (ghost planes included), then
// copied back, voxel-inside nodes reset to 0. Nodes with calculated = 1 are never touched.
void sweep(RankSlab& s, const Ppohdem10Grid& g, const NodeFlags& value, const NodeFlags& calculated) {
  const int ny = g.n[1];
  const int nz = g.n[2];
  std::vector<double> next(s.planes_size(), 0.0);
  for (int k = 2; k <= nz - 1; ++k) {
    for (int j = 2; j <= ny - 1; ++j) {
      for (int i = s.sweep_first; i <= s.sweep_last; ++i) {
        if (calculated(i, j, k)) continue;
        next[s.offset(i, j, k)] =
            ppohdem10_eikonal_update(s.at(i, j, k), s.at(i + 1, j, k), s.at(i - 1, j, k), s.at(i, j + 1, k),
                                     s.at(i, j - 1, k), s.at(i, j, k + 1), s.at(i, j, k - 1), g.w, g.w2);
      }
    }
  }
  for (int k = 2; k <= nz - 1; ++k) {
    for (int j = 2; j <= ny - 1; ++j) {
      for (int i = s.sweep_first; i <= s.sweep_last; ++i) {
        if (calculated(i, j, k)) continue;
        s.at(i, j, k) = next[s.offset(i, j, k)];
        if (value(i, j, k)) s.at(i, j, k) = 0.0;
      }
    }
  }
}

// "fill the edge": faces, edges and corners of the domain, in the original's order. Every
// assignment is guarded by calculated = 0. The j = gridY face is addressed with j = gridX, as in
// the original (the caller requires gridX <= gridY).
void extrapolate_boundary(RankSlab& s, const Ppohdem10Grid& g, const NodeFlags& calculated) {
  const int nx = g.n[0];
  const int ny = g.n[1];
  const int nz = g.n[2];
  const double w = g.w;
  const bool first_rank = s.rank == 0;
  const bool last_rank = s.rank == s.nprocs - 1;
  auto set = [&](int i, int j, int k, double v) {
    if (!calculated(i, j, k)) s.at(i, j, k) = v;
  };
  const int lo = s.sweep_first;
  const int hi = s.sweep_last;

  // Faces: neighbour + W (the j faces take the diagonal neighbour (i+1, j+-1), whose i+1 is the
  // stale ghost plane at i = hi on every rank but the last).
  for (int j = 2; j <= ny - 1; ++j)
    for (int i = lo; i <= hi; ++i) set(i, j, 1, s.at(i, j, 2) + w);
  for (int j = 1; j <= ny - 1; ++j)
    for (int i = lo; i <= hi; ++i) set(i, j, nz, s.at(i, j, nz - 1) + w);
  if (first_rank)
    for (int k = 2; k <= nz - 1; ++k)
      for (int j = 2; j <= ny - 1; ++j) set(1, j, k, s.at(2, j, k) + w);
  if (last_rank)
    for (int k = 2; k <= nz - 1; ++k)
      for (int j = 2; j <= ny - 1; ++j) set(nx, j, k, s.at(nx - 1, j, k) + w);
  for (int i = lo; i <= hi; ++i)
    for (int k = 2; k <= nz - 1; ++k) set(i, 1, k, s.at(i + 1, 2, k) + w);
  for (int i = lo; i <= hi; ++i)
    for (int k = 2; k <= nz - 1; ++k) set(i, nx, k, s.at(i + 1, nx - 1, k) + w);

  // Edges: diagonal neighbour + 2W.
  for (int i = lo; i <= hi; ++i) set(i, 1, 1, s.at(i, 2, 2) + 2 * w);
  for (int i = lo; i <= hi; ++i) set(i, ny, 1, s.at(i, ny - 1, 2) + 2 * w);
  for (int i = lo; i <= hi; ++i) set(i, ny, nz, s.at(i, ny - 1, nz - 1) + 2 * w);
  for (int i = lo; i <= hi; ++i) set(i, 1, nz, s.at(i, 2, nz - 1) + 2 * w);
  if (first_rank) {
    for (int j = 2; j <= ny; ++j) set(1, j, 1, s.at(2, j, 2) + 2 * w);
    for (int j = 2; j <= ny; ++j) set(1, j, nz, s.at(2, j, nz - 1) + 2 * w);
  }
  if (last_rank) {
    for (int j = 2; j <= ny; ++j) set(nx, j, nz, s.at(nx - 1, j, nz - 1) + 2 * w);
    for (int j = 2; j <= ny; ++j) set(nx, j, 1, s.at(nx - 1, j, 2) + 2 * w);
  }
  if (first_rank) {
    for (int k = 2; k <= nz; ++k) set(1, 1, k, s.at(2, 2, k) + 2 * w);
    for (int k = 2; k <= nz; ++k) set(1, ny, k, s.at(2, ny - 1, k) + 2 * w);
  }
  if (last_rank) {
    for (int k = 2; k <= nz; ++k) set(nx, 1, k, s.at(nx - 1, 2, k) + 2 * w);
    for (int k = 2; k <= nz; ++k) set(nx, ny, k, s.at(nx - 1, ny - 1, k) + 2 * w);
  }

  // Corners: body-diagonal neighbour + 3W.
  if (first_rank) {
    set(1, 1, 1, s.at(2, 2, 2) + 3 * w);
    set(1, ny, 1, s.at(2, ny - 1, 2) + 3 * w);
    set(1, 1, nz, s.at(2, 2, nz - 1) + 3 * w);
    set(1, ny, nz, s.at(2, ny - 1, nz - 1) + 3 * w);
  }
  if (last_rank) {
    set(nx, 1, 1, s.at(nx - 1, 2, 2) + 3 * w);
    set(nx, 1, nz, s.at(nx - 1, 2, nz - 1) + 3 * w);
    set(nx, ny, 1, s.at(nx - 1, ny - 1, 2) + 3 * w);
    set(nx, ny, nz, s.at(nx - 1, ny - 1, nz - 1) + 3 * w);
  }
}

}  // namespace

void jacobi_pass(std::vector<RankSlab>& ranks, const Ppohdem10Grid& g, const NodeFlags& value,
                 const NodeFlags& calculated) {
  const double sentinel = g.lx * 10;
  // Start: every node not yet calculated holds the sentinel, voxel-inside nodes 0.
  for (RankSlab& s : ranks) {
    for (int k = 1; k <= g.n[2]; ++k)
      for (int j = 1; j <= g.n[1]; ++j)
        for (int i = s.first; i <= s.last; ++i) {
          if (calculated(i, j, k)) continue;
          s.at(i, j, k) = sentinel;
          if (value(i, j, k)) s.at(i, j, k) = 0.0;
        }
  }
  // gridZ sweeps (the declared HPARAMS_ITERATE = 200 is not used).
  for (int iterate = 1; iterate <= g.n[2]; ++iterate) {
    exchange_ghost_planes(ranks);
    for (RankSlab& s : ranks) sweep(s, g, value, calculated);
  }
  for (RankSlab& s : ranks) extrapolate_boundary(s, g, calculated);
}

}  // namespace ppohdem::compat
