// The migrate plan: which rank owns each particle (the brick of its position), and the move
// of particles with their histories to it (docs/dem.md "Domain decomposition").
#include "engine_impl.hpp"

namespace ppohdem::dem::fast {

void FastEngine::Impl::load_particles(const Particles& particles) {
  auto& q = s;
  kick_cached = false;
  motion_valid = false;
  for_each_particle_array(q, [](auto& a) { a.clear(); });
  total = particles.size();
  r_max = 0.0;
  const int me = comm->rank();
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const Particle& p = particles[i];
    r_max = std::max(r_max, p.radius);
    if (distributed() && decomposition.owner(p.position) != me) continue;
    q.id.push_back(p.id);
    q.original.push_back(static_cast<std::uint32_t>(i));
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
  const std::size_t n = q.id.size();
  q.owned = n;
  q.first.assign(n + 1, 0);
  q.partner.clear();
  q.mirror.clear();
  q.upper_first.clear();
  q.spring_of.clear();
  q.lower_codes_valid = false;
  q.spring_pools.clear();
  q.result_pools.clear();
  q.records.clear();
  q.record_first.assign(n + 1, 0);
  q.split_stale = true;
  halo_send.assign(static_cast<std::size_t>(comm->size()), {});
  halo_recv.assign(static_cast<std::size_t>(comm->size()), 0);
  out_valid = false;
}

void FastEngine::Impl::migrate(History& h) {
  const int me = comm->rank();
  std::vector<Bytes> to(static_cast<std::size_t>(comm->size()));
  std::vector<std::uint32_t> keep;
  History kept;
  for (std::size_t k = 0; k < s.owned; ++k) {
    const int dest = decomposition.owner(s.x[k]);
    if (dest == me) {
      keep.push_back(static_cast<std::uint32_t>(k));
      kept.append_from(h, k);
      continue;
    }
    Packer p(to[static_cast<std::size_t>(dest)]);
    pack_particle(p, s, k);
    h.pack(p, k);
  }
  const std::vector<Bytes> from = comm->exchange(to);
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
