// libFuzzer target: ASCII STL (read_stl_bytes on text that starts with the keyword `solid`).
// Inputs that do not start with "solid" get "solid " prepended, so nearly every run reaches the
// ASCII grammar (stl_ascii.cpp); if the ASCII parse fails the reader may still try binary
// (size = 84 + 50 n), which this target then also exercises.
#include <cmath>
#include <string>

#include "fuzz_support.hpp"
#include "ppohdem/mesh/stl_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ppohdem;
  std::string text(fuzz::as_text(data, size));
  if (text.rfind("solid", 0) != 0) text.insert(0, "solid ");
  fuzz::run_reader([&] {
    StlReadReport report;
    const TriangleMesh mesh = read_stl_bytes(text, "fuzz.stl", &report);
    for (const Triangle& t : mesh.triangles) {
      for (const Vec3& v : t.v) PPOHDEM_FUZZ_CHECK(v.allFinite());  // the reader rejects NaN/Inf
      PPOHDEM_FUZZ_CHECK(t.file_normal.allFinite());                  // stored as zero if not finite
    }
    PPOHDEM_FUZZ_CHECK(report.degenerate_triangles <= mesh.size());
  });
  return 0;
}
