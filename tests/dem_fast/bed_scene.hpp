#pragma once
// What the fast engine's command-line tests share (fast_mpi_cli_test.cpp,
// alternate_threads_cli_test.cpp): their scratch directories, the frictional bed they run, and
// output files compared without their header lines, and scene edits.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "ppohdem/dem/particle_csv.hpp"

namespace ppohdem::test {

/// An empty directory <build>/tests_scratch/<suite>/<name>.
inline std::filesystem::path scratch(const std::string& suite, const std::string& name) {
  const std::filesystem::path dir = std::filesystem::path(PPOHDEM_BINARY_DIR) / "tests_scratch" / suite / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

/// The file without its '#' header lines (they name the rank and thread counts and the date).
inline std::string body(const std::filesystem::path& file) {
  std::ifstream in(file);
  EXPECT_TRUE(in.good()) << file;
  std::string line, out;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] == '#') continue;
    out += line + '\n';
  }
  return out;
}

/// The scene file with the first occurrence of `from` replaced by `to` (which must be there).
inline void replace_in_scene(const std::filesystem::path& scene, const std::string& from, const std::string& to) {
  std::ifstream in(scene);
  std::stringstream text;
  text << in.rdbuf();
  std::string toml = text.str();
  const auto at = toml.find(from);
  ASSERT_NE(at, std::string::npos) << scene << " has no " << from;
  toml.replace(at, from.size(), to);
  std::ofstream(scene) << toml;
}

/// A frictional bed in a walled box: nx x ny x nz spheres of radius 1 mm on a lattice of pitch
/// 2.1 mm (gaps 0.1 mm) with deterministic velocities of up to 0.3 m/s, so that within a few
/// hundred steps the particles collide, the lists are rebuilt many times (skin/2 = 0.1 mm) and
/// particles cross brick faces. Writes bed.csv and bed.toml into dir; returns the scene path.
inline std::filesystem::path write_bed(const std::filesystem::path& dir, int nx, int ny, int nz, long steps, long every) {
  using namespace ppohdem::dem;
  using ppohdem::Vec3;
  Particles ps;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        Particle p;
        p.id = 3 * static_cast<std::int64_t>(ps.size()) + 11;  // ids unrelated to storage
        p.radius = 1.0e-3 * (1.0 - 0.02 * ((i + 2 * j + 3 * k) % 3));
        p.position = Vec3(1.05e-3 + 2.1e-3 * i, 1.05e-3 + 2.1e-3 * j, 1.05e-3 + 2.1e-3 * k);
        const double a = 1.7 * i + 2.3 * j + 3.1 * k;
        p.velocity = 0.3 * Vec3(std::sin(a), std::cos(1.3 * a), std::sin(0.7 * a + 1.0));  // m/s
        p.angular_velocity = Vec3(50.0 * std::cos(a), 0.0, 30.0 * std::sin(a));            // rad/s
        ps.push_back(p);
      }
  write_particles_csv(dir / "bed.csv", ps, "dem_fast_mpi bed");
  const double lx = 2.1e-3 * nx, ly = 2.1e-3 * ny;
  std::ofstream toml(dir / "bed.toml");
  toml.precision(17);
  toml << "[simulation]\ndt = 1.0e-5\nsteps = " << steps << "\ngravity = [0.0, 0.0, -9.81]\n"
       << "[material]\ndensity = 2500.0\nyoung = 1.0e7\npoisson = 0.3\nrestitution = 0.5\nfriction = 0.5\n"
       << "[contact]\nmodel = \"hertz-mindlin\"\n[particles]\nfile = \"bed.csv\"\n"
       << "[[wall]]\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\n"
       << "[[wall]]\npoint = [0.0, 0.0, 0.0]\nnormal = [1.0, 0.0, 0.0]\n"
       << "[[wall]]\npoint = [" << lx << ", 0.0, 0.0]\nnormal = [-1.0, 0.0, 0.0]\n"
       << "[[wall]]\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 1.0, 0.0]\n"
       << "[[wall]]\npoint = [0.0, " << ly << ", 0.0]\nnormal = [0.0, -1.0, 0.0]\n"
       << "[output]\ndir = \"out\"\nevery = " << every << "\nformats = [\"csv\"]\nprogress = false\n";
  return dir / "bed.toml";
}

}  // namespace ppohdem::test
