// `ppohdem voxelize --compat ppohdem-1.0 input_constants_voxelizer.dat` run as a user would, in
// the original sample's own layout (input file + ./data/test-cube.stl): the distance files must
// be byte-identical to the ones the original Fortran program wrote (fixtures/ppohdem-1.0/).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "cli_runner.hpp"
#include "test_paths.hpp"
#include "xz_file.hpp"

namespace ppohdem {
namespace {
namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

fs::path prepare_cube_sample() {
  const fs::path dir = test::scratch_dir();
  fs::create_directories(dir / "data");
  fs::copy_file(test::fixture("ppohdem-1.0/test-cube.stl"), dir / "data" / "test-cube.stl");
  fs::copy_file(test::fixture("ppohdem-1.0/util-cube/input_constants_voxelizer.dat"), dir / "input_constants_voxelizer.dat");
  return dir;
}

TEST(CompatCli, CubeOneRankIsByteIdenticalToTheOriginal) {
  const fs::path dir = prepare_cube_sample();
  const auto r = test::run_ppohdem("voxelize --compat ppohdem-1.0 input_constants_voxelizer.dat", dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string ours = slurp(dir / "distance_0000.dat");
  const std::string original = test::read_xz_file(test::fixture("ppohdem-1.0/util-cube/np1/distance_0000.dat.xz"));
  EXPECT_EQ(ours.size(), original.size());
  EXPECT_TRUE(ours == original) << "distance_0000.dat differs from the original program's file";
}

TEST(CompatCli, CubeTwoRanksAreByteIdenticalToTheOriginal) {
  const fs::path dir = prepare_cube_sample();
  const auto r = test::run_ppohdem("voxelize --compat ppohdem-1.0 input_constants_voxelizer.dat --ranks 2", dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* name : {"distance_0000.dat", "distance_0001.dat"}) {
    const std::string original =
        test::read_xz_file(test::fixture(std::string("ppohdem-1.0/util-cube/np2/") + name + ".xz"));
    EXPECT_TRUE(slurp(dir / name) == original) << name << " differs from the original program's file";
  }
}

TEST(CompatCli, RejectsUnknownCompatMode) {
  const fs::path dir = prepare_cube_sample();
  const auto r = test::run_ppohdem("voxelize --compat ppohdem-2.0 input_constants_voxelizer.dat", dir.string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("ppohdem-1.0"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace ppohdem
