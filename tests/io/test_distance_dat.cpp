// The original program's distance_NNNN.dat files: E20.8 formatting against gfortran's own
// output, reading the original's 76^3 cube file, byte-identical rewriting of it, and round
// trips / malformed files for several rank counts.
#include <unistd.h>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "ppohdem/error.hpp"
#include "ppohdem/io/distance_dat.hpp"
#include "ppohdem/io/legacy_inputs.hpp"
#include "test_paths.hpp"
#include "xz_file.hpp"

namespace ppohdem {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

// The original program's 76^3 cube output (fixtures/ppohdem-1.0/util-cube/np1, stored as .xz),
// decompressed once per test process into a directory of its own (ctest runs tests in parallel).
std::filesystem::path original_cube_file() {
  static const std::filesystem::path file = [] {
    const auto dir = std::filesystem::path(PPOHDEM_BINARY_DIR) / "test-scratch" /
                     ("original-cube-np1-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const auto path = dir / "distance_0000.dat";
    std::ofstream(path, std::ios::binary)
        << test::read_xz_file(test::fixture("ppohdem-1.0/util-cube/np1/distance_0000.dat.xz"));
    return path;
  }();
  return file;
}

// ---- E20.8 ----------------------------------------------------------------------------------

TEST(FortranE20_8, HandCheckedValues) {
  EXPECT_EQ(format_fortran_e20_8(441.73684), "      0.44173684E+03");
  EXPECT_EQ(format_fortran_e20_8(-1.2345678), "     -0.12345678E+01");
  EXPECT_EQ(format_fortran_e20_8(0.0), "      0.00000000E+00");
  EXPECT_EQ(format_fortran_e20_8(1.0), "      0.10000000E+01");
  EXPECT_EQ(format_fortran_e20_8(0.05), "      0.50000000E-01");
  // 9.999999996 rounds up to 10.000000: the exponent moves.
  EXPECT_EQ(format_fortran_e20_8(9.999999996), "      0.10000000E+02");
  // Exact binary ties (9-digit integers ending in 5) go to the even 8th digit.
  EXPECT_EQ(format_fortran_e20_8(123456785.0), "      0.12345678E+09");
  EXPECT_EQ(format_fortran_e20_8(123456775.0), "      0.12345678E+09");
  // Not a tie: 0.123456785 is stored as 0.12345678499999999...; rounds down.
  EXPECT_EQ(format_fortran_e20_8(0.123456785), "      0.12345678E+00");
  EXPECT_EQ(format_fortran_e20_8(1e100), "      0.10000000+101");
  EXPECT_EQ(format_fortran_e20_8(-1e-100), "     -0.10000000E-99");  // 0.1 x 10^-99
  EXPECT_EQ(format_fortran_e20_8(-1e-101), "     -0.10000000-100");
  EXPECT_EQ(format_fortran_e20_8(std::numeric_limits<double>::infinity()).size(), 20u);
}

TEST(FortranE20_8, MatchesGfortranOutputForTrickyValues) {
  // Each line: the 16 hex digits of a double's bits, then gfortran 12's E20.8 of it (see
  // fixtures/legacy-cases/README.md: ties, rounding boundaries +-1 ulp, 3-digit exponents,
  // subnormals, +-0, inf, nan and random magnitudes).
  std::ifstream in(test::fixture("legacy-cases/e20_8_gfortran.txt"));
  ASSERT_TRUE(in) << "missing fixture";
  std::string line;
  int checked = 0;
  while (std::getline(in, line)) {
    ASSERT_EQ(line.size(), 36u) << line;
    const std::uint64_t bits = std::stoull(line.substr(0, 16), nullptr, 16);
    const double v = std::bit_cast<double>(bits);
    EXPECT_EQ(format_fortran_e20_8(v), line.substr(16)) << "bits " << line.substr(0, 16);
    ++checked;
  }
  EXPECT_GT(checked, 400);
}

TEST(FortranE20_8, ReformatsEveryValueOfTheOriginalCubeFile) {
  // The printed 8-digit decimal, read back as the nearest double, must print identically.
  const auto path = original_cube_file();
  ASSERT_TRUE(std::filesystem::exists(path)) << "original data not found at " << path;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // header
  std::size_t checked = 0;
  while (std::getline(in, line)) {
    ASSERT_EQ(line.size(), 44u);
    const std::string printed = line.substr(24);
    const double d = std::strtod(printed.c_str(), nullptr);
    ASSERT_EQ(format_fortran_e20_8(d), printed) << line;
    ++checked;
  }
  EXPECT_EQ(checked, 76u * 76u * 76u);
}

// ---- slabs ------------------------------------------------------------------------------------

TEST(DistanceDatSlab, FirstRanksGetTheRemainderPlanes) {
  // Original README: with 2 ranks and 76 planes, rank 0 has i = 1..38, rank 1 i = 39..76.
  EXPECT_EQ(distance_dat_slab(76, 2, 0).first_plane, 0);
  EXPECT_EQ(distance_dat_slab(76, 2, 0).plane_count, 38);
  EXPECT_EQ(distance_dat_slab(76, 2, 1).first_plane, 38);
  // 7 planes over 3 ranks: 3, 2, 2 (7 / 3 = 2, remainder 1 goes to rank 0).
  EXPECT_EQ(distance_dat_slab(7, 3, 0).plane_count, 3);
  EXPECT_EQ(distance_dat_slab(7, 3, 1).first_plane, 3);
  EXPECT_EQ(distance_dat_slab(7, 3, 1).plane_count, 2);
  EXPECT_EQ(distance_dat_slab(7, 3, 2).first_plane, 5);
  EXPECT_EQ(distance_dat_slab(7, 3, 2).plane_count, 2);
}

// ---- the original cube file ------------------------------------------------------------------

TEST(DistanceDat, ReadsTheOriginalCubeFile) {
  const auto path = original_cube_file();
  ASSERT_TRUE(std::filesystem::exists(path)) << "original data not found at " << path;
  const DistanceDat dat = read_distance_dat(path);
  EXPECT_EQ(dat.nodes, (Index3{76, 76, 76}));
  EXPECT_EQ(dat.nprocs, 1);
  ASSERT_EQ(dat.values.size(), 76u * 76u * 76u);
  const GridSpec grid = GridSpec::ppohdem_legacy(Vec3(44, 44, 44), dat.nodes);
  const ScalarField f = dat.on_grid(grid);
  const double h = 44.0 / 76.0;
  // Corner node: unreached sentinel 10 Lx = 440 plus 3 W (W = h), original README section
  // "Domain boundary"; printed at 8 digits, so compare to 5e-6 (half a unit in the 8th digit).
  EXPECT_NEAR(f.at(0, 0, 0), 440.0 + 3 * h, 5e-6);
  // An inside node of the cube [19,25]x[19,25]x[13,19]: (i,j,k) = (38,38,27) 0-based sits at
  // (22, 22, 15.63); its exact distance is -(z - 13) (nearest face z = 13). The original is
  // exact inside (README accuracy table); 1e-5 covers the 8-digit print and the mesh's
  // 9.999999e-01 vertices, which shift two faces by 3e-6.
  const Vec3 p = grid.position(38, 38, 27);
  EXPECT_NEAR(p.x(), 22.0, 1e-12);
  EXPECT_NEAR(f.at(38, 38, 27), -(p.z() - 13.0), 1e-5);
}

TEST(DistanceDat, RewritingTheOriginalCubeFileIsByteIdentical) {
  // The bytes being compared were written by the Fortran program: an independent check of
  // the whole layout (header, I8 columns, E20.8, record order, line ends).
  const auto path = original_cube_file();
  ASSERT_TRUE(std::filesystem::exists(path)) << "original data not found at " << path;
  const DistanceDat dat = read_distance_dat(path.parent_path());  // directory form
  const auto dir = test::scratch_dir();
  write_distance_dat(dir, dat.values, dat.nodes, 1);
  const std::string written = read_file_bytes(distance_dat_path(dir, 0));
  const std::string original = read_file_bytes(path);
  ASSERT_EQ(written.size(), original.size());
  EXPECT_TRUE(written == original) << "first difference at byte "
                                   << std::mismatch(written.begin(), written.end(), original.begin()).first -
                                          written.begin();
}

TEST(DistanceDat, EachRankFileAloneIsTheOriginalTwoRankFile) {
  // write_distance_dat_rank (one MPI rank writing its own file) against the Fortran program's
  // two rank files of the cube.
  const auto base = test::scratch_dir();  // emptied on each call: called once
  const auto dir = base / "original";
  const auto out = base / "mine";
  std::filesystem::create_directories(dir);
  std::filesystem::create_directories(out);
  for (int rank = 0; rank < 2; ++rank) {
    const std::string name = "distance_000" + std::to_string(rank) + ".dat";
    std::ofstream(dir / name, std::ios::binary)
        << test::read_xz_file(test::fixture("ppohdem-1.0/util-cube/np2/" + name + ".xz"));
  }
  const DistanceDat dat = read_distance_dat(dir);
  ASSERT_EQ(dat.nprocs, 2);
  for (int rank = 0; rank < 2; ++rank) {
    const auto file = out / ("mine_" + std::to_string(rank) + ".dat");
    write_distance_dat_rank(file, dat.values, dat.nodes, 2, rank);
    EXPECT_TRUE(read_file_bytes(file) == read_file_bytes(distance_dat_path(dir, rank))) << "rank " << rank;
  }
  EXPECT_THAT([&] { write_distance_dat_rank(out / "x.dat", dat.values, dat.nodes, 2, 2); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("expected 0 <= rank < nprocs = 2, found rank 2")));
}

// ---- round trips and malformed files ------------------------------------------------------

/// A small field whose values are exact 8-digit decimals (read back from their printed text),
/// so the round trip must reproduce them bit for bit.
std::vector<double> eight_digit_values(const Index3& nodes) {
  std::vector<double> v(static_cast<std::size_t>(nodes[0] * nodes[1] * nodes[2]));
  for (std::size_t n = 0; n < v.size(); ++n) {
    char text[40];
    const long mantissa = 10000000 + static_cast<long>((n * 7919 + 13) % 90000000);
    const int exponent = static_cast<int>(n % 9) - 4;
    std::snprintf(text, sizeof text, "%s0.%08ldE%+03d", n % 3 == 0 ? "-" : "", mantissa, exponent);
    v[n] = std::strtod(text, nullptr);
  }
  v[1] = 0.0;
  return v;
}

class DistanceDatRoundTrip : public ::testing::TestWithParam<int> {};

TEST_P(DistanceDatRoundTrip, WriteThenReadGivesTheSameValues) {
  const int nprocs = GetParam();
  const Index3 nodes = {7, 3, 2};
  const auto values = eight_digit_values(nodes);
  const auto dir = test::scratch_dir();
  write_distance_dat(dir, values, nodes, nprocs);
  for (int r = 0; r < nprocs; ++r) EXPECT_TRUE(std::filesystem::exists(distance_dat_path(dir, r)));
  EXPECT_FALSE(std::filesystem::exists(distance_dat_path(dir, nprocs)));
  const DistanceDat dat = read_distance_dat(distance_dat_path(dir, 0));
  EXPECT_EQ(dat.nodes, nodes);
  EXPECT_EQ(dat.nprocs, nprocs);
  EXPECT_EQ(dat.values, values);
}

INSTANTIATE_TEST_SUITE_P(Ranks, DistanceDatRoundTrip, ::testing::Values(1, 2, 3));

TEST(DistanceDat, RankFilesHoldTheirSlabWithHeaderOnlyOnRankZero) {
  const Index3 nodes = {7, 3, 2};
  const auto dir = test::scratch_dir();
  write_distance_dat(dir, eight_digit_values(nodes), nodes, 3);
  std::ifstream r0(distance_dat_path(dir, 0)), r1(distance_dat_path(dir, 1));
  std::string line;
  std::getline(r0, line);
  EXPECT_EQ(line, "       7       3       2       3");  // (4I8), typed by hand
  std::getline(r0, line);
  EXPECT_EQ(line.substr(0, 24), "       1       1       1");
  std::getline(r1, line);
  EXPECT_EQ(line.substr(0, 24), "       4       1       1");  // rank 1 starts at plane i = 4
  int lines = 1;
  while (std::getline(r1, line)) ++lines;
  EXPECT_EQ(lines, 2 * 3 * 2);  // 2 planes x 3 x 2
}

std::string replace_line(const std::string& text, int line_number, const std::string& by) {
  std::istringstream in(text);
  std::string out, line;
  for (int n = 1; std::getline(in, line); ++n) out += (n == line_number ? by : line) + "\n";
  return out;
}

void overwrite(const std::filesystem::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary | std::ios::trunc) << text;
}

std::string error_of(const std::filesystem::path& dir) {
  try {
    read_distance_dat(dir);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(DistanceDat, MissingRankFileIsReported) {
  const Index3 nodes = {7, 3, 2};
  const auto dir = test::scratch_dir();
  write_distance_dat(dir, eight_digit_values(nodes), nodes, 3);
  std::filesystem::remove(distance_dat_path(dir, 2));
  EXPECT_THAT(error_of(dir), AllOf(HasSubstr("distance_0002.dat"), HasSubstr("nprocs = 3"),
                                   HasSubstr("no such file")));
}

TEST(DistanceDat, TooFewRecordsAreReported) {
  const Index3 nodes = {4, 2, 2};
  const auto dir = test::scratch_dir();
  write_distance_dat(dir, eight_digit_values(nodes), nodes, 2);
  const auto rank1 = distance_dat_path(dir, 1);
  std::string text = read_file_bytes(rank1);
  text.erase(text.rfind('\n', text.size() - 2) + 1);  // drop the last record
  overwrite(rank1, text);
  EXPECT_THAT(error_of(dir), AllOf(HasSubstr("distance_0001.dat:8:"), HasSubstr("expected 8 records (i = 3..4"),
                                   HasSubstr("found only 7")));
}

TEST(DistanceDat, ExtraRecordsAreReported) {
  const Index3 nodes = {4, 2, 2};
  const auto dir = test::scratch_dir();
  write_distance_dat(dir, eight_digit_values(nodes), nodes, 1);
  const auto rank0 = distance_dat_path(dir, 0);
  overwrite(rank0, read_file_bytes(rank0) + "       1       1       1      0.10000000E+01\n");
  EXPECT_THAT(error_of(dir), AllOf(HasSubstr("distance_0000.dat:18:"), HasSubstr("found an extra line")));
}

TEST(DistanceDat, OutOfOrderIndicesAreReported) {
  const Index3 nodes = {4, 2, 2};
  const auto dir = test::scratch_dir();
  write_distance_dat(dir, eight_digit_values(nodes), nodes, 1);
  const auto rank0 = distance_dat_path(dir, 0);
  // Line 3 should be record (2,1,1); write (1,2,1) there instead.
  overwrite(rank0, replace_line(read_file_bytes(rank0), 3, "       1       2       1      0.10000000E+01"));
  EXPECT_THAT(error_of(dir), AllOf(HasSubstr("distance_0000.dat:3:"), HasSubstr("record out of order"),
                                   HasSubstr("expected i j k = 2 1 1, found 1 2 1")));
}

TEST(DistanceDat, MalformedHeaderAndRecordsAreReported) {
  const Index3 nodes = {4, 2, 2};
  const auto dir = test::scratch_dir();
  write_distance_dat(dir, eight_digit_values(nodes), nodes, 1);
  const auto rank0 = distance_dat_path(dir, 0);
  const std::string good = read_file_bytes(rank0);
  overwrite(rank0, replace_line(good, 1, "       4       2       2"));
  EXPECT_THAT(error_of(dir), AllOf(HasSubstr("distance_0000.dat:1:"), HasSubstr("4 integers")));
  overwrite(rank0, replace_line(good, 1, "       4       2       2       5"));  // nprocs > gridX
  EXPECT_THAT(error_of(dir), AllOf(HasSubstr("distance_0000.dat:1:"), HasSubstr("1 <= nprocs <= gridX")));
  overwrite(rank0, replace_line(good, 5, "       4       1       1      0.1000x000E+01"));
  EXPECT_THAT(error_of(dir), AllOf(HasSubstr("distance_0000.dat:5:"), HasSubstr("3 integers and a real")));
  overwrite(rank0, "");
  EXPECT_THAT(error_of(dir), AllOf(HasSubstr("distance_0000.dat:1:"), HasSubstr("an empty file")));
  std::filesystem::remove(rank0);
  EXPECT_THAT(error_of(dir), AllOf(HasSubstr("distance_0000.dat"), HasSubstr("no such file")));
}

TEST(DistanceDat, WriterRejectsBadArgumentsAndLeavesNoFiles) {
  const auto dir = test::scratch_dir();
  const std::vector<double> v(8, 1.0);
  EXPECT_THROW(write_distance_dat(dir, v, {2, 2, 2}, 3), InputError);  // nprocs > gridX
  EXPECT_THROW(write_distance_dat(dir, v, {2, 2, 2}, 0), InputError);
  EXPECT_THROW(write_distance_dat(dir, v, {2, 2, 3}, 1), InputError);  // 8 values for 12 nodes
  EXPECT_TRUE(std::filesystem::is_empty(dir));
}

TEST(DistanceDat, OnGridRejectsDifferentNodeCounts) {
  DistanceDat dat;
  dat.nodes = {2, 2, 2};
  dat.values.assign(8, 0.0);
  GridSpec g;
  g.nodes = {2, 2, 3};
  EXPECT_THROW(dat.on_grid(g), InputError);
}

}  // namespace
}  // namespace ppohdem
