// Particle insertion in the fast engine (DemEngine::insert_particles; docs/objects.md
// "Particle insertion"). One rank: the new particles are appended to the owned ones and one
// list build carries every history over, as a build between two steps does (insert_in_place),
// with no reload of the whole state (docs/objects.md "Cost of an event"). Several ranks: each
// rank's share of the state, with the new particles appended in construction order, goes
// through the restart from shares, whose bitwise continuation is the checkpoints' contract,
// and which re-cuts the bricks over the new centres; no rank gathers the state. Either way the
// result is the reference engine's, bit for bit (InsertRun, InsertionMpi).
#include "engine_impl.hpp"

namespace ppohdem::dem::fast {

void FastEngine::insert_particles(const Particles& added) {
  if (added.empty()) return;
  Impl& m = *impl_;
  if (!m.distributed()) {
    m.insert_in_place(added);
    return;
  }
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

void FastEngine::Impl::insert_in_place(const Particles& added) {
  double r_added = 0.0;
  for (const Particle& p : added) {
    if (p.material >= materials.size()) throw InputError("insert_particles: material index out of range");
    r_added = std::max(r_added, p.radius);
  }
  // The last evaluation's boundary loads, summed from its records before the build moves
  // them, as a checkpoint holds them (the restart's path, fast_checkpoint.cpp).
  if (loads_stale) sum_loads();
  // The build's cell sort zeroes the particles' energy records (cell_sort.cpp): until the next
  // evaluation the stored elastic energy is the total before it, as after a restart.
  if (energy_balance) restored_elastic = sum_energies().elastic;
  History& h = history;
  take_history(h);  // the owned particles' histories and boundary records, by storage index
  const std::size_t before = total;
  for (std::size_t i = 0; i < added.size(); ++i) {
    Particle p = added[i];
    p.force.setZero();  // they touch nothing: zero force, the others' forces stand
    p.torque.setZero();
    append_owned(p, before + i);
  }
  h.first.resize(s.id.size() + 1, h.first.back());  // the new particles carry nothing
  h.record_first.resize(s.id.size() + 1, h.record_first.back());
  total = before + added.size();
  r_max = std::max(r_max, r_added);
  skin = std::max(skin, skin_fraction * r_max);  // the list's skin for the largest radius
  equal_bricks_made = false;
  // The next step's half kick from the forces (a new particle has no cached one), as after a
  // restart; the energies and the output are summed afresh.
  kick_cached = false;
  drift_over_ranks.reset();
  energies_cache.reset();
  out_valid = false;
  ++builds;
  reset_lists();
  build_from(h);
  add_lost_energy();  // none: nothing moved, and every pair with a history is listed again
}

}  // namespace ppohdem::dem::fast
