// [[object.motion]] segments in scene files (issue 38, item 1): every type read into the
// program with its SI values, and bad input named by file, line and what was expected.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "object_fields.hpp"
#include "ppohdem/dem/scene.hpp"
#include "ppohdem/error.hpp"
#include "ppohdem/io/vtk_structured_points.hpp"
#include "ppohdem/units.hpp"
#include "test_paths.hpp"

namespace ppohdem::dem::test {
namespace {

namespace fs = std::filesystem;

const char* const kHead =
    "[simulation]\ndt = 1e-6\nsteps = 10\ngravity = [0, 0, -9.81]\n"
    "[material]\ndensity = 2500.0\nyoung = 1e7\npoisson = 0.3\nrestitution = 0.5\nfriction = 0.5\n"
    "[contact]\nmodel = \"hertz-mindlin\"\n"
    "[particles]\nfile = \"p.csv\"\n"
    "[[object]]\ndistance = \"plate.vtk\"\ncentroid = [0.001, 0.002, 0.003]\n";

fs::path scene_dir() {
  const fs::path dir = ppohdem::test::scratch_dir();
  std::ofstream(dir / "p.csv") << "id,x,y,z,vx,vy,vz,wx,wy,wz,radius\n1,0,0,0.01,0,0,0,0,0,0,0.001\n";
  const GridSpec grid{Vec3(-5e-3, -5e-3, -2e-3), Vec3::Constant(1e-3), {11, 11, 5}};
  write_vtk_structured_points(dir / "plate.vtk", half_space_field(grid, Vec3::Zero(), Vec3::UnitZ()));
  return dir;
}

/// 1-based line of the first occurrence of `needle` in `text`.
std::size_t line_of(const std::string& text, const std::string& needle) {
  const std::size_t at = text.find(needle);
  EXPECT_NE(at, std::string::npos) << needle;
  std::size_t line = 1;
  for (std::size_t i = 0; i < at; ++i) line += text[i] == '\n';
  return line;
}

TEST(MotionProgramScene, EveryTypeIsReadWithItsSiValues) {
  const fs::path dir = scene_dir();
  const std::string text = std::string(kHead) +
      "[[object.motion]]\nstart = 0.5\ntype = \"rest\"\n"
      "[[object.motion]]\nstart = 1\ntype = \"translate\"\nvelocity = [0.1, 0, 0]\n"
      "[[object.motion]]\nstart = 2.0\ntype = \"rotate\"\naxis = [0, 0, 2]\nomega = 3.0\npoint = [1, 2, 3]\n"
      "[[object.motion]]\nstart = 3.0\ntype = \"translate_rotate\"\nvelocity = [0, 0.2, 0]\naxis = [3, 0, 4]\n"
      "omega = -1.0\n"
      "[[object.motion]]\nstart = 4.0\ntype = \"vibrate_translate\"\namplitude = [0, 0, 0.001]\nfrequency = 50.0\n"
      "[[object.motion]]\nstart = 5.0\ntype = \"vibrate_rotate\"\naxis = [0, 1, 0]\namplitude = 0.1\nperiod = 0.25\n"
      "phase = 0.5\n";
  const Scene scene = read_scene_text(text, "s.toml", dir);
  ASSERT_EQ(scene.objects.size(), 1u);
  const MotionProgram& p = scene.objects[0].object->program();
  EXPECT_EQ(p.reference_point(), Vec3(0.001, 0.002, 0.003));
  const auto& s = p.segments();
  ASSERT_EQ(s.size(), 6u);
  const double starts[] = {0.5, 1.0, 2.0, 3.0, 4.0, 5.0};
  for (std::size_t k = 0; k < 6; ++k) EXPECT_EQ(s[k].start, starts[k]);
  EXPECT_EQ(s[0].translation.profile, MotionProfile::none);
  EXPECT_EQ(s[0].rotation.profile, MotionProfile::none);
  EXPECT_EQ(s[1].translation.profile, MotionProfile::linear);
  EXPECT_EQ(s[1].translation.vector, Vec3(0.1, 0, 0));
  EXPECT_EQ(s[2].rotation.profile, MotionProfile::linear);
  EXPECT_EQ(s[2].rotation.vector, Vec3(0, 0, 3.0));  // axis normalised times omega
  EXPECT_EQ(*s[2].point, Vec3(1, 2, 3));
  EXPECT_EQ(s[3].translation.vector, Vec3(0, 0.2, 0));
  EXPECT_LT((s[3].rotation.vector - Vec3(-0.6, 0, -0.8)).norm(), 1e-16);
  EXPECT_FALSE(s[3].point.has_value());  // default: the carried centroid
  EXPECT_EQ(s[4].translation.profile, MotionProfile::sine);
  EXPECT_EQ(s[4].translation.vector, Vec3(0, 0, 0.001));
  EXPECT_DOUBLE_EQ(s[4].translation.angular_frequency, 2 * units::kPi * 50.0);
  EXPECT_EQ(s[4].translation.phase, 0.0);
  EXPECT_EQ(s[5].rotation.profile, MotionProfile::sine);
  EXPECT_EQ(s[5].rotation.vector, Vec3(0, 0.1, 0));
  EXPECT_DOUBLE_EQ(s[5].rotation.angular_frequency, 2 * units::kPi / 0.25);
  EXPECT_EQ(s[5].rotation.phase, 0.5);
  // Hand-computed: at rest until 1 s, then 0.1 m/s along x for 1 s.
  EXPECT_EQ(scene.objects[0].object->pose_at(0.9).translation, Vec3::Zero());
  EXPECT_LT((scene.objects[0].object->pose_at(2.0).translation - Vec3(0.1, 0, 0)).norm(), 1e-16);
}

/// The InputError of reading `segments` after the head: its line and message.
InputError error_of(const fs::path& dir, const std::string& text) {
  try {
    read_scene_text(text, "bad.toml", dir);
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no error for:\n" << text;
  return InputError("none");
}

void expect_error(const fs::path& dir, const std::string& segments, const std::string& at, const std::string& says) {
  const std::string text = std::string(kHead) + segments;
  const InputError e = error_of(dir, text);
  EXPECT_EQ(e.file(), "bad.toml");
  EXPECT_EQ(e.line(), line_of(text, at)) << e.what();
  EXPECT_NE(e.message().find(says), std::string::npos) << e.what();
}

TEST(MotionProgramScene, BadSegmentsNameTheLineAndWhatWasExpected) {
  const fs::path dir = scene_dir();
  const std::string go = "[[object.motion]]\nstart = 0.0\ntype = \"translate\"\nvelocity = [1, 0, 0]\n";
  expect_error(dir, go + "[[object.motion]]\nstart = 0.0\ntype = \"rest\"\n", "start = 0.0\ntype = \"rest\"",
               "expected a time after the previous segment's start (0 s)");
  expect_error(dir, "[[object.motion]]\nstart = 1.0\ntype = \"spin\"\n", "type = \"spin\"",
               "type: expected \"rest\", \"translate\", \"rotate\", \"translate_rotate\", \"vibrate_translate\" or "
               "\"vibrate_rotate\", found \"spin\"");
  expect_error(dir, "[[object.motion]]\ntype = \"rest\"\n", "[[object.motion]]", "missing key 'start'");
  expect_error(dir, "[[object.motion]]\nstart = 0.0\ntype = \"translate\"\nvelocity = [1, 0, 0]\nomega = 2.0\n",
               "omega = 2.0", "unknown key 'omega' in [object.motion]");
  expect_error(dir, "[[object.motion]]\nstart = 0.0\ntype = \"rotate\"\naxis = [0, 0, 0]\nomega = 2.0\n",
               "axis = [0, 0, 0]", "axis: expected a non-zero finite vector");
  expect_error(dir, "[[object.motion]]\nstart = 0.0\ntype = \"rotate\"\naxis = [0, 0, 1]\n", "[[object.motion]]",
               "missing key 'omega'");
  expect_error(dir,
               "[[object.motion]]\nstart = 0.0\ntype = \"vibrate_translate\"\namplitude = [0, 0, 1e-3]\n"
               "frequency = 5.0\nperiod = 0.2\n",
               "[[object.motion]]", "needs exactly one of frequency = f [Hz] or period = T [s]");
  expect_error(dir,
               "[[object.motion]]\nstart = 0.0\ntype = \"vibrate_rotate\"\naxis = [0, 0, 1]\namplitude = 0.1\n"
               "period = -0.2\n",
               "period = -0.2", "period: expected a number > 0");
  expect_error(dir, "motion = 3\n", "motion = 3", "[[object.motion]] must be a non-empty array of tables");
  // Single-motion keys beside a program: one way to give the motion.
  expect_error(dir, "velocity = [1, 0, 0]\n" + go, "velocity = [1, 0, 0]\n[[object.motion]]",
               "[object] velocity is a single-motion key: with [[object.motion]] segments give the motion in the segments");
}

}  // namespace
}  // namespace ppohdem::dem::test
