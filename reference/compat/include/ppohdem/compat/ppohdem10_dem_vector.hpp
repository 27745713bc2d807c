#pragma once
/// \file ppohdem10_dem_vector.hpp
/// The original DEM's 3-vector, `type(ppohDEM_rvec3)`, and its helper functions
/// (`add_rvec3`, `sub_rvec3`, `mulc_rvec3`, `dot_rvec3`, `cross_rvec3`, `length_rvec3`,
/// `normalize_rvec3`), written out component by component in the original's operand order.
///
/// Why not Eigen: bit-for-bit agreement with the original needs every sum evaluated in the
/// original's order, e.g. dot = (x1 x2 + y1 y2) + z1 z2, and `mulc` as c * v (not v * c; the
/// product is commutative in IEEE arithmetic, but keeping the text identical makes the
/// transcription checkable line by line). Eigen may reorder reductions when it vectorises.
/// The sources using these are compiled with -ffp-contract=off (no fused multiply-add), as the
/// original was (gfortran -O2 on x86-64 emits none).
#include <cmath>

namespace ppohdem::compat {

/// type(ppohDEM_rvec3): a position [m], velocity [m/s], force [N], ... in the original's units.
struct Rvec3 {
  double x = 0.0;
  double y = 0.0;
  double z = 0.0;
};

inline Rvec3 add_rvec3(const Rvec3& a, const Rvec3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Rvec3 sub_rvec3(const Rvec3& a, const Rvec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Rvec3 negative_rvec3(const Rvec3& a) { return {-a.x, -a.y, -a.z}; }
/// c * v, component by component.
inline Rvec3 mulc_rvec3(const Rvec3& v, double c) { return {c * v.x, c * v.y, c * v.z}; }
/// (x1 x2 + y1 y2) + z1 z2.
inline double dot_rvec3(const Rvec3& a, const Rvec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Rvec3 cross_rvec3(const Rvec3& a, const Rvec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
/// sqrt((x x + y y) + z z).
inline double length_rvec3(const Rvec3& a) { return std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z); }
/// v / |v| component by component (three divisions, not one reciprocal); the zero vector stays 0.
inline void normalize_rvec3(Rvec3& v) {
  const double length = length_rvec3(v);
  if (length == 0.0) {
    v = Rvec3{};
  } else {
    v.x = v.x / length;
    v.y = v.y / length;
    v.z = v.z / length;
  }
}

}  // namespace ppohdem::compat
