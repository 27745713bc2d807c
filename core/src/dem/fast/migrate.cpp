// The migrate plan: which rank owns each particle (the brick of its position), and the move
// of particles with their histories to it (docs/dem.md "Domain decomposition").
#include "engine_impl.hpp"

namespace ppohdem::dem::fast {

void FastEngine::Impl::clear_particles() {
  kick_cached = false;
  drift_over_ranks.reset();
  energies_cache.reset();
  restored_elastic.reset();
  for_each_particle_array(s, [](auto& a) { a.clear(); });
}

void FastEngine::Impl::append_owned(const Particle& p, std::size_t original) {
  auto& q = s;
  q.id.push_back(p.id);
  q.original.push_back(static_cast<std::uint32_t>(original));
  q.x.push_back(p.position);
  q.v.push_back(p.velocity);
  q.w.push_back(p.angular_velocity);
  q.f.push_back(p.force);
  q.t.push_back(p.torque);
  q.pv.push_back(p.velocity);
  q.pw.push_back(p.angular_velocity);
  q.x_build.push_back(p.position);
  q.radius.push_back(p.radius);
  const Material& mat = materials[p.material];
  q.material.push_back(p.material);
  q.mass.push_back(mat.mass(p.radius));
  q.inertia.push_back(mat.moment_of_inertia(p.radius));
  q.escaped_via.push_back(0);
  q.terms.emplace_back();
}

void FastEngine::Impl::reset_lists() {
  auto& q = s;
  const std::size_t n = q.id.size();
  q.owned = n;
  q.first.assign(n + 1, 0);
  q.partner.clear();
  q.mirror.clear();
  q.upper_first.clear();
  q.lower_ghost.clear();
  q.spring_of.clear();
  q.lower_codes_valid = false;
  q.spring_pools.clear();
  q.result_pools.clear();
  q.records.clear();
  q.record_first.assign(n + 1, 0);
  q.split_stale = true;
  halo_send.assign(peers.size(), {});
  halo_recv.assign(peers.size(), 0);
  out_valid = false;
}

void FastEngine::Impl::load_particles(const Particles& particles) {
  clear_particles();
  total = particles.size();
  r_max = 0.0;
  for (const Particle& p : particles) r_max = std::max(r_max, p.radius);
  if (distributed()) decompose_whole(particles);
  const int me = comm->rank();
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const Particle& p = particles[i];
    if (distributed() && decomposition.owner(p.position, p.id) != me) continue;
    append_owned(p, i);
  }
  reset_lists();
}

void FastEngine::Impl::load_share(const Particles& particles, const ParticleShare& share) {
  History none;  // nothing carried yet
  place_share(particles, share, none);
  reset_lists();
}

void FastEngine::Impl::place_share(const Particles& particles, const ParticleShare& share, History& carried,
                                   const std::vector<std::uint8_t>* escaped_flags) {
  clear_particles();
  total = share.total;
  r_max = 0.0;
  for (const Particle& p : particles) r_max = std::max(r_max, p.radius);
  r_max = comm->max_over_ranks(r_max);  // exact: a maximum
  for (std::size_t i = 0; i < particles.size(); ++i) append_owned(particles[i], share.first + i);
  if (escaped_flags) s.escaped_via.assign(escaped_flags->begin(), escaped_flags->end());  // (only the warning uses the boundary)
  s.owned = s.id.size();
  decompose_owned();
  if (carried.first.size() != s.owned + 1) {  // nothing carried
    carried = History{};
    carried.first.assign(s.owned + 1, 0);
    carried.record_first.assign(s.owned + 1, 0);
  }
  migrate(carried, /*global=*/true);
}

void FastEngine::Impl::migrate(History& h, bool global) {
  const int me = comm->rank();
  std::vector<int> dest(s.owned);
  bool beyond_peers = false;  // a particle for a rank that is not a peer
  for (std::size_t k = 0; k < s.owned; ++k) {
    dest[k] = decomposition.owner(s.x[k], s.id[k]);
    if (dest[k] != me && !std::binary_search(peers.begin(), peers.end(), dest[k])) beyond_peers = true;
  }
  // Within a skin a particle moves far less than the halo reach, so its new owner is a peer;
  // a farther jump (or a re-cut) takes every rank, decided by all (docs/dem.md "Neighbour-only
  // exchanges").
  if (!global && comm->max_over_ranks(beyond_peers ? 1.0 : 0.0) > 0.0) {
    global = true;
    ++global_exchanges;
  }
  std::vector<int> partners = peers;
  if (global) {
    partners.clear();
    for (int r = 0; r < comm->size(); ++r) {
      if (r != me) partners.push_back(r);
    }
  }
  std::vector<int> slot(static_cast<std::size_t>(comm->size()), -1);  // rank -> index in partners
  for (std::size_t i = 0; i < partners.size(); ++i) slot[static_cast<std::size_t>(partners[i])] = static_cast<int>(i);
  std::vector<Bytes> to(partners.size());
  std::vector<std::uint32_t> keep;
  History kept;
  for (std::size_t k = 0; k < s.owned; ++k) {
    if (dest[k] == me) {
      keep.push_back(static_cast<std::uint32_t>(k));
      kept.append_from(h, k);
      continue;
    }
    Packer p(to[static_cast<std::size_t>(slot[static_cast<std::size_t>(dest[k])])]);
    pack_particle(p, s, k);
    h.pack(p, k);
  }
  const std::vector<Bytes> from = comm->exchange_with(partners, to);
  ++exchanges;
  for_each_particle_array(s, [&](auto& a) { permute(a, keep); });
  for (const Bytes& block : from) {
    Unpacker u(block);
    while (!u.done()) {
      unpack_particle(u, s);
      kept.unpack_append(u);
    }
  }
  s.owned = s.id.size();
  h = std::move(kept);
}

}  // namespace ppohdem::dem::fast
