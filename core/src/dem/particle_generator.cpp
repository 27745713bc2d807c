#include "ppohdem/dem/particle_generator.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <unordered_map>
#include <vector>

#include "ppohdem/error.hpp"

namespace ppohdem::dem {
namespace {

// Uniform in [0, 1) from the top 53 bits (fully specified, unlike std::uniform_real_distribution).
double uniform01(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

double uniform(std::mt19937_64& rng, double lo, double hi) { return lo + (hi - lo) * uniform01(rng); }

double draw_radius(const GeneratorSpec& spec, std::mt19937_64& rng) {
  return spec.radius_max > spec.radius ? uniform(rng, spec.radius, spec.radius_max) : spec.radius;
}

Particles lattice(const GeneratorSpec& spec, double r_max, const std::string& where) {
  const double jitter = spec.jitter * spec.radius;  // [m]
  const double pitch = 2.0 * r_max * (1.0 + 1.0e-3) + 2.0 * jitter;  // [m]
  const Vec3 extent = spec.box_max - spec.box_min;
  // Sites per axis, at most `count` (no lattice needs more along one axis): a tiny radius in a
  // large box gives far more sites than an int64 holds (fuzz_scene_toml, finding 9: radius
  // 1e-22 m, 2.3e20 sites; the conversion was undefined behaviour).
  const double most = static_cast<double>(std::max<std::int64_t>(spec.count, 1));
  auto per_axis = [&](double length) {
    const double n = std::min(std::floor((length - 2.0 * r_max) / pitch) + 1.0, most);
    return n > 0.0 ? static_cast<std::int64_t>(n) : std::int64_t{0};
  };
  const std::int64_t nx = per_axis(extent.x()), ny = per_axis(extent.y()), nz = per_axis(extent.z());
  // The capacity in double: the product of three clamped counts may exceed an int64.
  if (static_cast<double>(nx) * static_cast<double>(ny) * static_cast<double>(nz) < static_cast<double>(spec.count)) {
    throw InputError(where, 0, "[particles] lattice: the box holds " + std::to_string(nx * ny * nz) +
                                   " particles of radius_max " + std::to_string(r_max) +
                                   " m, asked for " + std::to_string(spec.count));
  }
  std::mt19937_64 rng(spec.seed);
  Particles particles;
  particles.reserve(static_cast<std::size_t>(spec.count));
  for (std::int64_t n = 0; n < spec.count; ++n) {
    const std::int64_t i = n % nx, j = (n / nx) % ny, k = (n / nx) / ny;
    Particle p;
    p.id = n + 1;
    p.radius = draw_radius(spec, rng);
    p.position = spec.box_min + Vec3::Constant(r_max + jitter) +
                 pitch * Vec3(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k));
    for (int a = 0; a < 3; ++a) p.position[a] += uniform(rng, -jitter, jitter);
    p.velocity = spec.velocity;
    particles.push_back(p);
  }
  return particles;
}

struct CellKeyHash {
  std::size_t operator()(const Index3& c) const {
    return static_cast<std::size_t>(c[0]) * 73856093u ^ static_cast<std::size_t>(c[1]) * 19349663u ^
           static_cast<std::size_t>(c[2]) * 83492791u;
  }
};

Particles random_fill(const GeneratorSpec& spec, double r_max, const std::string& where) {
  std::mt19937_64 rng(spec.seed);
  const double cell = 2.0 * r_max;  // [m] a neighbour is at most one cell away
  // Cell indices are int: a box of more than 2^30 cells per axis (fuzz_scene_toml, finding 8:
  // box_max z = 9.2e19 m) would overflow the conversion (undefined behaviour).
  for (int a = 0; a < 3; ++a) {
    if (!((spec.box_max[a] - spec.box_min[a]) / cell < 1073741824.0)) {
      throw InputError(where, 0, "[particles] random: the box is more than 2^30 particle diameters long along axis " +
                                     std::to_string(a) + " (box_min, box_max too far apart for the particle size)");
    }
  }
  std::unordered_map<Index3, std::vector<std::size_t>, CellKeyHash> grid;
  auto cell_of = [&](const Vec3& x) {
    const Vec3 s = (x - spec.box_min) / cell;
    return Index3{static_cast<int>(std::floor(s.x())), static_cast<int>(std::floor(s.y())),
                  static_cast<int>(std::floor(s.z()))};
  };
  Particles particles;
  particles.reserve(static_cast<std::size_t>(spec.count));
  for (std::int64_t n = 0; n < spec.count; ++n) {
    const double r = draw_radius(spec, rng);
    bool placed = false;
    for (int attempt = 0; attempt < 1000 && !placed; ++attempt) {
      Vec3 x;
      for (int a = 0; a < 3; ++a) x[a] = uniform(rng, spec.box_min[a] + r, spec.box_max[a] - r);
      const Index3 c = cell_of(x);
      bool free = true;
      for (int dx = -1; dx <= 1 && free; ++dx)
        for (int dy = -1; dy <= 1 && free; ++dy)
          for (int dz = -1; dz <= 1 && free; ++dz) {
            auto it = grid.find(Index3{c[0] + dx, c[1] + dy, c[2] + dz});
            if (it == grid.end()) continue;
            for (std::size_t j : it->second) {
              if ((particles[j].position - x).norm() < particles[j].radius + r) { free = false; break; }
            }
          }
      if (!free) continue;
      Particle p;
      p.id = n + 1;
      p.radius = r;
      p.position = x;
      p.velocity = spec.velocity;
      grid[c].push_back(particles.size());
      particles.push_back(p);
      placed = true;
    }
    if (!placed) {
      throw InputError(where, 0, "[particles] random: could not place particle " + std::to_string(n + 1) +
                                     " of " + std::to_string(spec.count) +
                                     " after 1000 attempts; use a larger box or fewer particles");
    }
  }
  return particles;
}

}  // namespace

Particles generate_particles(const GeneratorSpec& spec, const std::string& where) {
  if (spec.count < 0 || !(spec.radius > 0.0)) {
    throw InputError(where, 0, "[particles] generator: count must be >= 0 and radius > 0");
  }
  const double r_max = std::max(spec.radius, spec.radius_max);
  if ((spec.box_max - spec.box_min).minCoeff() < 2.0 * r_max) {
    throw InputError(where, 0, "[particles] generator: box_max - box_min must exceed 2 radius_max on every axis");
  }
  return spec.kind == GeneratorKind::kLattice ? lattice(spec, r_max, where)
                                              : random_fill(spec, r_max, where);
}

}  // namespace ppohdem::dem
