// Particle insertion in the fast engine (DemEngine::insert_particles; docs/objects.md
// "Particle insertion"): the new particles are appended to the owned ones (under mpirun each
// rank takes every P-th, and the bricks are cut again over all centres), then one list build
// carries every contact history over, as a build between two steps does. No rank reloads or
// gathers the state (docs/objects.md "Cost of an event"); the result is the reference
// engine's, bit for bit (InsertRun, InsertionMpi).
#include "engine_impl.hpp"

namespace ppohdem::dem::fast {

void FastEngine::insert_particles(const Particles& added) {
  if (added.empty()) return;
  impl_->insert_in_place(added);
}

void FastEngine::Impl::insert_in_place(const Particles& added) {
  // `added` is the same on every rank, so every rank throws alike.
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
  for_each_particle_array(s, [&](auto& a) { a.resize(s.owned); });  // drop the ghosts
  const std::size_t before = total;
  const auto ranks = static_cast<std::size_t>(comm->size()), me = static_cast<std::size_t>(comm->rank());
  for (std::size_t i = me; i < added.size(); i += ranks) {
    Particle p = added[i];
    p.force.setZero();  // they touch nothing: zero force, the others' forces stand
    p.torque.setZero();
    append_owned(p, before + i);
  }
  s.owned = s.id.size();
  h.first.resize(s.owned + 1, h.first.back());  // the new particles carry nothing
  h.record_first.resize(s.owned + 1, h.record_first.back());
  total = before + added.size();
  r_max = std::max(r_max, r_added);
  skin = std::max(skin, skin_fraction * r_max);  // the list's skin for the largest radius
  // The next step's half kick from the forces (a new particle has no cached one), as after a
  // restart; the energies and the output are summed afresh.
  kick_cached = false;
  drift_over_ranks.reset();
  energies_cache.reset();
  out_valid = false;
  ++builds;
  if (distributed()) {
    // A fill may start from few or no particles: the bricks over the new centres (the equal
    // ones too), and every particle to its brick, wherever it lies.
    equal_bricks_made = false;
    decompose_owned();
    migrate(h, /*global=*/true);
  }
  reset_lists();
  build_from(h);
  add_lost_energy();  // none: nothing moved, and every pair with a history is listed again
}

}  // namespace ppohdem::dem::fast
