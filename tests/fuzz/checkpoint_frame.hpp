#pragma once
// The fuzz targets of checkpoint files and parts mutate the PAYLOAD: a mutated file almost never
// passes the CRC-32s, so the payload is wrapped in a valid header and trailer (magic, version,
// this build, length, both CRCs), which exercises the parser behind the checksums.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "ppohdem/dem/checkpoint.hpp"

namespace ppohdem::fuzz {

inline void put_u32(std::vector<std::uint8_t>& b, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) b.push_back(static_cast<std::uint8_t>(v >> (8 * k)));
}

/// The file of a payload: `magic` (8 bytes), the format version, this build, the length, the
/// header's CRC-32, the payload and its CRC-32 (docs/formats.md "Checkpoints").
inline std::vector<std::uint8_t> framed_payload(const char* magic, const std::uint8_t* data, std::size_t size) {
  std::vector<std::uint8_t> file(magic, magic + 8);
  put_u32(file, dem::kCheckpointFormatVersion);
  const std::string build = dem::checkpoint_build_name();
  put_u32(file, static_cast<std::uint32_t>(build.size()));
  file.insert(file.end(), build.begin(), build.end());
  for (int k = 0; k < 8; ++k) file.push_back(static_cast<std::uint8_t>(static_cast<std::uint64_t>(size) >> (8 * k)));
  put_u32(file, dem::crc32_of(file.data(), file.size()));
  file.insert(file.end(), data, data + size);
  put_u32(file, dem::crc32_of(data, size));
  return file;
}

}  // namespace ppohdem::fuzz
