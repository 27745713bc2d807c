// The original program's per-rank distance files: see distance_dat.hpp for the layout.
#include "ppohdem/io/distance_dat.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <memory>
#include <optional>

#include "ppohdem/error.hpp"
#include "ppohdem/io/atomic_file.hpp"
#include "ppohdem/io/legacy_inputs.hpp"

namespace ppohdem {
namespace {

constexpr int kMaxI8 = 99999999;  // largest value an I8 field can show

std::string right_justify(const std::string& s, std::size_t width) {
  return s.size() >= width ? s : std::string(width - s.size(), ' ') + s;
}

std::string in_quotes(std::string_view s) {
  std::string q(1, '\'');
  q.append(s.substr(0, 80));
  q += '\'';
  return q;
}

/// Splits a small line into whitespace-separated words (at most `max_words` + 1 kept).
std::vector<std::string_view> words_of(std::string_view line, std::size_t max_words) {
  std::vector<std::string_view> words;
  std::size_t i = 0;
  while (i < line.size() && words.size() <= max_words) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    const std::size_t start = i;
    while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    if (i > start) words.push_back(line.substr(start, i - start));
  }
  return words;
}

std::optional<int> to_int(std::string_view w) {
  int v = 0;
  const auto r = std::from_chars(w.data(), w.data() + w.size(), v);
  if (r.ec != std::errc() || r.ptr != w.data() + w.size()) return std::nullopt;
  return v;
}

/// Line-by-line reader over a whole file's bytes, counting 1-based line numbers.
class LineCursor {
 public:
  explicit LineCursor(std::string_view bytes) : bytes_(bytes) {}
  std::optional<std::string_view> next() {
    if (pos_ >= bytes_.size()) return std::nullopt;
    std::size_t eol = bytes_.find('\n', pos_);
    if (eol == std::string_view::npos) eol = bytes_.size();
    std::string_view line = bytes_.substr(pos_, eol - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = eol + 1;
    ++line_;
    return line;
  }
  std::size_t line() const { return line_; }

 private:
  std::string_view bytes_;
  std::size_t pos_ = 0;
  std::size_t line_ = 0;
};

std::string show3(int a, int b, int c) {
  return std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(c);
}

}  // namespace

std::string format_fortran_e20_8(double v) {
  constexpr std::size_t kWidth = 20;
  if (std::isnan(v)) return right_justify("NaN", kWidth);
  if (std::isinf(v)) return right_justify(v < 0 ? "-Infinity" : "Infinity", kWidth);

  // printf's %.7e gives d.ddddddde±XX with the 8 significant digits correctly rounded from the
  // exact binary value (glibc: round-half-even on exact ties, the same digits gfortran prints;
  // checked against gfortran 12 output in fixtures/legacy-cases/e20_8_gfortran.txt).
  // Fortran's E form is 0.dddddddd × 10^(XX+1): shift the point one place left.
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.7e", v);
  const std::string_view s(buf);
  const bool negative = s.front() == '-';
  const std::size_t d0 = negative ? 1 : 0;
  std::string digits;
  digits += s[d0];
  digits += s.substr(d0 + 2, 7);  // skip the '.'
  const std::size_t e_pos = s.find('e');
  int exponent = std::atoi(buf + e_pos + 1) + 1;
  if (v == 0.0) exponent = 0;  // Fortran prints zero as 0.00000000E+00

  std::string out = negative ? "-0." : "0.";
  out += digits;
  const int magnitude = std::abs(exponent);
  char exp_buf[16];
  if (magnitude <= 99) {
    std::snprintf(exp_buf, sizeof exp_buf, "E%c%02d", exponent < 0 ? '-' : '+', magnitude);
  } else {  // Ew.d with a 3-digit exponent drops the letter: 0.10000000+101
    std::snprintf(exp_buf, sizeof exp_buf, "%c%03d", exponent < 0 ? '-' : '+', magnitude);
  }
  out += exp_buf;
  return right_justify(out, kWidth);
}

DistanceDatSlab distance_dat_slab(int grid_x, int nprocs, int rank) {
  const int base = grid_x / nprocs;
  const int extra = grid_x % nprocs;  // the first `extra` ranks hold one more plane
  DistanceDatSlab slab;
  slab.plane_count = base + (rank < extra ? 1 : 0);
  slab.first_plane = rank * base + (rank < extra ? rank : extra);
  return slab;
}

std::filesystem::path distance_dat_path(const std::filesystem::path& dir, int rank) {
  char name[32];
  std::snprintf(name, sizeof name, "distance_%04d.dat", rank);
  return dir / name;
}

ScalarField DistanceDat::on_grid(const GridSpec& grid) const {
  if (grid.nodes != nodes) {
    throw InputError("distance field: expected a grid of " + show3(nodes[0], nodes[1], nodes[2]) +
                     " nodes (from the distance files), found " + show3(grid.nodes[0], grid.nodes[1], grid.nodes[2]));
  }
  ScalarField field(grid);
  field.values = values;
  return field;
}

namespace {

// The checks every writer makes before writing anything; `where` names the file in messages.
void check_distance_dat_set(const std::string& where, std::span<const double> values, const Index3& nodes,
                            int nprocs) {
  for (int n : nodes) {
    if (n < 1 || n > kMaxI8) {
      throw InputError(where, 0, "cannot write: expected node counts in 1.." + std::to_string(kMaxI8) +
                                     ", found " + show3(nodes[0], nodes[1], nodes[2]));
    }
  }
  if (nprocs < 1 || nprocs > nodes[0]) {
    throw InputError(where, 0, "cannot write: expected 1 <= nprocs <= gridX = " + std::to_string(nodes[0]) +
                                   ", found nprocs " + std::to_string(nprocs));
  }
  const std::size_t count = static_cast<std::size_t>(nodes[0]) * static_cast<std::size_t>(nodes[1]) *
                            static_cast<std::size_t>(nodes[2]);
  if (values.size() != count) {
    throw InputError(where, 0, "cannot write: expected " + std::to_string(count) + " values, found " +
                                   std::to_string(values.size()));
  }
}

// Rank `rank`'s file: the header (rank 0), then its x-planes, k outer, j, i inner.
void stream_distance_dat_rank(std::ostream& out, std::span<const double> values, const Index3& nodes, int nprocs,
                              int rank) {
  char line[64];
  std::string text;
  if (rank == 0) {
    std::snprintf(line, sizeof line, "%8d%8d%8d%8d\n", nodes[0], nodes[1], nodes[2], nprocs);
    text += line;
  }
  const DistanceDatSlab slab = distance_dat_slab(nodes[0], nprocs, rank);
  for (int k = 0; k < nodes[2]; ++k) {
    for (int j = 0; j < nodes[1]; ++j) {
      for (int i = slab.first_plane; i < slab.first_plane + slab.plane_count; ++i) {
        const std::size_t index = static_cast<std::size_t>(i) +
                                  static_cast<std::size_t>(nodes[0]) *
                                      (static_cast<std::size_t>(j) + static_cast<std::size_t>(nodes[1]) *
                                                                         static_cast<std::size_t>(k));
        std::snprintf(line, sizeof line, "%8d%8d%8d", i + 1, j + 1, k + 1);
        text += line;
        text += format_fortran_e20_8(values[index]);
        text += '\n';
      }
    }
    out << text;  // flush per k-plane to bound memory
    text.clear();
  }
}

}  // namespace

void write_distance_dat(const std::filesystem::path& dir, std::span<const double> values, const Index3& nodes,
                        int nprocs) {
  check_distance_dat_set(distance_dat_path(dir, 0).string(), values, nodes, nprocs);
  // All files are written to temporaries first; none is renamed into place before all succeeded.
  std::vector<std::unique_ptr<AtomicFileWriter>> writers;
  for (int rank = 0; rank < nprocs; ++rank) {
    writers.push_back(std::make_unique<AtomicFileWriter>(distance_dat_path(dir, rank)));
    stream_distance_dat_rank(writers.back()->stream(), values, nodes, nprocs, rank);
  }
  for (auto& w : writers) w->commit();
}

void write_distance_dat_rank(const std::filesystem::path& file, std::span<const double> values,
                             const Index3& nodes, int nprocs, int rank) {
  check_distance_dat_set(file.string(), values, nodes, nprocs);
  if (rank < 0 || rank >= nprocs) {
    throw InputError(file.string(), 0, "cannot write: expected 0 <= rank < nprocs = " + std::to_string(nprocs) +
                                           ", found rank " + std::to_string(rank));
  }
  AtomicFileWriter writer(file);
  stream_distance_dat_rank(writer.stream(), values, nodes, nprocs, rank);
  writer.commit();
}

namespace {

/// Where the rank files come from: a directory (read_distance_dat) or memory
/// (read_distance_dat_bytes).
class RankFiles {
 public:
  virtual ~RankFiles() = default;
  /// The name used in messages.
  virtual std::filesystem::path path(int rank) const = 0;
  /// The file's size in bytes; nullopt if there is no such file.
  virtual std::optional<std::uintmax_t> size(int rank) const = 0;
  /// The file's bytes, valid until the next call of bytes(). The file must exist.
  virtual std::string_view bytes(int rank) = 0;
};

class DirectoryRankFiles final : public RankFiles {
 public:
  DirectoryRankFiles(std::filesystem::path rank0, std::filesystem::path dir)
      : rank0_(std::move(rank0)), dir_(std::move(dir)) {}
  std::filesystem::path path(int rank) const override { return rank == 0 ? rank0_ : distance_dat_path(dir_, rank); }
  std::optional<std::uintmax_t> size(int rank) const override {
    const std::filesystem::path p = path(rank);
    std::error_code ec;
    if (!std::filesystem::exists(p, ec)) return std::nullopt;
    if (std::filesystem::is_directory(p, ec)) throw InputError(p.string(), 0, "expected a file, found a directory");
    const std::uintmax_t bytes = std::filesystem::file_size(p, ec);
    if (ec) throw InputError(p.string(), 0, "cannot determine the file size: " + ec.message());
    return bytes;
  }
  std::string_view bytes(int rank) override {
    buffer_ = read_file_bytes(path(rank));
    return buffer_;
  }

 private:
  std::filesystem::path rank0_;
  std::filesystem::path dir_;
  std::string buffer_;
};

class MemoryRankFiles final : public RankFiles {
 public:
  MemoryRankFiles(std::span<const std::string_view> files, std::filesystem::path dir)
      : files_(files), dir_(std::move(dir)) {}
  std::filesystem::path path(int rank) const override { return distance_dat_path(dir_, rank); }
  std::optional<std::uintmax_t> size(int rank) const override {
    if (rank < 0 || static_cast<std::size_t>(rank) >= files_.size()) return std::nullopt;
    return files_[static_cast<std::size_t>(rank)].size();
  }
  std::string_view bytes(int rank) override { return files_[static_cast<std::size_t>(rank)]; }

 private:
  std::span<const std::string_view> files_;
  std::filesystem::path dir_;
};

/// The shortest record a file can hold, `1 1 1 0` (its newline not counted: the last line may
/// lack one). Used to reject impossible headers before allocating their node values.
constexpr std::uintmax_t kShortestRecordBytes = 7;

[[noreturn]] void throw_missing_file(const RankFiles& files, int rank, int nprocs) {
  throw InputError(files.path(rank).string(), 0,
                   rank == 0 ? "expected the rank-0 distance file, found no such file"
                             : "expected rank " + std::to_string(rank) + "'s file (the header of " +
                                   files.path(0).string() + " says nprocs = " + std::to_string(nprocs) +
                                   "), found no such file");
}

/// Rank 0's first line: `gridX gridY gridZ nprocs` into `dat` (values not yet allocated).
void read_header(LineCursor& cur, const std::string& file, DistanceDat& dat) {
  const auto header = cur.next();
  const auto words = header ? words_of(*header, 4) : std::vector<std::string_view>{};
  std::optional<int> h[4];
  for (std::size_t a = 0; a < 4 && a < words.size(); ++a) h[a] = to_int(words[a]);
  if (words.size() != 4 || !h[0] || !h[1] || !h[2] || !h[3]) {
    throw InputError(file, 1, "expected header 'gridX gridY gridZ nprocs' (4 integers), found " +
                                  (header ? in_quotes(*header) : std::string("an empty file")));
  }
  dat.nodes = {*h[0], *h[1], *h[2]};
  dat.nprocs = *h[3];
  if (dat.nodes[0] < 1 || dat.nodes[1] < 1 || dat.nodes[2] < 1 || dat.nprocs < 1 || dat.nprocs > dat.nodes[0]) {
    throw InputError(file, 1, "expected grid counts >= 1 and 1 <= nprocs <= gridX, found " + in_quotes(*header));
  }
}

/// Every rank file must exist, and together they must be large enough for one record per node:
/// checked before the node values are allocated, so a corrupt header cannot ask for terabytes.
/// Returns the node count.
std::size_t require_room_for_records(const RankFiles& files, const DistanceDat& dat) {
  std::uintmax_t total_bytes = 0;
  for (int rank = 0; rank < dat.nprocs; ++rank) {
    const auto bytes = files.size(rank);
    if (!bytes) throw_missing_file(files, rank, dat.nprocs);
    total_bytes += std::min(*bytes, std::numeric_limits<std::uintmax_t>::max() - total_bytes);  // saturate
  }
  const auto count = checked_node_count(dat.nodes);
  if (!count || *count > total_bytes / kShortestRecordBytes) {
    throw InputError(files.path(0).string(), 1,
                     "the header announces " + show3(dat.nodes[0], dat.nodes[1], dat.nodes[2]) +
                         " nodes, but the " + std::to_string(dat.nprocs) + " rank file(s) hold only " +
                         std::to_string(total_bytes) + " bytes: expected at least " +
                         std::to_string(kShortestRecordBytes) + " bytes per record ('1 1 1 0')");
  }
  return *count;
}

/// The records of `rank`'s slab from `cur` into dat.values, then nothing but blank lines.
void read_records(LineCursor& cur, const std::string& file, int rank, DistanceDat& dat) {
  const DistanceDatSlab slab = distance_dat_slab(dat.nodes[0], dat.nprocs, rank);
  const std::size_t expected_records = static_cast<std::size_t>(slab.plane_count) *
                                       static_cast<std::size_t>(dat.nodes[1]) *
                                       static_cast<std::size_t>(dat.nodes[2]);
  const std::string slab_text =
      "i = " + std::to_string(slab.first_plane + 1) + ".." + std::to_string(slab.first_plane + slab.plane_count);
  std::size_t records = 0;
  for (int k = 0; k < dat.nodes[2]; ++k) {
    for (int j = 0; j < dat.nodes[1]; ++j) {
      for (int i = slab.first_plane; i < slab.first_plane + slab.plane_count; ++i) {
        const auto line = cur.next();
        if (!line) {
          throw InputError(file, cur.line() + 1,
                           "expected " + std::to_string(expected_records) + " records (" + slab_text +
                               ", all j, k), found only " + std::to_string(records));
        }
        const auto w = words_of(*line, 4);
        const auto ii = w.size() == 4 ? to_int(w[0]) : std::nullopt;
        const auto jj = w.size() == 4 ? to_int(w[1]) : std::nullopt;
        const auto kk = w.size() == 4 ? to_int(w[2]) : std::nullopt;
        const auto d = w.size() == 4 ? parse_fortran_real(w[3]) : std::nullopt;
        if (!ii || !jj || !kk || !d) {
          throw InputError(file, cur.line(),
                           "expected a record 'i j k d' (3 integers and a real), found " + in_quotes(*line));
        }
        if (*ii != i + 1 || *jj != j + 1 || *kk != k + 1) {
          throw InputError(file, cur.line(),
                           "record out of order: expected i j k = " + show3(i + 1, j + 1, k + 1) + ", found " +
                               show3(*ii, *jj, *kk));
        }
        dat.values[static_cast<std::size_t>(i) +
                   static_cast<std::size_t>(dat.nodes[0]) *
                       (static_cast<std::size_t>(j) +
                        static_cast<std::size_t>(dat.nodes[1]) * static_cast<std::size_t>(k))] = *d;
        ++records;
      }
    }
  }
  while (const auto line = cur.next()) {
    if (!words_of(*line, 1).empty()) {
      throw InputError(file, cur.line(),
                       "expected " + std::to_string(expected_records) + " records (" + slab_text +
                           ") and then end of file, found an extra line " + in_quotes(*line));
    }
  }
}

DistanceDat read_rank_files(RankFiles& files) {
  if (!files.size(0)) throw_missing_file(files, 0, 0);
  DistanceDat dat;
  const std::string rank0_name = files.path(0).string();
  LineCursor rank0(files.bytes(0));
  read_header(rank0, rank0_name, dat);
  dat.values.assign(require_room_for_records(files, dat), 0.0);
  read_records(rank0, rank0_name, 0, dat);
  for (int rank = 1; rank < dat.nprocs; ++rank) {
    LineCursor cur(files.bytes(rank));
    read_records(cur, files.path(rank).string(), rank, dat);
  }
  return dat;
}

}  // namespace

DistanceDat read_distance_dat(const std::filesystem::path& dir_or_rank0_file) {
  std::error_code ec;
  const bool is_dir = std::filesystem::is_directory(dir_or_rank0_file, ec);
  const std::filesystem::path rank0 = is_dir ? distance_dat_path(dir_or_rank0_file, 0) : dir_or_rank0_file;
  const std::filesystem::path dir = is_dir ? dir_or_rank0_file
                                           : (rank0.has_parent_path() ? rank0.parent_path() : ".");
  DirectoryRankFiles files(rank0, dir);
  return read_rank_files(files);
}

DistanceDat read_distance_dat_bytes(std::span<const std::string_view> rank_files,
                                    const std::filesystem::path& source_dir) {
  MemoryRankFiles files(rank_files, source_dir);
  return read_rank_files(files);
}

}  // namespace ppohdem
