// The chaotic tier's scenes and their export (port_scenes.hpp; docs/port-validation.md "Scenes").
#include "port_scenes.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "ppohdem/dem/particle_csv.hpp"
#include "ppohdem/dem/scene.hpp"
#include "ppohdem/io/atomic_file.hpp"
#include "subprocess.hpp"

namespace ppohdem::port {
namespace fs = std::filesystem;
namespace {

std::vector<PortWall> open_box(double lx, double ly) {
  return {{Vec3(0, 0, 0), Vec3(0, 0, 1), "floor"},  {Vec3(0, 0, 0), Vec3(1, 0, 0), "x0"},
          {Vec3(lx, 0, 0), Vec3(-1, 0, 0), "x1"},   {Vec3(0, 0, 0), Vec3(0, 1, 0), "y0"},
          {Vec3(0, ly, 0), Vec3(0, -1, 0), "y1"}};
}

/// A lattice of spheres settling into an open-top box (the settling_10k scene, scaled down).
/// The trajectories of two members part to the size of the pile's gaps by about step 9,000
/// (RMS position difference 7e-5 m = 7 % of R, from 1e-17 m): the observables are taken after.
PortScene settling_bed() {
  PortScene s;
  s.name = "settling_bed";
  s.description = "1,000 spheres (R = 1 mm, Hertz-Mindlin, e = 0.5, mu = 0.5) released from a jittered lattice "
                  "into a 2 cm x 2 cm open-top box, 14,000 steps of 1e-5 s";
  s.steps = 14000;
  s.frame_every = 2000;
  s.observable_steps = {10000, 12000, 14000};
  s.dt = 1.0e-5;
  s.gravity = 9.81;
  s.density = 2500.0;
  s.young = 1.0e7;
  s.poisson = 0.3;
  s.restitution = 0.5;
  s.friction = 0.5;
  s.walls = open_box(0.02, 0.02);
  s.probe_min = Vec3(0.0, 0.0, 0.003);  // above the floor's layering, below the surface (~1.7 cm)
  s.probe_max = Vec3(0.02, 0.02, 0.012);
  s.box_min = Vec3(0, 0, 0);
  s.box_max = Vec3(0.02, 0.02, 0.03);
  s.count = 1000;
  s.radius = 1.0e-3;
  return s;
}

/// 216 spheres, 12,000 steps: the reduced ensemble of the ctest (a few seconds per 20 members).
/// Two members part to 6e-5 m (6 % of R) by step 10,000 and no further: saturated.
PortScene small_bed() {
  PortScene s = settling_bed();
  s.name = "small_bed";
  s.description = "216 spheres (R = 1 mm) settling into a 1.2 cm x 1.2 cm open-top box, 12,000 steps of 1e-5 s";
  s.steps = 12000;
  s.frame_every = 1000;
  s.observable_steps = {10000, 11000, 12000};
  s.walls = open_box(0.012, 0.012);
  s.probe_min = Vec3(0.0, 0.0, 0.002);  // the bed is ~1 cm high
  s.probe_max = Vec3(0.012, 0.012, 0.007);
  s.box_max = Vec3(0.012, 0.012, 0.02);
  s.count = 216;
  return s;
}

/// The seed's sample_main01 (fixtures/seed-sample) shortened: the same 600 particles, contact
/// law, box, dragon and motion, with dt 5x the original's (still 1/8 of the stability limit)
/// and the dragon 3 m higher, so that the sheet lands on it within 70 s instead of the
/// original's several hundred: 16,000 steps instead of 150,000.
PortScene seed_sample() {
  PortScene s;
  s.name = "seed_sample";
  s.description = "the seed's sample_main01 (600 particles falling on the rising, turning dragon), dt 0.01 s, "
                  "dragon 3 m higher, 16,000 steps";
  s.steps = 16000;
  s.frame_every = 1000;
  s.observable_steps = {10000, 13000, 16000};
  s.dt = 0.01;
  s.gravity = 0.01;
  s.density = 238.732414637843;
  s.restitution = 0.6643138826829587;
  s.friction = 0.5774;
  s.linear = true;
  s.stiffness = 30.0;
  s.tangential_ratio = 1.0 / 30.0;
  s.walls = open_box(11.0, 11.0);
  s.walls.push_back({Vec3(0, 0, 11), Vec3(0, 0, -1), "top"});
  s.probe_min = Vec3(0, 0, 0);
  s.probe_max = Vec3(11, 11, 1.0);  // the layer on the floor
  s.has_object = true;
  s.count = 600;
  s.max_overlap = 0.6;  // the soft original spring: the pile on the floor overlaps up to ~45 % of R
  return s;
}

std::string vec(const Vec3& v) {
  char b[160];
  std::snprintf(b, sizeof b, "[%.17g, %.17g, %.17g]", v.x(), v.y(), v.z());
  return b;
}

std::string num(double x) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", x);
  return b;
}

void write_text(const fs::path& file, const std::string& text) {
  AtomicFileWriter writer(file);
  writer.stream() << text;
  writer.commit();
}

std::string scene_toml(const PortScene& s, const std::string& particles) {
  std::ostringstream o;
  o << "# ppohdem port-validation scene '" << s.name << "' (docs/port-validation.md)\n"
    << "# " << s.description << "\n"
    << "# Observables are taken from the frames at steps";
  for (long k : s.observable_steps) o << " " << k;
  o << " (times";
  for (long k : s.observable_steps) o << " " << num(static_cast<double>(k) * s.dt);
  o << " s)\n"
    << "# Run a member: ppohdem simulate scene.toml --perturb-seed K --output-dir runK\n\n"
    << "[simulation]\ndt = " << num(s.dt) << "\nsteps = " << s.steps << "\ngravity = " << vec(Vec3(0, 0, -s.gravity))
    << "\n\n[material]\ndensity = " << num(s.density) << "\n";
  if (!s.linear) o << "young = " << num(s.young) << "\npoisson = " << num(s.poisson) << "\n";
  o << "restitution = " << num(s.restitution) << "\nfriction = " << num(s.friction) << "\n\n[contact]\n";
  if (s.linear) {
    o << "model = \"linear\"\nstiffness = " << num(s.stiffness) << "\ntangential_stiffness_ratio = "
      << num(s.tangential_ratio) << "\n";
  } else {
    o << "model = \"hertz-mindlin\"\n";
  }
  o << "\n[particles]\nfile = \"" << particles << "\"\n";
  for (const PortWall& w : s.walls) {
    o << "\n[[wall]]  # " << w.name << "\npoint = " << vec(w.point) << "\nnormal = " << vec(w.normal) << "\n";
  }
  if (s.has_object) {
    // The dragon of fixtures/seed-sample/sample_main01.toml, raised by 3 m (its field too).
    o << "\n[[object]]\nname = \"dragon\"\ndistance = \"dragon.vtk\"\n"
      << "velocity = [0.0, 0.0, 0.0028947368421052633]\naxis = [0.0, 0.0, 1.0]\nomega = 0.002617993877991494\n"
      << "centroid = [6.368421052631579, 6.368421052631579, -1.631578947368421]\n";
  }
  o << "\n[output]\ndir = \"out\"\nevery = " << s.frame_every << "\nformats = [\"csv\"]\nprogress = false\n"
    << "\n[checks]\nmax_overlap = " << num(s.max_overlap) << "\n";
  return o.str();
}

}  // namespace

const PortScene& port_scene(const std::string& name) {
  static const std::map<std::string, PortScene> scenes{
      {"settling_bed", settling_bed()}, {"seed_sample", seed_sample()}, {"small_bed", small_bed()}};
  const auto it = scenes.find(name);
  if (it == scenes.end()) {
    throw std::invalid_argument("unknown port-validation scene '" + name +
                                "' (expected settling_bed, seed_sample or small_bed)");
  }
  return it->second;
}

std::vector<std::string> port_scene_names() { return {"settling_bed", "seed_sample"}; }

PortScene scaled(PortScene s, const std::map<std::string, double>& factors) {
  for (const auto& [name, f] : factors) {
    if (name == "friction") s.friction *= f;
    else if (name == "restitution") s.restitution *= f;
    else if (name == "young") (s.linear ? s.stiffness : s.young) *= f;
    else if (name == "dt") s.dt *= f;
    else if (name == "gravity") s.gravity *= f;
    else throw std::invalid_argument("--scale-parameter: unknown parameter '" + name +
                                     "' (expected friction, restitution, young, dt or gravity)");
  }
  return s;
}

fs::path export_scene(const PortScene& s, const fs::path& dir, const fs::path& source_dir,
                      const std::string& ppohdem_program) {
  const fs::path out = dir / s.name;
  fs::create_directories(out);
  const fs::path particles = out / "particles.csv";
  const std::string header = "ppohdem port-validation scene " + s.name;
  if (s.has_object) {
    const auto sample = dem::read_particles_csv(source_dir / "fixtures" / "seed-sample" / "sample_particles.csv");
    dem::write_particles_csv(particles, sample, header);
    if (!fs::exists(out / "dragon.vtk")) {
      const int rc = run_program(
          {ppohdem_program, "voxelize", "--mesh", (source_dir / "fixtures" / "meshes" / "dragon_100k.stl").string(),
           "--placement", "10,10,10,6.368421052631579,6.368421052631579,-1.631578947368421", "--cells", "76", "76",
           "76", "--box", "-15.631578947368421", "-15.631578947368421", "-12.631578947368421", "27.789473684210527",
           "27.789473684210527", "27.789473684210527", "--out", (out / "dragon.vtk").string()},
          (out / "voxelize.log").string());
      if (rc != 0) throw std::runtime_error("ppohdem voxelize of the dragon failed: see " + (out / "voxelize.log").string());
    }
  } else {
    // The lattice generator's particles, written out so that every code starts from them.
    const fs::path generator = out / "generator.toml";
    std::string text = scene_toml(s, "unused.csv");
    const std::string file_line = "file = \"unused.csv\"\n";
    std::ostringstream g;
    g << "generator = \"lattice\"\nbox_min = " << vec(s.box_min) << "\nbox_max = " << vec(s.box_max)
      << "\ncount = " << s.count << "\nradius = " << num(s.radius) << "\nseed = 42\njitter = 0.1\n";
    text.replace(text.find(file_line), file_line.size(), g.str());
    write_text(generator, text);
    const dem::Scene scene = dem::read_scene(generator);
    dem::write_particles_csv(particles, scene.setup.particles, header);
    fs::remove(generator);
  }
  const fs::path scene_file = out / "scene.toml";
  write_text(scene_file, scene_toml(s, "particles.csv"));
  return scene_file;
}

}  // namespace ppohdem::port
