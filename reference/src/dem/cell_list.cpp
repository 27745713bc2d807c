#include "ppohdem/reference/dem/cell_list.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace ppohdem::reference::dem {
namespace {

struct CellHash {
  std::size_t operator()(const Index3& c) const {
    return static_cast<std::size_t>(c[0]) * 73856093u ^ static_cast<std::size_t>(c[1]) * 19349663u ^
           static_cast<std::size_t>(c[2]) * 83492791u;
  }
};

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

}  // namespace

std::vector<std::pair<std::size_t, std::size_t>> touching_pairs(const ppohdem::dem::Particles& particles) {
  double r_max = 0.0;
  for (const auto& p : particles) r_max = std::max(r_max, p.radius);
  const double cell = 2.0 * r_max;  // [m]
  auto cell_of = [cell](const Vec3& x) {
    return Index3{static_cast<int>(std::floor(x.x() / cell)), static_cast<int>(std::floor(x.y() / cell)),
                  static_cast<int>(std::floor(x.z() / cell))};
  };
  std::unordered_map<Index3, std::vector<std::size_t>, CellHash> cells;
  for (std::size_t i = 0; i < particles.size(); ++i) cells[cell_of(particles[i].position)].push_back(i);

  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const Index3 c = cell_of(particles[i].position);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = cells.find(Index3{c[0] + dx, c[1] + dy, c[2] + dz});
          if (it == cells.end()) continue;
          for (std::size_t j : it->second) {
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
