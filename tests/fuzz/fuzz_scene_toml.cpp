// libFuzzer target: TOML scene files (dem::read_scene). The reader takes a path, so each input
// is written to scene.toml in a per-process tmpfs directory that also holds the particle file
// the seed scenes name (two_spheres.csv); the input is only the TOML.
//
// Scenes name other files by path ([particles] file). So that a fuzzed scene cannot make the
// reader open /dev/zero, /dev/stdin or a FIFO (which would hang the run, not find a bug), inputs
// with '/' or '\' are skipped: without '/' a name stays in the scratch directory or is "..",
// and without '\' no TOML escape (\u002F) can produce a '/'.
//
// Findings 4-6 of docs/reliability.md were inside toml++ 3.3.0 (Debian); read_scene now guards
// against them (core/src/dem/toml_hardened.hpp) and their reproducers are replayed from
// tests/fuzz/regressions/scene_toml/ on every run, so no input is skipped for them any more.
#include <string_view>

#include "fuzz_support.hpp"
#include "ppohdem/dem/scene.hpp"

namespace {

// fixtures/scenes/two_spheres.csv
constexpr std::string_view kTwoSpheresCsv =
    "id,x,y,z,vx,vy,vz,wx,wy,wz,radius\n"
    "1,-0.00055,0,0,0.05,0,0,0,0,0,0.0005\n"
    "2,0.00055,0,0,-0.05,0,0,0,0,0,0.0005\n";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ppohdem;
  const std::string_view toml = fuzz::as_text(data, size);
  if (toml.find_first_of("/\\") != std::string_view::npos) return 0;
  static const auto csv = fuzz::scratch().write("two_spheres.csv", kTwoSpheresCsv);
  (void)csv;
  const auto scene_file = fuzz::scratch().write("scene.toml", toml);
  fuzz::run_reader([&] { (void)dem::read_scene(scene_file); });
  return 0;
}
