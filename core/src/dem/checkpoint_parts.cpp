// Checkpoints written per rank: the parts, the manifest, merging them (layout in
// ppohdem/dem/checkpoint.hpp "Parts"; docs/formats.md "Checkpoints").
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <regex>
#include <tuple>

#include "checkpoint_codec.hpp"
#include "checks_over_ranks.hpp"
#include "ppohdem/comm/comm.hpp"
#include "ppohdem/dem/checkpoint.hpp"
#include "ppohdem/error.hpp"
#include "ppohdem/io/block_file.hpp"

namespace ppohdem::dem {
namespace {

namespace fs = std::filesystem;
using checkpoint_codec::Reader;
using checkpoint_codec::Writer;

// Part payload (format 5):
//   i64 step, u32 rank, u32 ranks, u64 total particles,
//   u64 n, n x {u64 construction index, particle}, u64 n, n x contact, u64 n, n x i64 escaped id
// (particle and contact as in checkpoint_codec.hpp).
constexpr const char* kNoun = "checkpoint part";

std::string part_file_name(long step, int rank, int ranks) {
  char name[96];
  std::snprintf(name, sizeof name, "step_%010ld.rank_%d_of_%d.bin", step, rank, ranks);
  return name;
}

// "step_S.rank_R_of_P.bin": step, rank, ranks; nullopt for another name (temp files too).
std::optional<std::tuple<long, int, int>> parse_part_file_name(const std::string& name) {
  static const std::regex pattern(R"(step_([0-9]+)\.rank_([0-9]+)_of_([0-9]+)\.bin)");
  std::smatch m;
  if (!std::regex_match(name, m, pattern)) return std::nullopt;
  return std::tuple(std::stol(m[1].str()), std::stoi(m[2].str()), std::stoi(m[3].str()));
}

std::vector<std::uint8_t> read_bytes(const fs::path& file, const std::string& what) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string(), 0, "cannot open the " + what);
  std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw InputError(file.string(), 0, "cannot read the " + what);
  return bytes;
}

void sort_contacts(std::vector<ContactHistoryRecord>& contacts) {
  std::sort(contacts.begin(), contacts.end(), [](const auto& a, const auto& b) {
    return std::tuple(a.kind, a.id_a, a.id_b) < std::tuple(b.kind, b.id_a, b.id_b);
  });
}

}  // namespace

namespace {

std::uint64_t part_payload_length(const CheckpointPart& part) {
  return 8 + 4 + 4 + 8 + 8 + part.particles.size() * (8 + checkpoint_codec::kParticleBytes) + 8 +
         part.contacts.size() * checkpoint_codec::kContactBytes + 8 + part.escaped_ids.size() * 8;
}

// The part's file, handed to `sink(bytes, size)` in pieces of about 1 MiB (a part of a large
// state is never whole in memory); returns the payload's CRC-32.
template <class Sink>
std::uint32_t stream_part(const CheckpointPart& part, Sink&& sink) {
  const std::vector<std::uint8_t> header =
      checkpoint_codec::frame_header(kCheckpointPartMagic, kCheckpointFormatVersion, part_payload_length(part));
  sink(header.data(), header.size());
  std::uint32_t crc = crc32_of(nullptr, 0);
  Writer w;
  auto pass_on = [&](bool always) {
    if (!always && w.bytes.size() < (std::size_t{1} << 20)) return;
    crc = crc32_continue(crc, w.bytes.data(), w.bytes.size());
    sink(w.bytes.data(), w.bytes.size());
    w.bytes.clear();
  };
  w.i64(part.step);
  w.u32(part.rank);
  w.u32(part.ranks);
  w.u64(part.total);
  w.u64(part.particles.size());
  for (std::size_t i = 0; i < part.particles.size(); ++i) {
    w.u64(part.order.at(i));
    checkpoint_codec::put_particle(w, part.particles[i]);
    pass_on(false);
  }
  w.u64(part.contacts.size());
  for (const ContactHistoryRecord& c : part.contacts) {
    checkpoint_codec::put_contact(w, c);
    pass_on(false);
  }
  w.u64(part.escaped_ids.size());
  for (const std::int64_t id : part.escaped_ids) w.i64(id);
  pass_on(true);
  w.u32(crc);
  sink(w.bytes.data(), w.bytes.size());
  return crc;
}

}  // namespace

std::vector<std::uint8_t> encode_checkpoint_part(const CheckpointPart& part) {
  std::vector<std::uint8_t> bytes;
  stream_part(part, [&](const std::uint8_t* data, std::size_t size) { bytes.insert(bytes.end(), data, data + size); });
  return bytes;
}

CheckpointPart decode_checkpoint_part(const std::vector<std::uint8_t>& bytes, const std::string& source) {
  // Parts exist from format 5 on.
  const checkpoint_codec::Frame f = checkpoint_codec::unframe(bytes, kCheckpointPartMagic, kNoun, source,
                                                              kCheckpointFormatVersion, kCheckpointFormatVersion);
  Reader r(bytes.data() + f.payload_start, f.payload_length, source, f.payload_start, kNoun);
  CheckpointPart part;
  part.step = static_cast<long>(r.i64("step"));
  part.rank = r.u32("rank");
  part.ranks = r.u32("rank count");
  if (part.rank >= part.ranks) {
    r.fail("rank " + std::to_string(part.rank) + " of " + std::to_string(part.ranks) + ", expected a rank below the count");
  }
  part.total = r.u64("total particle count");
  const std::size_t n = r.count(8 + checkpoint_codec::kParticleBytes, "particles");
  part.order.resize(n);
  part.particles.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    part.order[i] = r.u64("construction index");
    if (part.order[i] >= part.total) {
      r.fail("construction index " + std::to_string(part.order[i]) + ", expected below the total of " +
             std::to_string(part.total) + " particles");
    }
    checkpoint_codec::get_particle(r, part.particles[i]);
  }
  part.contacts.resize(r.count(checkpoint_codec::kContactBytes, "contact histories"));
  for (ContactHistoryRecord& c : part.contacts) checkpoint_codec::get_contact(r, c);
  part.escaped_ids.resize(r.count(8, "escaped ids"));
  for (std::int64_t& id : part.escaped_ids) id = r.i64("escaped id");
  if (!r.done()) r.fail("unexpected bytes after the last field");
  return part;
}

namespace {

// Part k's fields against the manifest's entry k: step, rank, count, total and list sizes.
// `total`: the particle count the parts must agree on.
void check_part(const Checkpoint& manifest, const CheckpointPart& p, std::size_t k, const std::string& source,
                std::uint64_t total, const std::string& total_from) {
  const std::size_t ranks = manifest.parts.size();
  const CheckpointPartEntry& entry = manifest.parts[k];
  auto fail = [&](const std::string& why) {
    throw InputError(source, 0, std::string(kNoun) + ": " + why + "; the manifest expects part " +
                                    std::to_string(k) + " of " + std::to_string(ranks) + " at step " +
                                    std::to_string(manifest.engine.step) + " (a part of another checkpoint?)");
  };
  if (p.step != manifest.engine.step) fail("step " + std::to_string(p.step));
  if (p.rank != k || p.ranks != ranks) fail("rank " + std::to_string(p.rank) + " of " + std::to_string(p.ranks));
  if (p.total != total) fail("a total of " + std::to_string(p.total) + " particles, " + total_from + " " + std::to_string(total));
  if (p.particles.size() != entry.particles || p.contacts.size() != entry.contacts ||
      p.escaped_ids.size() != entry.escaped) {
    fail(std::to_string(p.particles.size()) + " particles, " + std::to_string(p.contacts.size()) + " contacts, " +
         std::to_string(p.escaped_ids.size()) + " escaped ids; the manifest lists " + std::to_string(entry.particles) +
         ", " + std::to_string(entry.contacts) + ", " + std::to_string(entry.escaped));
  }
}

// Part k of the manifest `file` names, read, decoded and matched to its entry's CRC-32.
CheckpointPart read_part(const Checkpoint& c, const fs::path& manifest, std::size_t k, std::string& source) {
  const CheckpointPartEntry& entry = c.parts[k];
  const fs::path name(entry.file);
  const bool plain = !name.empty() && name.is_relative() &&
                     std::none_of(name.begin(), name.end(), [](const fs::path& step) { return step == ".."; });
  if (!plain) {
    throw InputError(manifest.string(), 0, "checkpoint: part " + std::to_string(k) + " is named '" + entry.file +
                                               "', expected a path relative to the manifest's directory");
  }
  const fs::path file = manifest.parent_path() / name;
  source = file.string();
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) {
    throw InputError(manifest.string(), 0, "checkpoint: part " + std::to_string(k) + " of " +
                                               std::to_string(c.parts.size()) + ", " + file.string() +
                                               ", does not exist (a checkpoint is the manifest with its "
                                               "directory of parts; copy both)");
  }
  const std::vector<std::uint8_t> bytes = read_bytes(file, "checkpoint part");
  CheckpointPart part = decode_checkpoint_part(bytes, file.string());
  // Decoded: the last 4 bytes are the payload CRC-32, checked; it must be the manifest's.
  Reader trailer(bytes.data() + bytes.size() - 4, 4, file.string(), bytes.size() - 4, kNoun);
  const std::uint32_t crc = trailer.u32("payload CRC-32");
  if (crc != entry.payload_crc) {
    throw InputError(file.string(), 0, "checkpoint part: its CRC-32 differs from the one the manifest " +
                                           manifest.string() + " lists (a part of another checkpoint?)");
  }
  return part;
}

}  // namespace

void merge_checkpoint_parts(Checkpoint& manifest, const std::vector<CheckpointPart>& parts,
                            const std::vector<std::string>& sources) {
  const std::size_t ranks = manifest.parts.size();
  if (parts.size() != ranks || sources.size() != ranks) {
    throw InputError("merge_checkpoint_parts: " + std::to_string(parts.size()) + " parts for a manifest of " +
                     std::to_string(ranks));
  }
  EngineState& e = manifest.engine;
  const std::uint64_t total = ranks == 0 ? 0 : parts[0].total;
  std::uint64_t sum = 0;
  for (std::size_t k = 0; k < ranks; ++k) {
    check_part(manifest, parts[k], k, sources[k], total, "part 0 has");
    sum += parts[k].particles.size();
  }
  if (sum != total) {
    throw InputError(sources.front(), 0, std::string(kNoun) + ": the parts hold " + std::to_string(sum) +
                                             " particles, expected their total of " + std::to_string(total));
  }
  // Every construction index once (sum == total and no index twice: every index).
  e.particles.assign(static_cast<std::size_t>(total), Particle{});
  std::vector<bool> seen(static_cast<std::size_t>(total), false);
  for (std::size_t k = 0; k < ranks; ++k) {
    for (std::size_t i = 0; i < parts[k].particles.size(); ++i) {
      const std::uint64_t o = parts[k].order[i];
      if (seen[o]) {
        throw InputError(sources[k], 0, std::string(kNoun) + ": construction index " + std::to_string(o) +
                                            " appears in two parts (particle " + std::to_string(i) + " of this part)");
      }
      seen[o] = true;
      e.particles[o] = parts[k].particles[i];
    }
    e.contacts.insert(e.contacts.end(), parts[k].contacts.begin(), parts[k].contacts.end());
    e.escaped_ids.insert(e.escaped_ids.end(), parts[k].escaped_ids.begin(), parts[k].escaped_ids.end());
  }
  sort_contacts(e.contacts);
  std::sort(e.escaped_ids.begin(), e.escaped_ids.end());
  manifest.parts.clear();
}

namespace checkpoint_codec {

void read_parts(Checkpoint& c, const fs::path& manifest) {
  std::vector<CheckpointPart> parts;
  std::vector<std::string> sources(c.parts.size());
  for (std::size_t k = 0; k < c.parts.size(); ++k) parts.push_back(read_part(c, manifest, k, sources[k]));
  merge_checkpoint_parts(c, parts, sources);
}

}  // namespace checkpoint_codec

void write_checkpoint_parts(const fs::path& file, Checkpoint checkpoint, EngineStateShare share, const Comm& comm) {
  const int rank = comm.rank(), ranks = comm.size();
  const std::string dir_name = file.filename().string() + ".parts";
  const fs::path dir = file.parent_path() / dir_name;
  std::error_code ec;
  fs::create_directories(dir, ec);  // every rank: whichever comes first creates it
  if (!fs::is_directory(dir)) throw InputError(dir.string(), 0, "cannot create the directory of checkpoint parts");
  CheckpointPart part;
  part.step = share.state.step;
  part.rank = static_cast<std::uint32_t>(rank);
  part.ranks = static_cast<std::uint32_t>(ranks);
  part.total = share.total;
  part.order = std::move(share.order);
  part.particles = std::move(share.state.particles);
  part.contacts = std::move(share.state.contacts);
  part.escaped_ids = std::move(share.state.escaped_ids);
  const std::string name = part_file_name(part.step, rank, ranks);
  std::uint32_t crc = 0;
  {
    BlockFileWriter writer(dir / name);  // atomic, past the page cache (io/block_file.hpp)
    crc = stream_part(part, [&](const std::uint8_t* data, std::size_t size) {
      writer.write(reinterpret_cast<const char*>(data), size);
    });
    writer.commit(/*sync_to_disk=*/true);
  }
  // Every part is on disk once rank 0 has every rank's table entry.
  Writer mine;
  mine.u64(part.particles.size());
  mine.u64(part.contacts.size());
  mine.u64(part.escaped_ids.size());
  mine.u32(crc);
  const std::vector<Bytes> entries = comm.allgather(Bytes(mine.bytes.begin(), mine.bytes.end()));
  if (rank != 0) return;
  checkpoint.engine = std::move(share.state);  // the global fields, lists emptied above
  checkpoint.engine.particles.clear();
  checkpoint.engine.contacts.clear();
  checkpoint.engine.escaped_ids.clear();
  checkpoint.parts.clear();
  for (int r = 0; r < ranks; ++r) {
    const std::vector<std::uint8_t> block(entries[r].begin(), entries[r].end());
    Reader in(block.data(), block.size(), dir.string(), 0);
    CheckpointPartEntry entry;
    entry.file = dir_name + "/" + part_file_name(part.step, r, ranks);
    entry.particles = in.u64("part particle count");
    entry.contacts = in.u64("part contact count");
    entry.escaped = in.u64("part escaped-id count");
    entry.payload_crc = in.u32("part CRC-32");
    checkpoint.parts.push_back(entry);
  }
  write_checkpoint(file, checkpoint);
  // The manifest names this step's parts: the others are of older checkpoints (a part of a
  // later step is being written by a rank that has gone ahead: left alone).
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const auto parsed = parse_part_file_name(it->path().filename().string());
    if (!parsed) continue;
    const auto [step, r, p] = *parsed;
    if (step < part.step || (step == part.step && p != ranks)) {
      std::error_code rm;
      fs::remove(it->path(), rm);
    }
  }
}

CheckpointShareRead read_checkpoint_share(const fs::path& file, const Comm& comm) {
  CheckpointShareRead out;
  out.checkpoint = read_checkpoint_manifest(file);
  Checkpoint& c = out.checkpoint;
  if (c.parts.empty()) return out;  // a single file: the whole state, on every rank
  EngineStateShare share;
  share.state = c.engine;  // the global fields; the lists come from the parts
  for (const CheckpointPartEntry& entry : c.parts) share.total += entry.particles;
  // Rank r reads the parts r, r + P, ...; a rank that fails names its first failing part, and
  // every rank throws the earliest part's error (no rank is left waiting in a collective).
  std::optional<PlacedError> failure;
  const auto ranks = static_cast<std::size_t>(comm.size());
  for (std::size_t k = static_cast<std::size_t>(comm.rank()); k < c.parts.size() && !failure; k += ranks) {
    try {
      std::string source;
      CheckpointPart part = read_part(c, file, k, source);
      check_part(c, part, k, source, share.total, "the manifest's parts hold");
      EngineState& e = share.state;
      share.order.insert(share.order.end(), part.order.begin(), part.order.end());
      e.particles.insert(e.particles.end(), part.particles.begin(), part.particles.end());
      e.contacts.insert(e.contacts.end(), part.contacts.begin(), part.contacts.end());
      e.escaped_ids.insert(e.escaped_ids.end(), part.escaped_ids.begin(), part.escaped_ids.end());
    } catch (const InputError& e) {
      failure = PlacedError{k, e};
    }
  }
  throw_earliest_error(comm, failure);
  c.parts.clear();
  out.share = std::move(share);
  return out;
}

}  // namespace ppohdem::dem
