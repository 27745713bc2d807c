// STL writer: write -> read gives back the same bits (ASCII with 17 significant digits for any
// finite double; binary for float32-representable coordinates), and writing is atomic.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>

#include "mesh_test_support.hpp"
#include "ppohdem/mesh/stl_io.hpp"
#include "test_paths.hpp"

namespace ppohdem {
namespace {

using test::capture_input_error;

/// Bit-level equality: distinguishes -0.0 from +0.0, which == does not.
bool same_bits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

void expect_same_vertices(const TriangleMesh& written, const TriangleMesh& read) {
  ASSERT_EQ(written.size(), read.size());
  for (std::size_t t = 0; t < written.size(); ++t) {
    for (std::size_t k = 0; k < 3; ++k) {
      for (int a = 0; a < 3; ++a) {
        ASSERT_TRUE(same_bits(written.triangles[t].v[k][a], read.triangles[t].v[k][a]))
            << "triangle " << t << " vertex " << k << " axis " << a << ": wrote "
            << written.triangles[t].v[k][a] << ", read " << read.triangles[t].v[k][a];
      }
    }
  }
}

TriangleMesh float_mesh() {
  TriangleMesh mesh = test::unit_cube();
  for (Triangle& t : mesh.triangles) {
    for (Vec3& p : t.v) p = p * 0.375 + Vec3(-0.0, 3.25, -1.5);  // all float-representable
  }
  mesh.name = "float cube";
  return mesh;
}

TEST(StlWriter, AsciiRoundTripKeepsBits) {
  const auto path = test::scratch_dir() / "cube.stl";
  const TriangleMesh mesh = float_mesh();
  write_stl(path, mesh, StlEncoding::kAscii);
  StlReadReport report;
  const TriangleMesh back = read_stl(path, &report);
  EXPECT_EQ(report.encoding, StlEncoding::kAscii);
  EXPECT_EQ(back.name, "float cube");
  expect_same_vertices(mesh, back);
}

TEST(StlWriter, BinaryRoundTripKeepsBitsOfFloatCoordinates) {
  const auto path = test::scratch_dir() / "cube.stl";
  const TriangleMesh mesh = float_mesh();
  write_stl(path, mesh, StlEncoding::kBinary);
  EXPECT_EQ(std::filesystem::file_size(path), 84u + 50u * mesh.size());
  StlReadReport report;
  const TriangleMesh back = read_stl(path, &report);
  EXPECT_EQ(report.encoding, StlEncoding::kBinary);
  expect_same_vertices(mesh, back);
}

TEST(StlWriter, WritesUnitOutwardNormalsUnlessFileNormalsAsked) {
  const auto path = test::scratch_dir() / "cube.stl";
  TriangleMesh cube = test::unit_cube();
  cube.triangles[0].file_normal = Vec3(7, 8, 9);
  write_stl(path, cube, StlEncoding::kAscii);
  const TriangleMesh recomputed = read_stl(path);
  // face z = 0 of the unit cube: outward normal is -z, exactly representable
  EXPECT_EQ(recomputed.triangles[0].file_normal, Vec3(0, 0, -1));
  write_stl(path, cube, StlEncoding::kAscii, /*use_file_normals=*/true);
  EXPECT_EQ(read_stl(path).triangles[0].file_normal, Vec3(7, 8, 9));
}

TEST(StlWriter, FewerDigitsRoundCoordinates) {
  const auto path = test::scratch_dir() / "third.stl";
  TriangleMesh mesh;
  mesh.triangles.push_back(test::make_triangle(Vec3(1.0 / 3.0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)));
  write_stl(path, mesh, StlEncoding::kAscii, false, 6);
  EXPECT_EQ(read_stl(path).triangles[0].v[0].x(), 0.333333);  // "%.6g" of 1/3
}

TEST(StlWriter, RejectsInvalidPrecisionAndFloatOverflow) {
  const auto dir = test::scratch_dir();
  const auto e = capture_input_error(
      [&] { write_stl(dir / "p.stl", test::unit_cube(), StlEncoding::kAscii, false, 18); });
  EXPECT_NE(e.message().find("expected 1..17 significant digits, found 18"), std::string::npos);
  TriangleMesh huge = test::unit_cube();
  huge.triangles[3].v[1].y() = 1e300;  // beyond float32
  const auto e2 =
      capture_input_error([&] { write_stl(dir / "h.stl", huge, StlEncoding::kBinary); });
  EXPECT_NE(e2.message().find("triangle 4"), std::string::npos) << e2.what();
  EXPECT_FALSE(std::filesystem::exists(dir / "h.stl"));  // atomic: nothing left behind
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir),
                          std::filesystem::directory_iterator()),
            0);  // no temp file either
}

TEST(StlWriter, FailedWriteLeavesExistingFileUntouched) {
  const auto path = test::scratch_dir() / "keep.stl";
  write_stl(path, test::unit_cube(), StlEncoding::kBinary);
  const auto size_before = std::filesystem::file_size(path);
  TriangleMesh huge = test::unit_cube();
  huge.triangles[0].v[0].x() = -1e300;
  EXPECT_THROW(write_stl(path, huge, StlEncoding::kBinary), InputError);
  EXPECT_EQ(std::filesystem::file_size(path), size_before);
  EXPECT_EQ(read_stl(path).size(), 12u);
}

TEST(StlWriter, RejectsMissingDirectory) {
  const auto path = test::scratch_dir() / "no-such-dir" / "x.stl";
  EXPECT_THROW(write_stl(path, test::unit_cube(), StlEncoding::kAscii), InputError);
}

/// A finite double from arbitrary bits (covers subnormals, -0, huge and tiny values).
rc::Gen<double> finite_double() {
  return rc::gen::map(
      rc::gen::suchThat(rc::gen::arbitrary<std::uint64_t>(),
                        [](std::uint64_t b) { return std::isfinite(std::bit_cast<double>(b)); }),
      [](std::uint64_t b) { return std::bit_cast<double>(b); });
}

rc::Gen<double> finite_float_as_double() {
  return rc::gen::map(
      rc::gen::suchThat(rc::gen::arbitrary<std::uint32_t>(),
                        [](std::uint32_t b) { return std::isfinite(std::bit_cast<float>(b)); }),
      [](std::uint32_t b) { return static_cast<double>(std::bit_cast<float>(b)); });
}

TriangleMesh mesh_from(const std::vector<double>& c) {
  TriangleMesh mesh;
  for (std::size_t i = 0; i + 9 <= c.size(); i += 9) {
    mesh.triangles.push_back(test::make_triangle(Vec3(c[i], c[i + 1], c[i + 2]),
                                                 Vec3(c[i + 3], c[i + 4], c[i + 5]),
                                                 Vec3(c[i + 6], c[i + 7], c[i + 8])));
  }
  return mesh;
}

// Write `coords` (9 per triangle) with `encoding`, read back, and require identical bits.
void check_round_trip_keeps_bits(const std::vector<double>& coords, StlEncoding encoding, const char* file_name) {
  const TriangleMesh mesh = mesh_from(coords);
  const auto path = std::filesystem::path(PPOHDEM_BINARY_DIR) / "test-scratch" / file_name;
  std::filesystem::create_directories(path.parent_path());
  write_stl(path, mesh, encoding);
  const TriangleMesh back = read_stl(path);
  RC_ASSERT(back.size() == mesh.size());
  for (std::size_t t = 0; t < mesh.size(); ++t)
    for (std::size_t k = 0; k < 3; ++k)
      for (int a = 0; a < 3; ++a)
        RC_ASSERT(same_bits(back.triangles[t].v[k][a], mesh.triangles[t].v[k][a]));
}

RC_GTEST_PROP(StlWriterProperty, AsciiRoundTripKeepsBitsOfAnyFiniteDouble, ()) {
  const auto n = *rc::gen::inRange<std::size_t>(1, 8);
  check_round_trip_keeps_bits(*rc::gen::container<std::vector<double>>(9 * n, finite_double()),
                              StlEncoding::kAscii, "rc_ascii.stl");
}

RC_GTEST_PROP(StlWriterProperty, BinaryRoundTripKeepsBitsOfAnyFiniteFloat, ()) {
  const auto n = *rc::gen::inRange<std::size_t>(0, 8);
  check_round_trip_keeps_bits(*rc::gen::container<std::vector<double>>(9 * n, finite_float_as_double()),
                              StlEncoding::kBinary, "rc_binary.stl");
}

}  // namespace
}  // namespace ppohdem
