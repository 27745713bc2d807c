// The original DEM's cell list and its re-sort (ppohDEM_prepare_cells, make_search_cell,
// ppohDEM_check_update, ppohDEM_update_index, ppohDEM_iqsort2); see ppohdem10_dem.hpp.
#include <cmath>
#include <string>

#include "ppohdem/error.hpp"
#include "ppohdem/compat/ppohdem10_dem.hpp"

namespace ppohdem::compat {

Ppohdem10Cells ppohdem10_make_cells(const Vec3& box_length) {
  using C = Ppohdem10DemConstants;
  Ppohdem10Cells cells;
  // cellsize = L / Cn (a double divided by an integer) [m].
  cells.cellsize = {box_length.x() / C::kCellsPerAxis, box_length.y() / C::kCellsPerAxis,
                    box_length.z() / C::kCellsPerAxis};
  cells.cellnum = {C::kCellsPerAxis, C::kCellsPerAxis, C::kCellsPerAxis};
  const int nx = cells.cellnum[0];
  const int ny = cells.cellnum[1];
  const int nz = cells.cellnum[2];
  const auto total = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny) * static_cast<std::size_t>(nz);
  cells.start_partindex.assign(total, 0);
  cells.end_partindex.assign(total, -1);
  cells.nei_cellindex.assign(27 * total, 0);
  // make_search_cell: the 27 cells around each cell, kk outer, ii inner.
  // Q2: "if (mi <= 0) mi = mi + cellnum": the neighbours wrap around the box periodically,
  // although the box has walls. The wrapped cells are 11 m away, so no contact comes of it.
  for (int k = 1; k <= nz; ++k) {
    for (int j = 1; j <= ny; ++j) {
      for (int i = 1; i <= nx; ++i) {
        const int ijk = nx * ny * (k - 1) + nx * (j - 1) + i;
        int cn = 1;
        for (int kk = -1; kk <= 1; ++kk) {
          for (int jj = -1; jj <= 1; ++jj) {
            for (int ii = -1; ii <= 1; ++ii) {
              int mi = i + ii;
              int mj = j + jj;
              int mk = k + kk;
              if (mi <= 0) mi += nx;
              if (mi > nx) mi -= nx;
              if (mj <= 0) mj += ny;
              if (mj > ny) mj -= ny;
              if (mk <= 0) mk += nz;
              if (mk > nz) mk -= nz;
              const int pijk = nx * ny * (mk - 1) + nx * (mj - 1) + mi;
              cells.nei_cellindex[static_cast<std::size_t>(27 * (ijk - 1) + cn - 1)] = pijk;
              ++cn;
            }
          }
        }
      }
    }
  }
  return cells;
}

void ppohdem10_iqsort2(std::vector<int>& keys, std::vector<int>& values, int first, int last) {
  // Fortran's 1-based array: element i is keys[i - 1]. The pivot is the middle element
  // (first + last) / 2 of the 1-based range.
  auto key = [&keys](int i) -> int& { return keys[static_cast<std::size_t>(i - 1)]; };
  auto value = [&values](int i) -> int& { return values[static_cast<std::size_t>(i - 1)]; };
  const int pivot = key((first + last) / 2);
  int i = first;
  int j = last;
  for (;;) {
    while (key(i) < pivot) ++i;
    while (pivot < key(j)) --j;
    if (i >= j) break;
    std::swap(key(i), key(j));  // equal keys are swapped too: the sort is unstable
    std::swap(value(i), value(j));
    ++i;
    --j;
  }
  if (first < i - 1) ppohdem10_iqsort2(keys, values, first, i - 1);
  if (j + 1 < last) ppohdem10_iqsort2(keys, values, j + 1, last);
}

namespace {

/// floor(q) as an int (Fortran FLOOR); a non-finite or huge q (a run that blew up) is refused
/// rather than converted (undefined in C++ and in the original).
int floor_to_int(double q, long itime) {
  const double f = std::floor(q);
  if (!(std::abs(f) < 1e8)) {
    throw InputError("--compat ppohdem-1.0: step " + std::to_string(itime) + ": a particle position is not finite or "
                     "far outside the box");
  }
  return static_cast<int>(f);
}

/// ppohDEM_calc_cellindex: cell number (1-based) = nx ny cz + nx cy + cx + 1, c = floor(x / cellsize).
void calc_cellindex(Ppohdem10Particles& p, const Ppohdem10Cells& cells, long itime) {
  const int nx = cells.cellnum[0];
  const int ny = cells.cellnum[1];
  const int nz = cells.cellnum[2];
  for (std::size_t i = 0; i < p.size(); ++i) {
    const int cx = floor_to_int(p.pos[i].x / cells.cellsize.x, itime);
    const int cy = floor_to_int(p.pos[i].y / cells.cellsize.y, itime);
    const int cz = floor_to_int(p.pos[i].z / cells.cellsize.z, itime);
    const int index = nx * ny * cz + nx * cy + cx + 1;
    // A particle whose centre has left the box (x, y or z < 0 or > L, possible when a fast
    // particle meets a wall: the spring lets it through by up to v sqrt(m/Kn)) gets a cell
    // number of some other cell (e.g. cy = -1 lands in the row below). The original prints a
    // warning for a coordinate <= 0 and goes on with that number; so does this module, counting
    // the occurrences. Only a number outside the cell arrays (undefined in the original) is refused.
    if (cx < 0 || cy < 0 || cz < 0 || cx >= nx || cy >= ny || cz >= nz) ++p.outside_box_count;
    if (index < 1 || index > nx * ny * nz) {
      throw InputError("--compat ppohdem-1.0: step " + std::to_string(itime) + ": particle id " +
                       std::to_string(p.id[i]) + " at (" + std::to_string(p.pos[i].x) + ", " + std::to_string(p.pos[i].y) +
                       ", " + std::to_string(p.pos[i].z) +
                       ") has a cell number outside the cell arrays (the original's behaviour is undefined)");
    }
    p.cellindex[i] = index;
  }
}

/// ppohDEM_rearrange_index: particle i of the new order is particle newtoorig(i) of the old.
void rearrange_index(Ppohdem10Particles& p, const Ppohdem10Particles& old, const std::vector<int>& newtoorig) {
  std::vector<int> origtonew(newtoorig.size());  // the inverse, for the trace count below
  for (std::size_t i = 0; i < newtoorig.size(); ++i) {
    origtonew[static_cast<std::size_t>(newtoorig[i] - 1)] = static_cast<int>(i + 1);
  }
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto o = static_cast<std::size_t>(newtoorig[i] - 1);
    p.pos[i] = old.pos[o];
    p.vel[i] = old.vel[o];
    p.omega[i] = old.omega[o];
    p.radius[i] = old.radius[o];
    p.id[i] = old.id[o];  // the patched original's identity column, permuted the same way
    // Q3: the cell index is NOT copied back (the sort ran on a temporary copy of it), so
    // p.cellindex keeps the values computed in the PRE-sort order. The cell table below and
    // each particle's own cell in calcforce are read from that stale array.
    p.contact_list[i] = old.contact_list[o];
    // Q4: the partner's old index is mapped through newtoorig (new -> old) instead of its
    // inverse (old -> new): `pid(k) = newtoorig(pid(k))`. Unless the permutation is its own
    // inverse, the stored tangential spring is attached to another particle's index, so at
    // the next step the history lookup usually fails (a fresh spring) or, rarely, picks up
    // another pair's spring.
    for (Ppohdem10Contact& c : p.contact_list[i]) {
      const auto old_pid = static_cast<std::size_t>(c.pid - 1);
      c.pid = newtoorig[old_pid];
      if (c.pid != origtonew[old_pid]) ++p.misattributed_histories;  // trace only
    }
    p.contact_list_wall[i] = old.contact_list_wall[o];  // wall numbers need no mapping
  }
}

/// ppohDEM_clear_cellstartend + ppohDEM_calc_cellstartend, over the (stale, Q3) cell indices:
/// the last run of equal consecutive indices of a cell defines its range.
void calc_cellstartend(const Ppohdem10Particles& p, Ppohdem10Cells& cells) {
  std::fill(cells.start_partindex.begin(), cells.start_partindex.end(), 0);
  std::fill(cells.end_partindex.begin(), cells.end_partindex.end(), -1);
  auto cell = [&p](std::size_t i1) { return static_cast<std::size_t>(p.cellindex[i1 - 1] - 1); };
  const std::size_t n = p.size();
  cells.start_partindex[cell(1)] = 1;
  for (std::size_t i = 2; i <= n; ++i) {
    if (p.cellindex[i - 1] != p.cellindex[i - 2]) {
      cells.start_partindex[cell(i)] = static_cast<int>(i);
      cells.end_partindex[cell(i - 1)] = static_cast<int>(i - 1);
    }
  }
  cells.end_partindex[cell(n)] = static_cast<int>(n);
}

}  // namespace

void ppohdem10_update_index(Ppohdem10Particles& particles, Ppohdem10Cells& cells, long itime) {
  calc_cellindex(particles, cells, itime);
  // ppohDEM_sort_particles: copy to a temporary, sort the temporary's cell indices together
  // with the permutation newtoorig = 1..n, rearrange from the temporary.
  const Ppohdem10Particles old = particles;
  std::vector<int> sorted_cellindex = old.cellindex;
  std::vector<int> newtoorig(particles.size());
  for (std::size_t i = 0; i < newtoorig.size(); ++i) newtoorig[i] = static_cast<int>(i + 1);
  ppohdem10_iqsort2(sorted_cellindex, newtoorig, 1, static_cast<int>(particles.size()));
  rearrange_index(particles, old, newtoorig);
  calc_cellstartend(particles, cells);
}

bool ppohdem10_check_update(Ppohdem10Particles& particles, Ppohdem10Cells& cells, Ppohdem10Counter& counter,
                            const Ppohdem10Parameters& params) {
  // ppohDEM_accumulate_pos. Q1: README "the code adds max |v| per step without multiplying by
  // dt": pos_accum is a sum of speeds [m/s] compared with a length [m]. With dt = 0.002 the
  // particles have moved 500 times less than the test assumes, so the re-sort runs far more
  // often than needed (harmless for the result, costly in time).
  double max_vel = 0.0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const double vel = length_rvec3(particles.vel[i]);
    if (max_vel < vel) max_vel = vel;
  }
  counter.pos_accum = counter.pos_accum + max_vel;
  // 0.5 (cellsize_x - 2 MaxRadius): the margin a particle may move before it can meet a
  // particle outside the 27 cells.
  if (counter.pos_accum > 0.5 * (cells.cellsize.x - 2 * params.max_radius)) {
    ppohdem10_update_index(particles, cells, counter.itime);
    counter.pos_accum = 0.0;
    return true;
  }
  return false;
}

}  // namespace ppohdem::compat
