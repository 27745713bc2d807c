// The deterministic tier (deterministic.hpp; docs/port-validation.md "Deterministic tier").
#include "deterministic.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "observables.hpp"
#include "port_scenes.hpp"
#include "ppohdem/dem/particle_csv.hpp"
#include "ppohdem/dem/scene.hpp"
#include "ppohdem/io/atomic_file.hpp"
#include "subprocess.hpp"

namespace ppohdem::port {
namespace fs = std::filesystem;
namespace {

constexpr int kSteps = 4;

/// Uniform in [-1, 1) from a 64-bit LCG (Knuth's MMIX constants): the same numbers from every
/// compiler and standard library (std::uniform_real_distribution's are not specified).
class PortableRandom {
 public:
  explicit PortableRandom(std::uint64_t seed) : state_(seed) {}
  double next() {
    state_ = state_ * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state_ >> 11) * 0x1.0p-52 - 1.0;
  }

 private:
  std::uint64_t state_;
};

std::string g17(double x) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", x);
  return b;
}

std::string read_text(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void replace_line(std::string& text, const std::string& starts_with, const std::string& line) {
  const auto at = text.find("\n" + starts_with);
  if (at == std::string::npos) throw std::logic_error("scene text without '" + starts_with + "'");
  const auto end = text.find('\n', at + 1);
  text.replace(at + 1, end - at - 1, line);
}

void write_text(const fs::path& file, const std::string& text) {
  AtomicFileWriter w(file);
  w.stream() << text;
  w.commit();
}

/// 512 spheres of R = 1 mm on a cubic lattice of pitch 1.98 mm (every neighbour overlapping by
/// 2 % of R) in a closed box whose walls overlap the outer layer by 1 % of R, with random
/// velocities (+-1 cm/s) and spins (+-10 rad/s): every contact law term is at work at step 0.
void export_dense_bed(const fs::path& dir) {
  const double r = 1.0e-3, pitch = 1.98e-3, first = r - 1.0e-5, last = first + 7 * pitch + r - 1.0e-5;
  PortableRandom random(20261204);
  dem::Particles p;
  for (int k = 0; k < 8; ++k)
    for (int j = 0; j < 8; ++j)
      for (int i = 0; i < 8; ++i) {
        dem::Particle q;
        q.id = static_cast<std::int64_t>(p.size()) + 1;
        q.radius = r;
        q.position = Vec3(first + i * pitch, first + j * pitch, first + k * pitch) +
                     2.0e-6 * Vec3(random.next(), random.next(), random.next());
        q.velocity = 0.01 * Vec3(random.next(), random.next(), random.next());
        q.angular_velocity = 10.0 * Vec3(random.next(), random.next(), random.next());
        p.push_back(q);
      }
  fs::create_directories(dir / "dense_bed");
  dem::write_particles_csv(dir / "dense_bed" / "particles.csv", p, "ppohdem port-validation scene dense_bed");
  std::ostringstream o;
  o << "# ppohdem port-validation deterministic scene 'dense_bed' (docs/port-validation.md)\n"
    << "[simulation]\ndt = 1.0e-5\nsteps = " << kSteps << "\ngravity = [0.0, 0.0, -9.81]\n"
    << "[material]\ndensity = 2500.0\nyoung = 1.0e7\npoisson = 0.3\nrestitution = 0.5\nfriction = 0.5\n"
    << "[contact]\nmodel = \"hertz-mindlin\"\n[particles]\nfile = \"particles.csv\"\nallow_overlap = true\n";
  const char* normals[6] = {"[1.0, 0.0, 0.0]", "[-1.0, 0.0, 0.0]", "[0.0, 1.0, 0.0]",
                            "[0.0, -1.0, 0.0]", "[0.0, 0.0, 1.0]", "[0.0, 0.0, -1.0]"};
  for (int w = 0; w < 6; ++w) {
    Vec3 point = Vec3::Zero();
    if (w % 2 == 1) point[w / 2] = last;
    o << "[[wall]]\npoint = [" << g17(point.x()) << ", " << g17(point.y()) << ", " << g17(point.z())
      << "]\nnormal = " << normals[w] << "\n";
  }
  o << "[output]\ndir = \"out\"\nevery = 1\nformats = [\"csv\"]\nprogress = false\n";
  write_text(dir / "dense_bed" / "scene.toml", o.str());
}

/// The seed sample's contact law, box and dragon (raised as in seed_sample) with particles of
/// R = 0.1 m on a 0.21 m grid wherever they touch the dragon (overlap up to 0.08 m): several
/// hundred contacts spread over its surface, and no two particles touching.
void export_seed_object(const fs::path& dir, const fs::path& source_dir, const std::string& ppohdem_program) {
  const fs::path seed_file = export_scene(port_scene("seed_sample"), dir, source_dir, ppohdem_program);
  const dem::Scene seed = dem::read_scene(seed_file);
  const auto& dragon = *seed.objects.at(0).object;
  dem::Particles p;
  for (int k = 1; k < 52; ++k)
    for (int j = 1; j < 52; ++j)
      for (int i = 1; i < 52; ++i) {
        const double x = 0.21 * i, y = 0.21 * j, z = 0.21 * k;
        const auto c = dragon.contact(Vec3(x, y, z), 0.1, 0.0);
        if (!c || c->overlap > 0.08) continue;
        dem::Particle q;
        q.id = static_cast<std::int64_t>(p.size()) + 1;
        q.radius = 0.1;
        q.position = Vec3(x, y, z);
        p.push_back(q);
      }
  fs::create_directories(dir / "seed_object");
  dem::write_particles_csv(dir / "seed_object" / "particles.csv", p, "ppohdem port-validation scene seed_object");
  std::string text = read_text(seed_file);
  replace_line(text, "steps =", "steps = " + std::to_string(kSteps));
  replace_line(text, "every =", "every = 1");
  replace_line(text, "distance =", "distance = \"../seed_sample/dragon.vtk\"");
  replace_line(text, "file =", "file = \"particles.csv\"\nallow_overlap = true");
  write_text(dir / "seed_object" / "scene.toml", text);
}

struct RunNumbers {
  std::map<int, std::map<std::int64_t, std::array<double, 6>>> change;  // step -> id -> dv, dw
  std::map<int, std::array<double, 5>> energy;                           // step -> terms
  std::map<int, std::array<double, 6>> object;                           // step -> F, T
};

std::vector<std::vector<std::string>> csv_rows(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": missing");
  std::vector<std::vector<std::string>> rows;
  std::string line;
  bool header = true;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (header) {
      header = false;
      continue;
    }
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
    rows.push_back(f);
  }
  return rows;
}

RunNumbers read_run(const fs::path& run) {
  RunNumbers n;
  const auto start = dem::read_particles_csv(frame_file(run, 0));
  std::map<std::int64_t, const dem::Particle*> initial;
  for (const auto& q : start) initial[q.id] = &q;
  for (const int step : {1, kSteps}) {
    for (const auto& q : dem::read_particles_csv(frame_file(run, step))) {
      const auto* q0 = initial.at(q.id);
      const Vec3 dv = q.velocity - q0->velocity, dw = q.angular_velocity - q0->angular_velocity;
      n.change[step][q.id] = {dv.x(), dv.y(), dv.z(), dw.x(), dw.y(), dw.z()};
    }
  }
  for (const auto& f : csv_rows(run / "energy.csv")) {
    const int step = std::stoi(f.at(0));
    n.energy[step] = {std::stod(f.at(2)), std::stod(f.at(3)), std::stod(f.at(4)), std::stod(f.at(5)), std::stod(f.at(6))};
  }
  if (fs::exists(run / "objects.csv")) {
    for (const auto& f : csv_rows(run / "objects.csv")) {
      n.object[std::stoi(f.at(0))] = {std::stod(f.at(13)), std::stod(f.at(14)), std::stod(f.at(15)),
                                      std::stod(f.at(16)), std::stod(f.at(17)), std::stod(f.at(18))};
    }
  }
  return n;
}

RunNumbers read_reference(const fs::path& file) {
  RunNumbers n;
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": missing (make it with ppohdem validate --save-baseline)");
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
    const int step = std::stoi(f.at(1));
    if (f[0] == "change") {
      auto& a = n.change[step][std::stoll(f.at(2))];
      for (int k = 0; k < 6; ++k) a[static_cast<std::size_t>(k)] = std::stod(f.at(static_cast<std::size_t>(3 + k)));
    } else if (f[0] == "energy") {
      auto& a = n.energy[step];
      for (int k = 0; k < 5; ++k) a[static_cast<std::size_t>(k)] = std::stod(f.at(static_cast<std::size_t>(2 + k)));
    } else if (f[0] == "object") {
      auto& a = n.object[step];
      for (int k = 0; k < 6; ++k) a[static_cast<std::size_t>(k)] = std::stod(f.at(static_cast<std::size_t>(2 + k)));
    }
  }
  return n;
}

/// max |a - b| / max |b| over the given components of every entry.
template <class Map>
double relative_difference(const Map& run, const Map& ref, int first, int count) {
  double worst = 0.0, scale = 0.0;
  for (const auto& [key, b] : ref) {
    const auto it = run.find(key);
    if (it == run.end()) return std::numeric_limits<double>::infinity();
    for (int k = first; k < first + count; ++k) {
      worst = std::max(worst, std::abs(it->second[static_cast<std::size_t>(k)] - b[static_cast<std::size_t>(k)]));
      scale = std::max(scale, std::abs(b[static_cast<std::size_t>(k)]));
    }
  }
  return scale > 0.0 ? worst / scale : worst;
}

}  // namespace

std::vector<std::string> deterministic_scene_names() { return {"dense_bed", "seed_object"}; }

void export_deterministic_scenes(const fs::path& dir, const fs::path& source_dir, const std::string& ppohdem_program) {
  export_dense_bed(dir);
  export_seed_object(dir, source_dir, ppohdem_program);
}

std::vector<fs::path> run_deterministic_scenes(const fs::path& work, const fs::path& source_dir,
                                               const std::string& engine, const std::string& launcher) {
  const std::string program = find_ppohdem_program();
  export_deterministic_scenes(work / "scenes", source_dir, program);
  std::vector<std::string> words;
  std::istringstream in(launcher);
  for (std::string w; in >> w;) words.push_back(w);
  std::vector<fs::path> outs;
  for (const auto& name : deterministic_scene_names()) {
    const fs::path out = work / "deterministic" / name;
    fs::remove_all(out);
    fs::create_directories(out.parent_path());
    const std::string log = out.string() + ".log";
    const int rc = run_program({program, "simulate", (work / "scenes" / name / "scene.toml").string(), "--engine", engine,
                                "--quiet", "--output-dir", out.string()},
                               log, words);
    if (rc != 0) throw std::runtime_error("ppohdem simulate " + name + " exited " + std::to_string(rc) + ": see " + log);
    outs.push_back(out);
  }
  return outs;
}

void save_deterministic_reference(const fs::path& dir, const std::string& scene, const fs::path& run_dir) {
  const RunNumbers n = read_run(run_dir);
  AtomicFileWriter w(dir / ("deterministic_" + scene + ".csv"));
  auto& o = w.stream();
  o << "# the deterministic tier's reference numbers of " << scene << " (docs/port-validation.md):\n"
    << "# change,step,id,dvx,dvy,dvz,dwx,dwy,dwz (velocity and spin after step minus initial, m/s, rad/s)\n"
    << "# energy,step,kinetic,rotational,gravitational,elastic,dissipated [J]; object,step,F [N] x3,T [N m] x3\n";
  for (const auto& [step, particles] : n.change)
    for (const auto& [id, a] : particles) {
      o << "change," << step << "," << id;
      for (double x : a) o << "," << g17(x);
      o << "\n";
    }
  for (const auto& [step, a] : n.energy) {
    o << "energy," << step;
    for (double x : a) o << "," << g17(x);
    o << "\n";
  }
  for (const auto& [step, a] : n.object) {
    o << "object," << step;
    for (double x : a) o << "," << g17(x);
    o << "\n";
  }
  w.commit();
}

std::vector<DeterministicRow> compare_deterministic(const fs::path& dir, const std::string& scene, const fs::path& run_dir) {
  const RunNumbers ref = read_reference(dir / ("deterministic_" + scene + ".csv"));
  const RunNumbers run = read_run(run_dir);
  // Tolerances: ~100x the largest difference of a known-good build (FMA contraction: 3.8e-14 of
  // a velocity change, energy or object load; 1.3e-10 of a spin change, whose first step is
  // the small torque of barely loaded tangential springs and carries the round-off of the
  // larger forces). A 1e-6 change of E, k_n or dt moves both by ~1e-6, of the restitution the
  // velocity changes by >= 2.4e-8 (docs/port-validation.md "Two tiers").
  constexpr double tolerance = 1e-11;
  constexpr double spin_tolerance = 1e-8;
  std::vector<DeterministicRow> rows;
  for (const int step : {1, kSteps}) {
    const std::string after = " after " + std::to_string(step) + " step" + (step > 1 ? "s" : "");
    const auto& a = run.change.count(step) ? run.change.at(step) : decltype(ref.change)::mapped_type{};
    rows.push_back({scene, "velocity change" + after, relative_difference(a, ref.change.at(step), 0, 3), tolerance});
    rows.push_back({scene, "spin change" + after, relative_difference(a, ref.change.at(step), 3, 3), spin_tolerance});
  }
  rows.push_back({scene, "energies, steps 0-4 (kinetic, rotational, gravitational, elastic, dissipated)",
                  relative_difference(run.energy, ref.energy, 0, 5), tolerance});
  if (!ref.object.empty()) {
    rows.push_back({scene, "object force, steps 0-4", relative_difference(run.object, ref.object, 0, 3), tolerance});
    rows.push_back({scene, "object torque, steps 0-4", relative_difference(run.object, ref.object, 3, 3), tolerance});
  }
  return rows;
}

}  // namespace ppohdem::port
