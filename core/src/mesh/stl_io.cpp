/// \file stl_io.cpp
/// STL encoding detection, the binary reader, and both writers. The ASCII grammar is in
/// stl_ascii.cpp. Binary layout (little-endian): 80-byte header, uint32 triangle count n,
/// then n records of 50 bytes: 12 float32 (normal, v0, v1, v2) and a uint16 attribute.
#include "ppohdem/mesh/stl_io.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>

#include "ppohdem/error.hpp"
#include "ppohdem/io/atomic_file.hpp"
#include "stl_ascii.hpp"

namespace ppohdem {
namespace {

constexpr std::size_t kHeaderBytes = 80;
constexpr std::size_t kPreambleBytes = kHeaderBytes + 4;  // header + uint32 count
constexpr std::size_t kRecordBytes = 50;                  // 12 float32 + uint16

std::uint32_t load_u32_le(const char* p) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(p[i]);
  return v;
}

double load_f32_le(const char* p) {
  const std::uint32_t bits = load_u32_le(p);
  float f = 0.0f;
  std::memcpy(&f, &bits, sizeof f);
  return static_cast<double>(f);
}

void store_u32_le(char* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<char>((v >> (8 * i)) & 0xFFu);
}

void store_f32_le(char* p, float f) {
  std::uint32_t bits = 0;
  std::memcpy(&bits, &f, sizeof f);
  store_u32_le(p, bits);
}

/// 84 + 50 n, or 0 if `bytes` is too short to hold a count.
std::size_t expected_binary_size(std::string_view bytes) {
  if (bytes.size() < kPreambleBytes) return 0;
  return kPreambleBytes + kRecordBytes * std::size_t{load_u32_le(bytes.data() + kHeaderBytes)};
}

/// Printable header text, trailing NULs and blanks removed (informational name).
std::string header_text(std::string_view header) {
  std::string name;
  for (char c : header) name += (c >= 0x20 && c < 0x7F) ? c : ' ';
  while (!name.empty() && name.back() == ' ') name.pop_back();
  return name;
}

TriangleMesh parse_binary_stl(std::string_view bytes, const std::string& source,
                              StlReadReport& report) {
  if (bytes.size() < kPreambleBytes) {
    throw InputError(source, 0,
                     "truncated binary STL: expected at least 84 bytes (80-byte header and "
                     "uint32 triangle count), found " + std::to_string(bytes.size()) + " bytes");
  }
  const std::size_t count = load_u32_le(bytes.data() + kHeaderBytes);
  const std::size_t expected = expected_binary_size(bytes);
  if (bytes.size() != expected) {
    const bool truncated = bytes.size() < expected;
    std::string message = std::string(truncated ? "truncated" : "padded") +
                          " binary STL (size/count mismatch): the header says " +
                          std::to_string(count) + " triangles, so expected 84 + 50 * " +
                          std::to_string(count) + " = " + std::to_string(expected) +
                          " bytes, found " + std::to_string(bytes.size());
    if (truncated) {
      const std::size_t complete = (bytes.size() - kPreambleBytes) / kRecordBytes;
      message += "; triangle " + std::to_string(complete + 1) + " is incomplete";
    }
    throw InputError(source, 0, message);
  }
  TriangleMesh mesh;
  mesh.name = header_text(bytes.substr(0, kHeaderBytes));
  mesh.triangles.resize(count);
  for (std::size_t t = 0; t < count; ++t) {
    const char* record = bytes.data() + kPreambleBytes + t * kRecordBytes;
    Triangle& tri = mesh.triangles[t];
    for (int a = 0; a < 3; ++a) tri.file_normal[a] = load_f32_le(record + 4 * a);
    if (!tri.file_normal.allFinite()) {
      tri.file_normal.setZero();
      ++report.non_finite_normals;
    }
    for (int k = 0; k < 3; ++k) {
      for (int a = 0; a < 3; ++a) {
        const double x = load_f32_le(record + 12 * (k + 1) + 4 * a);
        if (!std::isfinite(x)) {
          throw InputError(source, 0,
                           "non-finite coordinate in triangle " + std::to_string(t + 1) + " of " +
                               std::to_string(count) + ", vertex " + std::to_string(k + 1) +
                               ", axis " + "xyz"[a] + ": expected a finite number");
        }
        tri.v[static_cast<std::size_t>(k)][a] = x;
      }
    }
    if (tri.area_vector() == Vec3::Zero()) ++report.degenerate_triangles;
  }
  return mesh;
}

/// The unit normal (file normal if asked). Vertices are first divided by their largest
/// coordinate magnitude so that the cross product neither overflows nor underflows.
Vec3 normal_to_write(const Triangle& t, bool use_file_normals) {
  if (use_file_normals) return t.file_normal;
  const double magnitude = std::max({t.v[0].cwiseAbs().maxCoeff(), t.v[1].cwiseAbs().maxCoeff(),
                                     t.v[2].cwiseAbs().maxCoeff()});
  if (!(magnitude > 0.0)) return Vec3::Zero();
  const Vec3 w0 = t.v[0] / magnitude;
  const Vec3 n = (t.v[1] / magnitude - w0).cross(t.v[2] / magnitude - w0);
  const double length = n.norm();
  return length > 0.0 ? Vec3(n / length) : Vec3::Zero();  // zero for degenerate facets
}

/// `x` with `digits` significant digits, shortest form std::to_chars gives ("%.17g"-like).
void append_number(std::string& out, double x, int digits) {
  char buffer[64];
  const auto result =
      std::to_chars(buffer, buffer + sizeof buffer, x, std::chars_format::general, digits);
  out.append(buffer, result.ptr);
}

void append_vec(std::string& out, const Vec3& v, int digits) {
  for (int a = 0; a < 3; ++a) {
    out += ' ';
    append_number(out, v[a], digits);
  }
  out += '\n';
}

/// One line, printable ASCII only, so the name cannot break the grammar.
std::string sanitized_name(const std::string& name) {
  std::string clean;
  for (char c : name) clean += (c >= 0x20 && c < 0x7F) ? c : ' ';
  return clean.empty() ? std::string("ppohdem") : clean;
}

void write_ascii(std::ostream& out, const TriangleMesh& mesh, bool use_file_normals,
                 int digits) {
  const std::string name = sanitized_name(mesh.name);
  std::string text = "solid " + name + "\n";
  for (const Triangle& t : mesh.triangles) {
    text += "  facet normal";
    append_vec(text, normal_to_write(t, use_file_normals), digits);
    text += "    outer loop\n";
    for (const Vec3& p : t.v) {
      text += "      vertex";
      append_vec(text, p, digits);
    }
    text += "    endloop\n  endfacet\n";
    if (text.size() > (1u << 20)) {  // stream in ~1 MB pieces
      out << text;
      text.clear();
    }
  }
  text += "endsolid " + name + "\n";
  out << text;
}

/// Finite and within float32 range (converting anything else to float is undefined).
bool fits_float(double x) {
  return std::isfinite(x) && std::abs(x) <= static_cast<double>(std::numeric_limits<float>::max());
}

void write_binary(std::ostream& out, const TriangleMesh& mesh, const std::filesystem::path& path,
                  bool use_file_normals) {
  if (mesh.size() > std::numeric_limits<std::uint32_t>::max()) {
    throw InputError(path.string(), 0, "binary STL holds at most 2^32 - 1 triangles, mesh has " +
                                           std::to_string(mesh.size()));
  }
  // The header must not begin with "solid", or readers would try ASCII first.
  char header[kPreambleBytes] = {};
  const std::string title = "ppohdem binary STL: " + sanitized_name(mesh.name);
  std::memcpy(header, title.data(), std::min(title.size(), kHeaderBytes));
  store_u32_le(header + kHeaderBytes, static_cast<std::uint32_t>(mesh.size()));
  out.write(header, sizeof header);
  char record[kRecordBytes] = {};
  for (std::size_t i = 0; i < mesh.size(); ++i) {
    const Triangle& t = mesh.triangles[i];
    const Vec3 n = normal_to_write(t, use_file_normals);
    for (int a = 0; a < 3; ++a) {
      store_f32_le(record + 4 * a, fits_float(n[a]) ? static_cast<float>(n[a]) : 0.0f);
    }
    for (int k = 0; k < 3; ++k) {
      for (int a = 0; a < 3; ++a) {
        const double x = t.v[static_cast<std::size_t>(k)][a];
        if (!fits_float(x)) {
          throw InputError(path.string(), 0,
                           "triangle " + std::to_string(i + 1) + ": coordinate " +
                               std::to_string(x) + " is not representable as a finite float32");
        }
        store_f32_le(record + 12 * (k + 1) + 4 * a, static_cast<float>(x));
      }
    }
    out.write(record, sizeof record);  // attribute bytes 48-49 stay zero
  }
}

}  // namespace

TriangleMesh read_stl_bytes(std::string_view bytes, const std::string& source_name,
                            StlReadReport* report) {
  StlReadReport local;
  if (bytes.empty()) throw InputError(source_name, 0, "empty file: expected an STL mesh");
  if (detail::starts_with_solid_keyword(bytes)) {
    try {
      local.encoding = StlEncoding::kAscii;
      TriangleMesh mesh = detail::parse_ascii_stl(bytes, source_name, local);
      if (report) *report = local;
      return mesh;
    } catch (const InputError&) {
      // Some binary exporters start the header with "solid": binary if the size says so.
      if (bytes.size() != expected_binary_size(bytes)) throw;
      local = StlReadReport{};
    }
  }
  local.encoding = StlEncoding::kBinary;
  TriangleMesh mesh = parse_binary_stl(bytes, source_name, local);
  if (report) *report = local;
  return mesh;
}

TriangleMesh read_stl(const std::filesystem::path& path, StlReadReport* report) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), 0, "cannot open: expected a readable STL file");
  // In blocks into a string reserved to the file's size: a character at a time through
  // istreambuf_iterator was most of the read's time (docs/performance.md "The whole voxelize process").
  std::string bytes;
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (!ec) bytes.reserve(static_cast<std::size_t>(size));
  std::array<char, 1 << 16> block;
  while (in.read(block.data(), block.size()), in.gcount() > 0) bytes.append(block.data(), static_cast<std::size_t>(in.gcount()));
  if (in.bad()) throw InputError(path.string(), 0, "read error while loading the STL file");
  return read_stl_bytes(bytes, path.string(), report);
}

void write_stl(const std::filesystem::path& path, const TriangleMesh& mesh, StlEncoding encoding,
               bool use_file_normals, int ascii_significant_digits) {
  if (encoding == StlEncoding::kAscii &&
      (ascii_significant_digits < 1 || ascii_significant_digits > 17)) {
    throw InputError(path.string(), 0,
                     "ASCII STL precision: expected 1..17 significant digits, found " +
                         std::to_string(ascii_significant_digits));
  }
  AtomicFileWriter writer(path, /*binary=*/true);
  if (encoding == StlEncoding::kAscii) {
    write_ascii(writer.stream(), mesh, use_file_normals, ascii_significant_digits);
  } else {
    write_binary(writer.stream(), mesh, path, use_file_normals);
  }
  writer.commit();
}

}  // namespace ppohdem
