// overlapping_pairs (simulation_setup.hpp): the initial-overlap check of every scene and the
// run check of engines that do not track their deepest contact. Cells of side 2 R_max hold
// every pair that can overlap in the 27 cells around a particle, so the search is O(N) (a
// sort-and-sweep along x is O(N^(5/3)) on a cubic bed: minutes at 10^6 particles;
// docs/performance.md "Reading and writing particles").
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <unordered_map>
#include <vector>

#include "ppohdem/dem/simulation_setup.hpp"

namespace ppohdem::dem {
namespace {

using Cell = std::array<std::int64_t, 3>;

struct CellHash {
  std::size_t operator()(const Cell& c) const {
    // splitmix-style mixing of the three indices
    std::uint64_t h = static_cast<std::uint64_t>(c[0]) * 0x9E3779B97F4A7C15ull;
    h ^= static_cast<std::uint64_t>(c[1]) + 0x7F4A7C159E3779B9ull + (h << 6) + (h >> 2);
    h ^= static_cast<std::uint64_t>(c[2]) + 0x94D049BB133111EBull + (h << 6) + (h >> 2);
    return static_cast<std::size_t>(h ^ (h >> 31));
  }
};

// The pair (i, j) overlaps by more than `fraction` of the smaller radius.
bool overlaps(const Particle& a, const Particle& b, double fraction) {
  const double overlap = a.radius + b.radius - (a.position - b.position).norm();
  return overlap > fraction * std::min(a.radius, b.radius);
}

// Sort and sweep along x: for coordinates the cells cannot index (not finite, or more than
// 2^26 cells across) and for a negative fraction.
std::vector<std::pair<std::size_t, std::size_t>> sweep(const Particles& particles, double fraction, double r_max) {
  std::vector<std::size_t> order(particles.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return particles[a].position.x() < particles[b].position.x();
  });
  std::vector<std::pair<std::size_t, std::size_t>> found;
  for (std::size_t a = 0; a < order.size(); ++a) {
    const Particle& pi = particles[order[a]];
    for (std::size_t b = a + 1; b < order.size(); ++b) {
      const Particle& pj = particles[order[b]];
      if (pj.position.x() - pi.position.x() > pi.radius + r_max) break;
      if (overlaps(pi, pj, fraction)) found.emplace_back(std::min(order[a], order[b]), std::max(order[a], order[b]));
    }
  }
  return found;
}

}  // namespace

std::vector<std::pair<std::size_t, std::size_t>> overlapping_pairs(const Particles& particles, double fraction) {
  double r_max = 0.0;
  Vec3 low = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 high = -low;
  bool finite = true;
  for (const Particle& p : particles) {
    r_max = std::max(r_max, p.radius);
    finite = finite && p.position.allFinite() && std::isfinite(p.radius);
    low = low.cwiseMin(p.position);
    high = high.cwiseMax(p.position);
  }
  // Two centres closer than R_i + R_j <= 2 R_max are in neighbouring cells; the margin covers
  // the rounding of (x - low) / side (relative 2^-51 of at most 2^26 cells: < 1e-7 of a cell).
  const double side = 2.0 * r_max * (1.0 + 1e-6);
  std::vector<std::pair<std::size_t, std::size_t>> found;
  if (particles.empty()) return found;
  // A negative fraction admits pairs that do not touch: the sweep's old bound then applies.
  if (!finite || !(fraction >= 0.0) || !(side > 0.0) || !std::isfinite(side) ||
      ((high - low) / side).maxCoeff() > 0x1p26) {
    found = sweep(particles, fraction, r_max);
  } else {
    auto cell_of = [&](const Vec3& x) {
      return Cell{static_cast<std::int64_t>(std::floor((x.x() - low.x()) / side)),
                  static_cast<std::int64_t>(std::floor((x.y() - low.y()) / side)),
                  static_cast<std::int64_t>(std::floor((x.z() - low.z()) / side))};
    };
    // Particles by cell: a counting sort through the map's running indices.
    std::unordered_map<Cell, std::uint32_t, CellHash> slot;
    slot.reserve(particles.size());
    std::vector<std::uint32_t> cell_of_particle(particles.size());
    std::vector<std::size_t> count;
    for (std::size_t i = 0; i < particles.size(); ++i) {
      const auto [it, inserted] = slot.try_emplace(cell_of(particles[i].position), static_cast<std::uint32_t>(count.size()));
      if (inserted) count.push_back(0);
      cell_of_particle[i] = it->second;
      ++count[it->second];
    }
    std::vector<std::size_t> first(count.size() + 1, 0);
    for (std::size_t c = 0; c < count.size(); ++c) first[c + 1] = first[c] + count[c];
    std::vector<std::size_t> members(particles.size());
    std::vector<std::size_t> fill(first.begin(), first.end() - 1);
    for (std::size_t i = 0; i < particles.size(); ++i) members[fill[cell_of_particle[i]]++] = i;  // ascending i per cell
    for (std::size_t i = 0; i < particles.size(); ++i) {
      const Cell c = cell_of(particles[i].position);
      for (std::int64_t dx = -1; dx <= 1; ++dx) {
        for (std::int64_t dy = -1; dy <= 1; ++dy) {
          for (std::int64_t dz = -1; dz <= 1; ++dz) {
            const auto it = slot.find(Cell{c[0] + dx, c[1] + dy, c[2] + dz});
            if (it == slot.end()) continue;
            for (std::size_t m = first[it->second]; m < first[it->second + 1]; ++m) {
              const std::size_t j = members[m];
              if (j > i && overlaps(particles[i], particles[j], fraction)) found.emplace_back(i, j);
            }
          }
        }
      }
    }
  }
  std::sort(found.begin(), found.end());
  return found;
}

}  // namespace ppohdem::dem
