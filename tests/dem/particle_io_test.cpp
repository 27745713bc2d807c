// The particle file reader and writer and the overlap search, against slow obvious versions
// (docs/performance.md "Reading and writing particles"):
// - the writer's lines are the ones snprintf("%.17g") gives, for doubles of every kind;
// - the reader gives, for every field, what std::stod decides: the same value bits, or an
//   error (fields of every format strtod accepts, and ones it refuses or reports out of range);
// - overlapping_pairs finds exactly the pairs an all-pairs loop finds (dense cells, hashed cells
//   and the sweep).
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <sys/stat.h>

#ifdef PPOHDEM_WITH_OPENMP
#include <omp.h>
#endif

#include "ppohdem/dem/particle_csv.hpp"
#include "ppohdem/dem/simulation_setup.hpp"
#include "ppohdem/error.hpp"
#include "test_paths.hpp"

namespace ppohdem::dem::test {
namespace {

namespace fs = std::filesystem;

std::string text_of(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Doubles of every kind: random bit patterns (any exponent), and the special cases.
std::vector<double> doubles_of_every_kind(std::size_t count) {
  std::mt19937_64 rng(20261205);
  std::vector<double> v = {0.0, -0.0, 1.0, -1.0, 0.1, 1.0 / 3.0, 1e-300, 5e-324, -2.2250738585072014e-308,
                           1.7976931348623157e308, 123456789012345678.0, 1e16, 1e17, 9.999999999999999e22,
                           std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                           std::numeric_limits<double>::quiet_NaN()};
  while (v.size() < count) v.push_back(std::bit_cast<double>(rng()));
  std::uniform_real_distribution<double> ordinary(-10.0, 10.0);  // the values of real files
  for (std::size_t k = 0; k < count; ++k) v.push_back(ordinary(rng));
  return v;
}

// Enough particles for several rounds of the threads' batches (particle_csv.cpp), written
// on 1, 2 and 3 threads.
TEST(ParticleIo, WriterLinesAreThoseOfPrintfG17) {
  const std::vector<double> values = doubles_of_every_kind(150000);
  Particles particles;
  std::string expected = "# provenance\nid,x,y,z,vx,vy,vz,wx,wy,wz,radius\n";
  for (std::size_t k = 0; k + 10 <= values.size(); k += 10) {
    Particle p;
    p.id = static_cast<std::int64_t>(k) * (k % 3 == 0 ? -7919 : 104729);
    p.position = Vec3(values[k], values[k + 1], values[k + 2]);
    p.velocity = Vec3(values[k + 3], values[k + 4], values[k + 5]);
    p.angular_velocity = Vec3(values[k + 6], values[k + 7], values[k + 8]);
    p.radius = values[k + 9];
    particles.push_back(p);
    char line[512];
    std::snprintf(line, sizeof line, "%lld,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n",
                  static_cast<long long>(p.id), values[k], values[k + 1], values[k + 2], values[k + 3], values[k + 4],
                  values[k + 5], values[k + 6], values[k + 7], values[k + 8], values[k + 9]);
    expected += line;
  }
  const fs::path file = ppohdem::test::scratch_dir() / "particle_io_writer.csv";
  for (const int threads : {1, 2, 3}) {
#ifdef PPOHDEM_WITH_OPENMP
    omp_set_num_threads(threads);
#endif
    write_particles_csv(file, particles, "provenance");
    EXPECT_EQ(text_of(file), expected) << threads << " thread(s)";
  }
}

/// What the reader must decide for a field: std::stod's value if it reads the whole field (the
/// reader's trimming of blanks, and of a line's '\r', aside) and the value is finite, else an
/// error.
std::optional<double> stod_decision(std::string field) {
  while (!field.empty() && (field.front() == ' ' || field.front() == '\t')) field.erase(0, 1);
  while (!field.empty() && (field.back() == ' ' || field.back() == '\t' || field.back() == '\r')) field.pop_back();
  if (field.empty()) return std::nullopt;
  try {
    std::size_t used = 0;
    const double v = std::stod(field, &used);
    if (used != field.size() || !std::isfinite(v)) return std::nullopt;
    return v;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

/// The reader's decision for `field` in column x of a one-particle file.
std::optional<double> reader_decision(const std::string& field) {
  const fs::path file = ppohdem::test::scratch_dir() / "particle_io_reader.csv";
  std::ofstream(file) << "id,x,y,z,vx,vy,vz,wx,wy,wz,radius\n1," << field << ",0,0,0,0,0,0,0,0,1e-3\n";
  try {
    const Particles p = read_particles_csv(file);
    return p.at(0).position.x();
  } catch (const InputError&) {
    return std::nullopt;
  }
}

void expect_same_decision(const std::string& field) {
  const auto want = stod_decision(field);
  const auto got = reader_decision(field);
  ASSERT_EQ(got.has_value(), want.has_value()) << "'" << field << "'";
  if (want) {
    EXPECT_EQ(std::bit_cast<std::uint64_t>(*got), std::bit_cast<std::uint64_t>(*want)) << "'" << field << "'";
  }
}

TEST(ParticleIo, ReaderDecidesEveryFieldAsStod) {
  for (const char* field :
       {"0", "-0", "0.000", "0e5", "-0.0e-400", "00012", "1", "+1.5", "-1.5", ".5", "5.", "1e5", "1E-5", "1e+5", "1e",
        "1e-400", "4e-320", "2.2250738585072014e-308", "2.2250738585072011e-308", "1e308", "1.8e308", "0x1p-3",
        "0X1.8P1", "inf", "-Infinity", "nan", "nan(12)", "1,5", "1 5", "1.5x", "--1", "", "e5", ".", "-.e1",
        "0.1000000000000000055511151231257827021181583404541015625", "123456789012345678901234567890",
        "7.2057594037927933e16", "\r1.5", "1.5\r", " 1.5", "1.5\t"}) {
    expect_same_decision(field);
  }
  // Every double written as the writers of real files write it.
  std::mt19937 rng(7);
  for (const double v : doubles_of_every_kind(3000)) {
    char text[64];
    const char* formats[] = {"%.17g", "%.10g", "%.6e", "%a", "%.3f"};
    std::snprintf(text, sizeof text, formats[rng() % 5], v);
    expect_same_decision(text);
  }
}

/// The parse of a file's text cut into `pieces`: each particle's id and value bits, or the
/// error's message.
std::string parse_outcome(const std::string& text, std::size_t pieces) {
  try {
    std::string out;
    for (const Particle& q : detail::parse_particles_csv(text, "pieces.csv", {}, pieces)) {
      out += std::to_string(q.id);
      for (const double v : {q.position.x(), q.position.y(), q.position.z(), q.velocity.x(), q.velocity.y(),
                             q.velocity.z(), q.angular_velocity.x(), q.angular_velocity.y(), q.angular_velocity.z(),
                             q.radius}) {
        out += ' ';
        out += std::to_string(std::bit_cast<std::uint64_t>(v));
      }
      out += "\n";
    }
    return out;
  } catch (const InputError& e) {
    return std::string("error: ") + e.what();
  }
}

// Files of every shape against a model of the format: comments and blank lines anywhere,
// blanks around fields, CRLF, no final newline, ids out of order or repeated, fields stod
// refuses, short and long lines. The model: each field as stod decides it (stod_decision),
// the error at the first bad line in file order; and any number of pieces (the threads'
// parse) gives what one piece gives, message for message.
RC_GTEST_PROP(ParticleIo, AnyPiecesReadAsTheModelSays, ()) {
  std::mt19937_64 rng(*rc::gen::arbitrary<std::uint64_t>());
  const auto lines = *rc::gen::inRange<std::size_t>(0, 60);
  const double bad_rate = *rc::gen::element(0.0, 0.0, 0.002, 0.02);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto chance = [&](double p) { return unit(rng) < p; };
  const char* const formats[] = {"%.17g", "%.6e", "%a", "%.3f", "%g"};
  auto number = [&] {
    if (chance(bad_rate)) {
      const char* const bad[] = {"", "abc", "nan", "inf", "1e-400", "1.5x", "1e999", "--1"};
      return std::string(bad[rng() % 8]);
    }
    const char* const odd[] = {"0", "-0", " 1.5", "1.5 ", "+2", "\t.5", "0e5", "5."};
    if (chance(0.1)) return std::string(odd[rng() % 8]);
    char text[64];
    std::snprintf(text, sizeof text, formats[rng() % 5], (unit(rng) - 0.5) * std::pow(10.0, static_cast<int>(rng() % 40) - 20));
    return std::string(text);
  };
  const std::string eol = chance(0.3) ? "\r\n" : "\n";
  std::string text;
  std::size_t line = 0;
  std::size_t first_bad = 0;  // the model's first bad line (0: none)
  auto add = [&](const std::string& l) {
    text += l + eol;
    ++line;
  };
  for (int k = static_cast<int>(rng() % 3); k > 0; --k) add(chance(0.5) ? "# comment" : " ");
  add("id,x,y,z,vx,vy,vz,wx,wy,wz,radius");
  std::vector<std::int64_t> ids;
  std::vector<std::array<double, 10>> values;
  for (std::size_t n = 0; n < lines; ++n) {
    if (chance(0.1)) {
      add(chance(0.5) ? "# comment, 1, 2" : "");
      continue;
    }
    std::int64_t id = static_cast<std::int64_t>(ids.size()) + 1;
    if (chance(0.1)) id = -static_cast<std::int64_t>(rng() % 1000) - 1;  // out of order
    if (!ids.empty() && chance(bad_rate * 5)) id = ids[rng() % ids.size()];  // repeated
    std::vector<std::string> fields{std::to_string(id)};
    for (int c = 0; c < 9; ++c) fields.push_back(number());
    fields.push_back(chance(bad_rate) ? "-1e-3" : "1e-3");
    if (chance(bad_rate)) fields.pop_back();
    if (chance(bad_rate)) fields.push_back("1");
    std::string l;
    for (std::size_t c = 0; c < fields.size(); ++c) l += (c > 0 ? "," : "") + fields[c];
    add(l);
    if (first_bad != 0) continue;
    // The model's decision of the line.
    bool good = fields.size() == 11 && std::find(ids.begin(), ids.end(), id) == ids.end();
    std::array<double, 10> v{};
    for (std::size_t c = 1; good && c < 11; ++c) {
      const auto d = stod_decision(fields[c]);
      good = d.has_value();
      if (good) v[c - 1] = *d;
    }
    good = good && v[9] > 0.0;
    if (!good) {
      first_bad = line;
      continue;
    }
    ids.push_back(id);
    values.push_back(v);
  }
  if (!text.empty() && chance(0.3)) text.resize(text.size() - eol.size());  // no final newline
  const std::string one = parse_outcome(text, 1);
  if (first_bad != 0) {
    try {
      detail::parse_particles_csv(text, "pieces.csv", {}, 1);
      RC_FAIL("no error, expected one at line " + std::to_string(first_bad));
    } catch (const InputError& e) {
      RC_ASSERT(e.line() == first_bad);
    }
  } else {
    std::string want;
    for (std::size_t i = 0; i < ids.size(); ++i) {
      want += std::to_string(ids[i]);
      for (const double v : values[i]) {
        want += ' ';
        want += std::to_string(std::bit_cast<std::uint64_t>(v));
      }
      want += "\n";
    }
    RC_ASSERT(one == want);
  }
  for (const std::size_t pieces : {2u, 3u, 5u, 8u, 61u}) RC_ASSERT(parse_outcome(text, pieces) == one);
}

// A particle file that is not a regular file (a named pipe: no size to read at once) is read
// to its end, the same as a file.
TEST(ParticleIo, ReaderReadsANamedPipe) {
  const fs::path pipe = ppohdem::test::scratch_dir() / "particle_io_pipe.csv";
  fs::remove(pipe);
  ASSERT_EQ(::mkfifo(pipe.c_str(), 0600), 0);
  const std::string text = "# from a pipe\nid,x,y,z,vx,vy,vz,wx,wy,wz,radius\n1,0.5,0,0,0,0,0,0,0,0,1e-3\n"
                           "2, 1.5 ,0,0,0,0,0,0,0,0,1e-3";
  std::signal(SIGPIPE, SIG_IGN);  // a reader that stops early must not kill the test
  std::thread writer([&] { std::ofstream(pipe) << text; });
  Particles p;
  std::string error;
  try {
    p = read_particles_csv(pipe);
  } catch (const InputError& e) {
    error = e.what();
  }
  writer.join();
  fs::remove(pipe);
  EXPECT_EQ(error, "");
  EXPECT_EQ(parse_outcome(text, 1), parse_outcome(text, 3));
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p[1].id, 2);
  EXPECT_EQ(p[1].position.x(), 1.5);
}

/// All pairs, the definition (simulation_setup.hpp).
std::vector<std::pair<std::size_t, std::size_t>> all_overlapping_pairs(const Particles& p, double fraction) {
  std::vector<std::pair<std::size_t, std::size_t>> found;
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (std::size_t j = i + 1; j < p.size(); ++j) {
      const double overlap = p[i].radius + p[j].radius - (p[i].position - p[j].position).norm();
      if (overlap > fraction * std::min(p[i].radius, p[j].radius)) found.emplace_back(i, j);
    }
  }
  return found;
}

RC_GTEST_PROP(ParticleIo, OverlappingPairsAreTheAllPairsOnes, ()) {
  // Clusters of spheres of radii over two decades, dense enough to overlap often, anywhere.
  const auto count = *rc::gen::inRange<std::size_t>(0, 300);
  const double spread = *rc::gen::element(1e-3, 1e-2, 1.0, 1e3);
  const double offset = *rc::gen::element(0.0, -7.5, 1e6);
  const double fraction = *rc::gen::element(0.0, 0.01, 0.1, 1.0);
  std::mt19937_64 rng(*rc::gen::arbitrary<std::uint64_t>());
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Particles p(count);
  for (Particle& q : p) {
    q.position = Vec3(offset + spread * unit(rng), offset + spread * unit(rng), offset + spread * unit(rng));
    q.radius = spread * 0.02 * std::pow(100.0, unit(rng)) / 10.0;
  }
  if (count > 1 && unit(rng) < 0.3) p[count - 1].position = p[0].position;  // coincident centres
  // Two clusters far apart: mostly empty cells between them (the hashed cells, not the dense grid).
  if (*rc::gen::arbitrary<bool>()) {
    for (std::size_t k = 0; k < count / 2; ++k) p[k].position += Vec3(40.0, -40.0, 40.0) * spread;
  }
  RC_ASSERT(overlapping_pairs(p, fraction) == all_overlapping_pairs(p, fraction));
}

TEST(ParticleIo, OverlappingPairsOfAFarApartPairAndOfALattice) {
  // Two touching spheres far from a third: the cells span 1e9 radii.
  Particles p(3);
  p[0].position = Vec3(0, 0, 0);
  p[1].position = Vec3(1.9e-3, 0, 0);
  p[2].position = Vec3(1e6, -1e6, 1e6);
  for (Particle& q : p) q.radius = 1e-3;
  EXPECT_EQ(overlapping_pairs(p, 0.01), all_overlapping_pairs(p, 0.01));
  EXPECT_EQ(overlapping_pairs(p, 0.01).size(), 1u);
  // A simple cubic lattice with spacing 1.98 R: every face neighbour overlaps by 2 % of R.
  Particles lattice;
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j)
      for (int k = 0; k < 8; ++k) {
        Particle q;
        q.position = Vec3(i, j, k) * 1.98e-3;
        q.radius = 1e-3;
        lattice.push_back(q);
      }
  const auto pairs = overlapping_pairs(lattice, 0.005);
  EXPECT_EQ(pairs, all_overlapping_pairs(lattice, 0.005));
  EXPECT_EQ(pairs.size(), 3u * 7u * 64u);  // 7 neighbour pairs per row, 64 rows, 3 axes
}

// even_part_of is even_part_first's inverse: every item of every split, against the parts'
// ranges counted out one by one (the split a piped file's shares and a restart's blocks use).
TEST(ParticleIo, EvenPartOfFindsThePartOfEveryItem) {
  for (std::size_t total = 1; total <= 40; ++total) {
    for (std::size_t parts = 1; parts <= 12; ++parts) {
      std::size_t part = 0, left = total / parts + (0 < total % parts ? 1 : 0);  // part 0's size
      for (std::size_t index = 0; index < total; ++index) {
        while (left == 0) left = total / parts + (++part < total % parts ? 1 : 0);
        ASSERT_EQ(even_part_of(total, parts, index), part) << total << " items, " << parts << " parts, item " << index;
        ASSERT_LE(even_part_first(total, parts, part), index);
        --left;
      }
    }
  }
}

}  // namespace
}  // namespace ppohdem::dem::test
