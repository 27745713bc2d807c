// Legacy VTK STRUCTURED_POINTS: bit-exact round trips, a hand-checked byte layout, a
// hand-written ASCII file, and one message per malformed header.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <bit>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>

#include "ppohdem/error.hpp"
#include "ppohdem/io/legacy_inputs.hpp"
#include "ppohdem/io/vtk_structured_points.hpp"
#include "test_paths.hpp"

namespace ppohdem {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

RC_GTEST_PROP(VtkStructuredPoints, DoubleRoundTripIsBitExact, ()) {
  GridSpec g;
  for (int a = 0; a < 3; ++a) {
    g.nodes[static_cast<std::size_t>(a)] = *rc::gen::inRange(1, 6);
    // Any finite origin and positive spacing: written with shortest round-trip text.
    g.origin[a] = *rc::gen::arbitrary<double>();
    g.spacing[a] = std::abs(*rc::gen::arbitrary<double>()) + 1e-300;
    RC_PRE(std::isfinite(g.origin[a]) && std::isfinite(g.spacing[a]));
  }
  ScalarField f(g);
  for (double& v : f.values) v = *rc::gen::arbitrary<double>();  // includes inf, nan, -0, subnormals
  // A fixed name: a property run may re-use the file (each write replaces it atomically).
  static const auto dir = [] {
    auto d = std::filesystem::path(PPOHDEM_BINARY_DIR) / "test-scratch" / "VtkStructuredPoints.RoundTrip";
    std::filesystem::create_directories(d);
    return d;
  }();
  const auto path = dir / "field.vtk";
  write_vtk_structured_points(path, f, "sdf");
  std::string name;
  const ScalarField back = read_vtk_structured_points(path, &name);
  RC_ASSERT(name == "sdf");
  RC_ASSERT(back.grid == g);
  RC_ASSERT(back.values.size() == f.values.size());
  for (std::size_t i = 0; i < f.values.size(); ++i) {
    RC_ASSERT(std::bit_cast<std::uint64_t>(back.values[i]) == std::bit_cast<std::uint64_t>(f.values[i]));
  }
}

TEST(VtkStructuredPoints, TinyFileHasTheExpectedBytes) {
  // 2 x 1 x 1 nodes, values 1.0 and -2.0: header typed by hand from the VTK legacy spec, data
  // bytes of the big-endian IEEE doubles typed by hand: 1.0 = 3F F0 00.., -2.0 = C0 00 00...
  GridSpec g;
  g.nodes = {2, 1, 1};
  g.origin = Vec3(0.5, -1, 0);
  g.spacing = Vec3(0.25, 1, 2);
  ScalarField f(g);
  f.values = {1.0, -2.0};
  const auto path = test::scratch_dir() / "tiny.vtk";
  write_vtk_structured_points(path, f, "distance", "tiny test");
  const std::string expected_header =
      "# vtk DataFile Version 3.0\n"
      "tiny test\n"
      "BINARY\n"
      "DATASET STRUCTURED_POINTS\n"
      "DIMENSIONS 2 1 1\n"
      "ORIGIN 0.5 -1 0\n"
      "SPACING 0.25 1 2\n"
      "POINT_DATA 2\n"
      "SCALARS distance double 1\n"
      "LOOKUP_TABLE default\n";
  const unsigned char data[] = {0x3F, 0xF0, 0, 0, 0, 0, 0, 0, 0xC0, 0x00, 0, 0, 0, 0, 0, 0, '\n'};
  const std::string expected = expected_header + std::string(reinterpret_cast<const char*>(data), sizeof data);
  EXPECT_EQ(read_file_bytes(path), expected);
}

TEST(VtkStructuredPoints, FloatFileHasBigEndianSinglesAndReadsBack) {
  GridSpec g;
  g.nodes = {1, 1, 2};
  ScalarField f(g);
  f.values = {1.0, 0.1};
  const auto path = test::scratch_dir() / "float.vtk";
  write_vtk_structured_points(path, f, "d", "t", VtkScalarType::kFloat);
  const std::string bytes = read_file_bytes(path);
  // 1.0f = 3F 80 00 00 (hand-typed); the data starts after "LOOKUP_TABLE default\n".
  const std::size_t start = bytes.find("LOOKUP_TABLE default\n") + 21;
  EXPECT_EQ(bytes.substr(start, 4), std::string("\x3F\x80\x00\x00", 4));
  EXPECT_THAT(bytes, HasSubstr("SCALARS d float 1\n"));
  const ScalarField back = read_vtk_structured_points(path);
  EXPECT_EQ(back.values[0], 1.0);
  EXPECT_EQ(back.values[1], static_cast<double>(0.1f));  // float precision, by design
}

TEST(VtkStructuredPoints, ReadsHandWrittenAsciiWithMixedCaseAndNoLookupTable) {
  const std::string text =
      "# vtk DataFile Version 2.0\r\n"
      "hand written\r\n"
      "ascii\r\n"
      "dataset structured_points\r\n"
      "Spacing 0.5 0.5 2\r\n"
      "Origin 1 2 3\r\n"
      "Dimensions 3 2 1\r\n"
      "\r\n"
      "point_data 6\r\n"
      "scalars phi float\r\n"
      "0 1.5 -2\r\n"
      "3e2   4\r\n"
      "5.25\r\n";
  std::string name;
  const ScalarField f = read_vtk_structured_points_bytes(text, "hand.vtk", &name);
  EXPECT_EQ(name, "phi");
  EXPECT_EQ(f.grid.nodes, (Index3{3, 2, 1}));
  EXPECT_EQ(f.grid.origin, Vec3(1, 2, 3));
  EXPECT_EQ(f.grid.spacing, Vec3(0.5, 0.5, 2));
  EXPECT_EQ(f.values, (std::vector<double>{0, 1.5, -2, 300, 4, 5.25}));
  EXPECT_EQ(f.at(2, 1, 0), 5.25);  // x fastest
}

TEST(VtkStructuredPoints, ReadsAsciiWithLookupTable) {
  const std::string text =
      "# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 1 1 2\n"
      "ORIGIN 0 0 0\nSPACING 1 1 1\nPOINT_DATA 2\nSCALARS distance double 1\nLOOKUP_TABLE default\n7 8\n";
  const ScalarField f = read_vtk_structured_points_bytes(text, "a.vtk");
  EXPECT_EQ(f.values, (std::vector<double>{7, 8}));
}

struct BadHeader {
  const char* name;
  std::string text;
  int line;
  std::string words;
};

std::string header_with(const std::string& replace_what, const std::string& by) {
  std::string t =
      "# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 1 1\n"
      "ORIGIN 0 0 0\nSPACING 1 1 1\nPOINT_DATA 2\nSCALARS distance double 1\nLOOKUP_TABLE default\n1 2\n";
  const auto at = t.find(replace_what);
  if (at == std::string::npos) throw std::logic_error("test setup: " + replace_what);
  return t.replace(at, replace_what.size(), by);
}

void PrintTo(const BadHeader& c, std::ostream* os) { *os << c.name; }

class MalformedVtk : public ::testing::TestWithParam<BadHeader> {};

TEST_P(MalformedVtk, FailsWithFileLineAndReason) {
  const BadHeader& c = GetParam();
  try {
    read_vtk_structured_points_bytes(c.text, "bad.vtk");
    FAIL() << c.name;
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("bad.vtk:" + std::to_string(c.line) + ":")) << c.name;
    EXPECT_THAT(e.what(), HasSubstr(c.words)) << c.name;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, MalformedVtk,
    ::testing::Values(
        BadHeader{"NotVtk", header_with("# vtk DataFile Version 3.0", "hello"), 1, "expected '# vtk DataFile"},
        BadHeader{"BadEncoding", header_with("ASCII", "TEXT"), 3, "expected 'ASCII' or 'BINARY'"},
        BadHeader{"UnsupportedDataset", header_with("STRUCTURED_POINTS", "UNSTRUCTURED_GRID"), 4,
                  "unsupported dataset 'UNSTRUCTURED_GRID'"},
        BadHeader{"TwoDimensions", header_with("DIMENSIONS 2 1 1", "DIMENSIONS 2 1"), 5,
                  "expected 'DIMENSIONS nx ny nz'"},
        BadHeader{"ZeroDimension", header_with("DIMENSIONS 2 1 1", "DIMENSIONS 2 0 1"), 5,
                  "DIMENSIONS >= 1"},
        BadHeader{"TextDimension", header_with("DIMENSIONS 2 1 1", "DIMENSIONS 2 x 1"), 5, "found 'x'"},
        BadHeader{"NegativeSpacing", header_with("SPACING 1 1 1", "SPACING 1 -1 1"), 7, "SPACING > 0"},
        BadHeader{"PointDataMismatch", header_with("POINT_DATA 2", "POINT_DATA 3"), 8,
                  "POINT_DATA 3 does not match DIMENSIONS 2 x 1 x 1 = 2"},
        BadHeader{"IntegerScalars", header_with("distance double", "distance int"), 9,
                  "unsupported scalar type 'int'"},
        BadHeader{"ThreeComponents", header_with("double 1", "double 3"), 9, "expected 1 component"},
        BadHeader{"UnknownKeyword", header_with("ORIGIN 0 0 0", "EXTENT 0 0 0"), 6, "found 'EXTENT'"},
        BadHeader{"ShortAscii", header_with("1 2\n", "1\n"), 11, "expected 2 ASCII values, found only 1"},
        BadHeader{"NonNumericAscii", header_with("1 2\n", "1 two\n"), 11, "expected a real value, found 'two'"},
        BadHeader{"ShortBinary", header_with("ASCII", "BINARY"), 11,
                  "expected 2 binary double values (16 bytes), found only 4 bytes"},
        BadHeader{"Truncated", "# vtk DataFile Version 3.0\nt\nBINARY\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 1 1\n",
                  5, "found end of file"}),
    [](const ::testing::TestParamInfo<BadHeader>& param_info) { return std::string(param_info.param.name); });

TEST(VtkStructuredPoints, MissingFileErrorNamesIt) {
  const auto path = test::scratch_dir() / "none.vtk";
  EXPECT_THROW(
      try { read_vtk_structured_points(path); } catch (const InputError& e) {
        EXPECT_THAT(e.what(), HasSubstr("none.vtk"));
        throw;
      },
      InputError);
}

TEST(VtkStructuredPoints, WriterRejectsNameWithSpacesAndWrongValueCount) {
  GridSpec g;
  g.nodes = {2, 2, 2};
  ScalarField f(g);
  const auto dir = test::scratch_dir();
  EXPECT_THROW(write_vtk_structured_points(dir / "a.vtk", f, "two words"), InputError);
  f.values.pop_back();
  EXPECT_THROW(write_vtk_structured_points(dir / "b.vtk", f), InputError);
  EXPECT_FALSE(std::filesystem::exists(dir / "b.vtk"));
}

TEST(VtkStructuredPoints, TitleIsKeptOnOneLine) {
  GridSpec g;
  ScalarField f(g, 1.0);
  const auto path = test::scratch_dir() / "t.vtk";
  write_vtk_structured_points(path, f, "d", "two\nlines");
  EXPECT_THAT(read_file_bytes(path), HasSubstr("\ntwo lines\nBINARY\n"));
  EXPECT_EQ(read_vtk_structured_points(path).values, std::vector<double>{1.0});
}

}  // namespace
}  // namespace ppohdem
