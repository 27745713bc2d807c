// The original's two control files: the seed samples parse to the values printed in the
// user's guide (Lists 2.1, 2.2), and each malformed case names file, line and the problem.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "ppohdem/error.hpp"
#include "ppohdem/io/legacy_inputs.hpp"
#include "test_paths.hpp"

namespace ppohdem {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

// ---- the seed samples (expected values typed from the guide / the original README) -----------

TEST(VoxelizerInput, SeedListTwoOneParsesToTheGuideValues) {
  const auto in = read_voxelizer_input(test::fixture("seed/input_constants_voxelizer.dat"));
  EXPECT_EQ(in.mesh_file, "./data/dragon.stl");
  EXPECT_EQ(in.output_dir, "./");
  EXPECT_EQ(in.voxels, (Index3{76, 76, 76}));
  EXPECT_EQ(in.length, Vec3(44, 44, 44));
  EXPECT_EQ(in.object_size, Vec3(10, 10, 10));
  EXPECT_EQ(in.object_position, Vec3(22, 22, 11));
}

TEST(VoxelizerInput, ShippedCubeFileWithCrlfAndTrailingBlanksParses) {
  const auto in = read_voxelizer_input(test::fixture("legacy-cases/voxelizer_util_cube_crlf.dat"));
  EXPECT_EQ(in.mesh_file, "./data/test-cube.stl");  // no '\r' left over
  EXPECT_EQ(in.output_dir, "./");
  EXPECT_EQ(in.voxels, (Index3{76, 76, 76}));
  EXPECT_EQ(in.object_size, Vec3(6, 6, 6));
  EXPECT_EQ(in.object_position, Vec3(22, 22, 16));
}

TEST(UpdateParamsInput, SeedListTwoTwoParsesToTheGuideValues) {
  const auto in = read_update_params_input(test::fixture("seed/input_params_update.dat"));
  EXPECT_EQ(in.domain_length, Vec3(11, 11, 11));
  EXPECT_EQ(in.time_finish, 300.0);
  EXPECT_EQ(in.window_nodes, (Index3{20, 20, 20}));
  EXPECT_EQ(in.window_start, (Index3{28, 28, 28}));
  EXPECT_EQ(in.velocity, Vec3(0, 0, 0.005));
  EXPECT_EQ(in.rotation_axis, Vec3(0, 0, 1));
  EXPECT_EQ(in.omega_pi_rad_per_w, 1200.0);
  EXPECT_EQ(in.centroid, Vec3(22, 22, 11));
}

TEST(UpdateParamsInput, FortranStyleRealsParse) {
  // 11. / 11.0D0 / 1.1E1, 3.0D2, 5.0d-3, 1.2D+3: the same values as the seed file.
  const auto in = read_update_params_input(test::fixture("legacy-cases/params_fortran_reals.dat"));
  EXPECT_EQ(in.domain_length, Vec3(11, 11, 11));
  EXPECT_EQ(in.time_finish, 300.0);
  EXPECT_EQ(in.velocity, Vec3(0, 0, 0.005));
  EXPECT_EQ(in.rotation_axis, Vec3(0, 0, 1));
  EXPECT_EQ(in.omega_pi_rad_per_w, 1200.0);
}

TEST(UpdateParamsInput, LabelsAreOptional) {
  const auto in = read_update_params_input(test::fixture("legacy-cases/params_no_labels.dat"));
  EXPECT_EQ(in.time_finish, 300.0);
  EXPECT_EQ(in.window_start, (Index3{28, 28, 28}));
  EXPECT_EQ(in.centroid, Vec3(22, 22, 11));
}

TEST(FortranReal, ParsesFortranSpellings) {
  EXPECT_EQ(parse_fortran_real("300."), 300.0);
  EXPECT_EQ(parse_fortran_real(".5"), 0.5);
  EXPECT_EQ(parse_fortran_real("+7"), 7.0);
  EXPECT_EQ(parse_fortran_real("1.0D-3"), 1.0e-3);
  EXPECT_EQ(parse_fortran_real("1.0d-3"), 1.0e-3);
  EXPECT_EQ(parse_fortran_real("-2.5E+01"), -25.0);
  EXPECT_EQ(parse_fortran_real("0.44173684E+03"), 441.73684);
  EXPECT_EQ(parse_fortran_real("0.10000000+101"), 1e100);  // Ew.d, 3-digit exponent
  EXPECT_EQ(parse_fortran_real("0.15000000-98"), 1.5e-99);
  EXPECT_FALSE(parse_fortran_real("").has_value());
  EXPECT_FALSE(parse_fortran_real("abc").has_value());
  EXPECT_FALSE(parse_fortran_real("1.0.0").has_value());
  EXPECT_FALSE(parse_fortran_real("++5").has_value());
  EXPECT_FALSE(parse_fortran_real("5x").has_value());
  EXPECT_TRUE(std::isnan(*parse_fortran_real("NaN")));
}

// ---- malformed files: the message names file, line, what was expected and found ------------

struct BadCase {
  const char* file;
  bool voxelizer;
  int line;
  std::vector<std::string> words;
};

void PrintTo(const BadCase& c, std::ostream* os) { *os << c.file; }

class MalformedLegacyInput : public ::testing::TestWithParam<BadCase> {};

TEST_P(MalformedLegacyInput, FailsNamingFileLineAndProblem) {
  const BadCase& c = GetParam();
  const auto path = test::fixture(std::string("legacy-cases/") + c.file);
  try {
    if (c.voxelizer) {
      read_voxelizer_input(path);
    } else {
      read_update_params_input(path);
    }
    FAIL() << "expected InputError for " << c.file;
  } catch (const InputError& e) {
    const std::string where = path.string() + ":" + std::to_string(c.line) + ":";
    EXPECT_THAT(e.what(), HasSubstr(where));
    EXPECT_EQ(e.line(), static_cast<std::size_t>(c.line));
    for (const auto& w : c.words) EXPECT_THAT(e.what(), HasSubstr(w));
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, MalformedLegacyInput,
    ::testing::Values(
        BadCase{"voxelizer_wrong_label.dat", true, 5, {"expected label 'sizeX_sizeY_sizeZ:'", "found 'size_X:'"}},
        BadCase{"voxelizer_missing_line.dat", true, 6, {"'posX_posY_posZ:'", "found end of file"}},
        BadCase{"voxelizer_non_numeric.dat", true, 4, {"expected a real number", "found 'forty-four'"}},
        BadCase{"voxelizer_zero_count.dat", true, 3, {"voxel counts >= 1", "found 76 0 76"}},
        BadCase{"voxelizer_negative_length.dat", true, 4, {"data-space length > 0", "found 44 -44 44"}},
        BadCase{"voxelizer_extra_token.dat", true, 6, {"expected 3 reals", "extra value '5'"}},
        BadCase{"empty.dat", true, 1, {"mesh (STL) file name", "found end of file"}},
        BadCase{"empty.dat", false, 1, {"'Lx_Ly_Lz:'", "found end of file"}},
        BadCase{"params_nan.dat", false, 5, {"expected a finite real number (object velocity)", "found 'NaN'"}},
        BadCase{"params_zero_time.dat", false, 2, {"end time > 0", "found 0"}},
        BadCase{"params_window_start_zero.dat", false, 4, {"window start (1-based) >= 1", "found 0 28 28"}},
        BadCase{"params_wrong_label.dat", false, 7,
                {"expected label 'Obj_omega_Pi_rad_per_w:'", "found 'Obj_omega_rad_per_w:'"}}),
    [](const ::testing::TestParamInfo<BadCase>& param_info) {
      std::string name = std::string(param_info.param.voxelizer ? "V_" : "P_") + param_info.param.file;
      for (char& ch : name) {
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
      }
      return name;
    });

TEST(VoxelizerInput, RejectsMissingValueOnALine) {
  try {
    parse_voxelizer_input("a.stl\n./\n76 76\n", "text.dat");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), AllOf(HasSubstr("text.dat:3:"), HasSubstr("expected 3 integers"),
                                HasSubstr("found 2 value(s)")));
  }
}

TEST(VoxelizerInput, RejectsRealWhereAnIntegerIsExpected) {
  EXPECT_THROW(parse_voxelizer_input("a.stl\n./\n76 76.5 76\nLx_Ly_Lz: 1 1 1\nsizeX_sizeY_sizeZ: 1 1 1\n"
                                     "posX_posY_posZ: 0 0 0\n",
                                     "t"),
               InputError);
}

TEST(VoxelizerInput, RejectsNonBlankTextAfterTheLastLine) {
  try {
    parse_voxelizer_input("a.stl\n./\n7 7 7\nLx_Ly_Lz: 1 1 1\nsizeX_sizeY_sizeZ: 1 1 1\n"
                          "posX_posY_posZ: 0 0 0\n\nextra\n",
                          "t.dat");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), AllOf(HasSubstr("t.dat:8:"), HasSubstr("expected end of file after line 6"),
                                HasSubstr("'extra'")));
  }
}

TEST(VoxelizerInput, TrailingBlankLinesAreAccepted) {
  EXPECT_NO_THROW(parse_voxelizer_input(
      "a.stl\n./\n7 7 7\nLx_Ly_Lz: 1 1 1\nsizeX_sizeY_sizeZ: 1 1 1\nposX_posY_posZ: 0 0 0\n\n  \n", "t"));
}

TEST(ReadFileBytes, ReadsBinaryContentExactly) {
  const auto path = test::scratch_dir() / "bytes.bin";
  const std::string content("a\0b\r\n\xff", 6);
  std::ofstream(path, std::ios::binary) << content;
  EXPECT_EQ(read_file_bytes(path), content);
}

TEST(ReadFileBytes, MissingFileErrorNamesTheFile) {
  const auto path = test::scratch_dir() / "does_not_exist.dat";
  try {
    read_file_bytes(path);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), AllOf(HasSubstr("does_not_exist.dat"), HasSubstr("cannot open")));
  }
  EXPECT_THROW(read_voxelizer_input(path), InputError);
}

}  // namespace
}  // namespace ppohdem
