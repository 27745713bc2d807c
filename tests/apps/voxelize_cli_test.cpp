// `ppohdem voxelize` end to end: both command forms, their outputs against the analytic SDF
// of a box, and every bad input giving a clear error with nothing half-written.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "cli_runner.hpp"
#include "ppohdem/io/vtk_structured_points.hpp"
#include "test_paths.hpp"

namespace ppohdem {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;
using test::run_ppohdem;

// Analytic signed distance of the axis-aligned box [lo, hi] (negative inside):
// q = |p - c| - half;  phi = |max(q, 0)| + min(max_a q_a, 0).
double box_sdf(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  const Vec3 c = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  const Vec3 q = (p - c).cwiseAbs() - half;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

const Vec3 kBoxLo(-1.0, -0.5, -0.25), kBoxHi(1.0, 0.5, 0.25);  // fixtures/meshes/box.stl

std::string quoted(const fs::path& p) {
  std::string q = p.string();  // built by append: GCC 12 warns falsely (-Wrestrict) on "'" + string
  q.insert(q.begin(), '\'');
  q.push_back('\'');
  return q;
}

TEST(VoxelizeCli, ModernFormWritesExactBoxDistanceAsVtk) {
  const fs::path dir = test::scratch_dir();
  const auto r = run_ppohdem("voxelize --mesh " + quoted(test::fixture("meshes/box.stl")) +
                             " --cells 21 11 7 --box -1.5 -1 -0.75 1.5 1 0.75 --method exact --out " +
                             quoted(dir / "box.vtk"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("1617 nodes"));
  EXPECT_THAT(r.output, HasSubstr("12 triangles"));
  const ScalarField f = read_vtk_structured_points(dir / "box.vtk");
  ASSERT_EQ(f.grid.node_count(), 21u * 11u * 7u);
  double worst = 0.0;
  for (int k = 0; k < 7; ++k)
    for (int j = 0; j < 11; ++j)
      for (int i = 0; i < 21; ++i)
        worst = std::max(worst, std::abs(f.at(i, j, k) - box_sdf(f.grid.position(i, j, k), kBoxLo, kBoxHi)));
  // A closest-point computation on O(1) coordinates: a few roundings of size 1e-16 each.
  EXPECT_LT(worst, 1e-12);
}

// Reads a distance_NNNN.dat record file (format (3I8,1E20.8)) into (i,j,k) -> d.
struct DatRecord {
  int i, j, k;
  double d;
};
std::vector<DatRecord> read_records(const fs::path& file, bool has_header, std::string* header) {
  std::ifstream in(file);
  std::string line;
  std::vector<DatRecord> out;
  if (has_header) std::getline(in, *header);
  while (std::getline(in, line)) {
    std::istringstream s(line);
    DatRecord rec{};
    s >> rec.i >> rec.j >> rec.k >> rec.d;
    out.push_back(rec);
  }
  return out;
}

void write_legacy_input(const fs::path& dir, const std::string& mesh, const std::string& counts) {
  std::ofstream f(dir / "input_constants_voxelizer.dat");
  f << mesh << "\n./\n" << counts << "\nLx_Ly_Lz: 44 44 44\nsizeX_sizeY_sizeZ: 6 6 6\nposX_posY_posZ: 22 22 16\n";
}

TEST(VoxelizeCli, LegacyFormWritesOriginalLayoutWithAnalyticValues) {
  const fs::path dir = test::scratch_dir();
  fs::copy_file(test::fixture("meshes/box.stl"), dir / "box.stl");
  write_legacy_input(dir, "./box.stl", "20 20 20");
  const auto r = run_ppohdem("voxelize input_constants_voxelizer.dat --ranks 2", dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // Fit placement of the 2 x 1 x 0.5 box into size 6: scale 3, centred at (22, 22, 16).
  const Vec3 lo(19.0, 20.5, 15.25), hi(25.0, 23.5, 16.75);
  std::string header;
  auto rank0 = read_records(dir / "distance_0000.dat", true, &header);
  auto rank1 = read_records(dir / "distance_0001.dat", false, nullptr);
  EXPECT_EQ(header, "      20      20      20       2");
  // Two ranks: x-slabs i = 1..10 and 11..20, k outer, j, i inner.
  ASSERT_EQ(rank0.size(), 4000u);
  ASSERT_EQ(rank1.size(), 4000u);
  EXPECT_EQ(rank0.front().i, 1);
  EXPECT_EQ(rank0[9].i, 10);
  EXPECT_EQ(rank0[10].j, 2);
  EXPECT_EQ(rank1.front().i, 11);
  const double h = 44.0 / 20.0;  // the original's node spacing L / n
  double worst_relative = 0.0;
  for (const auto* records : {&rank0, &rank1}) {
    for (const auto& rec : *records) {
      const Vec3 p(h * (rec.i - 1), h * (rec.j - 1), h * (rec.k - 1));
      const double exact = box_sdf(p, lo, hi);
      worst_relative = std::max(worst_relative, std::abs(rec.d - exact) / std::max(std::abs(exact), 1e-300));
    }
  }
  // E20.8 prints a mantissa 0.dddddddd in [0.1, 1): half a unit of the 8th digit is 5e-9 of a
  // mantissa that can be as small as 0.1, so the relative rounding is <= 5e-8 (the builder adds ~1e-15).
  EXPECT_LT(worst_relative, 5.0e-8 + 1e-12);
  EXPECT_TRUE(fs::exists(dir / "object_mesh.stl"));
  for (const auto& e : fs::directory_iterator(dir)) {
    EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << "temp file left: " << e.path();
  }
}

TEST(VoxelizeCli, RejectsZeroCellCount) {
  const fs::path dir = test::scratch_dir();
  const auto r = run_ppohdem("voxelize --mesh " + quoted(test::fixture("meshes/box.stl")) +
                             " --cells 0 10 10 --box -2 -2 -2 2 2 2 --out " + quoted(dir / "x.vtk"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_THAT(r.output, HasSubstr("--cells"));
  EXPECT_FALSE(fs::exists(dir / "x.vtk"));
}

TEST(VoxelizeCli, RejectsNegativeCountInLegacyFileWithFileAndLine) {
  const fs::path dir = test::scratch_dir();
  fs::copy_file(test::fixture("meshes/box.stl"), dir / "box.stl");
  write_legacy_input(dir, "./box.stl", "20 -3 20");
  const auto r = run_ppohdem("voxelize input_constants_voxelizer.dat", dir.string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_THAT(r.output, HasSubstr("input_constants_voxelizer.dat:3"));
  EXPECT_FALSE(fs::exists(dir / "distance_0000.dat"));
}

TEST(VoxelizeCli, RejectsMissingOutputDirectoryBeforeComputing) {
  const fs::path dir = test::scratch_dir();
  const auto r = run_ppohdem("voxelize --mesh " + quoted(test::fixture("meshes/box.stl")) +
                             " --cells 8 8 8 --box -2 -2 -2 2 2 2 --out " + quoted(dir / "no-such-dir" / "x.vtk"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_THAT(r.output, HasSubstr("no-such-dir"));
  EXPECT_THAT(r.output, HasSubstr("does not exist"));
}

TEST(VoxelizeCli, RejectsEmptyMesh) {
  const fs::path dir = test::scratch_dir();
  std::ofstream(dir / "empty.stl") << "solid nothing\nendsolid nothing\n";
  const auto r = run_ppohdem("voxelize --mesh " + quoted(dir / "empty.stl") +
                             " --cells 8 8 8 --box -2 -2 -2 2 2 2 --out " + quoted(dir / "x.vtk"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_THAT(r.output, HasSubstr("empty.stl"));
  EXPECT_FALSE(fs::exists(dir / "x.vtk"));
}

TEST(VoxelizeCli, WarnsWhenTheBoxDoesNotContainTheMesh) {
  const fs::path dir = test::scratch_dir();
  const auto r = run_ppohdem("voxelize --mesh " + quoted(test::fixture("meshes/box.stl")) +
                             " --cells 9 9 9 --box -0.5 -2 -2 2 2 2 --out " + quoted(dir / "x.vtk"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("does not contain the whole mesh"));
}

TEST(VoxelizeCli, WarnsForAnOpenMesh) {
  const fs::path dir = test::scratch_dir();
  // The box without its -x face (the last two facets of box.stl): 10 triangles, open.
  std::ifstream in(test::fixture("meshes/box.stl"));
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  // Keep the first 10 facets.
  std::size_t pos = 0;
  for (int f = 0; f < 10; ++f) pos = s.find("endfacet", pos) + 8;
  std::ofstream(dir / "open.stl") << s.substr(0, pos) << "\nendsolid box\n";
  const auto r = run_ppohdem("voxelize --mesh " + quoted(dir / "open.stl") +
                             " --cells 9 9 9 --box -2 -2 -2 2 2 2 --out " + quoted(dir / "x.vtk"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("not watertight"));
}

}  // namespace
}  // namespace ppohdem
