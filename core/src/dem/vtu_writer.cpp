// VTK XML particle frames with appended raw binary data (vtu_writer.hpp; docs/formats.md
// "VTK XML frames"). The layout follows "VTK File Formats", section "XML File Formats"
// (Kitware, VTK User's Guide 11th ed., and docs.vtk.org): header_type UInt64, so each array
// in the appended block is preceded by its byte count as a UInt64.
#include "ppohdem/dem/vtu_writer.hpp"

#include <bit>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <ostream>

#include "ppohdem/io/atomic_file.hpp"

namespace ppohdem::dem {
namespace {

static_assert(std::endian::native == std::endian::little, "the frames are written as LittleEndian");

/// The header as an XML comment: "--" may not appear inside one.
std::string xml_comment(const std::string& text) {
  std::string safe;
  for (const char c : text) {
    if (c == '-' && !safe.empty() && safe.back() == '-') safe += ' ';
    safe += c;
  }
  if (!safe.empty() && safe.back() == '-') safe += ' ';
  return "<!-- " + safe + " -->\n";
}

/// Text fit for an XML attribute value between double quotes.
std::string xml_attribute(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

const char* const kFileHead = "<VTKFile type=\"%s\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";

/// Appends the raw bytes of `n` values of T produced by value(i) to `block`.
template <class T, class Value>
void append_values(std::string& block, std::size_t n, Value value) {
  const std::size_t start = block.size();
  block.resize(start + n * sizeof(T));
  char* to = block.data() + start;
  for (std::size_t i = 0; i < n; ++i) {
    const T v = value(i);
    std::memcpy(to + i * sizeof(T), &v, sizeof(T));
  }
}

/// Appends x, y, z of get(particle) for every particle.
template <class Get>
void append_vectors(std::string& block, const Particles& p, Get get) {
  append_values<double>(block, 3 * p.size(), [&](std::size_t k) { return get(p[k / 3])[static_cast<Eigen::Index>(k % 3)]; });
}

}  // namespace

const std::vector<VtuArray>& vtu_point_arrays() {
  static const std::vector<VtuArray> arrays = {
      {"id", "Int64", 1},           {"radius", "Float64", 1}, {"velocity", "Float64", 3},
      {"angular_velocity", "Float64", 3}, {"material", "UInt16", 1}, {"force", "Float64", 3},
      {"torque", "Float64", 3}};
  return arrays;
}

std::string vtu_piece_name(long step, int rank, int ranks) {
  char buf[64];
  if (ranks <= 1) {
    std::snprintf(buf, sizeof buf, "frame_%06ld.vtu", step);
  } else {
    std::snprintf(buf, sizeof buf, "frame_%06ld_%04d.vtu", step, rank);
  }
  return buf;
}

void write_vtu_frame(const std::filesystem::path& file, const Particles& particles, const std::string& header) {
  const std::size_t n = particles.size();
  // The appended block: each array as [UInt64 byte count][bytes]; `offsets` are where each
  // array's count starts, relative to the block's first byte (after the '_').
  std::string block;
  std::vector<std::size_t> offsets;
  auto begin_array = [&](std::size_t bytes) {
    offsets.push_back(block.size());
    append_values<std::uint64_t>(block, 1, [&](std::size_t) { return static_cast<std::uint64_t>(bytes); });
  };
  block.reserve(8 * 11 + n * (8 * 18 + 2 + 8 + 8 + 1));
  begin_array(n * 24);  // points
  append_vectors(block, particles, [](const Particle& p) { return p.position; });
  begin_array(n * 8);
  append_values<std::int64_t>(block, n, [&](std::size_t i) { return particles[i].id; });
  begin_array(n * 8);
  append_values<double>(block, n, [&](std::size_t i) { return particles[i].radius; });
  begin_array(n * 24);
  append_vectors(block, particles, [](const Particle& p) { return p.velocity; });
  begin_array(n * 24);
  append_vectors(block, particles, [](const Particle& p) { return p.angular_velocity; });
  begin_array(n * 2);
  append_values<std::uint16_t>(block, n, [&](std::size_t i) { return particles[i].material; });
  begin_array(n * 24);
  append_vectors(block, particles, [](const Particle& p) { return p.force; });
  begin_array(n * 24);
  append_vectors(block, particles, [](const Particle& p) { return p.torque; });
  // Cells: one vertex (VTK_VERTEX = 1) per particle, so that every viewer draws the points.
  begin_array(n * 8);
  append_values<std::int64_t>(block, n, [](std::size_t i) { return static_cast<std::int64_t>(i); });
  begin_array(n * 8);
  append_values<std::int64_t>(block, n, [](std::size_t i) { return static_cast<std::int64_t>(i + 1); });
  begin_array(n);
  append_values<std::uint8_t>(block, n, [](std::size_t) { return std::uint8_t{1}; });

  std::string xml = "<?xml version=\"1.0\"?>\n" + xml_comment(header);
  char buf[256];
  std::snprintf(buf, sizeof buf, kFileHead, "UnstructuredGrid");
  xml += buf;
  std::snprintf(buf, sizeof buf, "  <UnstructuredGrid>\n    <Piece NumberOfPoints=\"%zu\" NumberOfCells=\"%zu\">\n", n, n);
  xml += buf;
  auto array = [&](const char* name, const char* type, int components, std::size_t offset) {
    std::snprintf(buf, sizeof buf,
                  "        <DataArray type=\"%s\"%s%s%s NumberOfComponents=\"%d\" format=\"appended\" offset=\"%zu\"/>\n",
                  type, *name ? " Name=\"" : "", name, *name ? "\"" : "", components, offset);
    xml += buf;
  };
  xml += "      <Points>\n";
  array("", "Float64", 3, offsets[0]);
  xml += "      </Points>\n      <PointData>\n";
  const auto& arrays = vtu_point_arrays();
  for (std::size_t a = 0; a < arrays.size(); ++a) array(arrays[a].name, arrays[a].type, arrays[a].components, offsets[1 + a]);
  xml += "      </PointData>\n      <Cells>\n";
  array("connectivity", "Int64", 1, offsets[8]);
  array("offsets", "Int64", 1, offsets[9]);
  array("types", "UInt8", 1, offsets[10]);
  xml += "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding=\"raw\">\n_";
  AtomicFileWriter writer(file, true);
  std::ostream& out = writer.stream();
  out.write(xml.data(), static_cast<std::streamsize>(xml.size()));
  out.write(block.data(), static_cast<std::streamsize>(block.size()));
  out << "\n  </AppendedData>\n</VTKFile>\n";
  writer.commit();
}

void write_pvtu_index(const std::filesystem::path& file, const std::vector<std::string>& piece_names,
                      const std::string& header) {
  AtomicFileWriter writer(file);
  std::ostream& out = writer.stream();
  char buf[256];
  std::snprintf(buf, sizeof buf, kFileHead, "PUnstructuredGrid");
  out << "<?xml version=\"1.0\"?>\n" << xml_comment(header) << buf << "  <PUnstructuredGrid GhostLevel=\"0\">\n";
  out << "    <PPoints>\n      <PDataArray type=\"Float64\" NumberOfComponents=\"3\"/>\n    </PPoints>\n";
  out << "    <PPointData>\n";
  for (const VtuArray& a : vtu_point_arrays()) {
    out << "      <PDataArray type=\"" << a.type << "\" Name=\"" << a.name << "\" NumberOfComponents=\"" << a.components
        << "\"/>\n";
  }
  out << "    </PPointData>\n";
  for (const std::string& piece : piece_names) out << "    <Piece Source=\"" << xml_attribute(piece) << "\"/>\n";
  out << "  </PUnstructuredGrid>\n</VTKFile>\n";
  writer.commit();
}

void write_pvd_collection(const std::filesystem::path& file, const std::vector<std::pair<double, std::string>>& frames,
                          const std::string& header) {
  AtomicFileWriter writer(file);
  std::ostream& out = writer.stream();
  out << "<?xml version=\"1.0\"?>\n" << xml_comment(header)
      << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n";
  char buf[64];
  for (const auto& [time, name] : frames) {
    std::snprintf(buf, sizeof buf, "%.17g", time);
    out << "    <DataSet timestep=\"" << buf << "\" group=\"\" part=\"0\" file=\"" << xml_attribute(name) << "\"/>\n";
  }
  out << "  </Collection>\n</VTKFile>\n";
  writer.commit();
}

}  // namespace ppohdem::dem
