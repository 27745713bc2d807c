// Legacy VTK STRUCTURED_POINTS writer and reader.
// Format: "VTK User's Guide", 11th ed., Kitware (2010), section "VTK File Formats" / legacy
// format: header line, title, ASCII|BINARY, DATASET, geometry, POINT_DATA + attributes.
// Binary data in legacy files is big-endian.
#include "ppohdem/io/vtk_structured_points.hpp"

#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <vector>

#include "ppohdem/error.hpp"
#include "ppohdem/io/atomic_file.hpp"
#include "ppohdem/io/block_file.hpp"
#include "ppohdem/io/legacy_inputs.hpp"

namespace ppohdem {
namespace {

// ---- big-endian encoding, independent of the host byte order ----------------------------

static_assert(std::endian::native == std::endian::little || std::endian::native == std::endian::big,
              "mixed-endian hosts are not supported");

template <class Word>
void store_big_endian(char* out, Word bits) {
  if constexpr (std::endian::native == std::endian::little) {
    if constexpr (sizeof(Word) == 8) bits = __builtin_bswap64(bits);
    if constexpr (sizeof(Word) == 4) bits = __builtin_bswap32(bits);
  }
  std::memcpy(out, &bits, sizeof bits);
}

std::uint64_t read_big_endian(const char* p, int bytes) {
  std::uint64_t bits = 0;
  for (int b = 0; b < bytes; ++b) bits = (bits << 8) | static_cast<unsigned char>(p[b]);
  return bits;
}

std::string shortest(double v) {  // shortest text that reads back to the same double
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

// ---- reader helpers ---------------------------------------------------------------------

std::string upper(std::string_view s) {
  std::string u(s);
  for (char& c : u) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return u;
}

std::vector<std::string_view> split_words(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    const std::size_t start = i;
    while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    if (i > start) words.push_back(line.substr(start, i - start));
  }
  return words;
}

/// Walks the header line by line, keeping the 1-based line number for messages.
class HeaderCursor {
 public:
  HeaderCursor(std::string_view bytes, std::string source) : bytes_(bytes), source_(std::move(source)) {}

  /// Next line without its end-of-line (LF or CRLF); nullopt at end of data.
  std::optional<std::string_view> next_line() {
    if (pos_ >= bytes_.size()) return std::nullopt;
    const std::size_t eol = bytes_.find('\n', pos_);
    const std::size_t end = eol == std::string_view::npos ? bytes_.size() : eol;
    std::string_view line = bytes_.substr(pos_, end - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = eol == std::string_view::npos ? bytes_.size() : eol + 1;
    ++line_;
    return line;
  }
  /// Next line that is not blank, split into words; fails with `expected` at end of data.
  std::vector<std::string_view> next_words(const std::string& expected) {
    while (auto line = next_line()) {
      auto words = split_words(*line);
      if (!words.empty()) return words;
    }
    fail("expected " + expected + ", found end of file");
  }
  /// Look at the next non-blank line's words without consuming it.
  std::vector<std::string_view> peek_words() {
    const std::size_t pos = pos_, line = line_;
    std::vector<std::string_view> words;
    while (auto l = next_line()) {
      words = split_words(*l);
      if (!words.empty()) break;
    }
    pos_ = pos;
    line_ = line;
    return words;
  }
  [[noreturn]] void fail(const std::string& message) const { throw InputError(source_, line_, message); }
  std::size_t line() const { return line_; }
  std::size_t offset() const { return pos_; }
  const std::string& source() const { return source_; }

 private:
  std::string_view bytes_;
  std::string source_;
  std::size_t pos_ = 0;
  std::size_t line_ = 0;
};

std::string in_quotes(std::string_view s) {
  std::string q(1, '\'');
  q.append(s.substr(0, 80));
  q += '\'';
  return q;
}

std::string join(const std::vector<std::string_view>& words) {
  std::string s;
  for (const auto& w : words) {
    if (!s.empty()) s += ' ';
    s.append(w);
  }
  return s;
}

template <class T>
T parse_number(HeaderCursor& cur, std::string_view word, const std::string& what) {
  T value{};
  const char* first = word.data();
  const char* last = word.data() + word.size();
  if (first != last && *first == '+') ++first;
  const auto r = std::from_chars(first, last, value);
  if (r.ec != std::errc() || r.ptr != last) cur.fail("expected " + what + ", found " + in_quotes(word));
  return value;
}

/// Checks `words` is KEYWORD followed by exactly `count` values.
void expect_count(HeaderCursor& cur, const std::vector<std::string_view>& words, std::size_t count,
                  const std::string& form) {
  if (words.size() != count + 1) cur.fail("expected '" + form + "', found " + in_quotes(join(words)));
}

}  // namespace

void write_vtk_structured_points(const std::filesystem::path& path, const ScalarField& field,
                                 std::string_view array_name, std::string_view title, VtkScalarType type) {
  field.grid.validate(path.string());
  if (field.values.size() != field.grid.node_count()) {
    throw InputError(path.string(), 0,
                     "cannot write VTK: expected " + std::to_string(field.grid.node_count()) +
                         " values for the grid, found " + std::to_string(field.values.size()));
  }
  if (array_name.empty() || std::any_of(array_name.begin(), array_name.end(), [](char c) {
        return std::isspace(static_cast<unsigned char>(c)) != 0;
      })) {
    throw InputError(path.string(), 0,
                     "cannot write VTK: expected an array name without spaces, found " + in_quotes(array_name));
  }
  std::string one_line_title(title.substr(0, 255));
  std::replace(one_line_title.begin(), one_line_title.end(), '\n', ' ');
  std::replace(one_line_title.begin(), one_line_title.end(), '\r', ' ');

  const GridSpec& g = field.grid;
  std::string out;
  out += "# vtk DataFile Version 3.0\n";
  out += one_line_title + "\n";
  out += "BINARY\n";
  out += "DATASET STRUCTURED_POINTS\n";
  out += "DIMENSIONS " + std::to_string(g.nodes[0]) + " " + std::to_string(g.nodes[1]) + " " +
         std::to_string(g.nodes[2]) + "\n";
  out += "ORIGIN " + shortest(g.origin.x()) + " " + shortest(g.origin.y()) + " " + shortest(g.origin.z()) + "\n";
  out += "SPACING " + shortest(g.spacing.x()) + " " + shortest(g.spacing.y()) + " " +
         shortest(g.spacing.z()) + "\n";
  out += "POINT_DATA " + std::to_string(g.node_count()) + "\n";
  out += "SCALARS " + std::string(array_name) + (type == VtkScalarType::kDouble ? " double" : " float") + " 1\n";
  out += "LOOKUP_TABLE default\n";

  // Past the page cache where the file system allows (io/block_file.hpp): a large field's
  // buffered write was the most variable part of `ppohdem voxelize` (docs/performance.md "The
  // whole voxelize process").
  BlockFileWriter writer(path);
  writer.write(out.data(), out.size());
  // The values in blocks, whole words byte-swapped (a byte at a time was most of the write's
  // time: docs/performance.md "The whole voxelize process").
  constexpr std::size_t kBlock = 1 << 16;
  std::vector<char> block(kBlock * 8);
  for (std::size_t first = 0; first < field.values.size(); first += kBlock) {
    const std::size_t count = std::min(kBlock, field.values.size() - first);
    char* p = block.data();
    for (std::size_t i = first; i < first + count; ++i) {
      if (type == VtkScalarType::kDouble) {
        store_big_endian(p, std::bit_cast<std::uint64_t>(field.values[i]));
        p += 8;
      } else {
        store_big_endian(p, std::bit_cast<std::uint32_t>(static_cast<float>(field.values[i])));
        p += 4;
      }
    }
    writer.write(block.data(), static_cast<std::size_t>(p - block.data()));
  }
  writer.write("\n", 1);  // VTK's own writer ends the binary block with a newline
  writer.commit();
}

ScalarField read_vtk_structured_points(const std::filesystem::path& path, std::string* array_name) {
  const std::string bytes = read_file_bytes(path);
  return read_vtk_structured_points_bytes(bytes, path.string(), array_name);
}

ScalarField read_vtk_structured_points_bytes(std::string_view bytes, const std::string& source_name,
                                             std::string* array_name) {
  HeaderCursor cur(bytes, source_name);

  // Line 1: "# vtk DataFile Version x.x"; line 2: title (anything); line 3: ASCII | BINARY.
  const auto magic = cur.next_line();
  if (!magic || upper(*magic).rfind("# VTK DATAFILE", 0) != 0) {
    cur.fail("expected '# vtk DataFile Version 3.0', found " + (magic ? in_quotes(*magic) : "end of file"));
  }
  if (!cur.next_line()) cur.fail("expected a title line, found end of file");
  const auto encoding = cur.next_line();
  const auto encoding_words = encoding ? split_words(*encoding) : std::vector<std::string_view>{};
  const std::string enc = encoding_words.size() == 1 ? upper(encoding_words[0]) : "";
  if (enc != "ASCII" && enc != "BINARY") {
    cur.fail("expected 'ASCII' or 'BINARY', found " + (encoding ? in_quotes(*encoding) : "end of file"));
  }
  const bool binary = enc == "BINARY";

  auto dataset = cur.next_words("'DATASET STRUCTURED_POINTS'");
  if (upper(dataset[0]) != "DATASET" || dataset.size() != 2) {
    cur.fail("expected 'DATASET STRUCTURED_POINTS', found " + in_quotes(join(dataset)));
  }
  if (upper(dataset[1]) != "STRUCTURED_POINTS") {
    cur.fail("unsupported dataset " + in_quotes(dataset[1]) + ": expected STRUCTURED_POINTS");
  }

  // Geometry keywords in any order, then POINT_DATA.
  GridSpec grid;
  bool have_dims = false;
  std::size_t point_data = 0;
  for (;;) {
    auto words = cur.next_words("DIMENSIONS, ORIGIN, SPACING or POINT_DATA");
    const std::string key = upper(words[0]);
    if (key == "DIMENSIONS") {
      expect_count(cur, words, 3, "DIMENSIONS nx ny nz");
      for (std::size_t a = 0; a < 3; ++a) {
        const int n = parse_number<int>(cur, words[a + 1], "a positive integer node count");
        if (n < 1) cur.fail("expected DIMENSIONS >= 1 on every axis, found " + in_quotes(join(words)));
        grid.nodes[a] = n;
      }
      have_dims = true;
    } else if (key == "ORIGIN") {
      expect_count(cur, words, 3, "ORIGIN ox oy oz");
      for (int a = 0; a < 3; ++a) {
        grid.origin[a] = parse_number<double>(cur, words[static_cast<std::size_t>(a) + 1], "a real origin");
        if (!std::isfinite(grid.origin[a])) cur.fail("expected a finite ORIGIN, found " + in_quotes(join(words)));
      }
    } else if (key == "SPACING" || key == "ASPECT_RATIO") {  // ASPECT_RATIO: VTK 1.0/2.0 name
      expect_count(cur, words, 3, "SPACING hx hy hz");
      for (int a = 0; a < 3; ++a) {
        grid.spacing[a] = parse_number<double>(cur, words[static_cast<std::size_t>(a) + 1], "a real spacing");
        if (!std::isfinite(grid.spacing[a]) || !(grid.spacing[a] > 0)) {
          cur.fail("expected SPACING > 0 on every axis, found " + in_quotes(join(words)));
        }
      }
    } else if (key == "POINT_DATA") {
      expect_count(cur, words, 1, "POINT_DATA n");
      if (!have_dims) cur.fail("expected DIMENSIONS before POINT_DATA");
      point_data = parse_number<std::size_t>(cur, words[1], "a point count");
      if (!checked_node_count(grid.nodes)) {  // the product would wrap around in size_t
        cur.fail("DIMENSIONS " + std::to_string(grid.nodes[0]) + " x " + std::to_string(grid.nodes[1]) + " x " +
                 std::to_string(grid.nodes[2]) + " is more nodes than this machine can address");
      }
      if (point_data != grid.node_count()) {
        cur.fail("POINT_DATA " + std::to_string(point_data) + " does not match DIMENSIONS " +
                 std::to_string(grid.nodes[0]) + " x " + std::to_string(grid.nodes[1]) + " x " +
                 std::to_string(grid.nodes[2]) + " = " + std::to_string(grid.node_count()));
      }
      break;
    } else {
      cur.fail("expected DIMENSIONS, ORIGIN, SPACING or POINT_DATA, found " + in_quotes(words[0]));
    }
  }

  auto scalars = cur.next_words("'SCALARS name double|float [1]'");
  if (upper(scalars[0]) != "SCALARS" || scalars.size() < 3 || scalars.size() > 4) {
    cur.fail("expected 'SCALARS name double|float [1]', found " + in_quotes(join(scalars)));
  }
  const std::string type = upper(scalars[2]);
  if (type != "DOUBLE" && type != "FLOAT") {
    cur.fail("unsupported scalar type " + in_quotes(scalars[2]) + ": expected double or float");
  }
  if (scalars.size() == 4 && scalars[3] != "1") {
    cur.fail("expected 1 component per point, found " + in_quotes(scalars[3]));
  }
  if (array_name) *array_name = std::string(scalars[1]);
  const auto maybe_table = cur.peek_words();
  if (!maybe_table.empty() && upper(maybe_table[0]) == "LOOKUP_TABLE") cur.next_words("LOOKUP_TABLE");

  // Check that the data can be there before allocating n values, so a corrupt header cannot
  // ask for terabytes: binary values take `width` bytes each, ASCII ones at least one (a digit).
  const std::size_t n = point_data;
  const std::size_t data_line = cur.line() + 1;
  const std::size_t have = bytes.size() - cur.offset();
  const std::size_t width = !binary ? 1 : type == "DOUBLE" ? 8 : 4;
  if (n > have / width) {
    if (!binary) {
      throw InputError(source_name, data_line,
                       "expected " + std::to_string(n) + " ASCII values (at least one byte each), found only " +
                           std::to_string(have) + " bytes");
    }
    const std::string need = n <= std::numeric_limits<std::size_t>::max() / width
                                 ? std::to_string(n * width)
                                 : std::to_string(n) + " x " + std::to_string(width);
    throw InputError(source_name, data_line,
                     "expected " + std::to_string(n) + " binary " + std::string(scalars[2]) + " values (" + need +
                         " bytes), found only " + std::to_string(have) + " bytes");
  }
  ScalarField field(grid);
  if (binary) {
    const char* p = bytes.data() + cur.offset();
    for (std::size_t i = 0; i < n; ++i, p += width) {
      field.values[i] = width == 8 ? std::bit_cast<double>(read_big_endian(p, 8))
                                   : static_cast<double>(std::bit_cast<float>(
                                         static_cast<std::uint32_t>(read_big_endian(p, 4))));
    }
  } else {
    std::size_t count = 0;
    while (count < n) {
      const auto line = cur.next_line();
      if (!line) {
        throw InputError(source_name, cur.line(),
                         "expected " + std::to_string(n) + " ASCII values, found only " + std::to_string(count));
      }
      for (const auto word : split_words(*line)) {
        if (count == n) break;  // trailing content (further arrays) is ignored
        field.values[count++] = parse_number<double>(cur, word, "a real value");
      }
    }
  }
  return field;
}

}  // namespace ppohdem
