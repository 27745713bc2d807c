// Far objects cost nothing (issue 38 item 4; docs/objects.md "Far objects cost nothing"): an
// object's reach box (Boundary::reach) holds every sphere it can touch or count, whatever its
// field; and the fast engine, which skips the spheres outside it, gives the same bits as
// without the skip and as the reference engine (which evaluates every sphere), on scenes with
// a translating-then-rotating object. The outside-grid count (item 7) is the same in all three
// runs: nothing outside the box is counted, and a normal scene counts nothing.
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <random>
#include <sstream>
#include <string>

#include "../dem/dem_test_support.hpp"
#include "ppohdem/dem/distance_field_object.hpp"
#include "ppohdem/dem/fast/fast_engine.hpp"
#include "ppohdem/dem/scene.hpp"
#include "ppohdem/mesh/stl_io.hpp"
#include "ppohdem/sdf/fast/fast_sdf_builder.hpp"

namespace ppohdem::dem::test {
namespace {

namespace fs = std::filesystem;
using ppohdem::dem::reference::ReferenceEngine;

const fs::path kScoopDir = fs::path(PPOHDEM_SOURCE_DIR) / "fixtures" / "scenes" / "scoop";

/// Random probes around an object moved by a translation and a rotation (object-frame points
/// in its grid's box widened by half its size on each side, moved by the pose): a sphere the
/// reach box excludes has no contact and is not counted (contact(), contacts()); the probes
/// must hit both kinds (excluded, touching), so the check is not vacuous.
void expect_reach_holds(const DistanceFieldObject& object, double r_max, int min_excluded, int min_touching,
                        unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const GridSpec& g = object.field().grid;
  const Vec3 size = g.upper_corner() - g.origin;
  const Vec3 lo = g.origin - 0.5 * size;
  int excluded = 0, touching = 0;
  std::vector<FeatureContact> found;
  for (int probe = 0; probe < 40000; ++probe) {
    const double time = 0.02 * u(rng);  // s
    const ReachBox reach = object.reach(time, r_max);
    const Vec3 x = object.pose_at(time).apply(lo + 2.0 * Vec3(u(rng), u(rng), u(rng)).cwiseProduct(size));
    const double r = r_max * (0.25 + 0.75 * u(rng));
    const std::size_t counted = object.outside_grid_count();
    object.contacts(x, r, time, found);
    const bool single = object.contact(x, r, time).has_value();
    if (!found.empty() || single) ++touching;
    if (!reach.excludes(x, r)) continue;
    ++excluded;
    EXPECT_TRUE(found.empty()) << "probe " << probe;
    EXPECT_FALSE(single) << "probe " << probe;
    EXPECT_EQ(object.outside_grid_count(), counted) << "probe " << probe;
  }
  EXPECT_GE(excluded, min_excluded);
  EXPECT_GE(touching, min_touching);
}

RigidMotion turning_motion() {
  RigidMotion m;
  m.velocity = Vec3(-0.5, 0.2, -0.3);          // m/s
  m.angular_velocity = Vec3(3.0, 20.0, -7.0);  // rad/s: up to 0.45 rad in 0.02 s
  m.centroid = Vec3(0.075, 0.014, 0.045);      // m
  return m;
}

TEST(ObjectReach, ExcludesOnlySpheresWithoutContactOrCountForMeshAndFieldContacts) {
  const TriangleMesh mesh = read_stl(kScoopDir / "scoop.stl");
  const BoundingBox box = bounding_box(mesh);
  const double r_max = 2e-3;  // m
  // A grid one margin r_max around the mesh, and one cut through it (the object is larger
  // than its grid: particles beyond the cut are counted).
  for (const double margin : {2.0 * r_max, -5e-3}) {
    const GridSpec grid = GridSpec::spanning(box.min - Vec3::Constant(margin), box.max + Vec3::Constant(margin), {25, 14, 22});
    for (const bool mesh_contacts : {true, false}) {
      DistanceFieldObject object(sdf::fast::FastSdfBuilder().build(mesh, grid), turning_motion(), "scoop");
      if (mesh_contacts) object.use_mesh_contacts(mesh);
      object.set_display_mesh(mesh);
      SCOPED_TRACE(std::string(mesh_contacts ? "mesh" : "field") + " contacts, margin " + std::to_string(margin));
      expect_reach_holds(object, r_max, margin > 0 ? 10000 : 1000, 100, 38);
      if (margin < 0) {
        EXPECT_GT(object.outside_grid_count(), 0u);
      } else {
        EXPECT_EQ(object.outside_grid_count(), 0u);  // a grid around the object: nothing counted
      }
    }
  }
}

TEST(ObjectReach, HoldsForAFieldThatIsNoDistance) {
  // The box comes from the field's values, not from a mesh: a field with a few low nodes far
  // apart (as a field with sign errors has) is still bounded. No mesh: the body box is the
  // box of the inside nodes, and the contacts at the low positive cell lie beyond it (a reach
  // from the body box alone fails here).
  GridSpec grid{Vec3(-5e-3, -4e-3, -3e-3), Vec3(1e-3, 1.2e-3, 0.8e-3), {11, 8, 9}};
  ScalarField field(grid);
  for (double& v : field.values) v = 4e-3;  // m: beyond r_max
  field.at(1, 1, 1) = -1e-3;
  for (int k = 6; k < 8; ++k)  // a cell of low positive values 3 mm beyond the inside nodes
    for (int j = 1; j < 3; ++j)
      for (int i = 8; i < 10; ++i) field.at(i, j, k) = 0.1e-3;
  field.at(4, 6, 3) = 1.5e-3;
  for (int k = 4; k < 6; ++k)
    for (int j = 3; j < 5; ++j) field.at(5, j, k) = -2e-3;
  const DistanceFieldObject object(field, turning_motion(), "odd");
  expect_reach_holds(object, 1e-3, 10000, 20, 7);  // 31 touching probes in this draw
}

/// The scene of the engine tests: 500 spheres in a box, the scoop driven into them (down and
/// back, then turning about its back-bottom edge), its grid `margin` around its mesh.
std::string scoop_scene(const std::string& contact, double margin) {
  std::ostringstream s;
  s << "[simulation]\ndt = 1.5e-5\nsteps = 0\ngravity = [0.0, 0.0, -9.81]\n"
       "[material]\ndensity = 2500.0\nyoung = 2.0e7\npoisson = 0.3\nrestitution = 0.5\nfriction = 0.5\n"
       "[contact]\nmodel = \"hertz-mindlin\"\n"
       "[particles]\ngenerator = \"random\"\nbox_min = [0.0, 0.0, 0.0]\nbox_max = [0.08, 0.028, 0.043]\n"
       "count = 500\nradius = 2.0e-3\nseed = 38\n"
       "[[wall]]\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\n"
       "[[object]]\nname = \"scoop\"\nmesh = \"scoop.stl\"\ncells = [15, 10, 12]\n"
       "contact = \""
    << contact << "\"\nmargin = " << margin
    << "\ncentroid = [0.075, 0.014, 0.045]\n"
       "[[object.motion]]\nstart = 0.0\ntype = \"translate\"\nvelocity = [-0.5, 0.0, -1.5]\n"
       "[[object.motion]]\nstart = 0.003\ntype = \"rotate\"\naxis = [0.0, 1.0, 0.0]\nomega = 20.0\n";
  return s.str();
}

struct RunResult {
  Particles particles;
  std::vector<BoundaryLoad> loads;
  std::size_t outside = 0;  ///< the object's outside-grid count
  std::size_t object_contacts = 0;  ///< evaluations with a load on the object
};

template <class MakeEngine>
RunResult run(const std::string& text, MakeEngine make_engine) {
  Scene scene = read_scene_text(text, "scoop.toml", kScoopDir);
  auto engine = make_engine(scene.setup);
  RunResult r;
  for (int n = 0; n < 400; ++n) {
    engine->step();
    if (engine->boundary_loads().at(1).force != Vec3::Zero()) ++r.object_contacts;
  }
  r.particles = engine->particles();
  r.loads = engine->boundary_loads();
  r.outside = scene.objects.at(0).object->outside_grid_count();
  return r;
}

void expect_same_bits(const Particles& a, const Particles& b, const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].position, b[i].position) << what << ", particle " << i;
    EXPECT_EQ(a[i].velocity, b[i].velocity) << what << ", particle " << i;
    EXPECT_EQ(a[i].angular_velocity, b[i].angular_velocity) << what << ", particle " << i;
  }
}

TEST(FarObjectSkip, SameBitsWithAndWithoutTheSkipAndAsTheReferenceEngine) {
  for (const char* contact : {"mesh", "field"}) {
    // margin 4 mm = 2 R (the default: a normal scene) and 0 (the grid is the mesh's box: the
    // particles beyond it within R are counted).
    for (const double margin : {4e-3, 0.0}) {
      SCOPED_TRACE(std::string(contact) + " contacts, margin " + std::to_string(margin));
      const std::string text = scoop_scene(contact, margin);
      const RunResult skipped = run(text, [](const SimulationSetup& s) { return std::make_unique<fast::FastEngine>(s); });
      const RunResult all = run(text, [](const SimulationSetup& s) {
        fast::FastOptions o;
        o.skip_far_objects = false;
        return std::make_unique<fast::FastEngine>(s, o);
      });
      const RunResult reference = run(text, [](const SimulationSetup& s) { return std::make_unique<ReferenceEngine>(s); });
      // Not vacuous: the scoop pushed on the spheres (in 78 of the 400 steps with 300
      // spheres); with the grid cut to the mesh's box, the centres under its plate
      // are outside the grid and have no contact (the warning's case).
      if (margin > 0) {
        EXPECT_GT(skipped.object_contacts, 50u);
      }
      expect_same_bits(skipped.particles, all.particles, "skip on/off");
      expect_same_bits(skipped.particles, reference.particles, "fast/reference");
      ASSERT_EQ(skipped.loads.size(), all.loads.size());
      for (std::size_t b = 0; b < all.loads.size(); ++b) {
        EXPECT_EQ(skipped.loads[b].force, all.loads[b].force) << "boundary " << b;
        EXPECT_EQ(skipped.loads[b].moment_about_origin, all.loads[b].moment_about_origin) << "boundary " << b;
      }
      EXPECT_EQ(skipped.outside, all.outside);
      EXPECT_EQ(skipped.outside, reference.outside);
      if (margin > 0) {
        EXPECT_EQ(skipped.outside, 0u);  // a normal scene counts nothing
      } else {
        EXPECT_GT(skipped.outside, 0u);
      }
    }
  }
}

}  // namespace
}  // namespace ppohdem::dem::test
