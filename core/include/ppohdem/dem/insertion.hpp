#pragma once
/// \file insertion.hpp
/// Particle insertion (scene tables [[insert]], docs/objects.md "Particle insertion"): at
/// scheduled steps, new spheres are drawn in a region (a box or a cylinder), with a size
/// distribution and an initial velocity, and kept only if they overlap no particle, wall or
/// object; LIGGGHTS' `fix insert/pack` and `insert/rate/region` are the models.
///
/// Determinism: an insertion event is a pure function of the spec, its counters
/// (InsertCounters) and the WHOLE system's particles, of which it needs the largest id and
/// radius and the particles near its region (insert_reach); every rank gets those
/// (DemEngine::particle_extent and particles_in are collective), so every rank draws and tests
/// the same candidates in the same order and accepts the same ones; the engines append them in candidate order with new ids
/// after the largest id so far. Random numbers: SplitMix64 (Steele, Lea & Flood 2014) of
/// (seed, counter), mapped to doubles by their top 53 bits (no library distribution, whose
/// algorithm is implementation-defined); the counter is the whole generator state.
///
/// Candidate k of an event uses 4 draws: u0 picks the size (and material), u1..u3 the
/// centre, uniformly among the centres whose WHOLE sphere lies in the region. It is rejected
/// if it comes closer than (1 + kInsertGap) (R_a + R_b) to a particle (existing or accepted
/// earlier in the event), within (1 + kInsertGap) R of a plane wall, or if an object's
/// field (and its mesh, with exact contacts) gives a contact with the sphere of radius
/// (1 + kInsertGap) R. A rejected candidate is drawn again, up to `attempts` times; then it
/// counts as failed (not carried to the next event).
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "ppohdem/dem/boundary.hpp"
#include "ppohdem/dem/particle.hpp"

namespace ppohdem::dem {

/// Relative gap kept between an inserted sphere and everything else: the engines' contact
/// tests then see no overlap whatever the rounding of a distance (~1e-16 relative); 1e-9 R
/// is no physical change.
inline constexpr double kInsertGap = 1e-9;

struct InsertRegion {
  enum class Kind { kBox, kCylinder };
  Kind kind = Kind::kBox;
  Vec3 lo = Vec3::Zero();  ///< box: lower corner [m]
  Vec3 hi = Vec3::Zero();  ///< box: upper corner [m]
  Vec3 point = Vec3::Zero();   ///< cylinder: centre of its base disc [m]
  Vec3 axis = Vec3::UnitZ();   ///< cylinder: unit axis, from the base into the cylinder
  double radius = 0.0;         ///< cylinder radius [m]
  double length = 0.0;         ///< cylinder length along the axis [m]

  /// The centre of candidate (u1, u2, u3) in [0,1)^3 of radius r: uniform over the centres
  /// whose sphere lies in the region (the region shrunk by r).
  Vec3 centre(double u1, double u2, double u3, double r) const;
  /// True if the sphere lies in the region (the oracle of the tests; 1e-12 m of slack for
  /// the rounding of centre()).
  bool holds(const Vec3& centre, double r) const;
  /// Whether a sphere of radius r fits at all.
  bool fits(double r) const;
  double volume() const;  ///< [m^3]
};

/// One entry of a discrete size distribution (LIGGGHTS' particledistribution/discrete).
struct InsertSize {
  double radius = 0.0;       ///< [m]
  double probability = 0.0;  ///< by number; the entries sum to 1
  std::uint16_t material = 0;  ///< index into the scene's materials
};

struct InsertSizes {
  enum class Kind { kConstant, kUniform, kDiscrete };
  Kind kind = Kind::kConstant;
  double r_min = 0.0;  ///< constant: the radius; uniform: the interval [r_min, r_max] [m]
  double r_max = 0.0;
  std::uint16_t material = 0;        ///< constant and uniform
  std::vector<InsertSize> entries;   ///< discrete
  /// Radius and material of u in [0, 1): constant r_min; uniform r_min + u (r_max - r_min);
  /// discrete the first entry whose cumulative probability exceeds u (the last one else).
  std::pair<double, std::uint16_t> draw(double u) const;
  double largest() const;   ///< [m]
  double smallest() const;  ///< [m]
};

/// When and how many: events at steps first_step + k every_steps (k = 0, 1, ...; a single
/// event if every_steps = 0) up to last_step. Per event either `count`, or with a rate the
/// particles due over the event's interval: floor(rate (k+1) every dt + 1e-9) minus the same
/// for k (1e-9: a count that is an integer in exact arithmetic is not lost to rounding).
/// `total` caps the particles asked for over all events.
struct InsertSchedule {
  long first_step = 0;
  long every_steps = 0;
  long last_step = std::numeric_limits<long>::max();
  long count = 0;     ///< per event (count mode)
  double rate = 0.0;  ///< [particles/s] (rate mode, if > 0)
  long total = -1;    ///< -1: no cap
  /// The step of event k.
  long step_of(std::uint64_t k) const { return first_step + static_cast<long>(k) * every_steps; }
  /// Whether event k exists (within last_step; a single event: k = 0 only).
  bool has_event(std::uint64_t k) const;
  /// Particles asked for at event k, `requested_so_far` before it (dt [s] for a rate).
  long wanted(std::uint64_t k, long requested_so_far, double dt) const;
};

struct InsertSpec {
  std::string name;  ///< "insert N" (for messages and insertions.csv)
  InsertRegion region;
  InsertSizes sizes;
  InsertSchedule schedule;
  Vec3 velocity = Vec3::Zero();          ///< initial velocity [m/s]
  Vec3 angular_velocity = Vec3::Zero();  ///< initial angular velocity [rad/s]
  std::uint64_t seed = 1;
  long attempts = 100;  ///< draws per particle before it counts as failed
};

/// The counters of one [[insert]] (checkpointed: a restart continues them).
struct InsertCounters {
  std::uint64_t events = 0;     ///< events done
  std::uint64_t draws = 0;      ///< random numbers used (the generator's state)
  std::int64_t requested = 0;   ///< particles asked for so far
  std::int64_t inserted = 0;
  std::int64_t failed = 0;
};

/// What a checkpoint keeps of the insertions (checkpoint.hpp): each [[insert]]'s counters,
/// the energy the particles inserted after step 0 brought in (the run's energy check adds it
/// to the initial energy) and the insertions.csv rows so far.
struct InsertionRecord {
  std::vector<InsertCounters> counters;
  double kinetic = 0.0;        ///< [J]
  double rotational = 0.0;     ///< [J]
  double gravitational = 0.0;  ///< [J]
  std::vector<std::string> rows;
};

/// The u-th random double in [0, 1) of stream `seed`: SplitMix64 of seed + (u + 1) gamma,
/// top 53 bits.
double insert_uniform(std::uint64_t seed, std::uint64_t u);

/// The box of centres [lo, hi] an event of `spec` can touch, `largest_radius` [m] being the
/// largest radius of the particles present: the region's bounding box grown by the largest new
/// plus the largest present radius (and the gap). Larger for a larger `largest_radius`.
std::pair<Vec3, Vec3> insert_reach(const InsertSpec& spec, double largest_radius);

/// The side of the cells over the box [lo, hi] that an event's overlap test files particles
/// in [m]: at least `reach` (two particles that can touch lie in adjacent cells), and large
/// enough that the box holds at most 2^22 cells (a table of 16 MiB), thin boxes included.
double insert_cell_side(const Vec3& lo, const Vec3& hi, double reach);

/// One event: `wanted` candidates against `existing` (the whole system) and `boundaries` at
/// `time`; accepted particles get ids next_id, next_id + 1, ... (next_id is advanced), zero
/// force. Counters advance (draws, inserted, failed; not events or requested).
Particles insert_event(const InsertSpec& spec, long wanted, InsertCounters& counters, const Particles& existing,
                       const BoundaryList& boundaries, double time, std::int64_t& next_id);
/// The same event from a part of the system: `nearby` holds at least every particle whose
/// centre lies in insert_reach(spec, largest_radius) (others are ignored), and
/// `largest_radius` is the largest radius of the whole system [m]. The same particles and
/// counters as from the whole system, which is what the run's ranks use instead of gathering
/// it (insertion_run.cpp).
Particles insert_event(const InsertSpec& spec, long wanted, InsertCounters& counters, const Particles& nearby,
                       double largest_radius, const BoundaryList& boundaries, double time, std::int64_t& next_id);

/// One particle per size extreme and material of the specs (positions far apart), for the
/// time-step limit of a scene whose particles are still to come.
Particles insert_size_probes(const std::vector<InsertSpec>& specs);

}  // namespace ppohdem::dem
