// The VTK XML frame writer (vtu_writer.hpp) read back by an independent reader
// (tests/support/vtu_test_reader.hpp): every particle double, id and material comes back with
// its bits; the index and collection files name what they should.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <filesystem>
#include <limits>
#include <random>

#include "ppohdem/dem/vtu_writer.hpp"
#include "vtu_test_reader.hpp"

namespace fs = std::filesystem;
using ppohdem::dem::Particle;
using ppohdem::dem::Particles;

namespace {

fs::path temp_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("ppohdem_vtu_" + name + "_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

bool same_bits(const ppohdem::Vec3& a, const ppohdem::Vec3& b) {
  for (int c = 0; c < 3; ++c) {
    if (std::bit_cast<std::uint64_t>(a[c]) != std::bit_cast<std::uint64_t>(b[c])) return false;
  }
  return true;
}

Particles random_particles(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  // Any finite double: random bit patterns, so that every bit of the mantissa and exponent is
  // exercised (a text format at fewer digits would lose them).
  auto any = [&] {
    for (;;) {
      const double x = std::bit_cast<double>(rng());
      if (std::isfinite(x)) return x;
    }
  };
  Particles p(n);
  for (std::size_t i = 0; i < n; ++i) {
    p[i].id = static_cast<std::int64_t>(rng());
    p[i].position = {any(), any(), any()};
    p[i].velocity = {any(), any(), any()};
    p[i].angular_velocity = {any(), any(), any()};
    p[i].radius = std::abs(any());
    p[i].material = static_cast<std::uint16_t>(rng() % 65536);
    p[i].force = {any(), -0.0, std::numeric_limits<double>::denorm_min()};
    p[i].torque = {any(), any(), any()};
  }
  return p;
}

}  // namespace

TEST(VtuWriter, ReaderGetsBackEveryBit) {
  const fs::path dir = temp_dir("bits");
  const Particles p = random_particles(1000, 7);
  const fs::path file = dir / ppohdem::dem::vtu_piece_name(42, 0, 1);
  EXPECT_EQ(file.filename(), "frame_000042.vtu");
  ppohdem::dem::write_vtu_frame(file, p, "ppohdem test -- a header with -- dashes & <symbols>");
  const ppohdem::test::VtuRead r = ppohdem::test::read_vtu(file);
  ASSERT_EQ(r.points, p.size());
  const Particles back = ppohdem::test::particles_of(r);
  for (std::size_t i = 0; i < p.size(); ++i) {
    ASSERT_EQ(back[i].id, p[i].id) << i;
    ASSERT_TRUE(same_bits(back[i].position, p[i].position)) << i;
    ASSERT_TRUE(same_bits(back[i].velocity, p[i].velocity)) << i;
    ASSERT_TRUE(same_bits(back[i].angular_velocity, p[i].angular_velocity)) << i;
    ASSERT_EQ(std::bit_cast<std::uint64_t>(back[i].radius), std::bit_cast<std::uint64_t>(p[i].radius)) << i;
    ASSERT_EQ(back[i].material, p[i].material) << i;
    ASSERT_TRUE(same_bits(back[i].force, p[i].force)) << i;
    ASSERT_TRUE(same_bits(back[i].torque, p[i].torque)) << i;
  }
  // One vertex cell per particle: connectivity i, offsets i + 1, type VTK_VERTEX = 1.
  for (std::size_t i = 0; i < p.size(); ++i) {
    ASSERT_EQ(ppohdem::test::vtu_value<std::int64_t>(r.arrays.at("connectivity"), i), static_cast<std::int64_t>(i));
    ASSERT_EQ(ppohdem::test::vtu_value<std::int64_t>(r.arrays.at("offsets"), i), static_cast<std::int64_t>(i + 1));
    ASSERT_EQ(ppohdem::test::vtu_value<std::uint8_t>(r.arrays.at("types"), i), 1);
  }
  // The header comment holds no "--" (not allowed inside an XML comment).
  const std::string text = ppohdem::test::read_whole_file(file);
  const std::string head = text.substr(0, text.find("<VTKFile"));
  EXPECT_EQ(head.find("-- a"), std::string::npos) << head;
  // No temp file is left behind.
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir)) files += e.is_regular_file();
  EXPECT_EQ(files, 1u);
  fs::remove_all(dir);
}

TEST(VtuWriter, EmptyPieceIsValid) {
  const fs::path dir = temp_dir("empty");
  ppohdem::dem::write_vtu_frame(dir / "e.vtu", {}, "h");
  const ppohdem::test::VtuRead r = ppohdem::test::read_vtu(dir / "e.vtu");
  EXPECT_EQ(r.points, 0u);
  EXPECT_EQ(r.arrays.size(), 11u);  // points, 7 point arrays, 3 cell arrays
  fs::remove_all(dir);
}

TEST(VtuWriter, IndexAndCollectionNameTheirFiles) {
  const fs::path dir = temp_dir("index");
  EXPECT_EQ(ppohdem::dem::vtu_piece_name(7, 3, 4), "frame_000007_0003.vtu");
  ppohdem::dem::write_pvtu_index(dir / "frame_000007.pvtu", {"frame_000007_0000.vtu", "frame_000007_0001.vtu"}, "h");
  EXPECT_EQ(ppohdem::test::listed_files(dir / "frame_000007.pvtu", "Source"),
            (std::vector<std::string>{"frame_000007_0000.vtu", "frame_000007_0001.vtu"}));
  const std::string pvtu = ppohdem::test::read_whole_file(dir / "frame_000007.pvtu");
  for (const auto& a : ppohdem::dem::vtu_point_arrays()) {
    EXPECT_NE(pvtu.find(std::string("Name=\"") + a.name + "\""), std::string::npos) << a.name;
  }
  ppohdem::dem::write_pvd_collection(dir / "frames.pvd", {{0.0, "frame_000000.vtu"}, {1e-4, "frame_000100.vtu"}}, "h");
  EXPECT_EQ(ppohdem::test::listed_files(dir / "frames.pvd", "file"),
            (std::vector<std::string>{"frame_000000.vtu", "frame_000100.vtu"}));
  EXPECT_EQ(ppohdem::test::listed_files(dir / "frames.pvd", "timestep"), (std::vector<std::string>{"0", "0.0001"}));
  fs::remove_all(dir);
}
