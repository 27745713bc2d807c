// Scenes of several materials (ppohdem/dem/pair_laws.hpp): binary impacts of two different
// materials against Hertz theory with the combined E* (typed over every engine), the pair
// restitution, a wall of another material, reference == fast bit for bit on a mixed random
// scene, one-material results unchanged, checkpoints, and the scene and CSV input errors.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include <unistd.h>

#include "dem_test_support.hpp"
#include "ppohdem/dem/pair_laws.hpp"
#include "ppohdem/dem/particle_csv.hpp"
#include "ppohdem/dem/particle_generator.hpp"
#include "ppohdem/dem/scene.hpp"

namespace ppohdem::dem::test {
namespace {

namespace fs = std::filesystem;

/// A stiff, dense material (steel-like elastic ratio to the soft one: E 1e4 times larger, other
/// density and Poisson ratio so that every per-material quantity is exercised).
Material stiff_material(double restitution, double friction) {
  Material m;
  m.density = 7800.0;  // kg/m^3
  m.young = 1.0e11;    // Pa
  m.poisson = 0.25;
  m.restitution = restitution;
  m.friction = friction;
  return m;
}

/// E* of two materials written out here (Johnson 1985, eq. 4.22), independent of material.cpp.
double combined_young(const Material& a, const Material& b) {
  return 1.0 / ((1.0 - a.poisson * a.poisson) / a.young + (1.0 - b.poisson * b.poisson) / b.young);
}

/// The elastic Hertz impact in closed form (Johnson 1985, sec. 11.4): maximum overlap
/// (15 m* v^2 / (16 E* sqrt(R*)))^{2/5}, force (4/3) E* sqrt(R*) delta^{3/2}, duration
/// 2 (2/5) B(2/5, 1/2) delta_max / v with the Beta function from std::tgamma.
struct Hertz {
  double overlap, force, duration;
};
Hertz hertz(double m_eff, double r_eff, double e_star, double v) {
  Hertz h{};
  h.overlap = std::pow(15.0 * m_eff * v * v / (16.0 * e_star * std::sqrt(r_eff)), 0.4);
  h.force = 4.0 / 3.0 * e_star * std::sqrt(r_eff) * std::pow(h.overlap, 1.5);
  const double beta = std::tgamma(0.4) * std::tgamma(0.5) / std::tgamma(0.9);  // B(2/5, 1/2)
  h.duration = 2.0 * 0.4 * beta * h.overlap / v;
  return h;
}

/// Soft sphere 1 (material 0, R_a) hits stiff sphere 2 (material 1, R_b) head on at speed v.
SimulationSetup soft_on_stiff(double restitution_pair, double ra, double rb, double v) {
  SimulationSetup s;
  s.material = peer_material(1.0, 0.0);
  s.law = HertzMindlin::from_material(s.material);
  s.more_materials = {stiff_material(1.0, 0.0)};
  s.material_names = {"soft", "stiff"};
  if (restitution_pair < 1.0) s.material_pairs.push_back({0, 1, restitution_pair, std::nullopt});
  s.particles = {sphere(1, Vec3(-ra - 1e-6, 0, 0), Vec3(v, 0, 0), ra), sphere(2, Vec3(rb + 1e-6, 0, 0), Vec3::Zero(), rb)};
  s.particles[1].material = 1;
  s.dt = time_step_limit(s).limit;  // set by the stiff material's Rayleigh time
  s.source = "multi_material_test";
  return s;
}

template <class Engine>
class TwoMaterials : public ::testing::Test {};
TYPED_TEST_SUITE(TwoMaterials, EngineTypes);

TYPED_TEST(TwoMaterials, ElasticImpactMatchesHertzWithTheCombinedModulus) {
  const double ra = 0.5e-3, rb = 0.8e-3, v = 0.1;  // m, m, m/s
  const SimulationSetup s = soft_on_stiff(1.0, ra, rb, v);
  const double ma = s.material.mass(ra), mb = s.more_materials[0].mass(rb);
  const Hertz h = hertz(ma * mb / (ma + mb), ra * rb / (ra + rb), combined_young(s.material, s.more_materials[0]), v);
  TypeParam engine(s);
  double max_force = 0.0, max_overlap = 0.0;
  auto gap = [&](const Particles& p) {
    max_force = std::max(max_force, p[1].force.norm());
    max_overlap = std::max(max_overlap, -pair_gap(p));
    return pair_gap(p);
  };
  const auto r = measure_impact(engine, gap, pair_separation_speed, 100000);
  // ~620 steps per contact (dt from the stiff material's Rayleigh time): Verlet's phase error
  // (pi/N)^2/24 ~ 1e-6 and the sampling of the peak (pi/(2N))^2 ~ 6e-6: 1e-4 (Chung & Ooi's
  // tolerance) leaves room, and a one-material E* (soft, 2x smaller) would miss by 30%.
  EXPECT_NEAR(r.duration / h.duration, 1.0, 1e-4);
  EXPECT_NEAR(max_force / h.force, 1.0, 1e-4);
  EXPECT_NEAR(max_overlap / h.overlap, 1.0, 1e-4);
  EXPECT_NEAR(r.rebound_velocity / v, 1.0, 1e-6);  // elastic; round-off and O(dt^2) only
}

TYPED_TEST(TwoMaterials, PairRestitutionIsMeasuredAndTheMixingRuleTakesTheSmaller) {
  // Tsuji's damping makes e independent of E*, m*, R* and v (contact_law.hpp), so a pair of
  // different materials rebounds with its pair value: explicit 0.5, or min(0.9, 0.6) = 0.6.
  const double r = 0.5e-3, v = 0.1;
  for (const bool explicit_pair : {true, false}) {
    SimulationSetup s = soft_on_stiff(explicit_pair ? 0.5 : 1.0, r, r, v);
    s.material.restitution = 0.9;
    s.law = HertzMindlin::from_material(s.material);
    s.more_materials[0].restitution = 0.6;
    TypeParam engine(s);
    const auto m = measure_impact(engine, pair_gap, pair_separation_speed, 100000);
    // The damping ratio alpha(e) is solved to 1e-6 (hertz_damping.cpp) and Verlet errs by
    // ~1e-6 at 1000 steps per contact: 1e-4 of e.
    EXPECT_NEAR(m.rebound_velocity / v, explicit_pair ? 0.5 : 0.6, 1e-4) << (explicit_pair ? "explicit" : "mixing");
  }
}

TYPED_TEST(TwoMaterials, WallOfAnotherMaterialUsesThePairModulus) {
  // A soft sphere moving at 0.1 m/s (no gravity) hits a wall made of the stiff material:
  // R* = R, m* = m, E* combined. Without a wall material, the wall is of the soft one's own.
  const double r = 0.5e-3, v = 0.1;
  for (const bool stiff_wall : {true, false}) {
    SimulationSetup s = soft_on_stiff(1.0, r, r, v);
    s.particles = {sphere(1, Vec3(0, 0, r + 1e-6), Vec3(0, 0, -v), r)};
    s.boundaries.push_back(std::make_shared<PlaneWall>(Vec3::Zero(), Vec3(0, 0, 1)));
    if (stiff_wall) s.boundary_materials = {1};
    s.dt = 0.2 * rayleigh_time(r, s.more_materials[0]);  // same dt both ways
    const Material& soft = s.material;
    const double e_star = stiff_wall ? combined_young(soft, s.more_materials[0])
                                     : 1.0 / (2.0 * (1.0 - soft.poisson * soft.poisson) / soft.young);
    const Hertz h = hertz(soft.mass(r), r, e_star, v);
    TypeParam engine(s);
    auto gap = [](const Particles& p) { return p[0].position.z() - p[0].radius; };
    auto speed = [](const Particles& p) { return p[0].velocity.z(); };
    const auto m = measure_impact(engine, gap, speed, 100000);
    EXPECT_NEAR(m.duration / h.duration, 1.0, 1e-4) << (stiff_wall ? "stiff wall" : "wall of the particle's material");
  }
}

/// A mixed random scene: three materials (soft, 10x stiffer, a third with other density),
/// friction with an explicit frictionless pair, walls of which one has a material, gravity.
SimulationSetup mixed_scene() {
  const double r = 0.5e-3, width = 10.0 * 2.0 * r;
  SimulationSetup s;
  s.material = peer_material(0.5, 0.5);
  s.law = HertzMindlin::from_material(s.material);
  Material hard = peer_material(0.8, 0.3);
  hard.young = 1.0e8;
  hard.poisson = 0.22;
  Material heavy = peer_material(0.4, 0.6);
  heavy.density = 6000.0;
  heavy.young = 3.0e8;
  s.more_materials = {hard, heavy};
  s.material_names = {"glass", "hard", "heavy"};
  s.material_pairs = {{0, 2, std::nullopt, 0.0}, {1, 2, 0.3, std::nullopt}};
  GeneratorSpec g;
  g.kind = GeneratorKind::kLattice;
  g.box_min = Vec3::Zero();
  g.box_max = Vec3(width, width, 2.0 * width);
  g.count = 600;
  g.radius = r;
  g.radius_max = 1.02 * r;
  g.jitter = 0.05;
  g.seed = 5;
  s.particles = generate_particles(g, "test");
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (Particle& q : s.particles) {
    q.velocity = 0.3 * Vec3(u(rng), u(rng), u(rng));           // [m/s]
    q.angular_velocity = 300.0 * Vec3(u(rng), u(rng), u(rng));  // [rad/s]
    q.material = static_cast<std::uint16_t>(rng() % 3);
  }
  s.gravity = Vec3(0, 0, -9.81);
  s.boundaries.push_back(std::make_shared<PlaneWall>(Vec3::Zero(), Vec3(0, 0, 1)));
  s.boundaries.push_back(std::make_shared<PlaneWall>(Vec3::Zero(), Vec3(1, 0, 0)));
  s.boundaries.push_back(std::make_shared<PlaneWall>(Vec3(width, 0, 0), Vec3(-1, 0, 0)));
  s.boundaries.push_back(std::make_shared<PlaneWall>(Vec3::Zero(), Vec3(0, 1, 0)));
  s.boundaries.push_back(std::make_shared<PlaneWall>(Vec3(0, width, 0), Vec3(0, -1, 0)));
  s.boundary_materials = {1, -1, 2};  // the y walls: each particle's own material
  s.dt = time_step_limit(s).limit;
  s.source = "mixed_scene";
  return s;
}

void expect_same_bits(const Particles& a, const Particles& b, const std::string& what) {
  ASSERT_EQ(a.size(), b.size());
  std::size_t differing = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const bool same = a[i].id == b[i].id && a[i].material == b[i].material && a[i].position == b[i].position &&
                      a[i].velocity == b[i].velocity && a[i].angular_velocity == b[i].angular_velocity &&
                      a[i].force == b[i].force && a[i].torque == b[i].torque;
    if (!same) ++differing;
  }
  EXPECT_EQ(differing, 0u) << what;
}

TEST(MultiMaterial, ReferenceAndFastEnginesAgreeBitwiseOnAMixedScene) {
  const SimulationSetup s = mixed_scene();
  ppohdem::dem::reference::ReferenceEngine reference(s);
  ppohdem::dem::fast::FastEngine fast(s);
  for (int block = 0; block < 3; ++block) {
    reference.advance(100);
    fast.advance(100);
    expect_same_bits(reference.particles(), fast.particles(), "after " + std::to_string(reference.step_count()));
  }
  // Not vacuous: contacts between particles and with the walls of every kind.
  EXPECT_GT(fast.contact_counts().particle_pairs, 50u) << fast.contact_counts().particle_pairs;
  EXPECT_GT(fast.contact_counts().particle_boundary, 10u) << fast.contact_counts().particle_boundary;
  EXPECT_GT(fast.neighbour_list_builds(), 3);
  // Checkpoints keep the material: the fast engine continues the reference's state exactly.
  ppohdem::dem::fast::FastEngine restarted(s);
  restarted.restore_state(reference.save_state());
  reference.advance(50);
  restarted.advance(50);
  expect_same_bits(reference.particles(), restarted.particles(), "fast continuing the reference's checkpoint");
  EngineState other = reference.save_state();
  other.particles[7].material = static_cast<std::uint16_t>((other.particles[7].material + 1) % 3);
  EXPECT_THROW(restarted.restore_state(other), InputError);  // another scene's materials
}

TEST(MultiMaterial, EqualMaterialsUnderTwoNamesRunExactlyTheOneMaterialScene) {
  // The pair formulas fall back to the one-material expressions for equal constants, and the
  // mixing rule gives e and mu themselves: a scene whose particles are split over two copies
  // of one material is the one-material scene bit for bit (the multi-material kernel of the
  // fast engine and the one-law kernel agree).
  SimulationSetup one = mixed_scene();
  one.more_materials.clear();
  one.material_names.clear();
  one.material_pairs.clear();
  one.boundary_materials.clear();
  for (Particle& p : one.particles) p.material = 0;
  one.dt = time_step_limit(one).limit;
  SimulationSetup two = one;
  two.more_materials = {one.material};
  for (Particle& p : two.particles) p.material = static_cast<std::uint16_t>(p.id % 2);
  for (int engine = 0; engine < 2; ++engine) {
    std::unique_ptr<DemEngine> a, b;
    if (engine == 0) {
      a = std::make_unique<ppohdem::dem::reference::ReferenceEngine>(one);
      b = std::make_unique<ppohdem::dem::reference::ReferenceEngine>(two);
    } else {
      a = std::make_unique<ppohdem::dem::fast::FastEngine>(one);
      b = std::make_unique<ppohdem::dem::fast::FastEngine>(two);
    }
    a->advance(150);
    b->advance(150);
    Particles pb = b->particles();
    for (Particle& p : pb) p.material = 0;
    expect_same_bits(a->particles(), pb, engine == 0 ? "reference" : "fast");
  }
}

TEST(MultiMaterial, PairFormulasAreSymmetricAndReduceToOneMaterial) {
  const Material a = peer_material(0.5, 0.3), b = stiff_material(0.7, 0.1);
  EXPECT_EQ(pair_effective_young(a, b), pair_effective_young(b, a));
  EXPECT_EQ(pair_effective_shear(a, b), pair_effective_shear(b, a));
  EXPECT_EQ(pair_effective_young(a, a), a.effective_young());  // bitwise: one-material form
  EXPECT_EQ(pair_effective_shear(a, a), a.effective_shear());
  // Against the formulas written out (Johnson 1985 eq. 4.22; Mindlin 1949): 1 ulp apart at
  // most (the same operations, possibly another rounding of the shear moduli).
  const double ga = a.young / (2.0 * (1.0 + a.poisson)), gb = b.young / (2.0 * (1.0 + b.poisson));
  EXPECT_NEAR(pair_effective_young(a, b) / combined_young(a, b), 1.0, 4e-16);
  EXPECT_NEAR(pair_effective_shear(a, b) * ((2.0 - a.poisson) / ga + (2.0 - b.poisson) / gb), 1.0, 4e-16);
}

// ---- scene files --------------------------------------------------------------------------

fs::path temp_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("ppohdem_multi_material_" + name + "_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

std::string scene_error(const std::string& name, const std::string& text, const std::string& csv = "") {
  const fs::path dir = temp_dir(name);
  std::ofstream(dir / "scene.toml") << text;
  if (!csv.empty()) std::ofstream(dir / "p.csv") << csv;
  try {
    read_scene(dir / "scene.toml");
  } catch (const InputError& e) {
    fs::remove_all(dir);
    return e.what();
  }
  fs::remove_all(dir);
  return "";
}

const std::string kHead = "[simulation]\ndt = 1e-8\nsteps = 1\n[contact]\nmodel = \"hertz-mindlin\"\n";
const std::string kTwo =
    "[[material]]\nname = \"soft\"\ndensity = 2500.0\nyoung = 1e7\npoisson = 0.3\nrestitution = 0.5\n"
    "[[material]]\nname = \"stiff\"\ndensity = 7800.0\nyoung = 1e11\npoisson = 0.25\nrestitution = 0.9\nfriction = 0.2\n";
const std::string kGenerator =
    "[particles]\ngenerator = \"lattice\"\nbox_min = [0, 0, 0]\nbox_max = [0.01, 0.01, 0.01]\ncount = 5\n"
    "radius = 0.001\n";

TEST(MultiMaterialScene, ReadsMaterialsPairsGeneratorCycleAndWallMaterial) {
  const fs::path dir = temp_dir("good");
  std::ofstream(dir / "scene.toml") << kHead << kTwo
                                    << "[[material_pair]]\nmaterials = [\"stiff\", \"soft\"]\nfriction = 0.05\n"
                                    << kGenerator << "material = [\"stiff\", \"soft\"]\n"
                                    << "[[wall]]\npoint = [0, 0, 0]\nnormal = [0, 0, 1]\n"
                                    << "[[wall]]\npoint = [0, 0, 0]\nnormal = [1, 0, 0]\nmaterial = \"stiff\"\n";
  const Scene scene = read_scene(dir / "scene.toml");
  const SimulationSetup& s = scene.setup;
  ASSERT_EQ(s.material_count(), 2u);
  EXPECT_EQ(s.material_names, (std::vector<std::string>{"soft", "stiff"}));
  EXPECT_EQ(s.more_materials[0].young, 1e11);
  ASSERT_EQ(s.particles.size(), 5u);
  for (const Particle& p : s.particles) EXPECT_EQ(p.material, p.id % 2 == 1 ? 1 : 0) << p.id;  // id 1: stiff
  EXPECT_EQ(s.boundary_materials, (std::vector<std::int32_t>{-1, 1}));
  const PairCoefficients c = pair_coefficients(s, 0, 1);
  EXPECT_EQ(c.restitution, 0.5);  // mixing rule: min(0.5, 0.9)
  EXPECT_EQ(c.friction, 0.05);    // explicit
  const PairLaws<HertzMindlin> laws(s, std::get<HertzMindlin>(s.law));
  EXPECT_EQ(laws.pair(0, 1).effective_young(), pair_effective_young(s.material, s.more_materials[0]));
  EXPECT_EQ(laws.boundary(0, 1).effective_young(), laws.pair(0, 1).effective_young());  // soft on the stiff wall
  EXPECT_EQ(laws.boundary(0, 0).effective_young(), s.material.effective_young());      // wall without material
  fs::remove_all(dir);
}

TEST(MultiMaterialScene, ParticleFileMaterialColumnRoundTrips) {
  const fs::path dir = temp_dir("csv");
  std::ofstream(dir / "p.csv") << "id,x,y,z,vx,vy,vz,wx,wy,wz,radius,material\n"
                               << "1,0,0,0,0,0,0,0,0,0,0.001,stiff\n2,0.003,0,0,0,0,0,0,0,0,0.001,soft\n";
  std::ofstream(dir / "scene.toml") << kHead << kTwo << "[particles]\nfile = \"p.csv\"\n";
  const Scene scene = read_scene(dir / "scene.toml");
  ASSERT_EQ(scene.setup.particles.size(), 2u);
  EXPECT_EQ(scene.setup.particles[0].material, 1);
  EXPECT_EQ(scene.setup.particles[1].material, 0);
  write_particles_csv(dir / "out.csv", scene.setup.particles, "", scene.setup.material_names);
  const Particles back = read_particles_csv(dir / "out.csv", scene.setup.material_names);
  EXPECT_EQ(back[0].material, 1);
  EXPECT_EQ(back[1].material, 0);
  // One material: no column is written (outputs of one-material scenes are unchanged).
  write_particles_csv(dir / "one.csv", scene.setup.particles, "", {"soft"});
  std::ifstream in(dir / "one.csv");
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, "id,x,y,z,vx,vy,vz,wx,wy,wz,radius");
  fs::remove_all(dir);
}

TEST(MultiMaterialScene, InputErrorsNameTheProblem) {
  const std::string p = kGenerator;
  struct Case {
    std::string name, text, csv, expected;
  };
  const std::vector<Case> cases = {
      {"unknown_generator_material", kHead + kTwo + p + "material = \"wood\"\n", "",
       "unknown material 'wood' (the scene has: soft, stiff)"},
      {"duplicate_name", kHead + kTwo + "[[material]]\nname = \"soft\"\ndensity = 1.0\nyoung = 1e7\nrestitution = 1.0\n" + p, "",
       "name 'soft' is used twice"},
      {"missing_name", kHead + "[[material]]\ndensity = 1.0\nyoung = 1e7\nrestitution = 1.0\n" + p, "",
       "missing key 'name'"},
      {"mixed_syntax", kHead + "[material]\ndensity = 1.0\nrestitution = 1.0\n" + kTwo + p, "", "scene.toml"},
      {"pair_same", kHead + kTwo + "[[material_pair]]\nmaterials = [\"soft\", \"soft\"]\nrestitution = 0.5\n" + p, "",
       "two different materials expected"},
      {"pair_unknown", kHead + kTwo + "[[material_pair]]\nmaterials = [\"soft\", \"x\"]\nrestitution = 0.5\n" + p, "",
       "unknown material 'x'"},
      {"pair_twice", kHead + kTwo + "[[material_pair]]\nmaterials = [\"soft\", \"stiff\"]\nrestitution = 0.5\n" +
                         "[[material_pair]]\nmaterials = [\"stiff\", \"soft\"]\nfriction = 0.5\n" + p,
       "", "this pair is given twice"},
      {"pair_restitution", kHead + kTwo + "[[material_pair]]\nmaterials = [\"soft\", \"stiff\"]\nrestitution = 1.5\n" + p,
       "", "restitution must be in (0, 1]"},
      {"bad_entry", kHead + kTwo + "[[material]]\nname = \"bad\"\ndensity = -1.0\nyoung = 1e7\nrestitution = 1.0\n" + p,
       "", "'bad': [material] density must be > 0"},
      {"wall_material", kHead + kTwo + p + "[[wall]]\npoint = [0, 0, 0]\nnormal = [0, 0, 1]\nmaterial = \"ice\"\n", "",
       "[wall] material: unknown material 'ice'"},
      {"csv_unknown", kHead + kTwo + "[particles]\nfile = \"p.csv\"\n",
       "id,x,y,z,vx,vy,vz,wx,wy,wz,radius,material\n1,0,0,0,0,0,0,0,0,0,0.001,ice\n",
       "p.csv:2: column 'material': unknown material 'ice'"},
      {"csv_file_and_material", kHead + kTwo + "[particles]\nfile = \"p.csv\"\nmaterial = \"soft\"\n",
       "id,x,y,z,vx,vy,vz,wx,wy,wz,radius\n1,0,0,0,0,0,0,0,0,0,0.001\n", "applies to a generator, not to file ="},
  };
  for (const Case& c : cases) {
    const std::string message = scene_error(c.name, c.text, c.csv);
    EXPECT_NE(message.find(c.expected), std::string::npos) << c.name << ": " << message;
    // The file at fault is named: the scene, or the particle file for its own errors.
    const bool in_csv = c.expected.rfind("p.csv", 0) == 0;
    EXPECT_NE(message.find(in_csv ? "p.csv:2:" : "scene.toml"), std::string::npos) << c.name << ": " << message;
  }
}

TEST(MultiMaterialScene, SetupValidationRefusesBadIndicesAcceptsLinearMixtures) {
  SimulationSetup s = soft_on_stiff(1.0, 0.5e-3, 0.5e-3, 0.1);
  s.particles[1].material = 2;  // only 0 and 1 exist
  EXPECT_THROW(validate_setup(s), InputError);
  // The linear law takes several materials (issue 38; contact_options_test.cpp).
  s = soft_on_stiff(1.0, 0.5e-3, 0.5e-3, 0.1);
  s.law = LinearSpringDashpot::from_stiffness(100.0, 1.0, 0.0);
  s.force_time_step = true;
  EXPECT_NO_THROW(validate_setup(s));
  s = soft_on_stiff(1.0, 0.5e-3, 0.5e-3, 0.1);
  s.boundary_materials = {5};
  EXPECT_THROW(validate_setup(s), InputError);  // more boundary materials than boundaries
}

}  // namespace
}  // namespace ppohdem::dem::test
