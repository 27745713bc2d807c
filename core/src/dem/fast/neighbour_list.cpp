// Verlet neighbour lists (cell search within R_i + R_j + skin), the mirror links between the
// two sides of a pair, and the boundaries near each particle.
#include <algorithm>
#include <limits>

#include "engine_impl.hpp"

namespace ppohdem::dem::fast {

void FastEngine::Impl::build_lists() {
  ++builds;
  out_valid = false;
  History& h = history;
  take_history(h);
  for_each_particle_array(s, [&](auto& a) { a.resize(s.owned); });  // drop the ghosts
  if (distributed()) {
    migrate(h);
    rebalance(h);
  }
  build_from(h);
  add_lost_energy();
}

void FastEngine::Impl::build_from(const History& h) {
  const CellOrder sorted = sort_owned_by_cell();
  make_ghosts();
  // With one rank there are no ghosts: the search's cells are the sort's (the same grid,
  // which depends only on the positions' values, and the particles now in its cell order).
  search_neighbours(distributed() ? nullptr : &sorted);
  install_history(h, sorted.order);
  mark_near_boundaries();
  mark_screen_gaps();
  s.split_stale = true;  // the kernel's ranges are cut afresh for the new order
}

void FastEngine::Impl::mark_screen_gaps() {
  drift_since_build = 0.0;
  const std::size_t n = s.owned;
  if (!skip_apart_slots || distributed() || s.spring_of.size() != s.partner.size() || s.upper_first.size() != n) {
    s.screen_gap.clear();  // (several ranks: a ghost's displacement is another rank's)
    return;
  }
  s.screen_gap.resize(n);
  PPOHDEM_OMP(omp parallel for schedule(static) if (n >= kParallelMin))
  for (std::size_t i = 0; i < n; ++i) {
    double gap = std::numeric_limits<double>::infinity();
    for (std::uint32_t slot = s.upper_first[i]; slot < s.first[i + 1]; ++slot) {
      if (s.spring_of[slot] != kNoSpring) {
        gap = -std::numeric_limits<double>::infinity();
        break;
      }
      const std::uint32_t j = s.partner[slot];
      gap = std::min(gap, (s.x[i] - s.x[j]).norm() - (s.radius[i] + s.radius[j]));
    }
    s.screen_gap[i] = gap;
  }
}

void FastEngine::Impl::mark_near_boundaries() {
  const std::size_t n = s.owned;
  const std::size_t nb = s.boundaries.size();
  std::uint32_t always = 0;  // boundaries evaluated for every particle
  for (std::size_t b = 0; b < std::min<std::size_t>(nb, 32); ++b) {
    if (!s.is_wall[b] || s.walls[b].velocity != Vec3::Zero()) always |= 1u << b;
  }
  s.near_boundaries.assign(n, always);
  PPOHDEM_OMP(omp parallel for schedule(static) if (n >= kParallelMin))
  for (std::size_t k = 0; k < n; ++k) {
    std::uint32_t near = always;
    for (std::size_t b = 0; b < std::min<std::size_t>(nb, 32); ++b) {
      if ((always >> b) & 1u) continue;
      const double distance = PlaneWall::signed_distance(s.walls[b].point0, s.walls[b].normal, s.x[k]);
      if (distance < s.radius[k] + skin) near |= 1u << b;
    }
    s.near_boundaries[k] = near;
  }
}

void FastEngine::Impl::search_neighbours(const CellOrder* sorted) {
  const std::size_t n = s.owned;
  const std::size_t all = s.size();
  std::vector<std::uint32_t> first(n + 1, 0);
  if (n == 0) {
    s.first.swap(first);
    s.partner.clear();
    s.mirror.clear();
    s.upper_first.clear();
    s.lower_ghost.clear();
    return;
  }
  std::vector<std::uint32_t> upper_first(n);
  // Members of each cell: members[start[c]] .. members[start[c + 1] - 1] are the particles in
  // cell c, and member_of[i] is owned particle i's index in members. Already in cell order
  // (`sorted`): members[k] = k. Else a counting sort of owned then ghosts.
  CellOrder made;
  std::vector<std::uint32_t> members(all);
  std::vector<std::uint32_t> member_of(n);
  if (sorted != nullptr) {
    std::iota(members.begin(), members.end(), 0u);
    std::iota(member_of.begin(), member_of.end(), 0u);
  } else {
    made.grid = grid_for(s.x, 2.0 * r_max + skin);
    std::vector<std::uint32_t> cell(all);
    made.start.assign(made.grid.size() + 1, 0);
    for (std::size_t i = 0; i < all; ++i) {
      cell[i] = static_cast<std::uint32_t>(made.grid.linear(made.grid.index(s.x[i])));
      ++made.start[cell[i] + 1];
    }
    for (std::size_t c = 0; c < made.grid.size(); ++c) made.start[c + 1] += made.start[c];
    std::vector<std::uint32_t> fill(made.start.begin(), made.start.end() - 1);
    for (std::size_t i = 0; i < all; ++i) {
      const std::uint32_t m = fill[cell[i]]++;
      members[m] = static_cast<std::uint32_t>(i);
      if (i < n) member_of[i] = m;
    }
  }
  const Grid& grid = sorted != nullptr ? sorted->grid : made.grid;
  const std::vector<std::uint32_t>& start = sorted != nullptr ? sorted->start : made.start;
  // The centres and radii in member order (one column each): a row of three cells along the
  // grid's fastest axis is one contiguous run of members, read in one sweep.
  search_probes.resize(all);
  PPOHDEM_OMP(omp parallel for schedule(static) if (all >= kParallelMin))
  for (std::size_t m = 0; m < all; ++m) {
    const std::uint32_t j = members[m];
    search_probes.x[m] = s.x[j].x();
    search_probes.y[m] = s.x[j].y();
    search_probes.z[m] = s.x[j].z();
    search_probes.r[m] = s.radius[j];
  }
  const bool x4 = x4_contacts_available();
  // The partners j != i with |x_i - x_j| < R_i + R_j + skin, as (id, storage index) into
  // `near` (unsorted): the 3 x 3 rows of three cells around i's cell along the grid's fastest
  // axis (contiguous in the cell order), tested by near_members (four at a time with AVX);
  // `candidates` has room for every member and the 3 more that near_members may write.
  // Named one by one, not a structured binding: Clang 14 cannot capture those in the lambda.
  const std::size_t along = grid.order[0], across1 = grid.order[1], across2 = grid.order[2];
  auto visit = [&](std::size_t i, std::vector<std::uint32_t>& candidates, std::vector<std::pair<std::int64_t, std::uint32_t>>& near) {
    const Vec3 xi = s.x[i];
    const Index3 c = grid.index(xi);
    Index3 corner = c;
    corner[along] = std::max(c[along] - 1, 0);
    const int row_end = std::min(c[along] + 1, grid.dims[along] - 1) + 1;
    const auto row_cells = static_cast<std::size_t>(row_end - corner[along]);
    MemberRun rows[9];
    std::size_t row_count = 0;
    for (int d2 = -1; d2 <= 1; ++d2) {
      corner[across2] = c[across2] + d2;
      if (corner[across2] < 0 || corner[across2] >= grid.dims[across2]) continue;
      for (int d1 = -1; d1 <= 1; ++d1) {
        corner[across1] = c[across1] + d1;
        if (corner[across1] < 0 || corner[across1] >= grid.dims[across1]) continue;
        const std::size_t row = grid.linear(corner);
        rows[row_count++] = {start[row], start[row + row_cells]};
      }
    }
    const NearQuery q{xi.x(), xi.y(), xi.z(), s.radius[i], skin, member_of[i]};
    const std::size_t count = x4 ? near_members_x4(search_probes, rows, row_count, q, candidates.data())
                                 : near_members(search_probes, rows, row_count, q, candidates.data());
    for (std::size_t k = 0; k < count; ++k) near.emplace_back(s.id[members[candidates[k]]], members[candidates[k]]);
  };
  // One pass: each of `blocks` contiguous blocks of particles lists its partners (each
  // particle's sorted by id) into its own buffer, and the buffers are joined in block order
  // (the list of a count pass and a fill pass, with half the distance tests;
  // docs/performance.md).
  const int blocks = n >= kParallelMin ? max_threads() : 1;
  search_buffers.resize(static_cast<std::size_t>(std::max(blocks, 1)));
  PPOHDEM_OMP(omp parallel for schedule(static, 1) num_threads(blocks))
  for (int b = 0; b < blocks; ++b) {
    const std::size_t lo = n * static_cast<std::size_t>(b) / static_cast<std::size_t>(blocks);
    const std::size_t hi = n * static_cast<std::size_t>(b + 1) / static_cast<std::size_t>(blocks);
    // The block's list in a vector object of this thread's own (its storage the reused
    // buffer's): the vector objects of search_buffers share a cache line, and every push_back
    // writes the vector's end, so appending through them bounced that line between the
    // threads (docs/performance.md "Cheaper list builds, second pass").
    std::vector<std::uint32_t> found;
    found.swap(search_buffers[static_cast<std::size_t>(b)]);
    found.clear();
    std::vector<std::pair<std::int64_t, std::uint32_t>> near;
    std::vector<std::uint32_t> candidates(all + ProbeColumns::kPadding);
    for (std::size_t i = lo; i < hi; ++i) {
      near.clear();
      visit(i, candidates, near);
      std::sort(near.begin(), near.end());  // by id (ids are unique)
      const std::int64_t id_i = s.id[i];
      std::uint32_t lower = 0;  // partners with a lower id: they come first
      for (const auto& [id, j] : near) {
        found.push_back(j);
        lower += static_cast<std::uint32_t>(id < id_i);
      }
      first[i + 1] = static_cast<std::uint32_t>(near.size());
      upper_first[i] = lower;  // made a slot index below
    }
    found.swap(search_buffers[static_cast<std::size_t>(b)]);
  }
  for (std::size_t i = 0; i < n; ++i) {
    first[i + 1] += first[i];
    upper_first[i] += first[i];
  }
  std::vector<std::uint32_t> partner(first[n]);
  for (int b = 0; b < blocks; ++b) {
    const std::size_t lo = n * static_cast<std::size_t>(b) / static_cast<std::size_t>(blocks);
    const std::vector<std::uint32_t>& found = search_buffers[static_cast<std::size_t>(b)];
    std::copy(found.begin(), found.end(), partner.begin() + first[lo]);
  }
  s.first.swap(first);
  s.partner.swap(partner);
  s.upper_first.swap(upper_first);
  s.lower_ghost.assign(n, 0);
  std::size_t misplaced = 0;  // interior particles with a ghost partner (put_halo_layer_last)
  PPOHDEM_OMP(omp parallel for schedule(static) reduction(+ : misplaced) if (n >= kParallelMin))
  for (std::size_t i = 0; i < n; ++i) {
    for (std::uint32_t slot = s.first[i]; slot < s.upper_first[i]; ++slot) {
      if (s.partner[slot] >= n) s.lower_ghost[i] = 1;
    }
    if (i < s.n_interior) {
      for (std::uint32_t slot = s.first[i]; slot < s.first[i + 1]; ++slot) misplaced += s.partner[slot] >= n;
    }
  }
  // The overlapped halo refresh evaluates the interior before the ghosts are refreshed.
  if (misplaced != 0) throw std::logic_error("fast engine: an interior particle has a ghost partner");
  link_mirrors();
}

void FastEngine::Impl::link_mirrors() {
  const std::size_t n = s.owned;
  if (!s.friction) {
    s.mirror.clear();
    return;
  }
  s.mirror.assign(s.partner.size(), kNoMirror);
  s.lower_codes_valid = false;
  std::size_t lower_slots = 0, linked = 0, unmatched = 0;
  PPOHDEM_OMP(omp parallel for schedule(static) reduction(+ : lower_slots, linked, unmatched) if (n >= kParallelMin))
  for (std::size_t i = 0; i < n; ++i) {
    for (std::uint32_t slot = s.first[i]; slot < s.upper_first[i]; ++slot) lower_slots += s.partner[slot] < n;
    for (std::uint32_t slot = s.upper_first[i]; slot < s.first[i + 1]; ++slot) {
      const std::uint32_t j = s.partner[slot];
      if (j >= n) continue;
      // i's slot among j's lower-id partners (each slot is written by one pair only).
      const auto begin = s.partner.begin() + s.first[j];
      const auto end = s.partner.begin() + s.upper_first[j];
      const auto it = std::lower_bound(begin, end, s.id[i], [&](std::uint32_t k, std::int64_t id) { return s.id[k] < id; });
      if (it == end || *it != i) {
        ++unmatched;
        continue;
      }
      const auto other = static_cast<std::uint32_t>(it - s.partner.begin());
      s.mirror[slot] = other;
      s.mirror[other] = slot;
      ++linked;
    }
  }
  if (unmatched != 0 || linked != lower_slots) throw std::logic_error("fast engine: neighbour lists are not symmetric");
}

}  // namespace ppohdem::dem::fast
