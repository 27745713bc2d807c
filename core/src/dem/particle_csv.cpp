#include "ppohdem/dem/particle_csv.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <string_view>
#include <unordered_set>
#include <vector>

#include "ppohdem/error.hpp"
#include "ppohdem/io/block_file.hpp"

namespace ppohdem::dem {
namespace {

constexpr std::string_view kHeader = "id,x,y,z,vx,vy,vz,wx,wy,wz,radius";
constexpr std::string_view kMaterialHeader = "id,x,y,z,vx,vy,vz,wx,wy,wz,radius,material";
constexpr std::size_t kColumns = 11;  // without the optional material column

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

void split(std::string_view line, std::vector<std::string_view>& fields) {
  fields.clear();
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    fields.push_back(trim(line.substr(start, comma == std::string_view::npos ? line.npos : comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
}

// The value std::stod gives a field, when std::from_chars reads it whole into a normal number
// or an exact zero: both round correctly, so the values are the same. Anything else (a '+',
// hexadecimal, inf/nan, an underflow or overflow, trailing characters) returns nothing and
// takes std::stod's path, which decides as before (docs/performance.md "Reading and writing
// particles").
std::optional<double> quick_number(std::string_view f) {
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(f.data(), f.data() + f.size(), v);
  if (ec != std::errc() || ptr != f.data() + f.size()) return std::nullopt;
  if (std::isnormal(v)) return v;
  if (v != 0.0) return std::nullopt;  // subnormal: strtod reports a range error
  for (const char c : f) {            // zero: exact only if no digit of the mantissa is non-zero
    if (c == 'e' || c == 'E') break;
    if (c >= '1' && c <= '9') return std::nullopt;
  }
  return v;
}

// %.17g without printf's multi-precision path: std::to_chars with a precision writes what
// printf's %.*g writes ([charconv.to.chars]); ParticleCsv.WriterMatchesPrintf checks it.
char* put_g17(char* at, char* end, double v) {
  return std::to_chars(at, end, v, std::chars_format::general, 17).ptr;
}

}  // namespace

Particles read_particles_csv(const std::filesystem::path& file,
                             const std::vector<std::string>& material_names) {
  std::ifstream in(file);
  const std::string name = file.string();
  if (!in) throw InputError(name, 0, "cannot open particle file");
  Particles particles;
  std::unordered_set<std::int64_t> ids;
  std::string raw;
  std::vector<std::string_view> fields;
  std::size_t line_no = 0;
  bool header_seen = false;
  bool with_material = false;
  while (std::getline(in, raw)) {
    ++line_no;
    const std::string_view line = trim(raw);
    if (line.empty() || line.front() == '#') continue;
    if (!header_seen) {
      std::string compact;
      for (char c : line) if (c != ' ' && c != '\t') compact += c;
      with_material = compact == kMaterialHeader;
      if (compact != kHeader && !with_material) {
        throw InputError(name, line_no, "expected header '" + std::string(kHeader) + "' (or with ',material'), found '" +
                                            std::string(line) + "'");
      }
      if (with_material && material_names.empty()) {
        throw InputError(name, line_no, "a 'material' column needs a scene whose materials have names "
                                        "([material] name = ... or [[material]] entries)");
      }
      header_seen = true;
      continue;
    }
    split(line, fields);
    const std::size_t columns = with_material ? kColumns + 1 : kColumns;
    if (fields.size() != columns) {
      throw InputError(name, line_no, "expected " + std::to_string(columns) + " comma-separated values, found " +
                                          std::to_string(fields.size()));
    }
    Particle p;
    {
      const auto f = fields[0];
      const auto [ptr, ec] = std::from_chars(f.data(), f.data() + f.size(), p.id);
      if (ec != std::errc() || ptr != f.data() + f.size()) {
        throw InputError(name, line_no, "column 'id': expected an integer, found '" + std::string(f) + "'");
      }
    }
    double v[kColumns - 1];
    for (std::size_t c = 1; c < kColumns; ++c) {
      if (const auto quick = quick_number(fields[c])) {
        v[c - 1] = *quick;
        continue;
      }
      const std::string field(fields[c]);
      std::size_t used = 0;
      bool ok = !field.empty();
      try {
        v[c - 1] = std::stod(field, &used);  // accepts "nan"/"inf": rejected below
      } catch (const std::exception&) {
        ok = false;
      }
      if (!ok || used != field.size()) {
        throw InputError(name, line_no, "column " + std::to_string(c + 1) + ": expected a number, found '" + field + "'");
      }
      if (!std::isfinite(v[c - 1])) {
        throw InputError(name, line_no, "column " + std::to_string(c + 1) + ": expected a finite number, found '" + field + "'");
      }
    }
    p.position = Vec3(v[0], v[1], v[2]);
    p.velocity = Vec3(v[3], v[4], v[5]);
    p.angular_velocity = Vec3(v[6], v[7], v[8]);
    p.radius = v[9];
    if (!(p.radius > 0.0)) {
      throw InputError(name, line_no, "radius must be > 0 m, found " + std::string(fields[10]));
    }
    if (with_material) {
      const std::string_view m = fields[kColumns];
      const auto it = std::find(material_names.begin(), material_names.end(), m);
      if (it == material_names.end()) {
        std::string known;
        for (const std::string& n : material_names) known += (known.empty() ? "" : ", ") + n;
        throw InputError(name, line_no, "column 'material': unknown material '" + std::string(m) + "' (the scene has: " +
                                            known + ")");
      }
      p.material = static_cast<std::uint16_t>(it - material_names.begin());
    }
    if (!ids.insert(p.id).second) {
      throw InputError(name, line_no, "id " + std::to_string(p.id) + " appears twice");
    }
    particles.push_back(p);
  }
  if (!header_seen) throw InputError(name, line_no, "expected header '" + std::string(kHeader) + "', found end of file");
  return particles;
}

void write_particles_csv(const std::filesystem::path& file, const Particles& particles,
                         const std::string& header_comment, const std::vector<std::string>& material_names) {
  // Blocks past the page cache (io/block_file.hpp; docs/performance.md "I/O: particle files").
  BlockFileWriter writer(file);
  const bool with_material = material_names.size() > 1;
  std::string block;  // handed to the writer 1 MiB at a time
  block.reserve((1u << 20) + 1024);
  if (!header_comment.empty()) block += "# " + header_comment + '\n';
  block += with_material ? kMaterialHeader : kHeader;
  block += '\n';
  char buf[512];
  for (const Particle& p : particles) {
    char* at = std::to_chars(buf, buf + 32, static_cast<long long>(p.id)).ptr;
    for (const double v : {p.position.x(), p.position.y(), p.position.z(), p.velocity.x(), p.velocity.y(),
                           p.velocity.z(), p.angular_velocity.x(), p.angular_velocity.y(), p.angular_velocity.z(),
                           p.radius}) {
      *at++ = ',';
      at = put_g17(at, buf + sizeof buf, v);
    }
    block.append(buf, at);
    if (with_material) {
      block += ',';
      block += material_names.at(p.material);
    }
    block += '\n';
    if (block.size() >= (1u << 20)) {
      writer.write(block.data(), block.size());
      block.clear();
    }
  }
  writer.write(block.data(), block.size());
  writer.commit();
}

}  // namespace ppohdem::dem
