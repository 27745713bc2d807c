// Observables of a run (observables.hpp; definitions in docs/port-validation.md "Observables").
#include "observables.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "ppohdem/dem/particle_csv.hpp"

namespace ppohdem::port {
namespace fs = std::filesystem;
namespace {

constexpr double kPi = std::numbers::pi;

/// Normal elastic force of a wall contact of overlap `delta` [N]: what the floor carries. The
/// wall is of the particle's material (Hertz: E* = E / (2 (1 - nu^2)), R* = R), as in ppohdem.
double wall_normal_force(const PortScene& s, double radius, double delta) {
  if (delta <= 0.0) return 0.0;
  if (s.linear) return s.stiffness * delta;
  const double e_star = s.young / (2.0 * (1.0 - s.poisson * s.poisson));
  return 4.0 / 3.0 * e_star * std::sqrt(radius) * std::pow(delta, 1.5);
}

/// Volume of a sphere (centre height z, radius r) below the plane at height t [m^3].
double volume_below(double z, double r, double t) {
  if (t <= z - r) return 0.0;
  if (t >= z + r) return 4.0 / 3.0 * kPi * r * r * r;
  const double h = t - (z - r);
  return kPi * h * h * (3.0 * r - h) / 3.0;
}

std::map<std::string, double> frame_observables(const PortScene& s, const dem::Particles& p) {
  std::map<std::string, double> o;
  const std::size_t n = p.size();
  if (n == 0) throw std::runtime_error("a frame without particles");
  double z_sum = 0.0, kinetic = 0.0, probe_volume = 0.0;  // probe: sphere volume in the slab
  std::vector<double> tops;
  Vec3 lo = p[0].position, hi = p[0].position;
  double diameter_sum = 0.0;
  for (const auto& q : p) {
    const double r = q.radius;
    const double volume = 4.0 / 3.0 * kPi * r * r * r;
    const double mass = s.density * volume;
    z_sum += q.position.z();
    tops.push_back(q.position.z() + r);
    kinetic += 0.5 * mass * q.velocity.squaredNorm() + 0.5 * (0.4 * mass * r * r) * q.angular_velocity.squaredNorm();
    const Vec3& x = q.position;
    // The slab's whole cross-section between the walls: exact volumes (caps), continuous in x.
    probe_volume += volume_below(x.z(), r, s.probe_max.z()) - volume_below(x.z(), r, s.probe_min.z());
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
    diameter_sum += 2.0 * r;
  }
  o["mean_height"] = z_sum / static_cast<double>(n);
  std::sort(tops.begin(), tops.end(), std::greater<>());
  const std::size_t top_count = std::max<std::size_t>(1, n / 20);  // the top 5 %
  double top_sum = 0.0;
  for (std::size_t k = 0; k < top_count; ++k) top_sum += tops[k];
  o["top_height"] = top_sum / static_cast<double>(top_count);
  o["packing_fraction"] = probe_volume / (s.probe_max - s.probe_min).prod();
  // Kinetic energy spans decades while the bed settles: its logarithm is what varies normally.
  o["log10_kinetic_energy"] = std::log10(std::max(kinetic, 1e-300));

  // Pairs: contacts (coordination, fabric) and the first peak of g(s), s = r / (R_i + R_j).
  constexpr double s_max = 1.5, bin = 0.01;
  std::vector<double> histogram(static_cast<std::size_t>(s_max / bin) + 1, 0.0);
  std::size_t contacts = 0;
  double first_peak_sum = 0.0;
  std::size_t first_peak_count = 0;
  Eigen::Matrix3d fabric = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      const Vec3 d = p[j].position - p[i].position;
      const double reach = (p[i].radius + p[j].radius) * s_max;
      if (std::abs(d.x()) > reach || std::abs(d.y()) > reach || std::abs(d.z()) > reach) continue;
      const double r = d.norm();
      const double sij = r / (p[i].radius + p[j].radius);
      if (sij >= s_max) continue;
      histogram[static_cast<std::size_t>(sij / bin)] += 1.0;
      if (sij < 1.1) {
        first_peak_sum += sij;
        ++first_peak_count;
      }
      if (sij < 1.0 && r > 0.0) {
        ++contacts;
        const Vec3 u = d / r;
        fabric += u * u.transpose();
      }
    }
  }
  o["coordination"] = 2.0 * static_cast<double>(contacts) / static_cast<double>(n);
  // Fabric phi = <n n> over contacts; for a distribution 1 + a (3 cos^2 - 1) / 2 about z,
  // phi_zz = 1/3 + 2 a / 15 (Rothenburg & Bathurst 1989).
  o["fabric_anisotropy"] = contacts > 0 ? 7.5 * (fabric(2, 2) / static_cast<double>(contacts) - 1.0 / 3.0) : 0.0;
  o["first_peak_position"] = first_peak_count > 0 ? first_peak_sum / static_cast<double>(first_peak_count) : 0.0;
  // g(s) = pairs in the bin / (pairs of an ideal gas of the centres' bounding-box density).
  const double mean_d = diameter_sum / static_cast<double>(n);
  const double box = std::max((hi - lo).prod(), mean_d * mean_d * mean_d);
  const double density = static_cast<double>(n) / box;
  double peak = 0.0;
  for (std::size_t k = 0; k < histogram.size(); ++k) {
    const double sc = (static_cast<double>(k) + 0.5) * bin;
    const double ideal = 0.5 * static_cast<double>(n) * density * 4.0 * kPi * std::pow(mean_d * sc, 2) * mean_d * bin;
    peak = std::max(peak, histogram[k] / ideal);
  }
  o["first_peak_height"] = peak;

  double floor_load = 0.0, side_load = 0.0;
  for (const PortWall& w : s.walls) {
    double load = 0.0;
    for (const auto& q : p) load += wall_normal_force(s, q.radius, q.radius - (q.position - w.point).dot(w.normal));
    (w.name == "floor" ? floor_load : side_load) += load;
  }
  o["floor_load"] = floor_load;
  o["side_wall_load"] = side_load;
  return o;
}

/// objects.csv rows by step: force and torque of object 0.
std::map<long, std::array<double, 6>> read_object_loads(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot open (a scene with an object needs objects.csv)");
  std::string line;
  std::vector<std::string> header;
  std::map<long, std::array<double, 6>> rows;
  long line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
    if (header.empty()) {
      header = f;
      continue;
    }
    auto col = [&](const std::string& name) -> double {
      const auto it = std::find(header.begin(), header.end(), name);
      if (it == header.end() || static_cast<std::size_t>(it - header.begin()) >= f.size()) {
        throw std::runtime_error(file.string() + ":" + std::to_string(line_number) + ": expected a column '" + name + "'");
      }
      return std::stod(f[static_cast<std::size_t>(it - header.begin())]);
    };
    if (col("object") != 0.0) continue;
    rows[std::lround(col("step"))] = {col("force_x"), col("force_y"), col("force_z"),
                                      col("torque_x"), col("torque_y"), col("torque_z")};
  }
  return rows;
}

}  // namespace

fs::path frame_file(const fs::path& run_dir, long step) {
  char name[64];
  std::snprintf(name, sizeof name, "frame_%06ld.csv", step);
  return run_dir / name;
}

Observables run_observables(const PortScene& scene, const fs::path& run_dir) {
  Observables result;
  std::map<long, std::array<double, 6>> loads;
  if (scene.has_object) loads = read_object_loads(run_dir / "objects.csv");
  for (const long step : scene.observable_steps) {
    const fs::path file = frame_file(run_dir, step);
    if (!fs::exists(file)) throw std::runtime_error(file.string() + ": missing (the frame of observable step " +
                                                    std::to_string(step) + ")");
    const auto frame = frame_observables(scene, dem::read_particles_csv(file));
    std::string at = "@";  // (not "@" + s: GCC 12 warns falsely, -Wrestrict)
    at += std::to_string(step);
    for (const auto& [name, value] : frame) {
      result.names.push_back(name + at);
      result.values.push_back(value);
    }
    if (scene.has_object) {
      const auto it = loads.find(step);
      if (it == loads.end()) throw std::runtime_error((run_dir / "objects.csv").string() + ": no row of step " +
                                                      std::to_string(step));
      const auto& l = it->second;
      result.names.push_back("object_force_z" + at);
      result.values.push_back(l[2]);
      result.names.push_back("object_force_xy" + at);
      result.values.push_back(std::hypot(l[0], l[1]));
      result.names.push_back("object_torque_z" + at);
      result.values.push_back(l[5]);
    }
  }
  return result;
}

RunFingerprint run_fingerprint(const fs::path& run_dir) {
  std::vector<fs::path> frames;
  for (const auto& e : fs::directory_iterator(run_dir)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("frame_", 0) == 0 && e.path().extension() == ".csv") frames.push_back(e.path());
  }
  if (frames.empty()) throw std::runtime_error(run_dir.string() + ": no frame_NNNNNN.csv (is it a run's output folder?)");
  std::sort(frames.begin(), frames.end());
  const auto p = dem::read_particles_csv(frames.front());
  RunFingerprint f;
  f.count = p.size();
  for (const auto& q : p) f.radius_sum += q.radius;
  return f;
}

}  // namespace ppohdem::port
