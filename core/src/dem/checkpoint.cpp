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
#include "ppohdem/io/atomic_file.hpp"

namespace ppohdem::dem {
namespace {

// ---- little-endian encoding -------------------------------------------------------------

class Writer {
 public:
  void u8(std::uint8_t v) { bytes.push_back(v); }
  void u32(std::uint32_t v) {
    for (int k = 0; k < 4; ++k) bytes.push_back(static_cast<std::uint8_t>(v >> (8 * k)));
  }
  void u64(std::uint64_t v) {
    for (int k = 0; k < 8; ++k) bytes.push_back(static_cast<std::uint8_t>(v >> (8 * k)));
  }
  void i64(std::int64_t v) { u64(static_cast<std::uint64_t>(v)); }
  void f64(double v) { u64(std::bit_cast<std::uint64_t>(v)); }
  void vec(const Vec3& v) {
    f64(v.x());
    f64(v.y());
    f64(v.z());
  }
  void str(const std::string& s) {
    u64(s.size());
    bytes.insert(bytes.end(), s.begin(), s.end());
  }
  std::vector<std::uint8_t> bytes;
};

class Reader {
 public:
  Reader(const std::uint8_t* data, std::size_t size, const std::string& source, std::size_t offset)
      : data_(data), size_(size), source_(source), base_(offset) {}

  std::uint8_t u8(const char* what) { return *take(1, what); }
  std::uint32_t u32(const char* what) {
    const std::uint8_t* p = take(4, what);
    std::uint32_t v = 0;
    for (int k = 0; k < 4; ++k) v |= static_cast<std::uint32_t>(p[k]) << (8 * k);
    return v;
  }
  std::uint64_t u64(const char* what) {
    const std::uint8_t* p = take(8, what);
    std::uint64_t v = 0;
    for (int k = 0; k < 8; ++k) v |= static_cast<std::uint64_t>(p[k]) << (8 * k);
    return v;
  }
  std::int64_t i64(const char* what) { return static_cast<std::int64_t>(u64(what)); }
  double f64(const char* what) { return std::bit_cast<double>(u64(what)); }
  Vec3 vec(const char* what) {
    const double x = f64(what), y = f64(what), z = f64(what);
    return {x, y, z};
  }
  std::string str(const char* what) {
    const std::size_t n = count(1, what);
    const std::uint8_t* p = take(n, what);
    return std::string(reinterpret_cast<const char*>(p), n);
  }
  /// A record count, checked against the bytes left (each record >= record_bytes) before
  /// anything is allocated.
  std::size_t count(std::size_t record_bytes, const char* what) {
    const std::uint64_t n = u64(what);
    if (n > (size_ - pos_) / record_bytes) {
      fail(std::string(what) + ": a count of " + std::to_string(n) + " records of >= " +
           std::to_string(record_bytes) + " bytes, but only " + std::to_string(size_ - pos_) +
           " bytes are left");
    }
    return static_cast<std::size_t>(n);
  }
  bool done() const { return pos_ == size_; }
  std::size_t position() const { return base_ + pos_; }
  [[noreturn]] void fail(const std::string& message) const {
    throw InputError(source_, 0, "checkpoint: " + message + " (byte " + std::to_string(base_ + pos_) + ")");
  }

 private:
  const std::uint8_t* take(std::size_t n, const char* what) {
    if (n > size_ - pos_) fail(std::string("unexpected end reading ") + what);
    const std::uint8_t* p = data_ + pos_;
    pos_ += n;
    return p;
  }
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
  const std::string& source_;
  std::size_t base_;  // offset of data_ in the file, for messages
};

// ---- payload, format version 4 -----------------------------------------------------------
//   str provenance, str scene
//   engine: str name, i64 step, f64 dt,
//           u64 n, n x particle {i64 id, vec position, vec velocity, vec angular_velocity,
//                                f64 radius, u32 material (< 65536), vec force, vec torque}
//           u64 n, n x contact {u8 kind, i64 id_a, i64 id_b, vec xi, f64 k_t, vec branch_i,
//                               vec branch_j, vec surface_velocity, vec rolling torque,
//                               f64 rolling stiffness}
//           energies {f64 kinetic, rotational, gravitational, elastic, dissipated,
//                     boundary_work}
//           u64 n, n x i64 escaped id
//           u64 n, n x load {vec force, vec moment_about_origin}
//           u64 particle_pairs, u64 particle_boundary, f64 boundary_power
//           u64 n, n bytes engine_private
//   objects: u64 n, n x {str name, f64 qw, qx, qy, qz, vec translation, u64 outside_grid}
//   run: u64 n, n x str energy row; u64 n, n x str object row; u64 frames
//   insertion (version 4): u64 n, n x {u64 events, u64 draws, i64 requested, i64 inserted,
//              i64 failed}; f64 kinetic, rotational, gravitational; u64 n, n x str row
// Version 3 was version 4 without the insertion record.
// Version 2 was version 3 without the rolling spring; version 1 also without the particles'
// material (one-material scenes only).
constexpr std::size_t kParticleBytes = 8 + 16 * 8 + 4;
constexpr std::size_t kContactBytes = 1 + 2 * 8 + 17 * 8;

void encode_payload(Writer& w, const Checkpoint& c) {
  w.str(c.provenance);
  w.str(c.scene);
  const EngineState& e = c.engine;
  w.str(e.engine);
  w.i64(e.step);
  w.f64(e.dt);
  w.u64(e.particles.size());
  for (const Particle& p : e.particles) {
    w.i64(p.id);
    w.vec(p.position);
    w.vec(p.velocity);
    w.vec(p.angular_velocity);
    w.f64(p.radius);
    w.u32(p.material);
    w.vec(p.force);
    w.vec(p.torque);
  }
  w.u64(e.contacts.size());
  for (const ContactHistoryRecord& r : e.contacts) {
    w.u8(static_cast<std::uint8_t>(r.kind));
    w.i64(r.id_a);
    w.i64(r.id_b);
    TangentialSpring::for_each_field(r.spring, [&w](const auto& field) {
      if constexpr (std::is_same_v<std::decay_t<decltype(field)>, double>) w.f64(field);
      else w.vec(field);
    });
  }
  const Energies& a = e.accumulators;
  for (double v : {a.kinetic, a.rotational, a.gravitational, a.elastic, a.dissipated, a.boundary_work}) w.f64(v);
  w.u64(e.escaped_ids.size());
  for (std::int64_t id : e.escaped_ids) w.i64(id);
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
  for (const std::string& row : c.run.energy_rows) w.str(row);
  w.u64(c.run.object_rows.size());
  for (const std::string& row : c.run.object_rows) w.str(row);
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
}

void decode_payload(Reader& r, Checkpoint& c, std::uint32_t version) {
  c.provenance = r.str("provenance");
  c.scene = r.str("scene name");
  EngineState& e = c.engine;
  e.engine = r.str("engine name");
  e.step = static_cast<long>(r.i64("step"));
  e.dt = r.f64("dt");
  e.particles.resize(r.count(kParticleBytes, "particles"));
  for (Particle& p : e.particles) {
    p.id = r.i64("particle id");
    p.position = r.vec("position");
    p.velocity = r.vec("velocity");
    p.angular_velocity = r.vec("angular velocity");
    p.radius = r.f64("radius");
    const std::uint32_t material = r.u32("material");
    if (material > 0xFFFF) r.fail("particle material index " + std::to_string(material) + ", expected < 65536");
    p.material = static_cast<std::uint16_t>(material);
    p.force = r.vec("force");
    p.torque = r.vec("torque");
  }
  e.contacts.resize(r.count(kContactBytes, "contact histories"));
  for (ContactHistoryRecord& h : e.contacts) {
    const std::uint8_t kind = r.u8("contact kind");
    if (kind > 1) r.fail("contact kind " + std::to_string(kind) + ", expected 0 (pair) or 1 (boundary)");
    h.kind = static_cast<ContactHistoryRecord::Kind>(kind);
    h.id_a = r.i64("contact id_a");
    h.id_b = r.i64("contact id_b");
    h.spring.displacement = r.vec("tangential displacement");
    h.spring.stiffness = r.f64("tangential stiffness");
    h.spring.branch_i = r.vec("branch vector i");
    h.spring.branch_j = r.vec("branch vector j");
    h.spring.surface_velocity = r.vec("boundary surface velocity");
    h.spring.rolling.torque = r.vec("rolling spring torque");
    h.spring.rolling.stiffness = r.f64("rolling spring stiffness");
  }
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
  if (!r.done()) r.fail("unexpected bytes after the last field");
}

}  // namespace

std::uint32_t crc32_of(const std::uint8_t* data, std::size_t size) {
  return static_cast<std::uint32_t>(::crc32_z(::crc32_z(0L, Z_NULL, 0), data, size));
}

std::string checkpoint_build_name() {
  return std::string("ppohdem ") + build_info::kVersion + " (git " + build_info::kGitHash + ")";
}

std::vector<std::uint8_t> encode_checkpoint(const Checkpoint& checkpoint) {
  Writer payload;
  encode_payload(payload, checkpoint);
  Writer w;
  w.bytes.assign(kCheckpointMagic, kCheckpointMagic + 8);
  w.u32(kCheckpointFormatVersion);
  const std::string build = checkpoint_build_name();
  w.u32(static_cast<std::uint32_t>(build.size()));
  w.bytes.insert(w.bytes.end(), build.begin(), build.end());
  w.u64(payload.bytes.size());
  w.u32(crc32_of(w.bytes.data(), w.bytes.size()));
  w.bytes.insert(w.bytes.end(), payload.bytes.begin(), payload.bytes.end());
  w.u32(crc32_of(payload.bytes.data(), payload.bytes.size()));
  return std::move(w.bytes);
}

Checkpoint decode_checkpoint(const std::vector<std::uint8_t>& bytes, const std::string& source) {
  // The fixed part of the header (magic, version, build) has the same place in every version.
  if (bytes.size() < 8 || std::memcmp(bytes.data(), kCheckpointMagic, 8) != 0) {
    throw InputError(source, 0, "not a ppohdem checkpoint (expected the magic bytes 'PPOHDEMC' at the start)");
  }
  Reader h(bytes.data() + 8, bytes.size() - 8, source, 8);
  const auto bad_header = [&](const std::string& why) {
    return InputError(source, 0, "checkpoint header is corrupted or the file is truncated (" + why + ")");
  };
  if (bytes.size() < 16) throw bad_header("shorter than 16 bytes");
  const std::uint32_t version = h.u32("format version");
  const std::uint32_t build_length = h.u32("build name length");
  // 4096: a build name is ~30 bytes; the limit only stops a damaged length early.
  if (build_length > 4096) throw bad_header("a build name of " + std::to_string(build_length) + " bytes");
  if (bytes.size() < 16 + std::size_t{build_length} + 12) throw bad_header("the header does not fit in the file");
  std::string build(build_length, '\0');
  for (char& ch : build) ch = static_cast<char>(h.u8("build name"));
  const std::uint64_t payload_length = h.u64("payload length");
  const std::size_t header_length = h.position();
  const std::uint32_t header_crc = h.u32("header CRC-32");
  if (crc32_of(bytes.data(), header_length) != header_crc) {
    throw InputError(source, 0, "checkpoint header is corrupted (CRC-32 mismatch); the file was damaged");
  }
  if (version < kOldestCheckpointFormatVersion || version > kCheckpointFormatVersion) {
    throw InputError(source, 0, "checkpoint format version " + std::to_string(version) + ", written by " +
                                    build + "; this build (" + checkpoint_build_name() +
                                    ") reads format versions " + std::to_string(kOldestCheckpointFormatVersion) +
                                    " to " + std::to_string(kCheckpointFormatVersion) +
                                    " only: restart with the build that wrote it");
  }
  const std::size_t payload_start = h.position();
  const std::uint64_t expected = payload_start + payload_length + 4;
  if (payload_length > bytes.size() || bytes.size() != expected) {
    throw InputError(source, 0, std::string(bytes.size() < expected ? "checkpoint is truncated" : "checkpoint is too long") +
                                    ": the header announces " + std::to_string(expected) + " bytes, the file has " +
                                    std::to_string(bytes.size()));
  }
  const std::uint8_t* payload = bytes.data() + payload_start;
  const auto length = static_cast<std::size_t>(payload_length);
  Reader trailer(payload + length, 4, source, payload_start + length);
  if (crc32_of(payload, length) != trailer.u32("payload CRC-32")) {
    throw InputError(source, 0, "checkpoint data is corrupted (CRC-32 mismatch over " + std::to_string(length) +
                                    " bytes); the file was damaged");
  }
  Checkpoint c;
  c.build = build;
  Reader r(payload, length, source, payload_start);
  decode_payload(r, c, version);
  return c;
}

void write_checkpoint(const std::filesystem::path& file, const Checkpoint& checkpoint) {
  const std::vector<std::uint8_t> bytes = encode_checkpoint(checkpoint);
  AtomicFileWriter writer(file, /*binary=*/true);
  writer.stream().write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  writer.commit(/*sync_to_disk=*/true);
}

Checkpoint read_checkpoint(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string(), 0, "cannot open the checkpoint file");
  std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw InputError(file.string(), 0, "cannot read the checkpoint file");
  return decode_checkpoint(bytes, file.string());
}

}  // namespace ppohdem::dem
