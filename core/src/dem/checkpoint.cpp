// Checkpoint files (layout in ppohdem/dem/checkpoint.hpp).
#include "ppohdem/dem/checkpoint.hpp"

#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>

#include "ppohdem/build_info.hpp"
#include "ppohdem/error.hpp"
#include "ppohdem/io/block_file.hpp"
#include "checkpoint_codec.hpp"

namespace ppohdem::dem {
namespace {

using checkpoint_codec::Reader;
using checkpoint_codec::Writer;

// ---- payload, format version 5 -----------------------------------------------------------
//   str provenance, str scene
//   engine: str name, i64 step, f64 dt,
//           u64 n, n x particle (checkpoint_codec.hpp)
//           u64 n, n x contact (checkpoint_codec.hpp)
//           energies {f64 kinetic, rotational, gravitational, elastic, dissipated,
//                     boundary_work}
//           u64 n, n x i64 escaped id
//           u64 n, n x load {vec force, vec moment_about_origin}
//           u64 particle_pairs, u64 particle_boundary, f64 boundary_power
//           u64 n, n bytes engine_private
//   objects: u64 n, n x {str name, f64 qw, qx, qy, qz, vec translation, u64 outside_grid}
//   run: u64 n, n x str energy row; u64 n, n x str object row; u64 frames
//   insertion: u64 n, n x {u64 events, u64 draws, i64 requested, i64 inserted, i64 failed};
//              f64 kinetic, rotational, gravitational; u64 n, n x str row
//   parts: u64 n, n x {str file, u64 particles, u64 contacts, u64 escaped ids,
//          u32 payload CRC-32}; n > 0 (a manifest): the three lists above are empty and
//          live in the parts (checkpoint_parts.cpp)
// Version 4 was version 5 without the parts; version 3 also without the insertion record.
// Version 2 was version 3 without the rolling spring; version 1 also without the particles'
// material (one-material scenes only).
using checkpoint_codec::kContactBytes;
using checkpoint_codec::kParticleBytes;

void encode_payload(Writer& w, const Checkpoint& c) {
  w.str(c.provenance);
  w.str(c.scene);
  const EngineState& e = c.engine;
  w.str(e.engine);
  w.i64(e.step);
  w.f64(e.dt);
  w.u64(e.particles.size());
  for (const Particle& p : e.particles) {
    checkpoint_codec::put_particle(w, p);
    w.pass_on();
  }
  w.u64(e.contacts.size());
  for (const ContactHistoryRecord& r : e.contacts) {
    checkpoint_codec::put_contact(w, r);
    w.pass_on();
  }
  const Energies& a = e.accumulators;
  for (double v : {a.kinetic, a.rotational, a.gravitational, a.elastic, a.dissipated, a.boundary_work}) w.f64(v);
  w.u64(e.escaped_ids.size());
  for (std::int64_t id : e.escaped_ids) {
    w.i64(id);
    w.pass_on();
  }
  w.u64(e.boundary_loads.size());
  for (const BoundaryLoad& l : e.boundary_loads) {
    w.vec(l.force);
    w.vec(l.moment_about_origin);
  }
  w.u64(e.contact_counts.particle_pairs);
  w.u64(e.contact_counts.particle_boundary);
  w.f64(e.boundary_power);
  w.u64(e.engine_private.size());
  w.bytes.insert(w.bytes.end(), e.engine_private.begin(), e.engine_private.end());
  w.u64(c.objects.size());
  for (const ObjectPoseRecord& o : c.objects) {
    w.str(o.name);
    w.f64(o.rotation.w());
    w.f64(o.rotation.x());
    w.f64(o.rotation.y());
    w.f64(o.rotation.z());
    w.vec(o.translation);
    w.u64(o.outside_grid);
  }
  w.u64(c.run.energy_rows.size());
  for (const std::string& row : c.run.energy_rows) {
    w.str(row);
    w.pass_on();
  }
  w.u64(c.run.object_rows.size());
  for (const std::string& row : c.run.object_rows) {
    w.str(row);
    w.pass_on();
  }
  w.u64(c.run.frames);
  const InsertionRecord& in = c.insertion;
  w.u64(in.counters.size());
  for (const InsertCounters& k : in.counters) {
    w.u64(k.events);
    w.u64(k.draws);
    w.i64(k.requested);
    w.i64(k.inserted);
    w.i64(k.failed);
  }
  w.f64(in.kinetic);
  w.f64(in.rotational);
  w.f64(in.gravitational);
  w.u64(in.rows.size());
  for (const std::string& row : in.rows) w.str(row);
  w.u64(c.parts.size());
  for (const CheckpointPartEntry& part : c.parts) {
    w.str(part.file);
    w.u64(part.particles);
    w.u64(part.contacts);
    w.u64(part.escaped);
    w.u32(part.payload_crc);
  }
}

void decode_payload(Reader& r, Checkpoint& c, std::uint32_t version) {
  c.provenance = r.str("provenance");
  c.scene = r.str("scene name");
  EngineState& e = c.engine;
  e.engine = r.str("engine name");
  e.step = static_cast<long>(r.i64("step"));
  e.dt = r.f64("dt");
  e.particles.resize(r.count(kParticleBytes, "particles"));
  for (Particle& p : e.particles) checkpoint_codec::get_particle(r, p);
  e.contacts.resize(r.count(kContactBytes, "contact histories"));
  for (ContactHistoryRecord& h : e.contacts) checkpoint_codec::get_contact(r, h);
  Energies& a = e.accumulators;
  for (double* v : {&a.kinetic, &a.rotational, &a.gravitational, &a.elastic, &a.dissipated, &a.boundary_work}) {
    *v = r.f64("energies");
  }
  e.escaped_ids.resize(r.count(8, "escaped ids"));
  for (std::int64_t& id : e.escaped_ids) id = r.i64("escaped id");
  e.boundary_loads.resize(r.count(48, "boundary loads"));
  for (BoundaryLoad& l : e.boundary_loads) {
    l.force = r.vec("boundary force");
    l.moment_about_origin = r.vec("boundary moment");
  }
  e.contact_counts.particle_pairs = static_cast<std::size_t>(r.u64("contact count"));
  e.contact_counts.particle_boundary = static_cast<std::size_t>(r.u64("contact count"));
  e.boundary_power = r.f64("boundary power");
  e.engine_private.resize(r.count(1, "engine private data"));
  for (std::uint8_t& b : e.engine_private) b = r.u8("engine private data");
  c.objects.resize(r.count(8 + 8 * 8, "objects"));
  for (ObjectPoseRecord& o : c.objects) {
    o.name = r.str("object name");
    const double qw = r.f64("object rotation"), qx = r.f64("object rotation");
    const double qy = r.f64("object rotation"), qz = r.f64("object rotation");
    o.rotation = Quat(qw, qx, qy, qz);
    o.translation = r.vec("object translation");
    o.outside_grid = r.u64("object outside-grid count");
  }
  c.run.energy_rows.resize(r.count(8, "energy rows"));
  for (std::string& row : c.run.energy_rows) row = r.str("energy row");
  c.run.object_rows.resize(r.count(8, "object rows"));
  for (std::string& row : c.run.object_rows) row = r.str("object row");
  c.run.frames = r.u64("frame count");
  if (version >= 4) {
    InsertionRecord& in = c.insertion;
    in.counters.resize(r.count(40, "insert counters"));
    for (InsertCounters& k : in.counters) {
      k.events = r.u64("insert events");
      k.draws = r.u64("insert draws");
      k.requested = r.i64("insert requested");
      k.inserted = r.i64("insert inserted");
      k.failed = r.i64("insert failed");
    }
    in.kinetic = r.f64("inserted energy");
    in.rotational = r.f64("inserted energy");
    in.gravitational = r.f64("inserted energy");
    in.rows.resize(r.count(8, "insertion rows"));
    for (std::string& row : in.rows) row = r.str("insertion row");
  }
  if (version >= 5) {
    c.parts.resize(r.count(8 + 3 * 8 + 4, "parts"));
    for (CheckpointPartEntry& part : c.parts) {
      part.file = r.str("part file name");
      part.particles = r.u64("part particle count");
      part.contacts = r.u64("part contact count");
      part.escaped = r.u64("part escaped-id count");
      part.payload_crc = r.u32("part CRC-32");
    }
    if (!c.parts.empty() && (!e.particles.empty() || !e.contacts.empty() || !e.escaped_ids.empty())) {
      r.fail("a manifest of " + std::to_string(c.parts.size()) +
             " parts must hold no particles, contacts or escaped ids itself (they are in the parts)");
    }
  }
  if (!r.done()) r.fail("unexpected bytes after the last field");
}

}  // namespace

std::uint32_t crc32_of(const std::uint8_t* data, std::size_t size) {
  return static_cast<std::uint32_t>(::crc32_z(::crc32_z(0L, Z_NULL, 0), data, size));
}

std::uint32_t crc32_continue(std::uint32_t crc, const std::uint8_t* data, std::size_t size) {
  return static_cast<std::uint32_t>(::crc32_z(crc, data, size));
}

std::string checkpoint_build_name() {
  return std::string("ppohdem ") + build_info::kVersion + " (git " + build_info::kGitHash + ")";
}

namespace checkpoint_codec {

std::vector<std::uint8_t> frame_header(const char* magic, std::uint32_t version, std::uint64_t payload_length) {
  Writer w;
  w.bytes.assign(magic, magic + 8);
  w.u32(version);
  const std::string build = checkpoint_build_name();
  w.u32(static_cast<std::uint32_t>(build.size()));
  w.bytes.insert(w.bytes.end(), build.begin(), build.end());
  w.u64(payload_length);
  w.u32(crc32_of(w.bytes.data(), w.bytes.size()));
  return std::move(w.bytes);
}

std::vector<std::uint8_t> framed(const char* magic, std::uint32_t version, const std::vector<std::uint8_t>& payload) {
  Writer w;
  w.bytes = frame_header(magic, version, payload.size());
  w.bytes.insert(w.bytes.end(), payload.begin(), payload.end());
  w.u32(crc32_of(payload.data(), payload.size()));
  return std::move(w.bytes);
}

Frame unframe(const std::vector<std::uint8_t>& bytes, const char* magic, const char* noun, const std::string& source,
              std::uint32_t oldest, std::uint32_t newest) {
  const std::string what(noun);
  // The fixed part of the header (magic, version, build) has the same place in every version.
  if (bytes.size() < 8 || std::memcmp(bytes.data(), magic, 8) != 0) {
    throw InputError(source, 0, "not a ppohdem " + what + " (expected the magic bytes '" + std::string(magic, 8) +
                                    "' at the start)");
  }
  Reader h(bytes.data() + 8, bytes.size() - 8, source, 8, noun);
  const auto bad_header = [&](const std::string& why) {
    return InputError(source, 0, what + " header is corrupted or the file is truncated (" + why + ")");
  };
  if (bytes.size() < 16) throw bad_header("shorter than 16 bytes");
  Frame f;
  f.version = h.u32("format version");
  const std::uint32_t build_length = h.u32("build name length");
  // 4096: a build name is ~30 bytes; the limit only stops a damaged length early.
  if (build_length > 4096) throw bad_header("a build name of " + std::to_string(build_length) + " bytes");
  if (bytes.size() < 16 + std::size_t{build_length} + 12) throw bad_header("the header does not fit in the file");
  f.build.assign(build_length, '\0');
  for (char& ch : f.build) ch = static_cast<char>(h.u8("build name"));
  const std::uint64_t payload_length = h.u64("payload length");
  const std::size_t header_length = h.position();
  const std::uint32_t header_crc = h.u32("header CRC-32");
  if (crc32_of(bytes.data(), header_length) != header_crc) {
    throw InputError(source, 0, what + " header is corrupted (CRC-32 mismatch); the file was damaged");
  }
  if (f.version < oldest || f.version > newest) {
    throw InputError(source, 0, what + " format version " + std::to_string(f.version) + ", written by " + f.build +
                                    "; this build (" + checkpoint_build_name() + ") reads format versions " +
                                    std::to_string(oldest) + " to " + std::to_string(newest) +
                                    " only: restart with the build that wrote it");
  }
  f.payload_start = h.position();
  const std::uint64_t expected = f.payload_start + payload_length + 4;
  if (payload_length > bytes.size() || bytes.size() != expected) {
    throw InputError(source, 0, what + (bytes.size() < expected ? " is truncated" : " is too long") +
                                    ": the header announces " + std::to_string(expected) + " bytes, the file has " +
                                    std::to_string(bytes.size()));
  }
  f.payload_length = static_cast<std::size_t>(payload_length);
  const std::uint8_t* payload = bytes.data() + f.payload_start;
  Reader trailer(payload + f.payload_length, 4, source, f.payload_start + f.payload_length, noun);
  if (crc32_of(payload, f.payload_length) != trailer.u32("payload CRC-32")) {
    throw InputError(source, 0, what + " data is corrupted (CRC-32 mismatch over " + std::to_string(f.payload_length) +
                                    " bytes); the file was damaged");
  }
  return f;
}

}  // namespace checkpoint_codec

std::vector<std::uint8_t> encode_checkpoint(const Checkpoint& checkpoint) {
  Writer payload;
  encode_payload(payload, checkpoint);
  return checkpoint_codec::framed(kCheckpointMagic, kCheckpointFormatVersion, payload.bytes);
}

Checkpoint decode_checkpoint(const std::vector<std::uint8_t>& bytes, const std::string& source) {
  const checkpoint_codec::Frame f = checkpoint_codec::unframe(bytes, kCheckpointMagic, "checkpoint", source,
                                                              kOldestCheckpointFormatVersion, kCheckpointFormatVersion);
  Checkpoint c;
  c.build = f.build;
  Reader r(bytes.data() + f.payload_start, f.payload_length, source, f.payload_start);
  decode_payload(r, c, f.version);
  return c;
}

// encode_checkpoint's bytes, streamed: the payload encoded once to count its length (the
// header's), then again into the file with its CRC-32.
void write_checkpoint(const std::filesystem::path& file, const Checkpoint& checkpoint) {
  std::uint64_t length = 0;
  {
    Writer counter;
    counter.sink = [&length](const std::uint8_t*, std::size_t size) { length += size; };
    encode_payload(counter, checkpoint);
    counter.pass_on(true);
  }
  BlockFileWriter writer(file);  // atomic, past the page cache (io/block_file.hpp)
  const std::vector<std::uint8_t> header =
      checkpoint_codec::frame_header(kCheckpointMagic, kCheckpointFormatVersion, length);
  writer.write(reinterpret_cast<const char*>(header.data()), header.size());
  std::uint32_t crc = crc32_of(nullptr, 0);
  Writer w;
  w.sink = [&](const std::uint8_t* data, std::size_t size) {
    crc = crc32_continue(crc, data, size);
    writer.write(reinterpret_cast<const char*>(data), size);
  };
  encode_payload(w, checkpoint);
  w.pass_on(true);
  w.u32(crc);
  writer.write(reinterpret_cast<const char*>(w.bytes.data()), w.bytes.size());
  writer.commit(/*sync_to_disk=*/true);
}

Checkpoint read_checkpoint_manifest(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string(), 0, "cannot open the checkpoint file");
  std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw InputError(file.string(), 0, "cannot read the checkpoint file");
  return decode_checkpoint(bytes, file.string());
}

Checkpoint read_checkpoint(const std::filesystem::path& file) {
  Checkpoint c = read_checkpoint_manifest(file);
  if (!c.parts.empty()) checkpoint_codec::read_parts(c, file);
  return c;
}

}  // namespace ppohdem::dem
