// The growth diagnostic (growth.hpp; docs/port-validation.md "Growth diagnostic").
#include "growth.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "ppohdem/dem/particle_csv.hpp"
#include "ppohdem/io/atomic_file.hpp"

namespace ppohdem::port {
namespace fs = std::filesystem;
namespace {

using Positions = std::map<std::int64_t, Vec3>;  // tracked id -> centre

/// Every 10th particle by id (ids 1, 11, 21, ...): an RMS over ~100 particles of a 1,000 bed.
bool tracked(std::int64_t id) { return id % 10 == 1; }

std::map<long, Positions> frames(const fs::path& run) {
  std::map<long, Positions> out;
  for (const auto& e : fs::directory_iterator(run)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("frame_", 0) != 0 || e.path().extension() != ".csv") continue;
    const long step = std::stol(name.substr(6, name.size() - 10));
    Positions& p = out[step];
    for (const auto& q : dem::read_particles_csv(e.path()))
      if (tracked(q.id)) p[q.id] = q.position;
  }
  return out;
}

double rms(const Positions& a, const Positions& b) {
  double sum = 0.0;
  std::size_t n = 0;
  for (const auto& [id, x] : a) {
    const auto it = b.find(id);
    if (it == b.end()) return std::numeric_limits<double>::quiet_NaN();
    sum += (x - it->second).squaredNorm();
    ++n;
  }
  return n > 0 ? std::sqrt(sum / static_cast<double>(n)) : std::numeric_limits<double>::quiet_NaN();
}

std::string g17(double x) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", x);
  return b;
}

}  // namespace

void save_growth(const fs::path& dir, const std::string& scene, const std::vector<fs::path>& pairs,
                 const fs::path& reference_run) {
  std::vector<std::map<long, Positions>> runs;
  for (const auto& p : pairs) runs.push_back(frames(p));
  const auto reference = frames(reference_run);
  AtomicFileWriter w(dir / (scene + ".growth.csv"));
  auto& o = w.stream();
  o << "# growth diagnostic of " << scene << " (docs/port-validation.md): envelope,step,min,median,max of the RMS\n"
    << "# distance [m] between " << runs.size() / 2 << " pairs of members (every 10th particle by id); "
    << "reference,step,id,x,y,z: the reference machine's run of seed " << kGrowthSeed << "\n";
  for (const auto& [step, ref] : reference) {
    std::vector<double> d;
    for (std::size_t k = 0; k + 1 < runs.size(); k += 2) {
      if (runs[k].count(step) && runs[k + 1].count(step)) d.push_back(rms(runs[k].at(step), runs[k + 1].at(step)));
    }
    if (d.empty()) continue;
    std::sort(d.begin(), d.end());
    o << "envelope," << step << "," << g17(d.front()) << "," << g17(d[d.size() / 2]) << "," << g17(d.back()) << "\n";
    for (const auto& [id, x] : ref) o << "reference," << step << "," << id << "," << g17(x.x()) << "," << g17(x.y()) << "," << g17(x.z()) << "\n";
  }
  w.commit();
}

std::vector<GrowthRow> growth_rows(const fs::path& dir, const std::string& scene, const fs::path& port_run) {
  std::ifstream in(dir / (scene + ".growth.csv"));
  if (!in) return {};
  std::map<long, GrowthRow> rows;
  std::map<long, Positions> reference;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
    const long step = std::stol(f.at(1));
    if (f[0] == "envelope") {
      rows[step] = {step, std::numeric_limits<double>::quiet_NaN(), std::stod(f.at(2)), std::stod(f.at(3)), std::stod(f.at(4))};
    } else if (f[0] == "reference") {
      reference[step][std::stoll(f.at(2))] = Vec3(std::stod(f.at(3)), std::stod(f.at(4)), std::stod(f.at(5)));
    }
  }
  const auto port = frames(port_run);
  std::vector<GrowthRow> out;
  for (auto& [step, row] : rows) {
    if (port.count(step) && reference.count(step)) row.port = rms(port.at(step), reference.at(step));
    out.push_back(row);
  }
  return out;
}

}  // namespace ppohdem::port
