#pragma once
/// \file engine.hpp
/// The DEM engine interface. The reference engine (ppohdem::dem::reference) and the later
/// optimized engine implement it; the typed contract tests in tests/dem run against every
/// implementation (STYLE.md habit 9).
///
/// Contract of step(), velocity Verlet (Allen & Tildesley 1987, sec. 3.2.1) for translation
/// and rotation of spheres (I = (2/5) m R^2; no orientation is kept, spheres are isotropic):
///   v(n+1/2) = v(n) + a(n) dt/2,            w(n+1/2) = w(n) + alpha(n) dt/2
///   x(n+1)   = x(n) + v(n+1/2) dt
///   forces at x(n+1), with the velocity-dependent parts (dashpot, tangential increment) using
///   v(n+1/2), w(n+1/2) and boundaries at time t(n+1)
///   v(n+1)   = v(n+1/2) + a(n+1) dt/2,      w(n+1) = w(n+1/2) + alpha(n+1) dt/2
/// with a = F/m + g, alpha = T/I. For constant acceleration this is exact (free fall).
/// Contacts are evaluated in (id_i, id_j) order so results do not depend on storage order.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ppohdem/dem/contact_force.hpp"
#include "ppohdem/dem/particle.hpp"
#include "ppohdem/dem/simulation_setup.hpp"
#include "ppohdem/error.hpp"

namespace ppohdem::dem {

/// Energies of the whole system [J]. With fixed boundaries
///   kinetic + rotational + gravitational + elastic + dissipated
/// is constant up to the integrator error; with moving boundaries subtract boundary_work.
struct Energies {
  double kinetic = 0.0;        ///< sum m v^2 / 2
  double rotational = 0.0;     ///< sum I w^2 / 2
  double gravitational = 0.0;  ///< sum -m g . x (zero at the origin)
  double elastic = 0.0;        ///< stored in normal and tangential contact springs
  double dissipated = 0.0;     ///< cumulative: dashpots, friction slip, broken springs,
                               ///< Mindlin stiffness change, frame change; each booked
                               ///< with Verlet's trapezoid rule (contact_force.hpp)
  double boundary_work = 0.0;  ///< cumulative work done on particles by moving boundaries
  double total() const { return kinetic + rotational + gravitational + elastic + dissipated - boundary_work; }
};

/// What the particles do to one boundary in the last force evaluation (the reaction: minus
/// the contact forces on the particles, applied at the contact points).
struct BoundaryLoad {
  Vec3 force = Vec3::Zero();                ///< F = -sum f_i  [N]
  Vec3 moment_about_origin = Vec3::Zero();  ///< M_0 = sum p_c x (-f_i)  [N m]
  /// Torque about point c: M_c = M_0 - c x F  [N m].
  Vec3 torque_about(const Vec3& c) const { return moment_about_origin - c.cross(force); }
};

struct ContactCounts {
  std::size_t particle_pairs = 0;     ///< touching particle pairs
  std::size_t particle_boundary = 0;  ///< particle-boundary contacts (a mesh object: one per touching feature)
};

/// The history of one frictional contact, keyed by global identities so that the record does
/// not depend on storage order or on the rank that owns the particles:
///   particle pair:     (id_a, id_b) = (smaller particle id, larger particle id)
///   particle-boundary: (id_a, id_b) = (particle id, index in SimulationSetup::boundaries)
/// For a boundary contact spring.branch_j is zero. Frictionless contacts keep no history.
struct ContactHistoryRecord {
  enum class Kind : std::uint8_t { kParticlePair = 0, kParticleBoundary = 1 };
  Kind kind = Kind::kParticlePair;
  std::int64_t id_a = 0;
  std::int64_t id_b = 0;
  TangentialSpring spring;
};

/// Everything an engine needs to continue a run exactly (checkpoint/restart, checkpoint.hpp),
/// in engine-neutral form. Contract:
///   - restore_state(save_state()) on an engine built from the same SimulationSetup, followed
///     by k steps, gives bitwise the same particles, energies, contact histories, loads and
///     counts as k more steps of the saving engine;
///   - particles in construction order (the order of particles()), whole system (an MPI
///     engine gathers), with force and torque of the last force evaluation;
///   - contacts sorted by (kind, id_a, id_b); escaped_ids sorted ascending.
struct EngineState {
  std::string engine;   ///< name() of the engine that saved it
  long step = 0;        ///< step_count()
  double dt = 0.0;      ///< time step [s] (restore refuses a different dt)
  Particles particles;  ///< positions, velocities, force/torque of the last evaluation
  std::vector<ContactHistoryRecord> contacts;
  Energies accumulators;  ///< elastic of the last evaluation; cumulative dissipated and
                          ///< boundary_work; kinetic, rotational, gravitational for checks
  std::vector<std::int64_t> escaped_ids;  ///< particles that crossed a boundary so far
  std::vector<BoundaryLoad> boundary_loads;  ///< boundary_loads() of the last evaluation
  ContactCounts contact_counts;              ///< contact_counts() of the last evaluation
  /// Power of the moving boundaries on the particles in the last evaluation without the
  /// dashpots' share, P(n), for the trapezoid rule of boundary_work (contact_force.hpp
  /// "Moving boundaries") [W]
  double boundary_power = 0.0;
  /// Engine-specific opaque bytes (e.g. an RNG state, a neighbour-list age); empty for the
  /// reference engine, which consumes no random numbers while stepping.
  std::vector<std::uint8_t> engine_private;
};

/// One rank's share of an EngineState, for checkpoints written per rank (checkpoint.hpp
/// "Parts"): `state` holds the fields that are the same on every rank (step, dt, accumulators,
/// loads, counts, power, private) and, in its three lists, this rank's share only: the
/// particles it owns, the contact histories it keeps (every record on exactly one rank) and
/// the escaped ids among its particles. The shares of all ranks, merged (particles placed by
/// `order`, the lists sorted), are save_state() exactly.
struct EngineStateShare {
  EngineState state;
  std::vector<std::uint64_t> order;  ///< construction index of each of state.particles
  std::uint64_t total = 0;           ///< the whole system's particle count
};

/// The deepest contact of the last force evaluation (run diagnostics, run.hpp).
struct LargestOverlap {
  double ratio = 0.0;      ///< overlap / smaller radius (boundary: / particle radius) [-]
  double overlap = 0.0;    ///< delta [m]
  std::int64_t id_a = 0;   ///< particle id
  std::int64_t id_b = 0;   ///< other particle id, or boundary index
  bool boundary = false;   ///< true: id_b is a boundary index
};

class DemEngine {
 public:
  virtual ~DemEngine() = default;
  virtual std::string name() const = 0;  ///< "reference", ...
  /// Advance by one time step dt (contract above).
  virtual void step() = 0;
  void advance(long steps) {
    for (long s = 0; s < steps; ++s) step();
  }
  virtual long step_count() const = 0;
  virtual double time() const = 0;  ///< [s] = step_count * dt
  /// Particles in the order given at construction; force/torque from the last evaluation.
  virtual const Particles& particles() const = 0;
  /// How many particles particles() holds (over all the ranks), without gathering them.
  virtual std::size_t particle_count() const { return particles().size(); }
  /// The particles this rank owns, in construction order: with several ranks (the fast
  /// engine's decomposition) a part of particles(), not collective (per-rank output pieces).
  virtual Particles owned_particles() const { return particles(); }
  /// This rank's consecutive part of particles() (construction order), as the ranks split
  /// the indices: rank r of P holds [first(r), first(r + 1)), first = even_part_first
  /// (simulation_setup.hpp). What a rank writes of a file in construction order (write_particles_csv
  /// with a Comm), without every rank holding particles(). Collective. Default: all of them.
  struct OrderedPart {
    Particles particles;
    std::size_t first = 0;  ///< construction index of particles[0]
    std::size_t total = 0;  ///< particles over all the ranks
  };
  virtual OrderedPart ordered_part() const { return {particles(), 0, particles().size()}; }
  virtual Energies energies() const = 0;
  /// A cheap screen for the per-step run checks (run_diagnostics.hpp): false if some
  /// position, velocity or angular velocity may not be finite (then the checks scan the
  /// particles). Default: the sum of the kinetic, rotational and gravitational energies is
  /// finite (it is not as soon as one of those values is not).
  virtual bool motion_finite() const {
    const Energies e = energies();
    return std::isfinite(e.kinetic + e.rotational + e.gravitational);
  }
  /// False if some particle's position, velocity, angular velocity, force or torque is not
  /// finite: the screen of the run's check at the start (run.cpp), which then scans
  /// particles() to name the particle. Collective. Default: that scan.
  virtual bool state_finite() const {
    for (const Particle& p : particles()) {
      if (!p.position.allFinite() || !p.velocity.allFinite() || !p.angular_velocity.allFinite() ||
          !p.force.allFinite() || !p.torque.allFinite()) {
        return false;
      }
    }
    return true;
  }
  virtual ContactCounts contact_counts() const = 0;
  /// Particles whose centre crossed a boundary (counted once each; they are then ignored by
  /// that boundary). A warning is printed on stderr the first time.
  virtual std::size_t escaped_count() const = 0;
  /// Loads on each boundary (same order as SimulationSetup::boundaries) from the last force
  /// evaluation; empty if the engine does not provide them.
  virtual std::vector<BoundaryLoad> boundary_loads() const { return {}; }

  /// Checkpoint/restart (EngineState above). Engines without support throw InputError.
  virtual EngineState save_state() const {
    throw InputError("engine '" + name() + "' does not support checkpoints (save_state)");
  }
  /// This rank's share of save_state() (EngineStateShare). Collective like save_state().
  /// Default: the whole state as the one share (an engine on one rank).
  virtual EngineStateShare save_state_share() const {
    EngineStateShare share{save_state(), {}, 0};
    share.total = share.state.particles.size();
    share.order.resize(share.state.particles.size());
    for (std::size_t i = 0; i < share.order.size(); ++i) share.order[i] = i;
    return share;
  }
  /// Continue from `state`; the engine must have been built from the same setup (same
  /// particle ids in the same order, same boundaries, same dt): throws InputError otherwise.
  virtual void restore_state(const EngineState& /*state*/) {
    throw InputError("engine '" + name() + "' does not support checkpoints (restore_state)");
  }
  /// Continue from a state spread over the ranks: `share` is this rank's (a checkpoint's parts
  /// it read, read_checkpoint_share), the shares of all ranks together the whole state, in any
  /// split. Collective; the same result and checks as restore_state of the merged state, with
  /// no rank holding it. `inserted`: the state's last particles (construction order) that
  /// [[insert]] events added after the engine's own, which are appended first, as
  /// insert_particles would (the same on every rank). Default: engines that run on one rank
  /// restore from checkpoint files.
  virtual void restore_state_share(const EngineStateShare& /*share*/, std::size_t /*inserted*/ = 0) {
    throw InputError("engine '" + name() + "' restores a checkpoint's parts only through restore_state");
  }
  /// Particle insertion (insertion.hpp): appends `added` after the existing particles (so
  /// particles() lists them last, in this order), with zero force and torque. The caller
  /// guarantees new ids and that they touch no particle and no boundary, so no force of the
  /// last evaluation changes. Several ranks: collective, the same `added` on every rank.
  /// Engines without support throw InputError.
  virtual void insert_particles(const Particles& /*added*/) {
    throw InputError("engine '" + name() + "' does not support particle insertion ([[insert]])");
  }
  /// What a particle insertion event needs of the system (insertion.hpp), without gathering
  /// it: the largest id and the largest radius over all the particles (0 and 0 m if there are
  /// none). Collective. Default: from particles().
  struct Extent {
    std::int64_t largest_id = 0;
    double largest_radius = 0.0;  ///< [m]
  };
  virtual Extent particle_extent() const {
    Extent e;
    for (const Particle& p : particles()) {
      e.largest_id = std::max(e.largest_id, p.id);
      e.largest_radius = std::max(e.largest_radius, p.radius);
    }
    return e;
  }
  /// An axis-aligned box [lo, hi] of centres [m] (closed: a centre on a face is in it).
  struct CentreBox {
    Vec3 lo = Vec3::Zero();
    Vec3 hi = Vec3::Zero();
    bool holds(const Vec3& x) const { return ((x.array() >= lo.array()) && (x.array() <= hi.array())).all(); }
  };
  /// The particles whose centre lies in at least one of `boxes`, in construction order, on
  /// every rank (an insertion event's neighbourhood). Collective; with several ranks only
  /// those particles travel. Default: filtered from particles().
  virtual Particles particles_in(const std::vector<CentreBox>& boxes) const {
    Particles in;
    for (const Particle& p : particles()) {
      if (std::any_of(boxes.begin(), boxes.end(), [&](const CentreBox& b) { return b.holds(p.position); })) in.push_back(p);
    }
    return in;
  }
  /// The deepest contact of the last force evaluation (ratio 0 if there is no contact), or
  /// nothing if the engine does not report it (the run diagnostics then check particle pairs
  /// themselves, by sort and sweep).
  virtual std::optional<LargestOverlap> largest_overlap() const { return std::nullopt; }
};

/// How applications make an engine without knowing its library (apps pick by name).
using EngineFactory = std::unique_ptr<DemEngine> (*)(const SimulationSetup&);

}  // namespace ppohdem::dem
