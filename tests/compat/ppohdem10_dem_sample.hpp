#pragma once
// The original DEM sample (fixtures/ppohdem-1.0/dem-sample/) laid out in a scratch directory as
// the original program's working directory, and comparisons of states with the original's
// full-precision dumps.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "ppohdem/compat/ppohdem10_dem.hpp"
#include "test_paths.hpp"
#include "xz_file.hpp"

namespace ppohdem::compat::test_support {

namespace fs = std::filesystem;

inline fs::path dem_fixture(const std::string& relative) {
  return ppohdem::test::fixture("ppohdem-1.0/dem-sample/" + relative);
}

inline void write_bytes(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out << bytes;
}

/// The original's working directory: input_params_update.dat, distance_0000.dat (the cube
/// sample's DEM-Util output) and object_mesh.stl, plus state_step000000.dat.
inline void lay_out_sample(const fs::path& dir) {
  fs::create_directories(dir);
  fs::copy_file(dem_fixture("input_params_update.dat"), dir / "input_params_update.dat",
                fs::copy_options::overwrite_existing);
  write_bytes(dir / "distance_0000.dat",
              ppohdem::test::read_xz_file(ppohdem::test::fixture("ppohdem-1.0/util-cube/np1/distance_0000.dat.xz")));
  fs::copy_file(ppohdem::test::fixture("ppohdem-1.0/object_mesh_cube.stl"), dir / "object_mesh.stl",
                fs::copy_options::overwrite_existing);
  write_bytes(dir / "state_step000000.dat", ppohdem::test::read_xz_file(dem_fixture("fullprec/state_step000000.dat.xz")));
}

/// The original's dump `name` (e.g. "state_step000010.dat").
inline Ppohdem10State original_state(const std::string& name) {
  return parse_ppohdem10_state(ppohdem::test::read_xz_file(dem_fixture("fullprec/" + name + ".xz")), name);
}

inline std::uint64_t bits(double v) {
  std::uint64_t b = 0;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

/// How a state differs from the original's, over the 16 reals of every particle (x, v, omega,
/// radius, f, t) and the two contact counts.
struct StateDiff {
  std::size_t values = 0;
  std::size_t bitwise_equal = 0;
  double max_relative = 0.0;   ///< |a - b| / max(|b|, 1e-300), over all values
  std::size_t count_mismatches = 0;
  bool same_ids = true;
};

inline StateDiff compare_states(const Ppohdem10State& ours, const Ppohdem10State& original) {
  StateDiff d;
  if (ours.particles.size() != original.particles.size()) {
    d.same_ids = false;
    return d;
  }
  for (std::size_t i = 0; i < ours.particles.size(); ++i) {
    const Ppohdem10ParticleRecord& a = ours.particles[i];
    const Ppohdem10ParticleRecord& b = original.particles[i];
    if (a.id != b.id) d.same_ids = false;
    const double va[16] = {a.pos.x, a.pos.y, a.pos.z, a.vel.x, a.vel.y, a.vel.z, a.omega.x, a.omega.y,
                           a.omega.z, a.radius, a.force.x, a.force.y, a.force.z, a.rforce.x, a.rforce.y, a.rforce.z};
    const double vb[16] = {b.pos.x, b.pos.y, b.pos.z, b.vel.x, b.vel.y, b.vel.z, b.omega.x, b.omega.y,
                           b.omega.z, b.radius, b.force.x, b.force.y, b.force.z, b.rforce.x, b.rforce.y, b.rforce.z};
    for (int k = 0; k < 16; ++k) {
      ++d.values;
      // The dumps print 18 significant digits (ES25.17), which identify a double uniquely, so
      // the parsed value is the original's double bit for bit.
      if (bits(va[k]) == bits(vb[k])) ++d.bitwise_equal;
      const double scale = std::max(std::abs(vb[k]), 1e-300);
      d.max_relative = std::max(d.max_relative, std::abs(va[k] - vb[k]) / scale);
    }
    if (a.ncontact != b.ncontact || a.ncontact_wall != b.ncontact_wall) ++d.count_mismatches;
  }
  return d;
}

}  // namespace ppohdem::compat::test_support
