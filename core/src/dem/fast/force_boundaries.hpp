#pragma once
// The force kernel's boundary pass (force_kernel.cpp): a particle's contacts with the scene's
// boundaries, in boundary order (a mesh object's several contacts in feature order: boundary.hpp
// FeatureContact), right after its pair contacts. A contact's spring is carried over from the
// particle's record of that boundary and feature at the last evaluation; a record that finds
// no contact ended (its stored energy is lost). Each contact writes a new record (force,
// point, spring, rolling torque), which the frictional kernels' sum pass adds to the particle
// (force_sums.hpp); the frictionless kernels add it here. Planar walls are evaluated inline
// with PlaneWall's formulas, other boundaries through their interface.
#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "force_pass.hpp"

namespace ppohdem::dem::fast {

/// A particle against a boundary: apart, touching (with a contact), or escaped through it.
enum class BoundaryTouch { kApart, kTouching, kEscaped };

/// Particle i of the first pass on its walk over the boundaries: its centre, radius and id, and
/// its records of the last evaluation not yet walked, [old, old_end) of s.records.
struct BoundaryWalk {
  std::size_t i;
  Vec3 x;
  double radius;
  std::int64_t id;
  std::uint32_t old;
  std::uint32_t old_end;
};

/// Whether the particle at x with radius r touches boundary b at time `time` or has escaped
/// through it. Touching: a wall's contact is `c`; another boundary's contacts are `several`
/// (Boundary::contacts: a mesh object gives one per touching face, edge or vertex).
template <class K>
inline BoundaryTouch touch_boundary(const FastState& s, std::size_t b, const Vec3& x, double r, double time,
                                    BoundaryContact& c, std::vector<FeatureContact>& several) {
  if (K::kWalls && s.is_wall[b]) {
    const WallData& wall = s.walls[b];
    const double distance = PlaneWall::signed_distance(wall.point, wall.normal, x);
    if (distance <= 0.0) return BoundaryTouch::kEscaped;
    if (distance < r) {
      c = PlaneWall::touching(wall.normal, wall.velocity, x, r, distance);
      return BoundaryTouch::kTouching;
    }
  } else if constexpr (K::kOthers) {
    if (s.reach[b].excludes(x, r)) return BoundaryTouch::kApart;  // far: nothing to evaluate
    const Boundary& boundary = *s.boundaries[b];
    if (boundary.has_escaped(x, time)) return BoundaryTouch::kEscaped;
    boundary.contacts(x, r, time, several);
    if (!several.empty()) return BoundaryTouch::kTouching;
  }
  return BoundaryTouch::kApart;
}

/// The particle's contact c with feature `feature` of boundary b: counted, offered as the
/// deepest, kinematics, the law (with the spring of its record of (b, feature), if the walk is
/// there; its records before that ended), the new record, and the particle's energy terms.
template <class K>
inline void boundary_contact(const K& kernel, RangePass& pass, BoundaryWalk& walk, std::size_t b,
                             const BoundaryContact& c, std::uint32_t feature, ParticleSums& sums) {
  FastState& s = pass.s;
  if constexpr (K::kFriction) {
    for (; walk.old < walk.old_end && record_key(s.records[walk.old]) < record_key(b, feature); ++walk.old) {
      if constexpr (K::kEnergy) sums.dissipated += s.records[walk.old].spring.stored_energy();  // ended
    }
  }
  ++pass.touching_boundaries;
  std::optional<LargestOverlap>& deepest = pass.out.deepest;
  if (!deepest || c.overlap / walk.radius >= deepest->ratio) {
    keep_deeper(deepest, LargestOverlap{c.overlap / walk.radius, c.overlap, walk.id, static_cast<std::int64_t>(b), true});
  }
  const std::size_t i = walk.i;
  const double dt = pass.dt;
  ContactKinematics k;
  k.normal = c.normal;
  k.overlap = c.overlap;
  const Vec3 r_a = c.point - walk.x;
  k.relative_velocity = s.pv[i] + s.pw[i].cross(r_a) - c.surface_velocity;
  k.pair.m_eff = s.mass[i];
  k.pair.r_eff = walk.radius;
  BoundaryRecord record;
  record.particle = static_cast<std::uint32_t>(i);
  record.boundary = static_cast<std::uint32_t>(b);
  record.feature = feature;
  ContactForce f;
  if constexpr (K::kFriction) {
    const bool continuing = walk.old < walk.old_end && record_key(s.records[walk.old]) == record_key(b, feature);
    if (continuing) record.spring = s.records[walk.old++].spring;
    TangentialSpring& sp = record.spring;
    // Trapezoid surface displacement (contact_force.hpp "Moving boundaries").
    const Vec3 v_s = boundary_step_velocity(sp, continuing, c.surface_velocity);
    k.relative_displacement = dt * (s.v[i] + s.w[i].cross(r_a) - v_s);
    if constexpr (K::kEnergy) k.relative_displacement_previous_arms = dt * (s.v[i] + s.w[i].cross(sp.branch_i) - v_s);
    if (s.rolling) {  // the boundary's spin is that of its material
      k.relative_spin = s.pw[i] - c.surface_spin;
      k.relative_rotation = dt * (s.w[i] - c.surface_spin);
    }
    f = frictional_contact_force(kernel.boundary_law(s, i, b), k, sp, dt);
    sp.branch_i = r_a;
    record.rolling = f.rolling_torque;
  } else {
    f = normal_contact_force(kernel.boundary_law(s, i, b), k, dt);
  }
  if constexpr (!K::kHalf) {  // else added after the pairs by the sum pass
    sums.force += f.on_i;
    sums.torque += r_a.cross(f.on_i);
  }
  if constexpr (K::kEnergy) {
    sums.elastic += f.elastic_energy;
    sums.dissipated += f.dissipated;
    // Boundary work: the dashpot's share now, the rest by the trapezoid rule of the power
    // P = (F - F_d) . v_s (reduced in the engine) [J], [W].
    sums.work += f.dashpot.dot(c.surface_velocity) * dt;
    sums.power += (f.on_i - f.dashpot).dot(c.surface_velocity);
  }
  record.force = f.on_i;
  record.point = c.point;
  pass.out.records.push_back(record);
}

/// Boundary b for the walking particle: its records of boundaries before b ended; then an
/// escape (noted once per particle), no contact, or its contacts in feature order.
template <class K>
inline void visit_boundary(const K& kernel, RangePass& pass, BoundaryWalk& walk, std::size_t b, ParticleSums& sums) {
  FastState& s = pass.s;
  if constexpr (K::kFriction) {
    for (; walk.old < walk.old_end && s.records[walk.old].boundary < b; ++walk.old) {
      if constexpr (K::kEnergy) sums.dissipated += s.records[walk.old].spring.stored_energy();  // ended
    }
  }
  BoundaryContact c;
  std::vector<FeatureContact>& several = pass.out.touching;
  const BoundaryTouch touch = touch_boundary<K>(s, b, walk.x, walk.radius, pass.time, c, several);
  if (touch == BoundaryTouch::kEscaped) {
    if (s.escaped_via[walk.i] == 0) {
      s.escaped_via[walk.i] = static_cast<std::int32_t>(b + 1);
      pass.out.newly_escaped.push_back(static_cast<std::uint32_t>(walk.i));
    }
    return;
  }
  if (touch == BoundaryTouch::kApart) return;
  if (K::kWalls && s.is_wall[b]) {
    boundary_contact(kernel, pass, walk, b, c, 0u, sums);
  } else {
    for (const FeatureContact& f : several) boundary_contact(kernel, pass, walk, b, f.contact, f.feature, sums);
  }
}

/// Particle i's energy terms of this evaluation (kEnergy): its elastic energy kept for the
/// state's sum (summed only when asked), its three rates added to the range's exact sums
/// (the dissipation through the range's buffer), the step's only pass over them (docs/dem.md
/// "Energy book-keeping"). A dissipation of +-0 (a particle that touches nothing) is written
/// but not kept (the count advances by 0 or 1, no branch: whether a particle touches is a
/// coin toss in an impact); the boundary rates are added only by a particle that has them.
inline void store_terms(RangePass& pass, std::size_t i, const ParticleSums& sums) {
  pass.s.terms[i].elastic = sums.elastic;
  ThreadOutput& out = pass.out;
  out.dissipation_buffer[out.buffered] = sums.dissipated;
  out.buffered += static_cast<std::size_t>((std::bit_cast<std::uint64_t>(sums.dissipated) << 1) != 0);
  if (out.buffered == out.dissipation_buffer.size()) out.add_dissipation_buffer();
  if (((std::bit_cast<std::uint64_t>(sums.work) | std::bit_cast<std::uint64_t>(sums.power)) << 1) != 0) {
    out.rates[1].add(sums.work);
    out.rates[2].add(sums.power);
  }
}

/// Particle i's boundary contacts in boundary order, then its stores: force and torque (the
/// frictionless kernels; the frictional ones store them after their sum pass), its energy
/// terms (kEnergy; else they keep their zeros) and the end of its block of new records.
template <class K>
inline void boundaries_and_stores(const K& kernel, RangePass& pass, std::size_t i, ParticleSums& sums) {
  FastState& s = pass.s;
  if constexpr (K::kRecords) {
    BoundaryWalk walk{i, s.x[i], s.radius[i], s.id[i], s.record_first[i], s.record_first[i + 1]};
    // A fixed wall farther than R + skin at the list build is neither touched nor crossed
    // before the next build (near_boundaries): nothing to evaluate, so only the set bits of
    // the first 32 boundaries are visited (most particles of a bed have none: no loop over the
    // boundaries, whose exits mispredicted once per particle). A record of a skipped boundary
    // (impossible then) would still end at the next one, as untouched.
    std::uint32_t near = s.near_boundaries[i] & pass.near_mask;
    for (; near != 0; near &= near - 1u) visit_boundary(kernel, pass, walk, static_cast<std::size_t>(std::countr_zero(near)), sums);
    for (std::size_t b = 32; b < pass.boundaries; ++b) visit_boundary(kernel, pass, walk, b, sums);
    if constexpr (K::kFriction) {
      for (; walk.old < walk.old_end; ++walk.old) {
        if constexpr (K::kEnergy) sums.dissipated += s.records[walk.old].spring.stored_energy();
      }
    }
  }
  if constexpr (!K::kHalf) {
    s.f[i] = sums.force;
    s.t[i] = sums.torque;
  }
  if constexpr (K::kEnergy) store_terms(pass, i, sums);
  if constexpr (K::kRecords) s.next_record_first[i + 1] = static_cast<std::uint32_t>(pass.out.records.size());
}

}  // namespace ppohdem::dem::fast
