// The original DEM's files: the patched original's full-precision state dumps, the inputs
// (object_mesh.stl as the original reads it), the initial sheet, and the per-frame outputs
// data/outNNN.dat, distance/objects_distanceNNN.csv, obj/objNNN.pov in the original's formats.
#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <string>

#include "ppohdem/error.hpp"
#include "ppohdem/compat/ppohdem10_dem.hpp"
#include "ppohdem10_dem_format.hpp"

namespace ppohdem::compat {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> split_words(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> words;
  std::string w;
  while (in >> w) words.push_back(w);
  return words;
}

double real_at(const std::vector<std::string>& words, std::size_t k, const std::string& source, std::size_t line,
               const char* what) {
  const auto v = parse_fortran_real(words[k]);
  if (!v || !std::isfinite(*v)) {
    throw InputError(source, line, std::string("expected a finite real for ") + what + ", found '" + words[k] + "'");
  }
  return *v;
}

long integer_at(const std::vector<std::string>& words, std::size_t k, const std::string& source, std::size_t line,
                const char* what) {
  std::size_t used = 0;
  long v = 0;
  try {
    v = std::stol(words[k], &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != words[k].size()) {
    throw InputError(source, line, std::string("expected an integer for ") + what + ", found '" + words[k] + "'");
  }
  return v;
}

}  // namespace

Ppohdem10State parse_ppohdem10_state(const std::string& text, const std::string& source) {
  std::istringstream in(text);
  std::string line;
  std::size_t line_no = 0;
  Ppohdem10State s;
  bool have_step = false;
  long announced = -1;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::vector<std::string> w = split_words(line);
    if (w.empty()) continue;
    if (w[0] == "#") {
      // `# step N rtime T n COUNT` (the column-name line is skipped)
      if (w.size() >= 7 && w[1] == "step" && w[3] == "rtime" && w[5] == "n") {
        s.step = integer_at(w, 2, source, line_no, "the step");
        s.rtime = real_at(w, 4, source, line_no, "rtime");
        announced = integer_at(w, 6, source, line_no, "the particle count");
        have_step = true;
      }
      continue;
    }
    if (w.size() != 19) {
      throw InputError(source, line_no,
                       "expected 19 columns (id x y z vx vy vz wx wy wz radius fx fy fz tx ty tz ncontact "
                       "ncontact_wall), found " + std::to_string(w.size()));
    }
    Ppohdem10ParticleRecord r;
    r.id = static_cast<int>(integer_at(w, 0, source, line_no, "id"));
    double v[16];
    for (std::size_t k = 0; k < 16; ++k) v[k] = real_at(w, k + 1, source, line_no, "a state value");
    r.pos = {v[0], v[1], v[2]};
    r.vel = {v[3], v[4], v[5]};
    r.omega = {v[6], v[7], v[8]};
    r.radius = v[9];
    r.force = {v[10], v[11], v[12]};
    r.rforce = {v[13], v[14], v[15]};
    r.ncontact = static_cast<int>(integer_at(w, 17, source, line_no, "ncontact"));
    r.ncontact_wall = static_cast<int>(integer_at(w, 18, source, line_no, "ncontact_wall"));
    if (!(r.radius > 0.0)) throw InputError(source, line_no, "expected a radius > 0");
    s.particles.push_back(r);
  }
  if (!have_step) throw InputError(source, 1, "expected a header line '# step N rtime T n COUNT'");
  if (announced != static_cast<long>(s.particles.size())) {
    throw InputError(source, line_no, "the header announces " + std::to_string(announced) + " particles, found " +
                                          std::to_string(s.particles.size()));
  }
  return s;
}

Ppohdem10State read_ppohdem10_state(const fs::path& path) {
  return parse_ppohdem10_state(read_file_bytes(path), path.string());
}

std::string format_ppohdem10_state(const Ppohdem10State& s) {
  using namespace fortran;
  std::string out;
  out.append("# step").append(i_format(s.step, 9)).append(" rtime ").append(es_format(s.rtime, 25, 17));
  out.append(" n").append(i_format(static_cast<long>(s.particles.size()), 7)).append("\n");
  out.append("# id x y z vx vy vz wx wy wz radius fx fy fz tx ty tz ncontact ncontact_wall\n");
  for (const Ppohdem10ParticleRecord& r : s.particles) {
    out.append(i_format(r.id, 6));
    for (const double v : {r.pos.x, r.pos.y, r.pos.z, r.vel.x, r.vel.y, r.vel.z, r.omega.x, r.omega.y, r.omega.z,
                           r.radius, r.force.x, r.force.y, r.force.z, r.rforce.x, r.rforce.y, r.rforce.z}) {
      out.append(es_format(v, 25, 17));
    }
    out.append(i_format(r.ncontact, 4)).append(i_format(r.ncontact_wall, 4)).append("\n");
  }
  return out;
}

Ppohdem10State ppohdem10_initial_sheet(const UpdateParamsInput& input, unsigned long long seed) {
  // ppohDEM_prepare_particles_bare + ppohDEM_locate_particles_2dbox, with the original's
  // single-precision literals (0.9, 0.01, 0.2 are floats in the original).
  using C = Ppohdem10DemConstants;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double lx = input.domain_length.x() * static_cast<double>(0.9f);
  const double lz = input.domain_length.z() * static_cast<double>(0.9f);
  const double x0 = 0.1;
  const double z0 = 5.0;
  const double y0 = static_cast<double>(0.5f) * input.domain_length.y();
  const double interval_ratio = 1.5;
  const double interval = 2 * C::kRadius * interval_ratio;  // 0.3 [m] pitch
  const long nx = static_cast<long>(std::floor(lx / interval));
  const long nz = static_cast<long>(std::floor(lz / interval));
  const long count = std::min<long>(C::kParticles, nx * nz);
  Ppohdem10State s;
  s.particles.resize(static_cast<std::size_t>(count));
  const double jitter = static_cast<double>(0.01f);
  for (long index = 1; index <= count; ++index) {
    const long i = (index - 1) % nx + 1;
    const long k = (index - 1) / nx + 1;
    Ppohdem10ParticleRecord& r = s.particles[static_cast<std::size_t>(index - 1)];
    r.id = static_cast<int>(index);
    r.pos.x = x0 + interval * static_cast<double>(i - 1) + C::kRadius * interval_ratio + jitter * (unit(rng) - 0.5);
    r.pos.y = y0;
    r.pos.z = z0 + interval * static_cast<double>(k - 1) + C::kRadius * interval_ratio + jitter * (unit(rng) - 0.5);
  }
  for (Ppohdem10ParticleRecord& r : s.particles) {
    r.radius = C::kRadius * (1 + static_cast<double>(0.2f) * unit(rng));
  }
  return s;
}

Ppohdem10DemInput read_ppohdem10_dem_input(const fs::path& params_file, const fs::path& work_dir,
                                           const std::optional<fs::path>& initial_state) {
  Ppohdem10DemInput in;
  in.params = read_update_params_input(params_file);
  // ppohDEM_prepare_objects_fromfile: ./distance_0000.dat names the rank files.
  in.data = read_distance_dat(work_dir / "distance_0000.dat");
  // The original counts the lines whose first word is `vertex` and reads 3 reals from each;
  // every other line is skipped. Triangles are consecutive triples.
  const fs::path stl = work_dir / "object_mesh.stl";
  std::istringstream text(read_file_bytes(stl));
  std::string line;
  std::size_t line_no = 0;
  while (std::getline(text, line)) {
    ++line_no;
    const std::vector<std::string> w = split_words(line);
    if (w.empty() || w[0] != "vertex") continue;
    if (w.size() < 4) throw InputError(stl.string(), line_no, "expected 'vertex x y z'");
    in.mesh_vertices.push_back({real_at(w, 1, stl.string(), line_no, "x"), real_at(w, 2, stl.string(), line_no, "y"),
                                real_at(w, 3, stl.string(), line_no, "z")});
  }
  in.initial = initial_state ? read_ppohdem10_state(*initial_state) : ppohdem10_initial_sheet(in.params, 12345);
  return in;
}

std::string ppohdem10_frame_text(const std::vector<Rvec3>& positions, const std::vector<double>& radius) {
  // ppohDEM_particles_fileout: write(12,'(7e16.6)') x, y, z, radius — 4 values, one line.
  if (positions.size() != radius.size()) throw InputError("ppohdem10_frame_text: positions and radii differ in count");
  std::string out;
  out.reserve(positions.size() * 65);
  for (std::size_t i = 0; i < positions.size(); ++i) {
    for (const double v : {positions[i].x, positions[i].y, positions[i].z, radius[i]}) {
      out.append(fortran::e_format(v, 16, 6));
    }
    out.push_back('\n');
  }
  return out;
}

std::string Ppohdem10Dem::frame_text() const { return ppohdem10_frame_text(particles_.pos, particles_.radius); }

std::string Ppohdem10Dem::object_field_csv() const {
  // write(313,*) ' x, y, z, distance ' then write(313,*) i // ', ' // j // ', ' // k // ', ' // d,
  // list-directed: each record starts with one blank.
  std::string out = "  x, y, z, distance \n";
  const Index3& n = object_.gridnum;
  for (int k = 1; k <= n[2]; ++k) {
    for (int j = 1; j <= n[1]; ++j) {
      for (int i = 1; i <= n[0]; ++i) {
        const int ijk = (k - 1) * n[0] * n[1] + (j - 1) * n[1] + i;
        out.append(" ").append(std::to_string(i)).append(", ").append(std::to_string(j)).append(", ");
        out.append(std::to_string(k)).append(", ");
        out.append(fortran::list_directed_real(object_.distance[static_cast<std::size_t>(ijk - 1)])).append("\n");
      }
    }
  }
  return out;
}

std::string Ppohdem10Dem::object_pov() const {
  // ppohDEM_output_object_pov: each vertex v rotated about `centroid` (coordinates, not the
  // field's index centre c: README "the two centres differ slightly, this only affects the
  // picture") by -omega_w f, shifted by vel f h and by -(winstart - 1) h, written
  // < x, z, y > (POV-Ray is y-up) with F12.8.
  const Ppohdem10Object& o = object_;
  const int omega_count = counter_.file_index;
  const Rvec3& w = o.omega_axis;
  const double norm = std::sqrt(w.x * w.x + w.y * w.y + w.z * w.z);
  const Rvec3 qn = {w.x / norm, w.y / norm, w.z / norm};
  const double half_angle = -o.omega_w * omega_count / 2;
  const double q0 = std::cos(half_angle);
  const double q1 = qn.x * std::sin(half_angle);
  const double q2 = qn.y * std::sin(half_angle);
  const double q3 = qn.z * std::sin(half_angle);
  auto place = [&](const Rvec3& v) {
    const Rvec3 m = {v.x - o.centroid.x, v.y - o.centroid.y, v.z - o.centroid.z};
    const double dx = (q0 * q0 + q1 * q1 - q2 * q2 - q3 * q3) * m.x + 2 * (q1 * q2 - q0 * q3) * m.y +
                      2 * (q1 * q3 + q0 * q2) * m.z;
    const double dy = 2 * (q1 * q2 + q0 * q3) * m.x + (q0 * q0 - q1 * q1 + q2 * q2 - q3 * q3) * m.y +
                      2 * (q2 * q3 - q0 * q1) * m.z;
    const double dz = 2 * (q1 * q3 - q0 * q2) * m.x + 2 * (q2 * q3 + q0 * q1) * m.y +
                      (q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3) * m.z;
    return Rvec3{dx + o.centroid.x + (o.vel.x * omega_count) * o.gridsize.x,
                 dy + o.centroid.y + (o.vel.y * omega_count) * o.gridsize.y,
                 dz + o.centroid.z + (o.vel.z * omega_count) * o.gridsize.z};
  };
  auto vertex_line = [&](const Rvec3& v, const char* end) {
    auto f = [](double x) {
      std::string s = fortran::f_format(x, 12, 8);
      return s.substr(s.find_first_not_of(' '));
    };
    std::string line = "     < ";
    line.append(f(v.x - (o.winstart[0] - 1) * o.gridsize.x)).append(", ");
    line.append(f(v.z - (o.winstart[2] - 1) * o.gridsize.z)).append(", ");
    line.append(f(v.y - (o.winstart[1] - 1) * o.gridsize.y)).append(end).append("\n");
    return line;
  };
  std::string out = "   \n  mesh { \n";
  for (std::size_t t = 0; t < o.mesh_v1.size(); ++t) {
    out.append("   triangle { \n");
    out.append(vertex_line(place(o.mesh_v1[t]), " >, "));
    out.append(vertex_line(place(o.mesh_v2[t]), " >, "));
    out.append(vertex_line(place(o.mesh_v3[t]), " > "));
    out.append("     texture {T_Silver_1A}  \n");
    out.append("   } \n");
  }
  out.append("  } \n");
  return out;
}

}  // namespace ppohdem::compat
