// Library pieces the Python module exposes (bindings/python, docs/python.md): scenes from TOML
// text with particles given as arrays, and the field-by-field comparison of two runs.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>

#include "ppohdem/dem/particle_compare.hpp"
#include "ppohdem/dem/scene.hpp"
#include "ppohdem/error.hpp"

namespace ppohdem::dem {
namespace {

constexpr const char* kScene = R"(
[simulation]
dt = 1.0e-7
steps = 10
[material]
density = 2500.0
young = 1.0e7
poisson = 0.3
restitution = 0.5
[contact]
model = "hertz-mindlin"
[output]
dir = "out"
)";

Particles two_particles() {
  Particles p(2);
  p[0].id = 1;
  p[0].position = Vec3(-0.00055, 0, 0);
  p[0].radius = 0.0005;
  p[1].id = 2;
  p[1].position = Vec3(0.00055, 0, 0);
  p[1].radius = 0.0005;
  return p;
}

TEST(SceneText, GivenParticlesAndBaseDirectory) {
  const Scene s = read_scene_text(kScene, "dict", "/some/where", two_particles());
  ASSERT_EQ(s.setup.particles.size(), 2u);
  EXPECT_EQ(s.setup.particles[1].id, 2);
  EXPECT_EQ(s.steps, 10);
  EXPECT_EQ(s.output.dir, std::filesystem::path("/some/where/out"));  // relative to base_dir
}

TEST(SceneText, ErrorsNameTheGivenNameAndLine) {
  try {
    read_scene_text(std::string(kScene) + "[particles]\nfile = \"p.csv\"\n", "dict", ".", two_particles());
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "dict");
    EXPECT_EQ(e.line(), 15u);  // the `file` key: given particles exclude file =
    EXPECT_NE(e.message().find("unknown key 'file'"), std::string::npos) << e.message();
  }
}

TEST(SceneText, WithoutParticlesNeedsTheTable) {
  EXPECT_THROW(read_scene_text(kScene, "dict", "."), InputError);
}

TEST(SceneText, MaterialIndexOutOfRangeIsAnError) {
  Particles p = two_particles();
  p[1].material = 1;  // the scene has one material
  EXPECT_THROW(read_scene_text(kScene, "dict", ".", p), InputError);
}

TEST(CompareParticles, EqualRunsAreBitwise) {
  const ParticleDifference d = compare_particles(two_particles(), two_particles());
  EXPECT_TRUE(d.bitwise);
  EXPECT_EQ(d.max_position, 0.0);
}

TEST(CompareParticles, ReportsTheLargestDifferencePerField) {
  Particles a = two_particles(), b = two_particles();
  b[1].velocity.y() = 0.25;
  b[0].velocity.z() = -0.5;
  b[0].torque.x() = 1e-9;
  const ParticleDifference d = compare_particles(a, b);
  EXPECT_FALSE(d.bitwise);
  EXPECT_EQ(d.max_velocity, 0.5);
  EXPECT_EQ(d.max_torque, 1e-9);
  EXPECT_EQ(d.max_position, 0.0);
}

TEST(CompareParticles, SignedZeroIsNotBitwiseAndNanPropagates) {
  Particles a = two_particles(), b = two_particles();
  b[0].force.x() = -0.0;
  EXPECT_FALSE(compare_particles(a, b).bitwise);
  EXPECT_EQ(compare_particles(a, b).max_force, 0.0);
  b[1].position.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(std::isnan(compare_particles(a, b).max_position));
}

TEST(CompareParticles, DifferentIdsAreAnError) {
  Particles a = two_particles(), b = two_particles();
  b[1].id = 7;
  EXPECT_THROW(compare_particles(a, b), InputError);
  b.pop_back();
  EXPECT_THROW(compare_particles(a, b), InputError);
}

}  // namespace
}  // namespace ppohdem::dem
