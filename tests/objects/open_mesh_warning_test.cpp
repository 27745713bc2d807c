// `ppohdem simulate` warns about an object whose mesh is open, as `ppohdem voxelize` does
// (issue 38 item 7), and says nothing about a closed one.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "../apps/cli_runner.hpp"
#include "test_paths.hpp"

namespace ppohdem::test {
namespace {

namespace fs = std::filesystem;

void write_text(const fs::path& file, const std::string& text) { std::ofstream(file) << text; }

// A square plate of two triangles (4 boundary edges) and a closed tetrahedron.
const char* kPlate =
    "solid plate\n"
    "facet normal 0 0 1\nouter loop\nvertex 0.02 0.02 0.01\nvertex 0.08 0.02 0.01\nvertex 0.08 0.08 0.01\nendloop\nendfacet\n"
    "facet normal 0 0 1\nouter loop\nvertex 0.02 0.02 0.01\nvertex 0.08 0.08 0.01\nvertex 0.02 0.08 0.01\nendloop\nendfacet\n"
    "endsolid plate\n";
const char* kTetrahedron =
    "solid tet\n"
    "facet normal 0 0 -1\nouter loop\nvertex 0.02 0.02 0.01\nvertex 0.02 0.08 0.01\nvertex 0.08 0.02 0.01\nendloop\nendfacet\n"
    "facet normal 0 -1 0\nouter loop\nvertex 0.02 0.02 0.01\nvertex 0.08 0.02 0.01\nvertex 0.02 0.02 0.04\nendloop\nendfacet\n"
    "facet normal -1 0 0\nouter loop\nvertex 0.02 0.02 0.01\nvertex 0.02 0.02 0.04\nvertex 0.02 0.08 0.01\nendloop\nendfacet\n"
    "facet normal 1 1 1\nouter loop\nvertex 0.08 0.02 0.01\nvertex 0.02 0.08 0.01\nvertex 0.02 0.02 0.04\nendloop\nendfacet\n"
    "endsolid tet\n";

std::string run_with_mesh(const std::string& name, const char* stl) {
  const fs::path dir = scratch_dir() / ("open_mesh_warning_" + name);
  fs::create_directories(dir);
  write_text(dir / "object.stl", stl);
  write_text(dir / "p.csv", "id,x,y,z,vx,vy,vz,wx,wy,wz,radius\n1,0.05,0.05,0.08,0,0,0,0,0,0,0.002\n");
  write_text(dir / "scene.toml",
             "[simulation]\ndt = 1e-6\nsteps = 5\ngravity = [0.0, 0.0, -9.81]\n"
             "[material]\ndensity = 2500.0\nyoung = 1e7\npoisson = 0.3\nrestitution = 0.5\nfriction = 0.5\n"
             "[contact]\nmodel = \"hertz-mindlin\"\n[particles]\nfile = \"p.csv\"\n"
             "[[object]]\nmesh = \"object.stl\"\ncells = [16, 16, 8]\n"
             "[output]\ndir = \"out\"\nevery = 0\n");
  const CommandResult r = run_shell("cd '" + dir.string() + "' && '" + std::string(PPOHDEM_EXE) +
                                    "' simulate scene.toml --quiet 2>&1");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return r.output;
}

TEST(OpenMeshWarning, AnOpenObjectMeshIsNamedAndAClosedOneIsNot) {
  const std::string open = run_with_mesh("plate", kPlate);
  EXPECT_NE(open.find("warning: object 0 "), std::string::npos) << open;
  EXPECT_NE(open.find("mesh is not watertight (4 boundary edges, 0 non-manifold edges"), std::string::npos) << open;
  const std::string closed = run_with_mesh("tetrahedron", kTetrahedron);
  EXPECT_EQ(closed.find("not watertight"), std::string::npos) << closed;
}

}  // namespace
}  // namespace ppohdem::test
