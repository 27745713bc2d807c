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
///   payload  (format version 5) see checkpoint.cpp, encode_payload()
///   trailer  u32 CRC-32 of the payload
/// Magic, version and build keep their place in every future version, so a file of another
/// version is refused naming both versions and builds. CRC-32 is zlib's crc32 (the
/// ISO-HDLC / gzip / PNG polynomial 0xEDB88320): it detects every error burst up to 32 bits
/// and any other corruption with probability 1 - 2^-32; it is not a defence against
/// deliberate tampering. Python's zlib.crc32 computes the same number.
///
/// Parts (format 5; docs/formats.md "Checkpoints"). A run on P > 1 ranks writes its checkpoint
/// per rank, without gathering the state: rank r writes its share (EngineStateShare: the
/// particles it owns with their construction indices, the contact histories it keeps, its
/// escaped ids) to "<name>.parts/step_SSSSSSSSSS.rank_R_of_P.bin" beside the checkpoint file,
/// framed like it (magic "PPOHDEMP", same version, build, length and CRCs). When every part
/// is on disk, rank 0 writes the checkpoint file itself, the manifest: the same payload with
/// the three lists empty and a table naming each part with its counts and payload CRC-32.
/// Every file is written to a temp name and renamed, the manifest last, and old parts are
/// removed only after it: the manifest on disk always names a complete set of parts.
/// read_checkpoint reads the parts and merges them into the whole state (any rank count).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "ppohdem/dem/engine.hpp"
#include "ppohdem/dem/insertion.hpp"
#include "ppohdem/geometry/vector.hpp"

namespace ppohdem {
class Comm;
}

namespace ppohdem::dem {

/// 5: the table of per-rank parts at the end of the payload (empty: a single file).
/// 4: the insertions' record (InsertionRecord) after the run record; version 3 (no
/// insertions) is still read. 2: particles carry their material index (multi-material
/// scenes); 1 (refused) did not.
inline constexpr std::uint32_t kCheckpointFormatVersion = 5;
inline constexpr std::uint32_t kOldestCheckpointFormatVersion = 3;
inline constexpr char kCheckpointMagic[9] = "PPOHDEMC";
inline constexpr char kCheckpointPartMagic[9] = "PPOHDEMP";

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

/// A part of a checkpoint written per rank, as its manifest names it.
struct CheckpointPartEntry {
  std::string file;  ///< relative to the manifest's directory: "<name>.parts/step_S.rank_R_of_P.bin"
  std::uint64_t particles = 0;
  std::uint64_t contacts = 0;
  std::uint64_t escaped = 0;
  std::uint32_t payload_crc = 0;  ///< the part's payload CRC-32 (its trailer): this very part
};

struct Checkpoint {
  std::string build;       ///< writer's "ppohdem VERSION (git HASH)"; set by encode_checkpoint
  std::string provenance;  ///< writer's full provenance line (information)
  std::string scene;       ///< scene file the run read (information)
  EngineState engine;
  std::vector<ObjectPoseRecord> objects;
  RunRecord run;
  InsertionRecord insertion;  ///< [[insert]] counters (empty counters: none; version 3 files)
  /// A manifest's parts (engine's particles, contacts and escaped ids are then in them);
  /// empty for a single file. read_checkpoint merges the parts and clears this.
  std::vector<CheckpointPartEntry> parts;
};

/// One rank's part of a checkpoint written per rank (EngineStateShare's three lists).
struct CheckpointPart {
  long step = 0;
  std::uint32_t rank = 0;
  std::uint32_t ranks = 1;
  std::uint64_t total = 0;               ///< particles of the whole system
  std::vector<std::uint64_t> order;      ///< construction index of each particle
  Particles particles;
  std::vector<ContactHistoryRecord> contacts;
  std::vector<std::int64_t> escaped_ids;
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
/// Reads and decodes (InputError naming the file if it cannot be read). A manifest's parts are
/// read and merged into checkpoint.engine (parts emptied): InputError naming the manifest or
/// the part for a missing or damaged part, a part of another checkpoint (step, rank, count,
/// CRC-32 not the manifest's), or parts that do not cover every particle exactly once.
Checkpoint read_checkpoint(const std::filesystem::path& file);
/// The file alone, decoded: a manifest keeps its table of parts (their lists are not read).
Checkpoint read_checkpoint_manifest(const std::filesystem::path& file);

/// What one rank of several reads of a checkpoint (read_checkpoint_share).
struct CheckpointShareRead {
  /// A manifest: its fields, with the three engine lists and the table of parts empty. A
  /// single file: the whole checkpoint.
  Checkpoint checkpoint;
  /// A manifest's: this rank's share, the lists of the parts it read, in state (the global
  /// fields are the manifest's), total = the manifest's particle count. A single file: none.
  std::optional<EngineStateShare> share;
};
/// Collective over `comm`: every rank reads the checkpoint file; of a manifest, rank r of P
/// reads only the parts r, r + P, r + 2P, ..., each checked as read_checkpoint checks it (its
/// file, CRC-32, step, rank, counts, and the total of the manifest's counts). If a rank finds an
/// error, every rank throws the error of the lowest part. No rank holds the whole state:
/// DemEngine::restore_state_share places the shares (docs/formats.md "Checkpoints").
CheckpointShareRead read_checkpoint_share(const std::filesystem::path& file, const Comm& comm);

/// The bytes of a part file; decoding throws InputError(source, 0, "checkpoint part: ...")
/// like decode_checkpoint, and for a rank >= ranks or a construction index >= total.
std::vector<std::uint8_t> encode_checkpoint_part(const CheckpointPart& part);
CheckpointPart decode_checkpoint_part(const std::vector<std::uint8_t>& bytes, const std::string& source);
/// The parts' lists merged into manifest.engine (particles placed by construction index,
/// contacts sorted by (kind, id_a, id_b), escaped ids ascending): `parts[k]` must be the k-th
/// entry's (the same step, rank k of parts.size(), the entry's counts and CRC-32);
/// `sources[k]` names it in errors.
void merge_checkpoint_parts(Checkpoint& manifest, const std::vector<CheckpointPart>& parts,
                            const std::vector<std::string>& sources);

/// Collective over `comm`: writes `checkpoint` per rank ("Parts" above). `share` is this
/// rank's (DemEngine::save_state_share()); checkpoint.engine is ignored.
void write_checkpoint_parts(const std::filesystem::path& file, Checkpoint checkpoint, EngineStateShare share,
                            const Comm& comm);

/// zlib's CRC-32 of `size` bytes.
std::uint32_t crc32_of(const std::uint8_t* data, std::size_t size);
/// The CRC-32 of the bytes whose CRC-32 is `crc` followed by these `size` bytes.
std::uint32_t crc32_continue(std::uint32_t crc, const std::uint8_t* data, std::size_t size);

}  // namespace ppohdem::dem
