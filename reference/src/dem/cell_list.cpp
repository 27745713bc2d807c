#include "ppohdem/reference/dem/cell_list.hpp"

#include <algorithm>
#include <cmath>

namespace ppohdem::reference::dem {
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

/// A dense grid of cubic cells of side `cell` [m] starting at `origin`, `dims` cells per
/// axis; positions outside are clamped into the border cells (see the header).
struct Grid {
  Vec3 origin = Vec3::Zero();
  double cell = 1.0;
  Index3 dims = {1, 1, 1};

  int axis_index(double x, int axis) const {
    const double c = std::floor((x - origin[axis]) / cell);
    return static_cast<int>(std::clamp(c, 0.0, static_cast<double>(dims[axis] - 1)));
  }
  Index3 index(const Vec3& x) const { return {axis_index(x.x(), 0), axis_index(x.y(), 1), axis_index(x.z(), 2)}; }
  std::size_t linear(const Index3& c) const {
    return static_cast<std::size_t>(c[0]) +
           static_cast<std::size_t>(dims[0]) * (static_cast<std::size_t>(c[1]) +
                                                static_cast<std::size_t>(dims[1]) * static_cast<std::size_t>(c[2]));
  }
  std::size_t size() const {
    return static_cast<std::size_t>(dims[0]) * static_cast<std::size_t>(dims[1]) * static_cast<std::size_t>(dims[2]);
  }
};

Grid grid_for(const ppohdem::dem::Particles& particles) {
  Grid g;
  double r_max = 0.0;
  for (const auto& p : particles) r_max = std::max(r_max, p.radius);
  g.cell = 2.0 * r_max;  // [m]
  const std::size_t n = particles.size();
  // Per axis: the 1st..99th percentile of the centres, plus one cell on each side.
  std::vector<double> x(n);
  Vec3 cells = Vec3::Ones();
  for (int axis = 0; axis < 3; ++axis) {
    for (std::size_t i = 0; i < n; ++i) x[i] = particles[i].position[axis];
    const auto lo = x.begin() + static_cast<std::ptrdiff_t>(n / 100);
    const auto hi = x.begin() + static_cast<std::ptrdiff_t>(n - 1 - n / 100);
    std::nth_element(x.begin(), lo, x.end());
    const double low = *lo;
    std::nth_element(x.begin(), hi, x.end());
    const double high = *hi;
    g.origin[axis] = low - g.cell;
    cells[axis] = std::ceil((high - low) / g.cell) + 2.0;
  }
  // At most ~8 N + 27 cells: a sparse bulk gets fewer, larger-in-effect border cells
  // (the clamp keeps the search correct, see the header).
  const double budget = 8.0 * static_cast<double>(n) + 27.0;
  const double total = cells.prod();
  if (total > budget) cells *= std::cbrt(budget / total);
  for (int axis = 0; axis < 3; ++axis) g.dims[axis] = static_cast<int>(std::max(1.0, std::floor(cells[axis])));
  return g;
}

}  // namespace

std::vector<std::pair<std::size_t, std::size_t>> touching_pairs(const ppohdem::dem::Particles& particles) {
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  if (particles.empty()) return pairs;
  const Grid grid = grid_for(particles);

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

}  // namespace ppohdem::reference::dem
