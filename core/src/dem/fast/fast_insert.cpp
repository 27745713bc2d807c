// Particle insertion in the fast engine (DemEngine::insert_particles; docs/objects.md
// "Particle insertion"): rare events, so the simplest exact way: each rank's share of the
// state, with the new particles appended in construction order, goes through the restart from
// shares, whose bitwise continuation is the checkpoints' contract; no rank gathers the state.
#include "engine_impl.hpp"

namespace ppohdem::dem::fast {

void FastEngine::insert_particles(const Particles& added) {
  if (added.empty()) return;
  Impl& m = *impl_;
  EngineStateShare share = save_state_share();  // this rank's (collective, no gather)
  const std::size_t before = m.total;
  const auto ranks = static_cast<std::size_t>(m.comm->size()), me = static_cast<std::size_t>(m.comm->rank());
  for (std::size_t i = me; i < added.size(); i += ranks) {  // `added` is the same on every rank: each takes every P-th
    Particle p = added[i];
    p.force.setZero();  // they touch nothing: zero force, the others' forces stand
    p.torque.setZero();
    share.state.particles.push_back(p);
    share.order.push_back(before + i);
  }
  share.total = before + added.size();
  restore_state_share(share, added.size());  // a restart's path for inserted particles
}

}  // namespace ppohdem::dem::fast
