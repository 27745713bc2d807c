// `ppohdem simulate` with an [[object]] made from an STL mesh: a frictionless sphere dropped
// into a 90-degree V-notch rests at the analytic two-contact height (docs/objects.md "Exact
// contacts for mesh objects") whatever the object's grid, in both engines with the same bits;
// with contact = "field" (the seed's method) it does not.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "../apps/cli_runner.hpp"
#include "mesh_shapes.hpp"
#include "ppohdem/dem/particle_csv.hpp"
#include "ppohdem/mesh/stl_io.hpp"
#include "test_paths.hpp"

namespace ppohdem::dem::test {
namespace {
namespace fs = std::filesystem;

constexpr double kRadius = 1e-3, kDensity = 2500.0, kStiffness = 10.0, kGravity = 9.81;

// The notch (crease on the x axis, x in [0, 12] mm) and one sphere 0.2 R off-centre, 0.3 R above
// its rest height; the object's grid is the mesh's box grown by 2 mm, cut into `cells`.
fs::path notch_case(const std::string& cells, const std::string& contact_line, const std::string& engine) {
  const fs::path dir = ppohdem::test::scratch_dir();
  write_stl(dir / "notch.stl", notched_block(0.012, 0.004, 0.002, 12), StlEncoding::kAscii);
  const double mass = kDensity * 4.0 / 3.0 * std::numbers::pi * std::pow(kRadius, 3);
  const double rest_z = std::sqrt(2.0) * (kRadius - mass * kGravity / (std::sqrt(2.0) * kStiffness));
  std::ofstream(dir / "p.csv") << "id,x,y,z,vx,vy,vz,wx,wy,wz,radius\n1,0.006," << 0.2 * kRadius << ","
                               << rest_z + 0.3 * kRadius << ",0,0,0,0,0,0," << kRadius << "\n";
  std::ofstream(dir / "notch.toml")
      << "[simulation]\ndt = 5e-5\nsteps = 20000\ngravity = [0, 0, -9.81]\n"
      << "[material]\ndensity = 2500.0\nyoung = 1e7\npoisson = 0.3\nrestitution = 0.3\nfriction = 0.0\n"
      << "[contact]\nmodel = \"linear\"\nstiffness = 10.0\n"
      << "[particles]\nfile = \"p.csv\"\n"
      << "[[object]]\nmesh = \"notch.stl\"\ncells = " << cells << "\nmargin = 0.002\n" << contact_line
      << "[output]\ndir = \"out\"\nevery = 20000\nformats = [\"csv\"]\n";
  const auto r = ppohdem::test::run_ppohdem("simulate notch.toml --quiet --engine " + engine, dir.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return dir;
}

Particle final_sphere(const fs::path& dir) {
  const Particles p = read_particles_csv(dir / "out" / "final.csv");
  EXPECT_EQ(p.size(), 1u);
  return p.at(0);
}

// Grids: [12, 12, 10] cells of 1 mm put a node on the crease; [12, 11, 9] put it half-way in y
// and 0.4 cells off in z. Tolerance 1e-12 m as MeshObjectDynamics.VNotchRests... (the same run:
// final.csv keeps 17 digits).
TEST(MeshObjectCli, SphereRestsAtTheTwoContactHeightWhateverTheGrid) {
  const double mass = kDensity * 4.0 / 3.0 * std::numbers::pi * std::pow(kRadius, 3);
  const double rest_z = std::sqrt(2.0) * (kRadius - mass * kGravity / (std::sqrt(2.0) * kStiffness));
  for (const std::string cells : {"[12, 12, 10]", "[12, 11, 9]"}) {
    const Particle reference = final_sphere(notch_case(cells, "", "reference"));
    const Particle fast = final_sphere(notch_case(cells, "", "fast"));
    EXPECT_NEAR(reference.position.z(), rest_z, 1e-12) << cells;
    EXPECT_NEAR(reference.position.y(), 0.0, 1e-12) << cells;
    EXPECT_EQ(reference.position, fast.position) << cells;
    EXPECT_EQ(reference.velocity, fast.velocity) << cells;
  }
  // The seed's contact on the grid with a node on the crease: the one-face height, m g / k low.
  const Particle field = final_sphere(notch_case("[12, 12, 10]", "contact = \"field\"\n", "reference"));
  EXPECT_GT(std::abs(field.position.z() - rest_z), 5e-6);
}

}  // namespace
}  // namespace ppohdem::dem::test
