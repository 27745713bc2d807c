// Particle insertion in the fast engine (DemEngine::insert_particles; docs/objects.md
// "Particle insertion"): rare events, so the simplest exact way: the whole state, with the new
// particles appended in construction order, goes through restore_state, whose bitwise
// continuation is the checkpoints' contract.
#include "engine_impl.hpp"

namespace ppohdem::dem::fast {

void FastEngine::insert_particles(const Particles& added) {
  if (added.empty()) return;
  Impl& m = *impl_;
  EngineState state = save_state();  // whole system, on every rank (collective)
  for (Particle p : added) {
    if (p.material >= m.materials.size()) throw InputError("insert_particles: material index out of range");
    p.force.setZero();  // they touch nothing: zero force, the others' forces stand
    p.torque.setZero();
    state.particles.push_back(p);
  }
  // The bricks over all centres now (a fill starts from few or no particles): the reload
  // re-cuts them, and makes the equal bricks (balance off) over the new box too; no result
  // depends on them.
  m.equal_bricks_made = false;
  double r_max = 0.0;
  for (const Particle& p : state.particles) r_max = std::max(r_max, p.radius);
  m.skin = std::max(m.skin, m.skin_fraction * r_max);  // the list's skin for the largest radius
  m.out = state.particles;  // restore_state checks the state against particles(): these now
  m.out_valid = true;
  restore_state(state);
}

}  // namespace ppohdem::dem::fast
