/// \file stl_ascii.cpp
/// ASCII STL, read token by token (whitespace-separated; line numbers kept for errors).
///
/// Grammar (keywords case-insensitive):
///   file   := solid+
///   solid  := 'solid' <rest of that line = name> facet* 'endsolid' <rest of that line>
///   facet  := 'facet' 'normal' n n n 'outer' 'loop' body 'endloop' 'endfacet'
///   body   := any sequence of 'vertex' keywords and numbers such that
///             - there are exactly 9 numbers, taken in order as 3 vertices of (x, y, z);
///             - a 'vertex' keyword stands only between whole triples (never inside one);
///             - there are at most 3 'vertex' keywords.
/// The body rule accepts the usual `vertex x y z` x3 and also the seed's List 1.1, where a
/// facet reads `vertex a b c` / `d e f` / `vertex` / `vertex g h i` (the second vertex's
/// numbers come before its keyword) or has only two keywords for three vertices. Such facets
/// are counted in StlReadReport::irregular_vertex_keywords.
#include "stl_ascii.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>

#include "ppohdem/error.hpp"

namespace ppohdem::detail {
namespace {

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

bool iequals(std::string_view a, std::string_view b) {
  return a.size() == b.size() &&
         std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) ==
                  std::tolower(static_cast<unsigned char>(y));
         });
}

struct Token {
  std::string_view text;  ///< empty at end of file
  std::size_t line = 0;   ///< 1-based; at end of file, the line of the last token
  bool end() const { return text.empty(); }
};

/// Splits text into whitespace-separated words, counting newlines.
class Tokenizer {
 public:
  explicit Tokenizer(std::string_view text) : text_(text) {}

  Token next() {
    while (pos_ < text_.size() && is_space(text_[pos_])) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
    if (start == pos_) return {{}, last_line_};
    last_line_ = line_;
    return {text_.substr(start, pos_ - start), line_};
  }

  /// The rest of the current line (without the newline), trimmed: the solid's name.
  std::string_view rest_of_line() {
    const std::size_t start = pos_;
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    std::string_view rest = text_.substr(start, pos_ - start);
    while (!rest.empty() && is_space(rest.front())) rest.remove_prefix(1);
    while (!rest.empty() && is_space(rest.back())) rest.remove_suffix(1);
    return rest;
  }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t line_ = 1;
  std::size_t last_line_ = 1;
};

std::string describe(const Token& t) {
  if (t.end()) return "end of file";
  constexpr std::size_t kMaxShown = 40;
  std::string shown(t.text.substr(0, kMaxShown));
  if (t.text.size() > kMaxShown) shown += "...";
  return "'" + shown + "'";
}

class Parser {
 public:
  Parser(std::string_view text, const std::string& source, StlReadReport& report)
      : tok_(text), source_(source), report_(report) {}

  TriangleMesh parse() {
    TriangleMesh mesh;
    Token t = tok_.next();
    if (!iequals(t.text, "solid")) {
      fail(t, "expected 'solid' at the start of an ASCII STL, found " + describe(t));
    }
    mesh.name = std::string(tok_.rest_of_line());
    for (;;) {
      t = tok_.next();
      if (iequals(t.text, "facet")) {
        mesh.triangles.push_back(parse_facet_after_keyword());
      } else if (iequals(t.text, "endsolid")) {
        tok_.rest_of_line();
        t = tok_.next();
        if (t.end()) break;
        if (!iequals(t.text, "solid")) {
          fail(t, "expected end of file or another 'solid' after 'endsolid', found " + describe(t));
        }
        tok_.rest_of_line();  // a further solid in the same file: its triangles are appended
      } else {
        fail(t, "expected 'facet' or 'endsolid', found " + describe(t) +
                    (t.end() ? " (missing 'endsolid')" : ""));
      }
    }
    return mesh;
  }

 private:
  [[noreturn]] void fail(const Token& at, const std::string& message) const {
    throw InputError(source_, at.line, message);
  }

  void expect_keyword(std::string_view keyword, std::string_view after) {
    const Token t = tok_.next();
    if (!iequals(t.text, keyword)) {
      fail(t, "expected '" + std::string(keyword) + "' after '" + std::string(after) +
                  "', found " + describe(t));
    }
  }

  enum class Number { kNone, kFinite, kNonFinite };

  /// Classify `t` and set `value` if it is a number (NaN/Inf -> kNonFinite). Throws for
  /// out-of-range values and words that start like a number but do not end as one ("3.1x").
  Number read_number(const Token& t, double& value) const {
    std::string_view s = t.text;
    if (s.size() > 1 && s.front() == '+') s.remove_prefix(1);  // from_chars rejects '+'
    const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
    if (ptr == s.data()) return Number::kNone;
    if (ptr != s.data() + s.size()) {
      fail(t, "bad number " + describe(t) + ": expected a decimal number such as 3.3e-02");
    }
    if (ec == std::errc::result_out_of_range) {
      fail(t, "number " + describe(t) + " is out of the range of double");
    }
    return std::isfinite(value) ? Number::kFinite : Number::kNonFinite;
  }

  Triangle parse_facet_after_keyword() {
    Triangle tri;
    expect_keyword("normal", "facet");
    bool non_finite_normal = false;
    for (int a = 0; a < 3; ++a) {
      const Token t = tok_.next();
      double n = 0.0;
      const Number kind = read_number(t, n);
      if (kind == Number::kNone) {
        fail(t, "expected normal component " + std::to_string(a + 1) +
                    " of 3 after 'facet normal', found " + describe(t));
      }
      tri.file_normal[a] = n;
      if (kind == Number::kNonFinite) non_finite_normal = true;
    }
    if (non_finite_normal) {  // some exporters write NaN normals: keep the facet
      tri.file_normal.setZero();
      ++report_.non_finite_normals;
    }
    expect_keyword("outer", "facet normal nx ny nz");
    expect_keyword("loop", "outer");
    parse_loop_body(tri);
    expect_keyword("endfacet", "endloop");
    if (tri.area_vector() == Vec3::Zero()) ++report_.degenerate_triangles;
    return tri;
  }

  /// Between 'outer loop' and 'endloop' (rule in the file comment); consumes 'endloop'.
  void parse_loop_body(Triangle& tri) {
    constexpr int kCoordinates = 9;
    std::array<double, kCoordinates> c{};
    int n = 0;         // coordinates read
    int keywords = 0;  // 'vertex' keywords read
    bool regular = true;
    for (;;) {
      const Token t = tok_.next();
      if (t.end()) fail(t, "expected 'endloop', found end of file");
      if (iequals(t.text, "endloop")) {
        if (n != kCoordinates) {
          fail(t, "wrong vertex count: expected 3 vertices (9 coordinates) before 'endloop', "
                  "found " + std::to_string(n) + " coordinates");
        }
        break;
      }
      if (iequals(t.text, "vertex")) {
        if (n % 3 != 0) {
          fail(t, "expected coordinate " + std::to_string(n % 3 + 1) + " of 3 of vertex " +
                      std::to_string(n / 3 + 1) + ", found 'vertex'");
        }
        if (++keywords > 3) {
          fail(t, "wrong vertex count: expected at most 3 'vertex' keywords in a facet, found a "
                  "4th");
        }
        if (n != 3 * (keywords - 1)) regular = false;
        continue;
      }
      double x = 0.0;
      const Number kind = read_number(t, x);
      if (kind == Number::kNone) {
        fail(t, "expected 'vertex', a coordinate or 'endloop', found " + describe(t));
      }
      if (kind == Number::kNonFinite) {
        fail(t, "non-finite coordinate " + describe(t) + ": expected a finite number");
      }
      if (n == kCoordinates) {
        fail(t, "wrong vertex count: expected 'endloop' after 3 vertices, found a further "
                "coordinate " + describe(t));
      }
      c[static_cast<std::size_t>(n++)] = x;
    }
    if (keywords != 3) regular = false;
    if (!regular) ++report_.irregular_vertex_keywords;
    for (std::size_t i = 0; i < 3; ++i) tri.v[i] = Vec3(c[3 * i], c[3 * i + 1], c[3 * i + 2]);
  }

  Tokenizer tok_;
  const std::string& source_;
  StlReadReport& report_;
};

}  // namespace

TriangleMesh parse_ascii_stl(std::string_view text, const std::string& source_name,
                             StlReadReport& report) {
  return Parser(text, source_name, report).parse();
}

bool starts_with_solid_keyword(std::string_view bytes) {
  return iequals(Tokenizer(bytes).next().text, "solid");
}

}  // namespace ppohdem::detail
