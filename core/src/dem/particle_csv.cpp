#include "ppohdem/dem/particle_csv.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include "ppohdem/comm/comm.hpp"
#include "checks_over_ranks.hpp"
#include "write_in_rank_order.hpp"
#include "ppohdem/error.hpp"
#include "ppohdem/io/block_file.hpp"

#ifdef PPOHDEM_WITH_OPENMP
#include <omp.h>
#endif

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

// A number std::from_chars reads from `at` into a normal number or an exact zero: both round
// correctly, so v is the value std::stod gives those characters. Returns the end of the
// number, or nullptr for anything else (a '+', hexadecimal, inf/nan, an underflow or
// overflow), which takes std::stod's path and is decided as before (docs/performance.md
// "Reading and writing particles").
const char* read_number(const char* at, const char* end, double& v) {
  const auto [ptr, ec] = std::from_chars(at, end, v);
  if (ec != std::errc()) return nullptr;
  if (std::isnormal(v)) return ptr;
  if (v != 0.0) return nullptr;  // subnormal: strtod reports a range error
  for (const char* d = at; d < ptr && *d != 'e' && *d != 'E'; ++d) {
    if (*d >= '1' && *d <= '9') return nullptr;  // an underflow to zero: stod's range error
  }
  return ptr;
}

// The value std::stod gives a whole field, when read_number reads all of it.
std::optional<double> quick_number(std::string_view f) {
  double v = 0.0;
  const char* const end = f.data() + f.size();
  if (read_number(f.data(), end, v) != end) return std::nullopt;
  return v;
}

// %.17g without printf's multi-precision path: std::to_chars with a precision writes what
// printf's %.*g writes ([charconv.to.chars]); ParticleCsv.WriterMatchesPrintf checks it.
char* put_g17(char* at, char* end, double v) {
  return std::to_chars(at, end, v, std::chars_format::general, 17).ptr;
}

// A line of eleven plain fields (no blanks, no material column, each number read whole by
// from_chars into a normal number or an exact zero, a positive radius): its particle, taken
// without splitting the line first. Anything else returns false and takes parse_line's path,
// which decides it as before (the same value bits: read_number serves both).
bool plain_line(std::string_view line, Particle& p) {
  const char* at = line.data();
  const char* const end = line.data() + line.size();
  const auto [id_end, id_ec] = std::from_chars(at, end, p.id);
  if (id_ec != std::errc() || id_end == end || *id_end != ',') return false;
  at = id_end + 1;
  double v[kColumns - 1];
  for (std::size_t c = 0; c < kColumns - 1; ++c) {
    const char* const ptr = read_number(at, end, v[c]);
    const bool last = c + 2 == kColumns;  // the radius ends the line
    if (ptr == nullptr || (last ? ptr != end : (ptr == end || *ptr != ','))) return false;
    at = ptr + 1;
  }
  if (!(v[9] > 0.0)) return false;
  p.position = Vec3(v[0], v[1], v[2]);
  p.velocity = Vec3(v[3], v[4], v[5]);
  p.angular_velocity = Vec3(v[6], v[7], v[8]);
  p.radius = v[9];
  return true;
}

// One line's particle, or the message of what is wrong with it (empty: a particle).
std::string parse_line(std::string_view line, bool with_material, const std::vector<std::string>& material_names,
                       std::vector<std::string_view>& fields, Particle& p) {
  if (!with_material && plain_line(line, p)) return {};
  split(line, fields);
  const std::size_t columns = with_material ? kColumns + 1 : kColumns;
  if (fields.size() != columns) {
    return "expected " + std::to_string(columns) + " comma-separated values, found " + std::to_string(fields.size());
  }
  {
    const auto f = fields[0];
    const auto [ptr, ec] = std::from_chars(f.data(), f.data() + f.size(), p.id);
    if (ec != std::errc() || ptr != f.data() + f.size()) return "column 'id': expected an integer, found '" + std::string(f) + "'";
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
    if (!ok || used != field.size()) return "column " + std::to_string(c + 1) + ": expected a number, found '" + field + "'";
    if (!std::isfinite(v[c - 1])) {
      return "column " + std::to_string(c + 1) + ": expected a finite number, found '" + field + "'";
    }
  }
  p.position = Vec3(v[0], v[1], v[2]);
  p.velocity = Vec3(v[3], v[4], v[5]);
  p.angular_velocity = Vec3(v[6], v[7], v[8]);
  p.radius = v[9];
  if (!(p.radius > 0.0)) return "radius must be > 0 m, found " + std::string(fields[10]);
  if (with_material) {
    const std::string_view m = fields[kColumns];
    const auto it = std::find(material_names.begin(), material_names.end(), m);
    if (it == material_names.end()) {
      std::string known;
      for (const std::string& n : material_names) known += (known.empty() ? "" : ", ") + n;
      return "column 'material': unknown material '" + std::string(m) + "' (the scene has: " + known + ")";
    }
    p.material = static_cast<std::uint16_t>(it - material_names.begin());
  }
  return {};
}

/// The lines of text[begin, end) (begin at a line's start): std::getline's lines, i.e. split at
/// '\n', a last piece without '\n' a line if not empty. Calls visit(line) until it returns false.
template <class Visit>
void for_each_line(std::string_view text, std::size_t begin, std::size_t end, Visit&& visit) {
  while (begin < end) {
    const void* nl = std::memchr(text.data() + begin, '\n', end - begin);
    const std::size_t stop = nl != nullptr ? static_cast<std::size_t>(static_cast<const char*>(nl) - text.data()) : end;
    if (!visit(text.substr(begin, stop - begin))) return;
    begin = stop + 1;
  }
}

/// One piece of the data lines: its particles, its line count, and its first bad line (within
/// the piece, 1-based; 0: none) with what is wrong there.
struct Piece {
  Particles particles;
  std::size_t lines = 0;
  std::size_t error_line = 0;
  std::string error;
};

/// `room`: the bytes whose lines to reserve particles for (the first piece: all the pieces',
/// which are then appended to it without growing it).
Piece parse_piece(std::string_view text, std::size_t begin, std::size_t end, std::size_t room, bool with_material,
                  const std::vector<std::string>& material_names) {
  Piece piece;
  // Room for lines as long as the piece's first 64 on average (a tenth more), at most as many
  // as 22-byte lines (the shortest): growing would copy every particle again.
  std::size_t sampled = 0;
  std::size_t sample_end = begin;
  for_each_line(text, begin, end, [&](std::string_view raw) {
    sample_end += raw.size() + 1;
    return ++sampled < 64;
  });
  const std::size_t shortest = room / (2 * kColumns) + 1;
  const double per_line =
      static_cast<double>(std::min(sample_end, end) - begin) / static_cast<double>(std::max<std::size_t>(sampled, 1));
  const auto expected = static_cast<std::size_t>(1.1 * static_cast<double>(room) / std::max(per_line, 1.0)) + 64;
  piece.particles.reserve(std::min(shortest, expected));
  std::vector<std::string_view> fields;
  for_each_line(text, begin, end, [&](std::string_view raw) {
    ++piece.lines;
    const std::string_view line = trim(raw);
    if (line.empty() || line.front() == '#') return true;
    Particle p;
    std::string error = parse_line(line, with_material, material_names, fields, p);
    if (!error.empty()) {
      piece.error_line = piece.lines;
      piece.error = std::move(error);
      return false;
    }
    piece.particles.push_back(p);
    return true;
  });
  return piece;
}

/// Where the data lines of a particle file start: its header line's number, the offset just
/// after that line, and whether it names the material column.
struct Header {
  std::size_t line_no = 0;
  std::size_t data = 0;
  bool with_material = false;
};

/// The header of `text`, the file's first bytes (all of them if `whole`): the first line that
/// is neither blank nor a comment. Throws on a wrong header; returns nothing when the text
/// ends before that line does and more of the file follows (read more, then ask again).
std::optional<Header> find_header(std::string_view text, const std::string& name,
                                  const std::vector<std::string>& material_names, bool whole) {
  Header h;
  bool seen = false, cut = false;
  std::size_t at = 0;
  for_each_line(text, 0, text.size(), [&](std::string_view raw) {
    ++h.line_no;
    at += raw.size() + 1;
    if (!whole && at > text.size()) {  // the prefix ends inside this line
      cut = true;
      return false;
    }
    const std::string_view line = trim(raw);
    if (line.empty() || line.front() == '#') return true;
    std::string compact;
    for (char c : line) if (c != ' ' && c != '\t') compact += c;
    h.with_material = compact == kMaterialHeader;
    if (compact != kHeader && !h.with_material) {
      throw InputError(name, h.line_no, "expected header '" + std::string(kHeader) + "' (or with ',material'), found '" +
                                          std::string(line) + "'");
    }
    if (h.with_material && material_names.empty()) {
      throw InputError(name, h.line_no, "a 'material' column needs a scene whose materials have names "
                                        "([material] name = ... or [[material]] entries)");
    }
    seen = true;
    h.data = std::min(at, text.size());
    return false;
  });
  if (seen) return h;
  if (cut || !whole) return std::nullopt;
  throw InputError(name, h.line_no, "expected header '" + std::string(kHeader) + "', found end of file");
}

/// The data lines text[data, end of text) parsed in `pieces` pieces at the same time: their
/// particles in file order, their line count, and the first bad line (counted from `data`,
/// 1-based; 0: none) with what is wrong there. Pieces after a bad one still give their
/// particles (the repeated-id check sees them all, for any number of pieces).
Piece parse_data_lines(std::string_view text, std::size_t data, bool with_material,
                       const std::vector<std::string>& material_names, std::size_t pieces) {
  // The data lines in pieces cut after a '\n', parsed at the same time; a piece's lines are
  // numbered once the pieces before it are counted.
  pieces = std::max<std::size_t>(1, pieces);
  std::vector<std::size_t> cut(pieces + 1, text.size());
  cut[0] = data;
  for (std::size_t k = 1; k < pieces; ++k) {
    std::size_t c = std::max(cut[k - 1], data + (text.size() - data) / pieces * k);
    if (c > cut[k - 1]) {  // to the start of the next line
      const void* nl = std::memchr(text.data() + c - 1, '\n', text.size() - (c - 1));
      c = nl != nullptr ? static_cast<std::size_t>(static_cast<const char*>(nl) - text.data()) + 1 : text.size();
    }
    cut[k] = c;
  }
  std::vector<Piece> parsed(pieces);
#ifdef PPOHDEM_WITH_OPENMP
#pragma omp parallel for schedule(static, 1) num_threads(static_cast<int>(pieces)) if (pieces > 1)
#endif
  for (std::size_t k = 0; k < pieces; ++k) {
    const std::size_t room = k == 0 ? text.size() - data : cut[k + 1] - cut[k];
    parsed[k] = parse_piece(text, cut[k], cut[k + 1], room, with_material, material_names);
  }
  // The first bad line in file order, and every piece's particles after the first's (whose
  // room holds them all unless its lines are shorter than the others').
  Piece all;
  for (std::size_t k = 0; k < pieces; ++k) {
    if (all.error_line == 0 && parsed[k].error_line != 0) {
      all.error_line = all.lines + parsed[k].error_line;
      all.error = std::move(parsed[k].error);
    }
    all.lines += parsed[k].lines;
  }
  std::size_t total = 0;
  for (const Piece& piece : parsed) total += piece.particles.size();
  all.particles = std::move(parsed[0].particles);
  all.particles.reserve(total);
  for (std::size_t k = 1; k < pieces; ++k) {
    all.particles.insert(all.particles.end(), parsed[k].particles.begin(), parsed[k].particles.end());
    Particles().swap(parsed[k].particles);
  }
  return all;
}

/// The index of the earliest particle whose id an earlier one has (its second line), or
/// particles.size() if the ids are distinct. Ids that increase (most files) need no search.
std::size_t first_repeated_id(const Particles& particles) {
  bool increasing = true;
  for (std::size_t i = 1; i < particles.size() && increasing; ++i) increasing = particles[i - 1].id < particles[i].id;
  if (increasing) return particles.size();
  std::vector<std::pair<std::int64_t, std::size_t>> order(particles.size());
  for (std::size_t i = 0; i < particles.size(); ++i) order[i] = {particles[i].id, i};
  std::sort(order.begin(), order.end());
  std::size_t repeat = particles.size();
  for (std::size_t i = 1; i < order.size(); ++i) {
    if (order[i].first == order[i - 1].first) repeat = std::min(repeat, order[i].second);  // seen at a smaller index
  }
  return repeat;
}

/// The line of data text[data, end) that holds its particle number `index` (0-based), counted
/// from `data` (1-based): counted again (an error's path), every data line before it a
/// particle or blank or a comment.
std::size_t line_of_particle(std::string_view text, std::size_t data, std::size_t index) {
  std::size_t line = 0, seen = 0;
  for_each_line(text, data, text.size(), [&](std::string_view raw) {
    ++line;
    const std::string_view l = trim(raw);
    return l.empty() || l.front() == '#' || seen++ < index;
  });
  return line;
}

}  // namespace

namespace detail {

Particles parse_particles_csv(std::string_view text, const std::string& name,
                              const std::vector<std::string>& material_names, std::size_t pieces) {
  const Header header = *find_header(text, name, material_names, true);
  Piece all = parse_data_lines(text, header.data, header.with_material, material_names, pieces);
  // The first bad line in file order: a piece's error, or a repeated id (its second line).
  const std::size_t repeat = first_repeated_id(all.particles);
  if (repeat < all.particles.size()) {
    const std::size_t line = line_of_particle(text, header.data, repeat);
    if (all.error_line == 0 || line < all.error_line) {
      throw InputError(name, header.line_no + line, "id " + std::to_string(all.particles[repeat].id) + " appears twice");
    }
  }
  if (all.error_line != 0) throw InputError(name, header.line_no + all.error_line, all.error);
  return std::move(all.particles);
}

}  // namespace detail

namespace {

/// Bytes [begin, end) of the open file `in` (fewer if it ends first).
std::string read_bytes(std::ifstream& in, std::size_t begin, std::size_t end) {
  std::string text(end > begin ? end - begin : 0, '\0');
  in.clear();
  in.seekg(static_cast<std::streamoff>(begin));
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  return text;
}

std::size_t parse_pieces_for(std::size_t bytes) {
  std::size_t threads = 1;
#ifdef PPOHDEM_WITH_OPENMP
  threads = static_cast<std::size_t>(std::max(1, omp_get_max_threads()));
#endif
  constexpr std::size_t kPieceBytes = std::size_t{1} << 20;  // a thread's start-up against its share
  return std::min(threads, bytes / kPieceBytes + 1);
}

}  // namespace

Particles read_particles_csv(const std::filesystem::path& file,
                             const std::vector<std::string>& material_names) {
  const std::string name = file.string();
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(name, 0, "cannot open particle file");
  // The whole file at once, then its lines in pieces on the threads (docs/performance.md
  // "Reading and writing particles").
  std::string text;
  std::error_code size_error;
  const auto size = std::filesystem::file_size(file, size_error);
  if (!size_error) {
    text.resize(static_cast<std::size_t>(size));
    in.read(text.data(), static_cast<std::streamsize>(text.size()));
    text.resize(static_cast<std::size_t>(in.gcount()));  // a file that shrank meanwhile
  } else {  // not a regular file (a pipe): read to its end
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  return detail::parse_particles_csv(text, name, material_names, parse_pieces_for(text.size()));
}

SharedParticles read_particles_csv(const std::filesystem::path& file, const std::vector<std::string>& material_names,
                                   const Comm& comm) {
  SharedParticles out;
  out.share.comm = &comm;
  const std::string name = file.string();
  const auto ranks = static_cast<std::size_t>(comm.size()), me = static_cast<std::size_t>(comm.rank());
  std::error_code size_error;
  const auto file_size = std::filesystem::file_size(file, size_error);
  std::ifstream in(file, std::ios::binary);
  std::optional<PlacedError> unopened;  // on any rank: all stop (collectives follow)
  if (!in) unopened = PlacedError{0, InputError(name, 0, "cannot open particle file (rank " + std::to_string(me) + ")")};
  throw_earliest_error(comm, unopened);
  if (size_error || ranks == 1) {  // one rank, or not a regular file (a pipe): all of it, then a share of it
    Particles all = read_particles_csv(file, material_names);
    out.share.total = all.size();
    out.share.first = even_part_first(all.size(), ranks, me);
    const std::size_t count = even_part_first(all.size(), ranks, me + 1) - out.share.first;
    if (ranks == 1) out.particles = std::move(all);
    else out.particles.assign(all.begin() + static_cast<std::ptrdiff_t>(out.share.first),
                              all.begin() + static_cast<std::ptrdiff_t>(out.share.first + count));
    return out;
  }
  const auto size = static_cast<std::size_t>(file_size);
  // The header, from the file's first bytes (every rank reads them: they are few, and a bad
  // header throws the same error on every rank).
  std::optional<Header> header;
  for (std::size_t want = std::size_t{64} << 10; !header; want *= 4) {
    const std::size_t asked = std::min(want, size);
    const std::string prefix = read_bytes(in, 0, asked);
    header = find_header(prefix, name, material_names, asked == size || prefix.size() < asked);
  }
  // This rank's share of the data lines: from the first line start at or after its nominal
  // first byte to the next rank's (docs/dem.md "Reading on every rank").
  const std::size_t data = header->data;
  auto line_start = [&](std::size_t k) {  // of rank k's share; the file's end for k = ranks
    if (k >= ranks) return size;
    const std::size_t nominal = data + (size - data) / ranks * k;
    if (nominal <= data) return data;
    for (std::size_t at = nominal - 1; at < size;) {  // the '\n' that ends the line before
      const std::string block = read_bytes(in, at, std::min(size, at + (std::size_t{64} << 10)));
      if (block.empty()) break;
      if (const std::size_t nl = block.find('\n'); nl != std::string::npos) return at + nl + 1;
      at += block.size();
    }
    return size;
  };
  const std::size_t begin = line_start(me), end = std::max(begin, line_start(me + 1));
  const std::string text = read_bytes(in, begin, end);
  Piece mine = parse_data_lines(text, 0, header->with_material, material_names, parse_pieces_for(text.size()));
  // The lines and particles of the shares before this one number its lines and particles. (A
  // share with a bad line counts its lines only up to it: the later shares' numbers then come
  // out lower than the file's, but still after that line, which is the error thrown.)
  std::vector<double> counts(2 * ranks, 0.0);  // exact: counts below 2^53
  counts[me] = static_cast<double>(mine.lines);
  counts[ranks + me] = static_cast<double>(mine.particles.size());
  counts = comm.sum_each_over_ranks(std::move(counts));
  std::size_t lines_before = 0;
  for (std::size_t k = 0; k < ranks; ++k) {
    if (k < me) {
      lines_before += static_cast<std::size_t>(counts[k]);
      out.share.first += static_cast<std::size_t>(counts[ranks + k]);
    }
    out.share.total += static_cast<std::size_t>(counts[ranks + k]);
  }
  // The first bad line in file order over all the shares: a line that does not parse, or a
  // repeated id (its second line).
  std::optional<PlacedError> error;
  if (mine.error_line != 0) {
    const std::size_t line = header->line_no + lines_before + mine.error_line;
    error = PlacedError{line, InputError(name, line, mine.error)};
  }
  const std::size_t repeat = first_repeated_id(comm, mine.particles, out.share.first);
  if (repeat != kNoRepeat && repeat >= out.share.first && repeat - out.share.first < mine.particles.size()) {
    const std::size_t index = repeat - out.share.first;
    const std::size_t line = header->line_no + lines_before + line_of_particle(text, 0, index);
    if (!error || line < error->place) {
      error = PlacedError{line, InputError(name, line, "id " + std::to_string(mine.particles[index].id) + " appears twice")};
    }
  }
  throw_earliest_error(comm, error);
  out.particles = std::move(mine.particles);
  return out;
}

namespace {

/// The header lines of a particle file.
std::string header_text(const std::string& header_comment, bool with_material) {
  std::string header;
  if (!header_comment.empty()) header += "# " + header_comment + '\n';
  header += with_material ? kMaterialHeader : kHeader;
  header += '\n';
  return header;
}

/// The particles' lines, formatted in rounds of one batch per thread at the same time and
/// given to `emit` in order: the bytes of one thread's loop (docs/performance.md "I/O: particle
/// files").
template <class Emit>
void format_lines(const Particles& particles, const std::vector<std::string>& material_names, Emit&& emit) {
  const bool with_material = material_names.size() > 1;
  constexpr std::size_t kBatch = 8192;  // particles, about 0.8 MiB of text
  const std::size_t n = particles.size();
  std::size_t threads = 1;
#ifdef PPOHDEM_WITH_OPENMP
  threads = std::min(static_cast<std::size_t>(std::max(1, omp_get_max_threads())), n / kBatch + 1);
#endif
  if (with_material) {  // checked before the threads, which must not throw
    for (const Particle& p : particles) (void)material_names.at(p.material);
  }
  std::vector<std::string> texts(threads);
  for (std::size_t round = 0; round < n; round += kBatch * threads) {
#ifdef PPOHDEM_WITH_OPENMP
#pragma omp parallel for schedule(static, 1) num_threads(static_cast<int>(threads)) if (threads > 1)
#endif
    for (std::size_t t = 0; t < threads; ++t) {
      std::string& text = texts[t];
      text.clear();
      char buf[512];
      const std::size_t last = std::min(n, round + (t + 1) * kBatch);
      for (std::size_t i = round + t * kBatch; i < last; ++i) {
        const Particle& p = particles[i];
        char* at = std::to_chars(buf, buf + 32, static_cast<long long>(p.id)).ptr;
        for (const double v : {p.position.x(), p.position.y(), p.position.z(), p.velocity.x(), p.velocity.y(),
                               p.velocity.z(), p.angular_velocity.x(), p.angular_velocity.y(), p.angular_velocity.z(),
                               p.radius}) {
          *at++ = ',';
          at = put_g17(at, buf + sizeof buf, v);
        }
        text.append(buf, at);
        if (with_material) {
          text += ',';
          text += material_names[p.material];
        }
        text += '\n';
      }
    }
    for (const std::string& text : texts) emit(text);
  }
}

}  // namespace

void write_particles_csv(const std::filesystem::path& file, const Particles& particles,
                         const std::string& header_comment, const std::vector<std::string>& material_names) {
  // Blocks past the page cache (io/block_file.hpp; docs/performance.md "I/O: particle files").
  BlockFileWriter writer(file);
  const std::string header = header_text(header_comment, material_names.size() > 1);
  writer.write(header.data(), header.size());
  format_lines(particles, material_names, [&](const std::string& text) { writer.write(text.data(), text.size()); });
  writer.commit();
}

void write_particles_csv(const std::filesystem::path& file, const Particles& mine, const std::string& header_comment,
                         const std::vector<std::string>& material_names, const Comm& comm) {
  Bytes text;
  format_lines(mine, material_names, [&](const std::string& lines) { text.insert(text.end(), lines.begin(), lines.end()); });
  std::unique_ptr<BlockFileWriter> writer;
  if (comm.rank() == 0) {
    writer = std::make_unique<BlockFileWriter>(file);
    const std::string header = header_text(header_comment, material_names.size() > 1);
    writer->write(header.data(), header.size());
  }
  write_in_rank_order(writer.get(), std::move(text), comm);
  if (writer) writer->commit();
}

}  // namespace ppohdem::dem
