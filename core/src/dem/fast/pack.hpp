#pragma once
// Packing of particle data into the byte messages of the Comm interface (ppohdem/comm/comm.hpp)
// for the fast engine's ghost exchange, migration and gathers. Private to core/src/dem/fast.
// Values are copied byte for byte (memcpy), so a double arrives with the same bits.
#include <cstddef>
#include <cstring>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include "ppohdem/comm/comm.hpp"
#include "ppohdem/dem/contact_force.hpp"
#include "ppohdem/dem/particle.hpp"

namespace ppohdem::dem::fast {

class Packer {
 public:
  explicit Packer(Bytes& out) : out_(out) {}
  /// `count` trivially copyable records in one copy (a per-particle table: one insert instead of
  /// one per value, docs/performance.md "Ranks gather once per evaluation").
  template <class T>
  void put_rows(const T* rows, std::size_t count) {
    static_assert(std::is_trivially_copyable_v<T>);
    raw(rows, count * sizeof(T));
  }
  template <class T>
  void put(const T& value) {
    if constexpr (std::is_arithmetic_v<T> || std::is_enum_v<T>) {
      raw(&value, sizeof value);
    } else if constexpr (std::is_same_v<T, Vec3>) {
      raw(value.data(), 3 * sizeof(double));
    } else if constexpr (requires { typename T::packed_as_bytes; }) {  // a record of doubles
      static_assert(std::is_trivially_copyable_v<T>);
      raw(&value, sizeof value);
    } else {
      static_assert(std::is_same_v<T, TangentialSpring>, "Packer: no rule for this type");
      TangentialSpring::for_each_field(value, [&](const auto& field) { put(field); });
    }
  }

 private:
  void raw(const void* p, std::size_t n) {
    // resize + memcpy, not insert: GCC 12 flags insert's inlined memmove with a false
    // -Wstringop-overflow in some callers.
    if (n == 0) return;
    const std::size_t old = out_.size();
    out_.resize(old + n);
    std::memcpy(out_.data() + old, p, n);
  }
  Bytes& out_;
};

class Unpacker {
 public:
  explicit Unpacker(const Bytes& in) : in_(in) {}
  /// Packer::put_rows's records, appended to `rows`.
  template <class T>
  void get_rows(std::vector<T>& rows, std::size_t count) {
    static_assert(std::is_trivially_copyable_v<T>);
    const std::size_t old = rows.size();
    rows.resize(old + count);
    raw(rows.data() + old, count * sizeof(T));
  }
  template <class T>
  void get(T& value) {
    if constexpr (std::is_arithmetic_v<T> || std::is_enum_v<T>) {
      raw(&value, sizeof value);
    } else if constexpr (std::is_same_v<T, Vec3>) {
      raw(value.data(), 3 * sizeof(double));
    } else if constexpr (requires { typename T::packed_as_bytes; }) {
      static_assert(std::is_trivially_copyable_v<T>);
      raw(&value, sizeof value);
    } else {
      static_assert(std::is_same_v<T, TangentialSpring>, "Unpacker: no rule for this type");
      TangentialSpring::for_each_field(value, [&](auto& field) { get(field); });
    }
  }
  template <class T>
  T get() {
    T value{};
    get(value);
    return value;
  }
  bool done() const { return pos_ == in_.size(); }

 private:
  void raw(void* p, std::size_t n) {
    if (pos_ + n > in_.size()) throw std::logic_error("fast engine: truncated message (pack/unpack mismatch)");
    std::memcpy(p, in_.data() + pos_, n);
    pos_ += n;
  }
  const Bytes& in_;
  std::size_t pos_ = 0;
};

/// A Particle's fields, in its declaration order.
inline void put_particle(Packer& p, const Particle& q) {
  p.put(q.id);
  p.put(q.position);
  p.put(q.velocity);
  p.put(q.angular_velocity);
  p.put(q.radius);
  p.put(q.material);
  p.put(q.force);
  p.put(q.torque);
}

inline Particle get_particle(Unpacker& u) {
  Particle q;
  u.get(q.id);
  u.get(q.position);
  u.get(q.velocity);
  u.get(q.angular_velocity);
  u.get(q.radius);
  u.get(q.material);
  u.get(q.force);
  u.get(q.torque);
  return q;
}

}  // namespace ppohdem::dem::fast
