// The reference DEM engine: one time step, as a lecture (docs/dem.md).
//
// Equations of motion of sphere i (mass m_i = rho (4/3) pi R_i^3 [kg], moment of inertia
// I_i = (2/5) m_i R_i^2 [kg m^2]):
//   m_i dv_i/dt = sum_c F_c + m_i g              [N]
//   I_i dw_i/dt = sum_c (r_c x F_c + M_c)        [N m]   (M_c: rolling resistance only)
// Integrated with velocity Verlet (Allen & Tildesley, "Computer Simulation of Liquids", 1987,
// sec. 3.2.1; second order, time-reversible for conservative forces):
//   v(n+1/2) = v(n) + a(n) dt/2          half kick                  [m/s]
//   x(n+1)   = x(n) + v(n+1/2) dt        drift                      [m]
//   a(n+1)   = F(x(n+1), ...) / m        forces (force_passes.hpp)  [m/s^2]
//   v(n+1)   = v(n+1/2) + a(n+1) dt/2    second half kick           [m/s]
// The dashpots need a velocity at t(n+1), which Verlet does not have yet: they use the
// prediction v(n+1/2) + a(n) dt/2 (contact_force.hpp explains why this keeps the energy book
// second order). Spins follow the same scheme with torque / I (spheres: I is isotropic).
// Energies [J]: kinetic m|v|^2/2, rotational I|w|^2/2, gravitational -m g.x, plus the
// contacts' elastic, dissipated and boundary work (contact_force.hpp, "Energy book-keeping").
#include "ppohdem/dem/reference/reference_engine.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <string>

#include "force_passes.hpp"
#include "ppohdem/dem/exact_sum.hpp"

namespace ppohdem::dem::reference {

namespace {

// Choose the kernels once, from the scene: law x {frictionless, frictional}; frictional if
// any pair of materials has friction (pair_laws.hpp).
template <class Law>
std::unique_ptr<ForcePass> make_pair_pass(const ppohdem::dem::PairLaws<Law>& laws) {
  if (laws.any_friction()) return std::make_unique<PairForces<Law, true>>(laws);
  return std::make_unique<PairForces<Law, false>>(laws);
}

template <class Law>
std::unique_ptr<ForcePass> make_boundary_pass(const ppohdem::dem::PairLaws<Law>& laws,
                                              const ppohdem::dem::BoundaryList& b) {
  if (b.empty()) return nullptr;  // no wall code without walls
  if (laws.any_friction()) return std::make_unique<BoundaryForces<Law, true>>(laws, b);
  return std::make_unique<BoundaryForces<Law, false>>(laws, b);
}

}  // namespace

ReferenceEngine::ReferenceEngine(const SimulationSetup& setup)
    : particles_(setup.particles), dt_(setup.dt), gravity_(setup.gravity),
      boundary_count_(setup.boundaries.size()), energy_balance_(setup.energy_balance) {
  ppohdem::dem::validate_setup(setup);
  for (std::size_t k = 0; k < setup.material_count(); ++k) materials_.push_back(setup.material_at(k));
  for (const Particle& p : particles_) {
    const ppohdem::dem::Material& material = setup.material_at(p.material);
    mass_.push_back(material.mass(p.radius));
    inertia_.push_back(material.moment_of_inertia(p.radius));
    predicted_velocity_.push_back(p.velocity);
    predicted_angular_velocity_.push_back(p.angular_velocity);
  }
  std::visit(
      [&](const auto& law) {
        const ppohdem::dem::PairLaws laws(setup, law);  // the law of each pair of materials
        pair_pass_ = make_pair_pass(laws);
        boundary_pass_ = make_boundary_pass(laws, setup.boundaries);
      },
      setup.law);
  evaluate_forces(0.0);  // a(0); no history increment at start-up
}

ReferenceEngine::~ReferenceEngine() = default;

std::unique_ptr<ppohdem::dem::DemEngine> ReferenceEngine::make(const SimulationSetup& setup) {
  return std::make_unique<ReferenceEngine>(setup);
}

void ReferenceEngine::evaluate_forces(double history_dt) {
  for (Particle& p : particles_) {
    p.force.setZero();
    p.torque.setZero();
  }
  ForceContext context{particles_, predicted_velocity_, predicted_angular_velocity_, mass_, time(),
                       history_dt, {}, {}, {}};
  pair_pass_->add_forces(context);
  if (boundary_pass_) boundary_pass_->add_forces(context);
  if (energy_balance_) {  // else not tracked (SimulationSetup::energy_balance): zero, reported NaN
    elastic_ = context.elastic.value();
    dissipated_ += context.dissipated.value();
    boundary_work_ += context.boundary_work.value();
  }
  deepest_ = context.deepest.value_or(ppohdem::dem::LargestOverlap{});  // ratio 0: no contact
}

void ReferenceEngine::step() {
  const double half = 0.5 * dt_;
  // Half kick and drift: v(n+1/2) = v(n) + a(n) dt/2, x(n+1) = x(n) + v(n+1/2) dt.
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    Particle& p = particles_[i];
    const Vec3 kick = half * (p.force / mass_[i] + gravity_);
    const Vec3 spin_kick = half * p.torque / inertia_[i];
    p.velocity += kick;
    p.angular_velocity += spin_kick;
    p.position += dt_ * p.velocity;
    // Prediction of v(n+1) for the dashpots: v(n+1/2) + a(n) dt/2.
    predicted_velocity_[i] = p.velocity + kick;
    predicted_angular_velocity_[i] = p.angular_velocity + spin_kick;
  }
  ++steps_;
  // Forces at x(n+1), t(n+1); springs advance with the half-step velocities, dashpots use the
  // predicted v(n+1).
  evaluate_forces(dt_);
  // Second half kick: v(n+1) = v(n+1/2) + a(n+1) dt/2.
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    Particle& p = particles_[i];
    p.velocity += half * (p.force / mass_[i] + gravity_);
    p.angular_velocity += half * p.torque / inertia_[i];
  }
}

Energies ReferenceEngine::energies() const {
  // Sums over the particles, exact and rounded once to the nearest double (exact_sum.hpp:
  // Kulisch's long accumulator), so the value does not depend on the order of the terms and
  // the parallel fast engine gives the same bits [J].
  ppohdem::dem::ExactSums<3> total;
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    const Particle& p = particles_[i];
    total.add({0.5 * mass_[i] * p.velocity.squaredNorm(),          // m |v|^2 / 2
               0.5 * inertia_[i] * p.angular_velocity.squaredNorm(),  // I |w|^2 / 2
               -(mass_[i] * gravity_.dot(p.position))});              // -m g . x
  }
  const std::array<double, 3> sums = total.values();
  Energies e;
  e.kinetic = sums[0];
  e.rotational = sums[1];
  e.gravitational = sums[2];
  e.elastic = elastic_;
  e.dissipated = dissipated_;
  e.boundary_work = boundary_work_;
  if (!energy_balance_) e.elastic = e.dissipated = e.boundary_work = std::numeric_limits<double>::quiet_NaN();
  return e;
}

ContactCounts ReferenceEngine::contact_counts() const {
  ContactCounts c;
  c.particle_pairs = pair_pass_->active_contacts();
  c.particle_boundary = boundary_pass_ ? boundary_pass_->active_contacts() : 0;
  return c;
}

std::size_t ReferenceEngine::escaped_count() const {
  return boundary_pass_ ? boundary_pass_->escaped() : 0;
}

std::vector<ppohdem::dem::BoundaryLoad> ReferenceEngine::boundary_loads() const {
  return boundary_pass_ ? boundary_pass_->loads() : std::vector<ppohdem::dem::BoundaryLoad>{};
}

std::optional<ppohdem::dem::LargestOverlap> ReferenceEngine::largest_overlap() const { return deepest_; }

void ReferenceEngine::insert_particles(const Particles& added) {
  // They touch nothing (the caller's promise), so the last evaluation's forces stand and
  // theirs are zero: a(n) = g for the next half kick.
  for (Particle p : added) {
    if (p.material >= materials_.size()) throw InputError("insert_particles: material index out of range");
    p.force.setZero();
    p.torque.setZero();
    const ppohdem::dem::Material& material = materials_[p.material];
    mass_.push_back(material.mass(p.radius));
    inertia_.push_back(material.moment_of_inertia(p.radius));
    predicted_velocity_.push_back(p.velocity);
    predicted_angular_velocity_.push_back(p.angular_velocity);
    particles_.push_back(p);
  }
}

EngineState ReferenceEngine::save_state() const {
  EngineState state;
  state.engine = name();
  state.step = steps_;
  state.dt = dt_;
  state.particles = particles_;
  state.accumulators = energies();
  pair_pass_->save(state);  // pair histories first: contacts sorted by (kind, id_a, id_b)
  if (boundary_pass_) boundary_pass_->save(state);
  return state;
}

void ReferenceEngine::restore_state(const EngineState& state) {
  // Refuse a state that does not belong to this setup, naming the first difference.
  if (state.dt != dt_) {
    throw InputError("checkpoint: dt " + std::to_string(state.dt) + " s, the scene has dt " +
                     std::to_string(dt_) + " s");
  }
  if (state.particles.size() != particles_.size()) {
    throw InputError("checkpoint: " + std::to_string(state.particles.size()) +
                     " particles, the scene has " + std::to_string(particles_.size()));
  }
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    if (state.particles[i].id != particles_[i].id || state.particles[i].radius != particles_[i].radius ||
        state.particles[i].material != particles_[i].material) {
      throw InputError("checkpoint: particle " + std::to_string(i) + " has id " +
                       std::to_string(state.particles[i].id) + ", the scene has id " +
                       std::to_string(particles_[i].id) + " (or a different radius or material)");
    }
  }
  if (state.boundary_loads.size() != boundary_count_) {
    throw InputError("checkpoint: " + std::to_string(state.boundary_loads.size()) +
                     " boundaries, the scene has " + std::to_string(boundary_count_));
  }
  pair_pass_->restore(state);
  if (boundary_pass_) {
    boundary_pass_->restore(state);
  } else if (!state.escaped_ids.empty() ||
             std::any_of(state.contacts.begin(), state.contacts.end(), [](const auto& r) {
               return r.kind == ppohdem::dem::ContactHistoryRecord::Kind::kParticleBoundary;
             })) {
    throw InputError("checkpoint: boundary contacts or escaped particles, but the scene has no boundaries");
  }
  particles_ = state.particles;
  steps_ = state.step;
  elastic_ = state.accumulators.elastic;
  dissipated_ = state.accumulators.dissipated;
  boundary_work_ = state.accumulators.boundary_work;
  deepest_ = ppohdem::dem::LargestOverlap{};  // of the evaluation before the checkpoint: not saved
}

}  // namespace ppohdem::dem::reference
