// Contact detection by a cell list (Allen & Tildesley 1987, sec. 5.3.2): space is cut into
// cubic cells of edge h >= 2 R_max [m], so two touching spheres (|x_i - x_j| < R_i + R_j <=
// 2 R_max) lie in the same or in neighbouring cells; each particle is tested against the 27
// cells around its own, O(N) per step instead of the O(N^2) of all pairs. The pairs are then
// sorted by (id_i, id_j) so that nothing depends on the storage order of the particles.
#include "ppohdem/dem/reference/cell_list.hpp"

#include <algorithm>
#include <cmath>

#include "ppohdem/dem/cell_grid.hpp"

namespace ppohdem::dem::reference {
namespace {

bool touching(const ppohdem::dem::Particle& a, const ppohdem::dem::Particle& b) {
  const double reach = a.radius + b.radius;
  return (a.position - b.position).squaredNorm() < reach * reach;
}

// Order each pair by id and the list by (id_a, id_b).
void sort_by_id(const ppohdem::dem::Particles& particles,
                std::vector<std::pair<std::size_t, std::size_t>>& pairs) {
  for (auto& [a, b] : pairs) {
    if (particles[a].id > particles[b].id) std::swap(a, b);
  }
  std::sort(pairs.begin(), pairs.end(), [&](const auto& p, const auto& q) {
    return std::pair(particles[p.first].id, particles[p.second].id) <
           std::pair(particles[q.first].id, particles[q.second].id);
  });
}

/// Cells of side 2 R_max [m] over the centres (ppohdem/dem/cell_grid.hpp): two touching
/// spheres are then in the same or in adjacent cells.
ppohdem::dem::CellGrid grid_for(const ppohdem::dem::Particles& particles) {
  double r_max = 0.0;
  std::vector<Vec3> centres;
  centres.reserve(particles.size());
  for (const auto& p : particles) {
    r_max = std::max(r_max, p.radius);
    centres.push_back(p.position);
  }
  return ppohdem::dem::cell_grid_for(centres, 2.0 * r_max);
}

}  // namespace

std::vector<std::pair<std::size_t, std::size_t>> touching_pairs(const ppohdem::dem::Particles& particles) {
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  if (particles.empty()) return pairs;
  const ppohdem::dem::CellGrid grid = grid_for(particles);

  // Counting sort of the particles by cell: the particles of cell c are
  // sorted[start[c] .. start[c+1]).
  std::vector<std::size_t> cell_of(particles.size());
  std::vector<std::size_t> start(grid.size() + 1, 0);
  for (std::size_t i = 0; i < particles.size(); ++i) {
    cell_of[i] = grid.linear(grid.index(particles[i].position));
    ++start[cell_of[i] + 1];
  }
  for (std::size_t c = 0; c < grid.size(); ++c) start[c + 1] += start[c];
  std::vector<std::size_t> sorted(particles.size());
  std::vector<std::size_t> fill(start.begin(), start.end() - 1);
  for (std::size_t i = 0; i < particles.size(); ++i) sorted[fill[cell_of[i]]++] = i;

  for (std::size_t i = 0; i < particles.size(); ++i) {
    const Index3 c = grid.index(particles[i].position);
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const Index3 nb = {c[0] + dx, c[1] + dy, c[2] + dz};
          if (nb[0] < 0 || nb[1] < 0 || nb[2] < 0 || nb[0] >= grid.dims[0] ||
              nb[1] >= grid.dims[1] || nb[2] >= grid.dims[2]) {
            continue;
          }
          const std::size_t cell = grid.linear(nb);
          for (std::size_t s = start[cell]; s < start[cell + 1]; ++s) {
            const std::size_t j = sorted[s];
            if (j > i && touching(particles[i], particles[j])) pairs.emplace_back(i, j);
          }
        }
  }
  sort_by_id(particles, pairs);
  return pairs;
}

std::vector<std::pair<std::size_t, std::size_t>> touching_pairs_brute_force(
    const ppohdem::dem::Particles& particles) {
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (std::size_t i = 0; i < particles.size(); ++i)
    for (std::size_t j = i + 1; j < particles.size(); ++j)
      if (touching(particles[i], particles[j])) pairs.emplace_back(i, j);
  sort_by_id(particles, pairs);
  return pairs;
}

}  // namespace ppohdem::dem::reference
