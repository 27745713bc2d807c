#pragma once
// Little-endian byte encoding shared by checkpoint files and their per-rank parts
// (checkpoint.cpp, checkpoint_parts.cpp; layout in ppohdem/dem/checkpoint.hpp). Internal.
#include <bit>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "ppohdem/dem/checkpoint.hpp"
#include "ppohdem/error.hpp"

namespace ppohdem::dem::checkpoint_codec {

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
  /// With a sink, the bytes so far go to it once they reach 1 MiB (or always): a large file
  /// is then streamed, never whole in memory.
  void pass_on(bool always = false) {
    if (!sink || (!always && bytes.size() < (std::size_t{1} << 20))) return;
    sink(bytes.data(), bytes.size());
    bytes.clear();
  }
  std::vector<std::uint8_t> bytes;
  std::function<void(const std::uint8_t*, std::size_t)> sink;
};

class Reader {
 public:
  /// `noun` starts every message ("checkpoint", "checkpoint part").
  Reader(const std::uint8_t* data, std::size_t size, const std::string& source, std::size_t offset,
         const char* noun = "checkpoint")
      : data_(data), size_(size), source_(source), base_(offset), noun_(noun) {}

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
    throw InputError(source_, 0, std::string(noun_) + ": " + message + " (byte " + std::to_string(base_ + pos_) + ")");
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
  const char* noun_;
};

// ---- records -------------------------------------------------------------------------------
//   particle {i64 id, vec position, vec velocity, vec angular_velocity, f64 radius,
//             u32 material (< 65536), vec force, vec torque}
//   contact  {u8 kind, i64 id_a, i64 id_b, vec xi, f64 k_t, vec branch_i, vec branch_j,
//             vec surface_velocity, vec rolling torque, f64 rolling stiffness}
inline constexpr std::size_t kParticleBytes = 8 + 16 * 8 + 4;
inline constexpr std::size_t kContactBytes = 1 + 2 * 8 + 17 * 8;

inline void put_particle(Writer& w, const Particle& p) {
  w.i64(p.id);
  w.vec(p.position);
  w.vec(p.velocity);
  w.vec(p.angular_velocity);
  w.f64(p.radius);
  w.u32(p.material);
  w.vec(p.force);
  w.vec(p.torque);
}

inline void get_particle(Reader& r, Particle& p) {
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

inline void put_contact(Writer& w, const ContactHistoryRecord& r) {
  w.u8(static_cast<std::uint8_t>(r.kind));
  w.i64(r.id_a);
  w.i64(r.id_b);
  TangentialSpring::for_each_field(r.spring, [&w](const auto& field) {
    if constexpr (std::is_same_v<std::decay_t<decltype(field)>, double>) w.f64(field);
    else w.vec(field);
  });
}

inline void get_contact(Reader& r, ContactHistoryRecord& h) {
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

// ---- framing: header {magic, u32 version, u32 n + build, u64 payload length, u32 CRC},
// payload, u32 CRC of the payload --------------------------------------------------------------

/// The header of a file of `payload_length` payload bytes (this build's name), CRC included.
std::vector<std::uint8_t> frame_header(const char* magic, std::uint32_t version, std::uint64_t payload_length);
/// The file's bytes around `payload` (this build's name).
std::vector<std::uint8_t> framed(const char* magic, std::uint32_t version, const std::vector<std::uint8_t>& payload);

/// Where a framed file's payload is, after every check of the frame.
struct Frame {
  std::uint32_t version = 0;
  std::string build;
  std::size_t payload_start = 0;
  std::size_t payload_length = 0;
};
/// Checks magic, header CRC, version in [oldest, newest], size and payload CRC; throws
/// InputError(source, 0, ...) starting with `noun` ("checkpoint", "checkpoint part").
Frame unframe(const std::vector<std::uint8_t>& bytes, const char* magic, const char* noun, const std::string& source,
              std::uint32_t oldest, std::uint32_t newest);

/// A manifest's parts read (beside `manifest`) and merged into c.engine (checkpoint_parts.cpp).
void read_parts(Checkpoint& c, const std::filesystem::path& manifest);

}  // namespace ppohdem::dem::checkpoint_codec
