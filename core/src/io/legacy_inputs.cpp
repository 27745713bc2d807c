// Parsers for the original program's two control files (seed user's guide, Lists 2.1, 2.2).
// The original reads lines 1-2 of the voxelizer file with format (a80), the voxel counts
// list-directed, and every other line as "one label word, then the values" (list-directed).
// We accept the same files, make the label optional (it must be the expected one when present)
// and reject anything the original would silently misread: missing or extra values,
// non-numbers, non-finite numbers, counts or lengths out of range, extra non-blank lines.
#include "ppohdem/io/legacy_inputs.hpp"

#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

#include "ppohdem/error.hpp"

namespace ppohdem {
namespace {

std::string in_quotes(std::string_view s) {
  std::string q(1, '\'');
  q.append(s.substr(0, 80));
  q += '\'';
  return q;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

/// List-directed input separates values by blanks or commas.
std::vector<std::string_view> split_values(std::string_view line) {
  std::vector<std::string_view> tokens;
  std::size_t i = 0;
  auto is_sep = [](char c) { return c == ',' || std::isspace(static_cast<unsigned char>(c)); };
  while (i < line.size()) {
    while (i < line.size() && is_sep(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !is_sep(line[i])) ++i;
    if (i > start) tokens.push_back(line.substr(start, i - start));
  }
  return tokens;
}

std::optional<int> parse_int(std::string_view token) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  int value = 0;
  const auto r = std::from_chars(token.data(), token.data() + token.size(), value);
  if (r.ec != std::errc() || r.ptr != token.data() + token.size() || token.empty()) return std::nullopt;
  return value;
}

/// The lines of a small text file, numbered from 1, end-of-line (LF or CRLF) removed.
class Lines {
 public:
  Lines(std::string_view text, std::string source) : source_(std::move(source)) {
    std::size_t pos = 0;
    while (pos < text.size()) {
      std::size_t eol = text.find('\n', pos);
      if (eol == std::string_view::npos) eol = text.size();
      std::string_view line = text.substr(pos, eol - pos);
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      lines_.push_back(line);
      pos = eol + 1;
    }
  }
  /// Line n (1-based); InputError at line n if the file is shorter.
  std::string_view line(std::size_t n, const std::string& expected) const {
    if (n > lines_.size()) fail(n, "expected " + expected + ", found end of file");
    return lines_[n - 1];
  }
  /// Nothing but blank lines may follow line n.
  void expect_end_after(std::size_t n) const {
    for (std::size_t i = n; i < lines_.size(); ++i) {
      if (!trim(lines_[i]).empty()) {
        fail(i + 1, "expected end of file after line " + std::to_string(n) + ", found " + in_quotes(trim(lines_[i])));
      }
    }
  }
  [[noreturn]] void fail(std::size_t n, const std::string& message) const { throw InputError(source_, n, message); }

 private:
  std::string source_;
  std::vector<std::string_view> lines_;
};

/// The values of line n after an optional label; `label` empty means no label is allowed.
/// `what` names the quantity for messages, e.g. "3 reals (data-space length)".
std::vector<std::string_view> value_tokens(const Lines& lines, std::size_t n, std::string_view label,
                                           std::size_t count, const std::string& what) {
  const std::string expected = label.empty() ? what : in_quotes(label) + " and " + what;
  auto tokens = split_values(lines.line(n, expected));
  if (tokens.empty()) lines.fail(n, "expected " + expected + ", found an empty line");
  const std::string_view first = tokens.front();
  if (first.back() == ':' || !parse_fortran_real(first)) {
    // Not a number: it has to be the label.
    if (label.empty()) lines.fail(n, "expected " + what + ", found " + in_quotes(first));
    if (first != label) lines.fail(n, "expected label " + in_quotes(label) + ", found " + in_quotes(first));
    tokens.erase(tokens.begin());
  }
  if (tokens.size() < count) {
    lines.fail(n, "expected " + what + ", found " + std::to_string(tokens.size()) + " value(s)");
  }
  if (tokens.size() > count) {
    lines.fail(n, "expected " + what + ", found an extra value " + in_quotes(tokens[count]));
  }
  return tokens;
}

template <std::size_t N>
std::array<double, N> reals(const Lines& lines, std::size_t n, std::string_view label, const std::string& what) {
  const std::string desc = std::to_string(N) + (N == 1 ? " real (" : " reals (") + what + ")";
  const auto tokens = value_tokens(lines, n, label, N, desc);
  std::array<double, N> out{};
  for (std::size_t a = 0; a < N; ++a) {
    const auto v = parse_fortran_real(tokens[a]);
    if (!v) lines.fail(n, "expected a real number (" + what + "), found " + in_quotes(tokens[a]));
    if (!std::isfinite(*v)) lines.fail(n, "expected a finite real number (" + what + "), found " + in_quotes(tokens[a]));
    out[a] = *v;
  }
  return out;
}

Index3 ints(const Lines& lines, std::size_t n, std::string_view label, const std::string& what) {
  const auto tokens = value_tokens(lines, n, label, 3, "3 integers (" + what + ")");
  Index3 out{};
  for (std::size_t a = 0; a < 3; ++a) {
    const auto v = parse_int(tokens[a]);
    if (!v) lines.fail(n, "expected an integer (" + what + "), found " + in_quotes(tokens[a]));
    out[a] = *v;
  }
  return out;
}

Vec3 vec(const std::array<double, 3>& a) { return Vec3(a[0], a[1], a[2]); }

std::string show(const Vec3& v) {
  std::ostringstream s;
  s << v.x() << " " << v.y() << " " << v.z();
  return s.str();
}
std::string show(const Index3& v) {
  return std::to_string(v[0]) + " " + std::to_string(v[1]) + " " + std::to_string(v[2]);
}

void require_positive(const Lines& lines, std::size_t n, const Vec3& v, const std::string& what) {
  if (!(v.minCoeff() > 0.0)) lines.fail(n, "expected " + what + " > 0 on every axis, found " + show(v));
}
void require_at_least_one(const Lines& lines, std::size_t n, const Index3& v, const std::string& what) {
  if (v[0] < 1 || v[1] < 1 || v[2] < 1) {
    lines.fail(n, "expected " + what + " >= 1 on every axis, found " + show(v));
  }
}

std::string text_line(const Lines& lines, std::size_t n, const std::string& what) {
  const std::string_view s = trim(lines.line(n, what));
  if (s.empty()) lines.fail(n, "expected " + what + ", found an empty line");
  return std::string(s);
}

}  // namespace

std::optional<double> parse_fortran_real(std::string_view token) {
  if (token.empty()) return std::nullopt;
  std::string s(token);
  if (s.front() == '+') s.erase(0, 1);
  for (char& c : s) {
    if (c == 'D' || c == 'd') c = 'e';  // Fortran double-precision exponent letter
  }
  // Fortran writes exponents of 3 digits without the letter: 0.10000000-199.
  if (s.find_first_of("eE") == std::string::npos) {
    const std::size_t sign = s.find_last_of("+-");
    if (sign != std::string::npos && sign > 0 && std::isdigit(static_cast<unsigned char>(s[sign - 1]))) {
      s.insert(sign, 1, 'e');
    }
  }
  if (s.empty() || s.front() == '+') return std::nullopt;  // no "++5"
  double value = 0.0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), value);
  if (r.ec == std::errc::result_out_of_range) {
    // Overflow or underflow: report as non-finite / zero like strtod would, for the caller to judge.
    errno = 0;
    return std::strtod(s.c_str(), nullptr);
  }
  if (r.ec != std::errc() || r.ptr != s.data() + s.size()) return std::nullopt;
  return value;
}

std::string read_file_bytes(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw InputError(path.string(), 0, "expected a file, found a directory");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw InputError(path.string(), 0, std::string("cannot open file for reading: ") + std::strerror(errno));
  }
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw InputError(path.string(), 0, "read error");
  return std::move(buffer).str();
}

VoxelizerInput parse_voxelizer_input(std::string_view text, const std::string& source_name) {
  const Lines lines(text, source_name);
  VoxelizerInput in;
  in.mesh_file = text_line(lines, 1, "the mesh (STL) file name");
  in.output_dir = text_line(lines, 2, "the output directory");
  in.voxels = ints(lines, 3, {}, "voxel counts gridX gridY gridZ");
  require_at_least_one(lines, 3, in.voxels, "voxel counts");
  in.length = vec(reals<3>(lines, 4, "Lx_Ly_Lz:", "data-space length"));
  require_positive(lines, 4, in.length, "data-space length");
  in.object_size = vec(reals<3>(lines, 5, "sizeX_sizeY_sizeZ:", "object size"));
  require_positive(lines, 5, in.object_size, "object size");
  in.object_position = vec(reals<3>(lines, 6, "posX_posY_posZ:", "object centre position"));
  lines.expect_end_after(6);
  return in;
}

VoxelizerInput read_voxelizer_input(const std::filesystem::path& path) {
  return parse_voxelizer_input(read_file_bytes(path), path.string());
}

UpdateParamsInput parse_update_params_input(std::string_view text, const std::string& source_name) {
  const Lines lines(text, source_name);
  UpdateParamsInput in;
  in.domain_length = vec(reals<3>(lines, 1, "Lx_Ly_Lz:", "computational-space length"));
  require_positive(lines, 1, in.domain_length, "computational-space length");
  in.time_finish = reals<1>(lines, 2, "Time_finish:", "end time")[0];
  if (!(in.time_finish > 0.0)) {
    lines.fail(2, "expected end time > 0, found " + std::to_string(in.time_finish));
  }
  in.window_nodes = ints(lines, 3, "Obj_n_x_y_z:", "window node counts");
  require_at_least_one(lines, 3, in.window_nodes, "window node counts");
  in.window_start = ints(lines, 4, "Obj_winstart_x_y_z:", "1-based window start node");
  require_at_least_one(lines, 4, in.window_start, "window start (1-based)");
  in.velocity = vec(reals<3>(lines, 5, "Obj_velocity_x_y_z:", "object velocity"));
  in.rotation_axis = vec(reals<3>(lines, 6, "Obj_omega_x_y_z:", "rotation axis"));
  in.omega_pi_rad_per_w = reals<1>(lines, 7, "Obj_omega_Pi_rad_per_w:", "rotation divisor w")[0];
  in.centroid = vec(reals<3>(lines, 8, "Obj_centroid_x_y_z:", "centre of rotation"));
  lines.expect_end_after(8);
  return in;
}

UpdateParamsInput read_update_params_input(const std::filesystem::path& path) {
  return parse_update_params_input(read_file_bytes(path), path.string());
}

}  // namespace ppohdem
