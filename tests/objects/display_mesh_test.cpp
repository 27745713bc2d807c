// Objects' display meshes in the run outputs (output_writers.hpp): objects/object_K_NNNNNN.vtk
// holds the mesh moved by the object's pose, and every POV frame draws one mesh per object.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "ppohdem/dem/run.hpp"
#include "ppohdem/dem/scene.hpp"
#include "ppohdem/dem/reference/reference_engine.hpp"
#include "test_paths.hpp"

namespace ppohdem::dem::test {
namespace {

namespace fs = std::filesystem;

// The 12 triangles of the box [lo, hi] (outward, counter-clockwise), vertex by vertex.
std::vector<std::array<Vec3, 3>> box_triangles(const Vec3& lo, const Vec3& hi) {
  auto corner = [&](int i) { return Vec3(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z()); };
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  std::vector<std::array<Vec3, 3>> out;
  for (const auto& q : quads) {
    out.push_back({corner(q[0]), corner(q[1]), corner(q[2])});
    out.push_back({corner(q[0]), corner(q[2]), corner(q[3])});
  }
  return out;
}

void write_ascii_stl(const fs::path& file, const std::vector<std::array<Vec3, 3>>& triangles) {
  std::ofstream out(file);
  out << "solid box\n";
  char buf[200];
  for (const auto& t : triangles) {
    out << "facet normal 0 0 0\nouter loop\n";
    for (const Vec3& v : t) {
      std::snprintf(buf, sizeof buf, "vertex %.17g %.17g %.17g\n", v.x(), v.y(), v.z());
      out << buf;
    }
    out << "endloop\nendfacet\n";
  }
  out << "endsolid box\n";
}

// POINTS of a legacy VTK POLYDATA file written by write_mesh_vtk.
std::vector<Vec3> read_vtk_points(const fs::path& file) {
  std::ifstream in(file);
  std::string word;
  while (in >> word && word != "POINTS") {
  }
  std::size_t n = 0;
  in >> n >> word;
  std::vector<Vec3> points(n);
  for (Vec3& p : points) in >> p.x() >> p.y() >> p.z();
  return points;
}

std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t count = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++count;
  return count;
}

TEST(ObjectDisplayMesh, VtkVerticesArePoseAppliedToTheMeshAndPovHasOneMeshPerObject) {
  const fs::path dir = ppohdem::test::scratch_dir();
  const auto box = box_triangles(Vec3(0.1, 0.2, 0.3), Vec3(0.5, 0.4, 0.9));
  write_ascii_stl(dir / "box.stl", box);
  // One particle (R = 1 m, so dt = 1e-3 s is stable) far from the object; two objects: the moving box and a fixed copy.
  std::ofstream(dir / "p.csv") << "id,x,y,z,vx,vy,vz,wx,wy,wz,radius\n1,50,50,50,0,0,0,0,0,0,1.0\n";
  const Vec3 velocity(0.1, -0.2, 0.3), axis(1.0, 2.0, 3.0), centroid(0.3, 0.3, 0.6);
  const double omega = 5.0, dt = 1e-3;  // [rad/s], [s]
  std::ofstream(dir / "scene.toml")
      << "[simulation]\ndt = 1e-3\nsteps = 10\n"
         "[material]\ndensity = 2500.0\nyoung = 1e7\npoisson = 0.3\nrestitution = 0.5\n"
         "[contact]\nmodel = \"hertz-mindlin\"\n[particles]\nfile = \"p.csv\"\n"
         "[[object]]\nmesh = \"box.stl\"\ncells = [4, 4, 4]\nvelocity = [0.1, -0.2, 0.3]\n"
         "axis = [1, 2, 3]\nomega = 5.0\ncentroid = [0.3, 0.3, 0.6]\n"
         "[[object]]\nmesh = \"box.stl\"\ncells = [4, 4, 4]\n"
         "[output]\ndir = \"out\"\nevery = 5\nformats = [\"pov\", \"vtk\"]\nprogress = false\n";
  const Scene scene = read_scene(dir / "scene.toml");
  ppohdem::dem::reference::ReferenceEngine engine(scene.setup);
  std::ostringstream log;
  run_scene(engine, scene, "test", log);

  for (long step : {0L, 5L, 10L}) {
    // Independent pose, rigid_motion.hpp (1): x -> R(t) (x - c0) + c0 + v t, R(t) the turn by
    // omega t about the axis (Eigen's angle-axis matrix, not the library's quaternion path).
    const double t = static_cast<double>(step) * dt;
    const Eigen::Matrix3d rot = Eigen::AngleAxisd(omega * t, axis.normalized()).toRotationMatrix();
    char name[64];
    std::snprintf(name, sizeof name, "object_0_%06ld.vtk", step);
    const std::vector<Vec3> moved = read_vtk_points(dir / "out" / "objects" / name);
    ASSERT_EQ(moved.size(), 3 * box.size()) << name;
    std::snprintf(name, sizeof name, "object_1_%06ld.vtk", step);
    const std::vector<Vec3> fixed = read_vtk_points(dir / "out" / "objects" / name);
    ASSERT_EQ(fixed.size(), 3 * box.size()) << name;
    for (std::size_t i = 0; i < box.size(); ++i) {
      for (std::size_t k = 0; k < 3; ++k) {
        const Vec3 x = box[i][k];
        const Vec3 expected = rot * (x - centroid) + centroid + velocity * t;
        // 1e-12 m: quaternion vs matrix rotation and %.17g text round-trip differ by a few
        // ulps of O(1) coordinates (~1e-16); a wrong pose is off by >= 1e-6 here.
        EXPECT_LT((moved[3 * i + k] - expected).norm(), 1e-12) << "step " << step << " triangle " << i;
        EXPECT_LT((fixed[3 * i + k] - x).norm(), 1e-12) << "step " << step << " triangle " << i;
      }
    }
    std::ifstream pov(dir / "out" / ("frame_" + std::string(6 - std::to_string(step).size(), '0') +
                                     std::to_string(step) + ".pov"));
    ASSERT_TRUE(pov.good()) << step;
    const std::string text((std::istreambuf_iterator<char>(pov)), std::istreambuf_iterator<char>());
    EXPECT_EQ(count_of(text, "mesh {"), 2u) << step;  // one per object
    EXPECT_EQ(count_of(text, "triangle {"), 2 * box.size()) << step;
  }
}

TEST(ObjectDisplayMesh, PovTriangleIsWrittenXZY) {
  // A fixed one-triangle object: POV-Ray is y-up, so world (x, y, z) is written <x, z, y>.
  const fs::path dir = ppohdem::test::scratch_dir();
  write_ascii_stl(dir / "tri.stl", {{Vec3(1, 2, 3), Vec3(4, 2, 3), Vec3(1, 5, 3)}});
  std::ofstream(dir / "p.csv") << "id,x,y,z,vx,vy,vz,wx,wy,wz,radius\n1,50,50,50,0,0,0,0,0,0,1.0\n";
  std::ofstream(dir / "scene.toml")
      << "[simulation]\ndt = 1e-3\nsteps = 1\n"
         "[material]\ndensity = 2500.0\nyoung = 1e7\npoisson = 0.3\nrestitution = 0.5\n"
         "[contact]\nmodel = \"hertz-mindlin\"\n[particles]\nfile = \"p.csv\"\n"
         "[[object]]\nmesh = \"tri.stl\"\ncells = [2, 2, 2]\nmargin = 0.5\n"
         "[output]\ndir = \"out\"\nevery = 1\nformats = [\"pov\"]\nprogress = false\n";
  const Scene scene = read_scene(dir / "scene.toml");
  ppohdem::dem::reference::ReferenceEngine engine(scene.setup);
  std::ostringstream log;
  run_scene(engine, scene, "test", log);
  std::ifstream pov(dir / "out" / "frame_000001.pov");
  const std::string text((std::istreambuf_iterator<char>(pov)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("triangle { <1, 3, 2>, <4, 3, 2>, <1, 3, 5> }"), std::string::npos) << text;
  EXPECT_EQ(count_of(text, "mesh {"), 1u);
  // pov only: the object VTK is still written (documented: with vtk or pov frames).
  EXPECT_TRUE(fs::exists(dir / "out" / "objects" / "object_0_000001.vtk"));
}

}  // namespace
}  // namespace ppohdem::dem::test
