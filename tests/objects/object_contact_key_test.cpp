// [[object]] contact = "mesh" | "field" (docs/objects.md "Exact contacts for mesh objects"):
// the default of each kind of object and the errors.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "ppohdem/dem/scene.hpp"
#include "ppohdem/error.hpp"
#include "test_paths.hpp"

namespace ppohdem::dem::test {
namespace {

namespace fs = std::filesystem;

void write_text(const fs::path& file, const std::string& text) {
  std::ofstream out(file);
  out << text;
}

std::string scene_with_object(const std::string& object_lines) {
  return "[simulation]\ndt = 1e-6\nsteps = 10\n"
         "[material]\ndensity = 2500.0\nyoung = 1e7\npoisson = 0.3\nrestitution = 0.5\nfriction = 0.5\n"
         "[contact]\nmodel = \"hertz-mindlin\"\n"
         "[particles]\nfile = \"p.csv\"\n"
         "[[object]]\n" + object_lines;
}

std::string message_of(const fs::path& scene) {
  try {
    read_scene(scene);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ObjectContactKey, MeshObjectsUseTheirMeshUnlessToldField) {
  const fs::path dir = ppohdem::test::scratch_dir();
  write_text(dir / "p.csv", "id,x,y,z,vx,vy,vz,wx,wy,wz,radius\n1,5,5,5,0,0,0,0,0,0,0.01\n");
  const std::string mesh = "mesh = \"" + ppohdem::test::fixture("meshes/box.stl").string() + "\"\ncells = [8, 4, 2]\n";
  write_text(dir / "default.toml", scene_with_object(mesh));
  write_text(dir / "mesh.toml", scene_with_object(mesh + "contact = \"mesh\"\n"));
  write_text(dir / "field.toml", scene_with_object(mesh + "contact = \"field\"\n"));
  const auto contact_mesh = [&](const char* file) { return read_scene(dir / file).objects.at(0).object->contact_mesh(); };
  ASSERT_NE(contact_mesh("default.toml"), nullptr);
  EXPECT_EQ(contact_mesh("default.toml")->face_count(), 6u);  // the box's 12 triangles, 6 faces
  EXPECT_NE(contact_mesh("mesh.toml"), nullptr);
  EXPECT_EQ(contact_mesh("field.toml"), nullptr);
}

TEST(ObjectContactKey, BadValuesAreErrorsNamingTheKey) {
  const fs::path dir = ppohdem::test::scratch_dir();
  write_text(dir / "p.csv", "id,x,y,z,vx,vy,vz,wx,wy,wz,radius\n1,5,5,5,0,0,0,0,0,0,0.01\n");
  write_text(dir / "a.toml", scene_with_object("distance = \"phi.vtk\"\ncontact = \"mesh\"\n"));
  EXPECT_NE(message_of(dir / "a.toml").find("contact = \"mesh\" needs mesh ="), std::string::npos) << message_of(dir / "a.toml");
  EXPECT_NE(message_of(dir / "a.toml").find(":16"), std::string::npos) << message_of(dir / "a.toml");  // the key's line
  write_text(dir / "b.toml", scene_with_object("distance = \"phi.vtk\"\ncontact = \"exact\"\n"));
  EXPECT_NE(message_of(dir / "b.toml").find("expected \"mesh\" or \"field\", found \"exact\""), std::string::npos)
      << message_of(dir / "b.toml");
}

}  // namespace
}  // namespace ppohdem::dem::test
