// Regression tests for fuzzing findings 4-9 (docs/reliability.md): malformed TOML that reached
// internal preconditions of toml++ 3.3.0 (assert / __builtin_assume / __builtin_unreachable)
// must be refused by read_scene with an InputError naming the file and the line, and nothing
// else. The inputs are the reproducers the scene fuzz target replays on every run
// (tests/fuzz/regressions/scene_toml/). Before the guards of core/src/dem/toml_hardened.hpp,
// the first three aborted a build without NDEBUG and the last two were undefined behaviour in
// every build.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <iterator>
#include <fstream>
#include <string>

#include "ppohdem/dem/particle_generator.hpp"
#include "ppohdem/dem/scene.hpp"
#include "ppohdem/error.hpp"
#include "test_paths.hpp"

namespace ppohdem {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

std::filesystem::path reproducer(const std::string& name) {
  return std::filesystem::path(PPOHDEM_SOURCE_DIR) / "tests/fuzz/regressions/scene_toml" / name;
}

/// The message of the InputError read_scene throws for `file`; fails the test otherwise.
std::string scene_error(const std::filesystem::path& file) {
  try {
    (void)dem::read_scene(file);
  } catch (const InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected InputError, got another exception: " << e.what();
    return {};
  }
  ADD_FAILURE() << "expected InputError, the scene was accepted";
  return {};
}

std::string located(const std::string& name, int line) {
  return name + ":" + std::to_string(line) + ":";
}

TEST(SceneTomlGuards, TableHeaderThatCannotStartAKey) {
  // `[#`: parse_key() asserted that a key starts here (finding 4).
  EXPECT_THAT(scene_error(reproducer("tomlplusplus_parse_key_assert_1")),
              AllOf(HasSubstr(located("tomlplusplus_parse_key_assert_1", 1)), HasSubstr("malformed TOML")));
  // `[[[1]]]`: the same precondition through an array-of-tables header.
  EXPECT_THAT(scene_error(reproducer("tomlplusplus_parse_key_assert_2")),
              AllOf(HasSubstr(located("tomlplusplus_parse_key_assert_2", 1)), HasSubstr("malformed TOML")));
}

TEST(SceneTomlGuards, ArrayElementThatIsAValueTerminator) {
  // `x = [0,}]`: parse_value() asserted that a value starts here (finding 6).
  EXPECT_THAT(scene_error(reproducer("tomlplusplus_parse_value_assert_1")),
              AllOf(HasSubstr(located("tomlplusplus_parse_value_assert_1", 1)), HasSubstr("malformed TOML")));
}

TEST(SceneTomlGuards, NonAsciiOutsideCommentsIsRefusedBeforeToml) {
  // `x = [0.П]`: U+041F (bytes D0 9F) where toml++ tests for whitespace (finding 5); the
  // first non-ASCII byte is the 8th character of line 1.
  EXPECT_THAT(scene_error(reproducer("tomlplusplus_unreachable_whitespace_1")),
              AllOf(HasSubstr(located("tomlplusplus_unreachable_whitespace_1", 1)), HasSubstr("0xD0"),
                    HasSubstr("column 8")));
  EXPECT_THAT(scene_error(reproducer("tomlplusplus_unreachable_whitespace_2")),
              AllOf(HasSubstr(located("tomlplusplus_unreachable_whitespace_2", 1)), HasSubstr("0xCC"),
                    HasSubstr("column 1")));
}

TEST(SceneTomlGuards, CampaignReproducersNameTheirLine) {
  // Whole scenes mutated by the fuzzer. 10c5...: line 7 is `gravity = [0.0, 0.0, 0.П`, the
  // П (D0 9F) being the 24th character; 7132...: line 2 starts with `[#`; e9e1...: line 14
  // holds `0.0,}0.0}}}`.
  EXPECT_THAT(scene_error(reproducer("crash-10c5c545bab567c498f488eb828c34c56a62a459")),
              AllOf(HasSubstr(":7:"), HasSubstr("0xD0 at column 24")));
  EXPECT_THAT(scene_error(reproducer("crash-7132d68625197e8e662c03b2d0afe5d21dfaaf61")),
              AllOf(HasSubstr(":2:"), HasSubstr("malformed TOML")));
  EXPECT_THAT(scene_error(reproducer("crash-e9e10f1b6891bc22df61d4f422173355563ed911")),
              AllOf(HasSubstr(":14:"), HasSubstr("malformed TOML")));
}

/// two_spheres.toml (a valid scene) with `extra` appended, in a scratch directory next to its
/// particle file; returns the scene's path.
std::filesystem::path two_spheres_with(const std::string& extra) {
  const auto dir = test::scratch_dir();
  std::filesystem::copy_file(test::fixture("scenes/two_spheres.csv"), dir / "two_spheres.csv");
  std::ifstream in(test::fixture("scenes/two_spheres.toml"), std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text.append(extra);
  const auto file = dir / "scene.toml";
  std::ofstream(file, std::ios::binary) << text;
  return file;
}

TEST(SceneTomlGuards, NonAsciiInCommentsIsAccepted) {
  // The guard must not refuse what users write: units and names in comments.
  const auto file = two_spheres_with("# radius 500 \xC2\xB5m, Poisson \xCE\xBD = 0.3\n");
  const dem::Scene scene = dem::read_scene(file);
  EXPECT_EQ(scene.setup.particles.size(), 2u);
}

TEST(SceneTomlGuards, HashInsideAStringDoesNotStartAComment) {
  // `"a#\xC2\xB5"` is a string holding '#': the non-ASCII byte after it is in the string, not
  // in a comment, so it is refused, on the second appended line.
  const auto file = two_spheres_with("[extra]\nname = \"a#\xC2\xB5\"\n");
  std::ifstream in(test::fixture("scenes/two_spheres.toml"), std::ios::binary);
  const auto lines_before = std::count(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>(), '\n');
  EXPECT_THAT(scene_error(file), AllOf(HasSubstr(located("scene.toml", static_cast<int>(lines_before) + 2)),
                                       HasSubstr("0xC2"), HasSubstr("column 11")));
}

TEST(SceneTomlGuards, IntegerBeyondADoubleIsANumber) {
  // Finding 7: an integer that a double cannot hold exactly (2^63 - 1) made toml++'s
  // value<double>() empty and read_scene threw std::bad_optional_access (an abort in the fuzz
  // target). Integers are now read as the nearest double and meet the range checks.
  // d6a0...: the fuzzer's scene, `restitution = 9223372036854775807` on line 11.
  EXPECT_THAT(scene_error(reproducer("crash-d6a0ba0dee51dc798e01bafbb7d3cff3016003cc")),
              HasSubstr("restitution"));
  // In an array (the other number reader): -(2^63 - 1) rounds to -2^63, exactly representable.
  const auto file = two_spheres_with("");
  std::ifstream in(file, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  const std::string zero_gravity = "gravity = [0.0, 0.0, 0.0]";
  const auto at = text.find(zero_gravity);
  ASSERT_NE(at, std::string::npos);
  text.replace(at, zero_gravity.size(), "gravity = [0, 0, -9223372036854775807]");
  std::ofstream(file, std::ios::binary) << text;
  const dem::Scene scene = dem::read_scene(file);
  EXPECT_EQ(scene.setup.gravity.z(), -9223372036854775808.0);
  EXPECT_EQ(scene.setup.gravity.x(), 0.0);
}

/// The scene of finding 8 with `box_max` z replaced by `z` [m].
std::filesystem::path finding8_with_box_z(const std::string& z) {
  std::ifstream in(reproducer("crash-30f24aa4d0eb5630580bbf2972e1dff5233a681a"), std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string huge = "92233720368547758070.06";
  const auto at = text.find(huge);
  if (at == std::string::npos) return {};
  text.replace(at, huge.size(), z);
  // The fuzzer cut the file inside its [[wall]] table (no `normal`): drop that table, so the
  // scene is valid apart from the box.
  const auto wall = text.find("[[wall]]");
  if (wall != std::string::npos) text.erase(wall);
  const auto file = std::filesystem::path(::testing::TempDir()) / "finding8.toml";
  std::ofstream(file, std::ios::binary) << text;
  return file;
}

TEST(SceneTomlGuards, RandomFillBoxBeyondTheCellIndexRangeIsRefused) {
  // Finding 8: box_max z = 9.2e19 m with radius_max 9.2 mm is ~5e21 cells of one diameter
  // (2 radius_max = 18.4 mm) along z; the random generator's int cell index overflowed
  // (undefined behaviour, caught by UBSan). Now an InputError names the limit and the axis.
  EXPECT_THAT(scene_error(reproducer("crash-30f24aa4d0eb5630580bbf2972e1dff5233a681a")),
              AllOf(HasSubstr("2^30 particle diameters"), HasSubstr("axis 2")));
  // The limit is 2^30 cells = 2^30 x 18.4 mm = 1.9757e7 m: 2.0e7 m is refused, 1.9e7 m (a
  // valid if silly box: the index then fits an int) is accepted and its 8 spheres generated
  // inside it.
  const auto over = finding8_with_box_z("2.0e7");
  ASSERT_FALSE(over.empty());
  EXPECT_THAT(scene_error(over), HasSubstr("axis 2"));
  const auto under = finding8_with_box_z("1.9e7");
  const dem::Scene scene = dem::read_scene(under);
  ASSERT_EQ(scene.setup.particles.size(), 8u);
  for (const auto& p : scene.setup.particles) {
    EXPECT_GE(p.position.z(), 0.0);
    EXPECT_LE(p.position.z(), 1.9e7);
  }
}

TEST(SceneTomlGuards, LatticeOfATinyRadiusInALargeBox) {
  // Finding 9: `radius = 10.0e-23` in a 5 cm box gave 2.3e20 lattice sites per axis; the
  // conversion of that count to int64 was undefined behaviour (UBSan). The reproducer now
  // reads without it (its [material] lacks `young`, so it ends in an InputError).
  const std::string message = scene_error(reproducer("crash-f77523134e8975befcd2ebe74c391514760b28da"));
  EXPECT_THAT(message, HasSubstr("crash-f77523134e8975befcd2ebe74c391514760b28da"));
  // The generator itself: 8 spheres of R = 1e-22 m fit (one row along x), at the pitch
  // 2 R (1 + 1e-3) + 2 jitter R of the lattice, ids 1..8.
  dem::GeneratorSpec g;
  g.kind = dem::GeneratorKind::kLattice;
  g.box_max = Vec3(0.05, 0.03, 0.06);
  g.count = 8;
  g.radius = 1.0e-22;
  g.jitter = 0.1;
  g.seed = 42;
  const dem::Particles p = dem::generate_particles(g, "test");
  ASSERT_EQ(p.size(), 8u);
  const double pitch = 2.0 * g.radius * (1.0 + 1.0e-3) + 2.0 * g.jitter * g.radius;
  for (std::size_t n = 0; n < p.size(); ++n) {
    EXPECT_EQ(p[n].id, static_cast<std::int64_t>(n + 1));
    // Site n at (R + jitter R) + n pitch along x, moved by at most jitter R per axis.
    EXPECT_NEAR(p[n].position.x(), 1.1 * g.radius + static_cast<double>(n) * pitch, 0.1 * g.radius * (1.0 + 1e-12));
    EXPECT_NEAR(p[n].position.y(), 1.1 * g.radius, 0.1 * g.radius * (1.0 + 1e-12));
    EXPECT_NEAR(p[n].position.z(), 1.1 * g.radius, 0.1 * g.radius * (1.0 + 1e-12));
  }
  // A box that cannot hold the count is still refused, with the true (small) capacity: a
  // 2.5 x 2.5 x 1 mm box holds 2 x 2 x 1 spheres of R = 0.5 mm (pitch 1.051 mm with jitter 0.05).
  g.radius = 0.5e-3;
  g.jitter = 0.05;
  g.box_max = Vec3(2.5e-3, 2.5e-3, 1.0e-3);
  g.count = 5;
  try {
    (void)dem::generate_particles(g, "test");
    ADD_FAILURE() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("holds 4 particles"));
  }
}

}  // namespace
}  // namespace ppohdem
