// Particle insertion in the fast engine (DemEngine::insert_particles; docs/objects.md
// "Particle insertion"): rare events, so the simplest exact way: each rank's share of the
// state, with the new particles appended in construction order, goes through the restart from
// shares, whose bitwise continuation is the checkpoints' contract; no rank gathers the state.
#include "engine_impl.hpp"

namespace ppohdem::dem::fast {

void FastEngine::insert_particles(const Particles& added) {
  if (added.empty()) return;
  Impl& m = *impl_;
  for (const Particle& p : added) {
    if (p.material >= m.materials.size()) throw InputError("insert_particles: material index out of range");
  }
  EngineStateShare share = save_state_share();  // this rank's (collective, no gather)
  const std::size_t before = m.total;
  const auto ranks = static_cast<std::size_t>(m.comm->size()), me = static_cast<std::size_t>(m.comm->rank());
  double r_max = 0.0;
  for (const Particle& p : share.state.particles) r_max = std::max(r_max, p.radius);
  for (std::size_t i = 0; i < added.size(); ++i) {  // `added` is the same on every rank: each takes every P-th
    r_max = std::max(r_max, added[i].radius);
    if (i % ranks != me) continue;
    Particle p = added[i];
    p.force.setZero();  // they touch nothing: zero force, the others' forces stand
    p.torque.setZero();
    share.state.particles.push_back(p);
    share.order.push_back(before + i);
  }
  share.total = before + added.size();
  prepare_for_inserted(m, m.comm->max_over_ranks(r_max));
  restore_shares(m, share, before);
}

void prepare_for_inserted(FastEngine::Impl& m, double largest_radius) {
  // The bricks over all centres now (a fill starts from few or no particles): the reload
  // re-cuts them, and makes the equal bricks (balance off) over the new box too; no result
  // depends on them.
  m.equal_bricks_made = false;
  m.skin = std::max(m.skin, m.skin_fraction * largest_radius);  // the list's skin for the largest radius
}

}  // namespace ppohdem::dem::fast
