// libFuzzer target: binary STL (read_stl_bytes on bytes behind a fixed 80-byte header that does
// not start with "solid", so the binary reader is always the one that runs).
// Input byte 0 chooses the triangle count written after the header:
//   even: the count that matches the record bytes (84 + 50 n = size), so the records are parsed;
//   odd:  the next 4 input bytes, raw (little-endian), so size/count mismatches and huge counts
//         (e.g. 4e9 triangles in a 200-byte file) are exercised.
// The rest of the input is the record data.
#include <array>
#include <cstring>
#include <string>

#include "fuzz_support.hpp"
#include "ppohdem/mesh/stl_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ppohdem;
  if (size < 1) return 0;
  const bool matching_count = (data[0] & 1u) == 0;
  ++data;
  --size;

  std::string bytes(80, ' ');
  const std::string title = "ppohdem fuzz binary STL";
  bytes.replace(0, title.size(), title);
  std::array<std::uint8_t, 4> count_le{};
  if (matching_count) {
    const auto n = static_cast<std::uint32_t>(size / 50);
    for (std::size_t b = 0; b < 4; ++b) count_le[b] = static_cast<std::uint8_t>((n >> (8 * b)) & 0xFFu);
  } else {
    if (size < 4) return 0;
    std::memcpy(count_le.data(), data, 4);
    data += 4;
    size -= 4;
  }
  bytes.append(reinterpret_cast<const char*>(count_le.data()), 4);
  bytes.append(fuzz::as_text(data, size));

  fuzz::run_reader([&] {
    StlReadReport report;
    const TriangleMesh mesh = read_stl_bytes(bytes, "fuzz_binary.stl", &report);
    PPOHDEM_FUZZ_CHECK(report.encoding == StlEncoding::kBinary);
    PPOHDEM_FUZZ_CHECK(84 + 50 * mesh.size() == bytes.size());
    for (const Triangle& t : mesh.triangles) {
      for (const Vec3& v : t.v) PPOHDEM_FUZZ_CHECK(v.allFinite());
      PPOHDEM_FUZZ_CHECK(t.file_normal.allFinite());
    }
  });
  return 0;
}
