// libFuzzer target: TOML scene files (dem::read_scene). The reader takes a path, so each input
// is written to scene.toml in a per-process tmpfs directory that also holds the particle file
// the seed scenes name (two_spheres.csv); the input is only the TOML.
//
// Scenes name other files by path ([particles] file). So that a fuzzed scene cannot make the
// reader open /dev/zero, /dev/stdin or a FIFO (which would hang the run, not find a bug), inputs
// with '/' or '\' are skipped: without '/' a name stays in the scratch directory or is "..",
// and without '\' no TOML escape (\u002F) can produce a '/'.
//
// Two known findings, both in toml++ 3.3.0 (Debian), not in ppohdem (docs/reliability.md);
// reproducers in tests/fuzz/regressions/open/scene_toml/. Inputs that reach them are skipped so
// that the campaign keeps searching for other problems:
//  1. parser::parse_key() checks its precondition with assert(): a table header starting with a
//     character that cannot start a key (`[#`, `[[[1]]]`) aborts a build without NDEBUG; a
//     clang build with NDEBUG turns it into __builtin_assume (undefined behaviour). Fixed
//     upstream in marzer/tomlplusplus PR #301.
//  2. is_non_ascii_horizontal_whitespace() reaches TOML_UNREACHABLE (__builtin_unreachable, so
//     undefined behaviour in every build) for some non-ASCII code points, e.g. `x = [0.П]` or
//     the bytes CC AA. Upstream issue marzer/tomlplusplus#295, fixed by PR #305. Inputs with any
//     byte >= 0x80 are skipped.
#include <cctype>
#include <string_view>

#include "fuzz_support.hpp"
#include "ppohdem/dem/scene.hpp"

namespace {

// fixtures/scenes/two_spheres.csv
constexpr std::string_view kTwoSpheresCsv =
    "id,x,y,z,vx,vy,vz,wx,wy,wz,radius\n"
    "1,-0.00055,0,0,0.05,0,0,0,0,0,0.0005\n"
    "2,0.00055,0,0,-0.05,0,0,0,0,0,0.0005\n";

/// True if a line starts (after blanks) a table header `[` or `[[` whose next non-blank
/// character is neither a bare-key character, a quote, nor `]`: finding 1 above. Errs on the side of skipping (a `[` line inside an array also counts).
bool trips_tomlplusplus_parse_key_assert(std::string_view toml) {
  std::size_t pos = 0;
  while (pos < toml.size()) {
    std::size_t eol = toml.find('\n', pos);
    if (eol == std::string_view::npos) eol = toml.size();
    std::string_view line = toml.substr(pos, eol - pos);
    pos = eol + 1;
    const auto is_blank = [](char c) { return c == ' ' || c == '\t'; };
    std::size_t i = 0;
    while (i < line.size() && is_blank(line[i])) ++i;
    if (i == line.size() || line[i] != '[') continue;
    ++i;
    if (i < line.size() && line[i] == '[') ++i;
    while (i < line.size() && is_blank(line[i])) ++i;
    if (i == line.size()) return true;  // end of line right after the bracket(s)
    const char c = line[i];
    const bool key_start = std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '"' ||
                           c == '\'' || c == ']';
    if (!key_start) return true;
  }
  return false;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ppohdem;
  const std::string_view toml = fuzz::as_text(data, size);
  if (toml.find_first_of("/\\") != std::string_view::npos) return 0;
  if (trips_tomlplusplus_parse_key_assert(toml)) return 0;                         // finding 1
  for (const char c : toml) if (static_cast<unsigned char>(c) >= 0x80) return 0;  // finding 2
  static const auto csv = fuzz::scratch().write("two_spheres.csv", kTwoSpheresCsv);
  (void)csv;
  const auto scene_file = fuzz::scratch().write("scene.toml", toml);
  fuzz::run_reader([&] { (void)dem::read_scene(scene_file); });
  return 0;
}
