#pragma once
/// \file checkpoint.hpp
/// Checkpoint files of `ppohdem simulate --checkpoint-every N` / `--restart FILE`: the engine
/// state (engine.hpp EngineState: particles, contact histories keyed by particle ids, energy
/// accumulators, ...), the poses of the scene's rigid objects and what the run driver needs to
/// continue its outputs exactly (run.hpp).
///
/// Layout (every integer little-endian, every double the little-endian IEEE 754 binary64 bit
/// pattern, independent of the machine that writes or reads):
///   header   magic "PPOHDEMC" (8 bytes)
///            u32 format version (kCheckpointFormatVersion)
///            u32 n + n bytes: the writer's build ("ppohdem 0.1.0 (git abc123)")
///            u64 payload length [bytes]
///            u32 CRC-32 of the header bytes above
///   payload  (format version 3) see checkpoint.cpp, encode_payload()
///   trailer  u32 CRC-32 of the payload
/// Magic, version and build keep their place in every future version, so a file of another
/// version is refused naming both versions and builds. CRC-32 is zlib's crc32 (the
/// ISO-HDLC / gzip / PNG polynomial 0xEDB88320): it detects every error burst up to 32 bits
/// and any other corruption with probability 1 - 2^-32; it is not a defence against
/// deliberate tampering. Python's zlib.crc32 computes the same number.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "ppohdem/dem/engine.hpp"
#include "ppohdem/geometry/vector.hpp"

namespace ppohdem::dem {

/// 2: particles carry their material index (multi-material scenes); 1 (refused) did not.
inline constexpr std::uint32_t kCheckpointFormatVersion = 3;
inline constexpr char kCheckpointMagic[9] = "PPOHDEMC";

/// A rigid object's pose when the checkpoint was written (the motion is prescribed, so this
/// is a check that the restarting scene moves its objects the same way) and its count of samples
/// outside its grid within reach of it (distance_field_object.hpp; objects.csv continues it).
struct ObjectPoseRecord {
  std::string name;
  Quat rotation = Quat::Identity();  ///< object frame -> world
  Vec3 translation = Vec3::Zero();   ///< [m]
  std::uint64_t outside_grid = 0;
};

/// What the run driver needs to continue its outputs as if never interrupted.
struct RunRecord {
  std::vector<std::string> energy_rows;  ///< energy.csv data rows so far
  std::vector<std::string> object_rows;  ///< objects.csv data rows so far
  std::uint64_t frames = 0;              ///< frames written so far
};

struct Checkpoint {
  std::string build;       ///< writer's "ppohdem VERSION (git HASH)"; set by encode_checkpoint
  std::string provenance;  ///< writer's full provenance line (information)
  std::string scene;       ///< scene file the run read (information)
  EngineState engine;
  std::vector<ObjectPoseRecord> objects;
  RunRecord run;
};

/// "ppohdem VERSION (git HASH)" of this build.
std::string checkpoint_build_name();

/// The bytes of a checkpoint file (header, payload, CRCs); sets the build to this build's.
std::vector<std::uint8_t> encode_checkpoint(const Checkpoint& checkpoint);
/// Parses the bytes of a checkpoint file. Throws InputError(source, 0, ...) for: not a
/// checkpoint (magic), a corrupted header (CRC), another format version (naming both
/// versions and builds), a truncated or over-long file (the expected and actual size), a
/// corrupted payload (CRC), or a payload that does not parse. Never allocates more than the
/// file's size justifies.
Checkpoint decode_checkpoint(const std::vector<std::uint8_t>& bytes, const std::string& source);

/// Writes atomically (io/atomic_file.hpp): readers see the old or the new file, never a part.
void write_checkpoint(const std::filesystem::path& file, const Checkpoint& checkpoint);
/// Reads and decodes (InputError naming the file if it cannot be read).
Checkpoint read_checkpoint(const std::filesystem::path& file);

/// zlib's CRC-32 of `size` bytes.
std::uint32_t crc32_of(const std::uint8_t* data, std::size_t size);

}  // namespace ppohdem::dem
