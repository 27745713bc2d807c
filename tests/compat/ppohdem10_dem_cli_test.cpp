// `ppohdem simulate --compat ppohdem-1.0 input_params_update.dat --initial state_step000000.dat`
// run as a user would, in the original sample's working directory: every file it writes must be
// byte-identical to the one the original Fortran program wrote (fixtures/ppohdem-1.0/dem-sample/).
#include <gtest/gtest.h>

#include <string>

#include "cli_runner.hpp"
#include "ppohdem/io/legacy_inputs.hpp"
#include "ppohdem10_dem_sample.hpp"

namespace ppohdem {
namespace {

using compat::test_support::dem_fixture;
using compat::test_support::lay_out_sample;
namespace fs = std::filesystem;

TEST(CompatDemCli, FirstFramesAreByteIdenticalToTheOriginal) {
  const fs::path dir = test::scratch_dir();
  lay_out_sample(dir);
  const auto r = test::run_ppohdem(
      "simulate --compat ppohdem-1.0 input_params_update.dat --initial state_step000000.dat --steps 1000 --quiet",
      dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("1000 steps"), std::string::npos) << r.output;
  const std::string frames = test::read_xz_file(dem_fixture("data/out001_to_out300.dat.xz"));
  EXPECT_TRUE(read_file_bytes(dir / "data/out001.dat") == frames.substr(0, 39000)) << "data/out001.dat";
  EXPECT_TRUE(read_file_bytes(dir / "data/out002.dat") == frames.substr(39000, 39000)) << "data/out002.dat";
  EXPECT_FALSE(fs::exists(dir / "data/out003.dat"));
  for (const char* f : {"001", "002"}) {
    EXPECT_TRUE(read_file_bytes(dir / "distance" / (std::string("objects_distance") + f + ".csv")) ==
                test::read_xz_file(dem_fixture(std::string("objects_distance/objects_distance") + f + ".csv.xz")))
        << "objects_distance" << f << ".csv";
    EXPECT_TRUE(read_file_bytes(dir / "obj" / (std::string("obj") + f + ".pov")) ==
                read_file_bytes(dem_fixture(std::string("obj/obj") + f + ".pov")))
        << "obj" << f << ".pov";
  }
  EXPECT_TRUE(read_file_bytes(dir / "objects_distance.csv") ==
              test::read_xz_file(dem_fixture("objects_distance/objects_distance_init.csv.xz")));
}

TEST(CompatDemCli, RejectsUnknownModeAndInitialWithoutCompat) {
  const fs::path dir = test::scratch_dir();
  lay_out_sample(dir);
  auto r = test::run_ppohdem("simulate --compat ppohdem-2.0 input_params_update.dat --steps 1", dir.string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("ppohdem-1.0"), std::string::npos) << r.output;
  r = test::run_ppohdem("simulate input_params_update.dat --initial state_step000000.dat --steps 1", dir.string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("--initial"), std::string::npos) << r.output;
}

TEST(CompatDemCli, MissingDistanceFileIsNamed) {
  const fs::path dir = test::scratch_dir();
  lay_out_sample(dir);
  fs::remove(dir / "distance_0000.dat");
  const auto r = test::run_ppohdem("simulate --compat ppohdem-1.0 input_params_update.dat --steps 1", dir.string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("distance_0000.dat"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace ppohdem
