#pragma once
// Forging a checkpoint's part for the refusal tests (checkpoint_parts_mpi_cli_test.cpp,
// insertion_mpi_cli_test.cpp): the part rewritten through an edit and its manifest entry
// fixed (counts, CRC-32), so that the file frames and checksums well and only the restore's
// own checks can find what is wrong.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "ppohdem/dem/checkpoint.hpp"

namespace ppohdem::test {

inline std::vector<std::uint8_t> bytes_of(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Rewrites part k of `manifest` through `edit(dem::CheckpointPart&)` and the manifest's entry.
template <class Edit>
void forge_part(const std::filesystem::path& manifest, std::size_t k, Edit&& edit) {
  namespace dem = ppohdem::dem;
  dem::Checkpoint m = dem::decode_checkpoint(bytes_of(manifest), manifest.string());
  const std::filesystem::path file = manifest.parent_path() / m.parts.at(k).file;
  dem::CheckpointPart part = dem::decode_checkpoint_part(bytes_of(file), file.string());
  edit(part);
  const std::vector<std::uint8_t> bytes = dem::encode_checkpoint_part(part);
  std::ofstream(file, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  dem::CheckpointPartEntry& entry = m.parts[k];
  entry.particles = part.particles.size();
  entry.contacts = part.contacts.size();
  entry.escaped = part.escaped_ids.size();
  entry.payload_crc = static_cast<std::uint32_t>(bytes[bytes.size() - 4]) | static_cast<std::uint32_t>(bytes[bytes.size() - 3]) << 8 |
                      static_cast<std::uint32_t>(bytes[bytes.size() - 2]) << 16 | static_cast<std::uint32_t>(bytes[bytes.size() - 1]) << 24;
  dem::write_checkpoint(manifest, m);
}

}  // namespace ppohdem::test
