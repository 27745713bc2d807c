// loads.csv (formats in load_log.hpp, docs/objects.md "Loads output").
#include "ppohdem/dem/load_log.hpp"

#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "ppohdem/io/atomic_file.hpp"

namespace ppohdem::dem {

LoadLog::LoadLog(std::filesystem::path file, std::string header, std::vector<std::string> names)
    : file_(std::move(file)), header_(std::move(header)), names_(std::move(names)) {}

void LoadLog::accumulate(const std::vector<BoundaryLoad>& loads) {
  sums_.resize(loads.size());
  for (std::size_t b = 0; b < loads.size(); ++b) {
    sums_[b].force += loads[b].force;
    sums_[b].moment_about_origin += loads[b].moment_about_origin;
  }
  ++samples_;
}

void LoadLog::add(long step, double time, const std::vector<BoundaryLoad>& loads) {
  const bool averaged = samples_ > 0;
  const std::size_t count = averaged ? sums_.size() : loads.size();
  for (std::size_t b = 0; b < count; ++b) {
    BoundaryLoad l = averaged ? sums_[b] : loads[b];
    if (averaged) {
      l.force /= static_cast<double>(samples_);
      l.moment_about_origin /= static_cast<double>(samples_);
    }
    char buf[400];
    std::snprintf(buf, sizeof buf, "%ld,%.17g,%zu,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%ld", step, time, b,
                  l.force.x(), l.force.y(), l.force.z(), l.moment_about_origin.x(), l.moment_about_origin.y(),
                  l.moment_about_origin.z(), averaged ? samples_ : 1L);
    rows_.emplace_back(buf);
  }
  sums_.assign(sums_.size(), BoundaryLoad{});
  samples_ = 0;
}

void LoadLog::flush() const {
  AtomicFileWriter writer(file_);
  std::ostream& out = writer.stream();
  out << "# " << header_ << '\n';
  for (std::size_t b = 0; b < names_.size(); ++b) out << "# boundary " << b << ": " << names_[b] << '\n';
  out << "step,time,boundary,force_x,force_y,force_z,moment_x,moment_y,moment_z,samples\n";
  for (const std::string& row : rows_) out << row << '\n';
  writer.commit();
}

void LoadLog::continue_from_disk(long step) {
  std::ifstream in(file_);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] < '0' || line[0] > '9') continue;  // comments, header
    char* end = nullptr;
    const long row_step = std::strtol(line.c_str(), &end, 10);
    if (end != nullptr && *end == ',' && row_step <= step) rows_.push_back(line);
  }
}

}  // namespace ppohdem::dem
