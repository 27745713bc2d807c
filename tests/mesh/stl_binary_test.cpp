// Binary STL reader and the ASCII/binary detection rule. Bytes are built field by field in
// mesh_test_support.hpp, independently of write_stl.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "mesh_test_support.hpp"
#include "ppohdem/mesh/stl_io.hpp"
#include "test_paths.hpp"

namespace ppohdem {
namespace {

using test::binary_stl_bytes;
using test::capture_input_error;
using Record = std::array<float, 12>;

const Record kTriangleA = {0, 0, 1, 0.1f, 0.2f, 0.3f, 1.5f, 0.25f, -3, 1e-3f, 7, 0};
const Record kTriangleB = {0, 0, 0, -1, -1, -1, 2, 2, 2, 3e5f, -2e-5f, 4};

TEST(StlBinaryReader, ReadsFloat32RecordsExactly) {
  StlReadReport report;
  const auto mesh = read_stl_bytes(binary_stl_bytes({kTriangleA, kTriangleB}), "b.stl", &report);
  EXPECT_EQ(report.encoding, StlEncoding::kBinary);
  ASSERT_EQ(mesh.size(), 2u);
  EXPECT_EQ(mesh.name, "test");
  const Record* records[2] = {&kTriangleA, &kTriangleB};
  for (std::size_t t = 0; t < 2; ++t) {
    const Record& r = *records[t];
    for (int a = 0; a < 3; ++a) {
      EXPECT_EQ(mesh.triangles[t].file_normal[a], static_cast<double>(r[static_cast<std::size_t>(a)]));
      for (std::size_t k = 0; k < 3; ++k) {
        // float -> double is exact, so equality is the right test
        EXPECT_EQ(mesh.triangles[t].v[k][a], static_cast<double>(r[3 * (k + 1) + static_cast<std::size_t>(a)]));
      }
    }
  }
}

TEST(StlBinaryReader, HeaderStartingWithSolidIsReadAsBinaryWhenSizeMatches) {
  const auto bytes = binary_stl_bytes({kTriangleA}, "solid exported by a CAD tool");
  StlReadReport report;
  const auto mesh = read_stl_bytes(bytes, "b.stl", &report);
  EXPECT_EQ(report.encoding, StlEncoding::kBinary);
  ASSERT_EQ(mesh.size(), 1u);
  EXPECT_EQ(mesh.triangles[0].v[1], Vec3(1.5f, 0.25f, -3.0f));
}

TEST(StlBinaryReader, FixtureWithSolidHeaderIsBinary) {
  StlReadReport report;
  const auto mesh = read_stl(test::fixture("mesh-cases/binary_header_solid.stl"), &report);
  EXPECT_EQ(report.encoding, StlEncoding::kBinary);
  ASSERT_EQ(mesh.size(), 2u);
  // the fixture's README lists its vertices: a unit right triangle in z = 0 and one in z = 1
  EXPECT_EQ(mesh.triangles[1].v[2], Vec3(0, 1, 1));
}

TEST(StlBinaryReader, RejectsFileShorterThanPreamble) {
  const auto e = capture_input_error([] { read_stl_bytes("hello", "short.stl"); });
  EXPECT_EQ(e.file(), "short.stl");
  EXPECT_NE(e.message().find("truncated binary STL: expected at least 84 bytes"),
            std::string::npos)
      << e.what();
  EXPECT_NE(e.message().find("found 5 bytes"), std::string::npos) << e.what();
}

TEST(StlBinaryReader, RejectsTruncatedBinaryNamingIncompleteTriangle) {
  std::string bytes = binary_stl_bytes({kTriangleA, kTriangleB, kTriangleA});
  bytes.resize(bytes.size() - 25);  // half of triangle 3 missing
  const auto e = capture_input_error([&] { read_stl_bytes(bytes, "cut.stl"); });
  EXPECT_NE(e.message().find("truncated"), std::string::npos) << e.what();
  EXPECT_NE(e.message().find("84 + 50 * 3 = 234 bytes, found 209"), std::string::npos)
      << e.what();
  EXPECT_NE(e.message().find("triangle 3 is incomplete"), std::string::npos) << e.what();
}

TEST(StlBinaryReader, RejectsPaddedBinary) {
  std::string bytes = binary_stl_bytes({kTriangleA});
  bytes += "xyz";
  const auto e = capture_input_error([&] { read_stl_bytes(bytes, "pad.stl"); });
  EXPECT_NE(e.message().find("padded binary STL (size/count mismatch)"), std::string::npos)
      << e.what();
}

TEST(StlBinaryReader, RejectsCountLargerThanData) {
  const auto bytes = binary_stl_bytes({kTriangleA}, "hdr", 1000);
  const auto e = capture_input_error([&] { read_stl_bytes(bytes, "n.stl"); });
  EXPECT_NE(e.message().find("the header says 1000 triangles"), std::string::npos) << e.what();
  EXPECT_NE(e.message().find("triangle 2 is incomplete"), std::string::npos) << e.what();
}

TEST(StlBinaryReader, RejectsNonFiniteCoordinateNamingTriangle) {
  Record bad = kTriangleB;
  bad[11] = std::numeric_limits<float>::quiet_NaN();  // vertex 3, z
  const auto e = capture_input_error(
      [&] { read_stl_bytes(binary_stl_bytes({kTriangleA, bad}), "nan.stl"); });
  EXPECT_NE(e.message().find("non-finite coordinate in triangle 2 of 2, vertex 3, axis z"),
            std::string::npos)
      << e.what();
}

TEST(StlBinaryReader, ZeroesNonFiniteNormalsAndCountsDegenerateTriangles) {
  Record flat = {std::numeric_limits<float>::infinity(), 0, 0, 1, 1, 1, 1, 1, 1, 2, 2, 2};
  StlReadReport report;
  const auto mesh = read_stl_bytes(binary_stl_bytes({flat, kTriangleA}), "d.stl", &report);
  EXPECT_EQ(mesh.size(), 2u);
  EXPECT_EQ(mesh.triangles[0].file_normal, Vec3::Zero());
  EXPECT_EQ(report.non_finite_normals, 1u);
  EXPECT_EQ(report.degenerate_triangles, 1u);
}

TEST(StlDetection, SolidTextWithWrongBinarySizeKeepsTheAsciiError) {
  // Not valid ASCII and its size is not 84 + 50 n: the user sees the ASCII problem.
  const std::string text = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n";
  const auto e = capture_input_error([&] { read_stl_bytes(text, "a.stl"); });
  EXPECT_EQ(e.line(), 4u);
  EXPECT_NE(e.message().find("found end of file"), std::string::npos) << e.what();
}

}  // namespace
}  // namespace ppohdem
