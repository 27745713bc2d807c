// [[object]] blocks in scene files, objects.csv, and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "object_fields.hpp"
#include "ppohdem/dem/run.hpp"
#include "ppohdem/dem/scene.hpp"
#include "ppohdem/error.hpp"
#include "ppohdem/grid/trilinear.hpp"
#include "ppohdem/io/vtk_structured_points.hpp"
#include "ppohdem/dem/reference/reference_engine.hpp"
#include "test_paths.hpp"

namespace ppohdem::dem::test {
namespace {

namespace fs = std::filesystem;

void write_text(const fs::path& file, const std::string& text) {
  std::ofstream out(file);
  out << text;
}

// Hertz material of the DEM tests; one particle from a CSV.
std::string scene_head(const std::string& particle_csv) {
  return "[simulation]\ndt = 1e-6\nsteps = 10\ngravity = [0, 0, -9.81]\n"
         "[material]\ndensity = 2500.0\nyoung = 1e7\npoisson = 0.3\nrestitution = 0.5\nfriction = 0.5\n"
         "[contact]\nmodel = \"hertz-mindlin\"\n"
         "[particles]\nfile = \"" + particle_csv + "\"\n";
}

std::string message_of(const fs::path& scene) {
  try {
    read_scene(scene);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(SceneObject, RestingParticleLoadsThePlateWithItsWeight) {
  const fs::path dir = ppohdem::test::scratch_dir();
  // Plate: half-space z < 0 as a VTK distance file, h = 1 mm.
  const GridSpec grid{Vec3(-5e-3, -5e-3, -2e-3), Vec3::Constant(1e-3), {11, 11, 5}};
  write_vtk_structured_points(dir / "plate.vtk", half_space_field(grid, Vec3::Zero(), Vec3::UnitZ()));
  // A particle of R = 0.5 mm at its static Hertz overlap: m g = K delta^(3/2),
  // K = (4/3) E* sqrt(R), E* = E / (2 (1 - nu^2)).
  const double r = 0.5e-3, rho = 2500.0, g = 9.81;
  const double mass = rho * 4.0 / 3.0 * M_PI * r * r * r;
  const double k = 4.0 / 3.0 * (1e7 / (2.0 * (1.0 - 0.09))) * std::sqrt(r);
  const double delta = std::pow(mass * g / k, 2.0 / 3.0);
  const Vec3 x(1e-3, 2e-3, r - delta);
  std::ostringstream csv;
  csv.precision(17);
  csv << "id,x,y,z,vx,vy,vz,wx,wy,wz,radius\n1," << x.x() << "," << x.y() << "," << x.z() << ",0,0,0,0,0,0," << r << "\n";
  write_text(dir / "p.csv", csv.str());
  write_text(dir / "scene.toml", scene_head("p.csv") +
                                     "[[object]]\nname = \"plate\"\ndistance = \"plate.vtk\"\ncentroid = [0, 0, 0]\n"
                                     "[output]\ndir = \"out\"\nevery = 5\nprogress = false\n");
  const Scene scene = read_scene(dir / "scene.toml");
  ASSERT_EQ(scene.objects.size(), 1u);
  EXPECT_EQ(scene.objects[0].boundary_index, 0u);
  ppohdem::dem::reference::ReferenceEngine engine(scene.setup);
  std::ostringstream log;
  run_scene(engine, scene, "test", log);
  std::ifstream in(dir / "out" / "objects.csv");
  ASSERT_TRUE(in.good());
  std::string line;
  std::getline(in, line);  // header comment
  std::getline(in, line);  // column names
  EXPECT_EQ(line.substr(0, 30), "step,time,object,centroid_x,ce");
  std::getline(in, line);  // step 0
  std::vector<double> v;
  std::stringstream row(line);
  for (std::string cell; std::getline(row, cell, ',');) v.push_back(std::stod(cell));
  ASSERT_EQ(v.size(), 20u);
  // Force on the plate = the weight (0, 0, -m g); torque about the centroid (origin) =
  // p x F with the contact point p = (x, y, 0). 1e-9 relative: delta is computed from the same
  // closed form the law evaluates, up to rounding of pow (~1e-15).
  const Vec3 force(v[13], v[14], v[15]);
  const Vec3 torque(v[16], v[17], v[18]);
  const Vec3 weight(0, 0, -mass * g);
  EXPECT_LT((force - weight).norm(), 1e-9 * mass * g);
  EXPECT_LT((torque - Vec3(x.x(), x.y(), 0).cross(weight)).norm(), 1e-9 * mass * g * 1e-3);
  EXPECT_EQ(v[19], 0.0);  // nothing outside the grid
}

TEST(SceneObject, MeshIsVoxelizedWithTheExactDistance) {
  // fixtures/meshes/box.stl is the box [-1,1] x [-0.5,0.5] x [-0.25,0.25]: its distance at the
  // centre is -0.25 and at (1.5, 0, 0) it is +0.5 (analytic).
  const fs::path dir = ppohdem::test::scratch_dir();
  write_text(dir / "p.csv", "id,x,y,z,vx,vy,vz,wx,wy,wz,radius\n1,5,5,5,0,0,0,0,0,0,0.01\n");
  write_text(dir / "scene.toml", scene_head("p.csv") + "[[object]]\nmesh = \"" +
                                     ppohdem::test::fixture("meshes/box.stl").string() +
                                     "\"\ncells = [20, 10, 6]\nmargin = 0.6\nomega = 1.0\naxis = [0, 0, 2]\n");
  const Scene scene = read_scene(dir / "scene.toml");
  ASSERT_EQ(scene.objects.size(), 1u);
  const DistanceFieldObject& object = *scene.objects[0].object;
  EXPECT_EQ(object.field().grid.nodes, (Index3{21, 11, 7}));
  EXPECT_LT((object.field().grid.origin - Vec3(-1.6, -1.1, -0.85)).norm(), 1e-12);
  // The centre is a node (even cell counts on a box symmetric about 0) and on the x axis beyond
  // the end face phi = x - 1 is linear between the neighbouring nodes, so trilinear
  // interpolation returns the exact distance there; 1e-12 allows the builder's rounding.
  EXPECT_NEAR(sample_trilinear(object.field(), Vec3(0, 0, 0))->value, -0.25, 1e-12);
  EXPECT_NEAR(sample_trilinear(object.field(), Vec3(1.5, 0, 0))->value, 0.5, 1e-12);
  EXPECT_LT((object.motion().angular_velocity - Vec3(0, 0, 1)).norm(), 1e-15);
  // Default centroid: the grid's centre.
  EXPECT_LT((object.motion().centroid - Vec3(0, 0, 0)).norm(), 1e-12);
}

TEST(SceneObject, UnreadableDistanceFileIsAClearError) {
  const fs::path dir = ppohdem::test::scratch_dir();
  write_text(dir / "p.csv", "id,x,y,z,vx,vy,vz,wx,wy,wz,radius\n1,0,0,0,0,0,0,0,0,0,0.01\n");
  write_text(dir / "missing.toml", scene_head("p.csv") + "[[object]]\ndistance = \"nowhere.vtk\"\n");
  EXPECT_NE(message_of(dir / "missing.toml").find("nowhere.vtk"), std::string::npos) << message_of(dir / "missing.toml");
  write_text(dir / "garbage.vtk", "this is not a VTK file\n");
  write_text(dir / "garbage.toml", scene_head("p.csv") + "[[object]]\ndistance = \"garbage.vtk\"\n");
  EXPECT_NE(message_of(dir / "garbage.toml").find("garbage.vtk"), std::string::npos) << message_of(dir / "garbage.toml");
}

TEST(SceneObject, UnknownKeysAndMissingPartsAreErrorsNamingThem) {
  const fs::path dir = ppohdem::test::scratch_dir();
  write_text(dir / "p.csv", "id,x,y,z,vx,vy,vz,wx,wy,wz,radius\n1,0,0,0,0,0,0,0,0,0,0.01\n");
  write_text(dir / "a.toml", scene_head("p.csv") + "[[object]]\ndistance = \"x.vtk\"\nspin = 3\n");
  EXPECT_NE(message_of(dir / "a.toml").find("unknown key 'spin'"), std::string::npos) << message_of(dir / "a.toml");
  write_text(dir / "b.toml", scene_head("p.csv") + "[[object]]\nomega = 3\n");
  EXPECT_NE(message_of(dir / "b.toml").find("exactly one of distance"), std::string::npos) << message_of(dir / "b.toml");
  write_text(dir / "c.toml", scene_head("p.csv") + "[[object]]\nmesh = \"m.stl\"\n");
  EXPECT_NE(message_of(dir / "c.toml").find("cells"), std::string::npos) << message_of(dir / "c.toml");
}

}  // namespace
}  // namespace ppohdem::dem::test
