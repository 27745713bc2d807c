// A restart from a checkpoint's parts spread over the ranks (FastEngine::restore_state_share;
// docs/formats.md "Checkpoints"): no rank ever holds the whole state. The particles
// go to the rank of their construction-index block, where they are checked against the scene's
// particles of that block; then to their bricks, each carrying its contact histories, which a
// list build installs.
#include "../checks_over_ranks.hpp"
#include "engine_impl.hpp"

namespace ppohdem::dem::fast {

namespace {

/// A checkpoint particle with what it carries, at the rank of its construction-index block.
struct Arrival {
  std::uint64_t original = 0;  ///< construction index
  Particle particle;
  std::uint8_t escaped = 0;
  std::vector<std::pair<std::int64_t, TangentialSpring>> pairs;   ///< (higher partner id, spring)
  std::vector<std::pair<std::int64_t, TangentialSpring>> walls;   ///< (boundary_history_key, spring)
};

/// Continues `m` from the ranks' shares of a state whose first `scene_particles` particles (in
/// construction order) are m's, checked against them, and any after them new. Collective.
void restore_shares(FastEngine::Impl& m, const EngineStateShare& share, std::size_t scene_particles);

}  // namespace

void FastEngine::restore_state_share(const EngineStateShare& share, std::size_t inserted) {
  Impl& m = *impl_;
  if (share.total != m.total + inserted) {
    throw InputError("checkpoint: " + std::to_string(share.total) + " particles, the scene has " + std::to_string(m.total) +
                     (inserted > 0 ? " and " + std::to_string(inserted) + " inserted" : std::string()));
  }
  if (inserted > 0) {  // particles the events of the run inserted after the scene's (a restart)
    double r_max = 0.0;
    bool unknown_material = false;
    for (std::size_t i = 0; i < share.state.particles.size(); ++i) {
      const Particle& p = share.state.particles[i];
      unknown_material = unknown_material || (share.order[i] >= m.total && p.material >= m.materials.size());
      r_max = std::max(r_max, p.radius);
    }
    if (m.comm->max_over_ranks(unknown_material ? 1.0 : 0.0) > 0.0) {  // every rank throws alike
      throw InputError("insert_particles: material index out of range");  // one rank's words
    }
    // The bricks over all centres now (a fill starts from few or no particles): the reload
    // re-cuts them, and makes the equal bricks (balance off) over the new box too; no result
    // depends on them. The list's skin for the largest radius.
    m.equal_bricks_made = false;
    m.skin = std::max(m.skin, m.skin_fraction * m.comm->max_over_ranks(r_max));
  }
  restore_shares(m, share, m.total);
}

namespace {

void restore_shares(FastEngine::Impl& m, const EngineStateShare& share, std::size_t scene_particles) {
  FastState& s = m.s;
  const Comm& comm = *m.comm;
  const EngineState& state = share.state;
  // The fields every rank has alike: every rank throws alike.
  if (state.dt != s.dt) throw InputError("restore_state: the checkpoint's dt differs from the scene's");
  if (state.boundary_loads.size() != s.boundaries.size()) {
    throw InputError("restore_state: the checkpoint's boundary count differs from the scene's");
  }
  if (share.order.size() != state.particles.size() || m.total != scene_particles || share.total < scene_particles) {
    throw std::logic_error("restore_shares: an order per particle, and the scene's particles first, expected");
  }
  const std::size_t total = share.total;
  const auto ranks = static_cast<std::size_t>(comm.size()), me = static_cast<std::size_t>(comm.rank());
  const std::size_t first = even_part_first(total, ranks, me);
  const std::size_t count = even_part_first(total, ranks, me + 1) - first;

  // 1. Each checkpoint particle, with its histories, to its block's rank; so do the scene's
  // particles (id, radius, material) that this rank owns now.
  std::optional<PlacedError> failure;  // the earliest, by the serial restore's order of checks
  const std::uint64_t records_place = 3 * total;  // after the particles' (step 2)
  auto fail = [&](std::uint64_t place, const std::string& why) {
    if (!failure || place < failure->place) failure = PlacedError{place, InputError(why)};
  };
  std::unordered_map<std::int64_t, std::uint32_t> local;  // id -> index in the share
  for (std::size_t i = 0; i < state.particles.size(); ++i) local[state.particles[i].id] = static_cast<std::uint32_t>(i);
  std::vector<std::vector<const ContactHistoryRecord*>> carried(state.particles.size());
  for (const ContactHistoryRecord& c : state.contacts) {
    const auto it = local.find(c.id_a);
    // A part keeps the histories of its own particles, a pair's at its lower id (the writer's
    // rule, fast_checkpoint.cpp): anything else is not a part this engine wrote.
    if (it == local.end()) {
      fail(records_place, "restore_state: contact names particle id " + std::to_string(c.id_a) + ", which its part does not hold");
      continue;
    }
    if (c.kind == ContactHistoryRecord::Kind::kParticleBoundary) {
      if (c.id_b < 0 || boundary_of_history_key(c.id_b) >= s.boundaries.size()) {
        fail(records_place, "restore_state: boundary index " + std::to_string(boundary_of_history_key(c.id_b)) + " out of range");
        continue;
      }
    } else if (!(c.id_a < c.id_b)) {
      fail(records_place, "restore_state: a pair history (ids " + std::to_string(c.id_a) + ", " + std::to_string(c.id_b) +
                  ") not kept at its lower id");
      continue;
    }
    carried[it->second].push_back(&c);
  }
  std::vector<std::uint8_t> escaped(state.particles.size(), 0);
  for (const std::int64_t id : state.escaped_ids) {
    const auto it = local.find(id);
    if (it == local.end()) fail(records_place, "restore_state: escaped id " + std::to_string(id) + ", which its part does not hold");
    else escaped[it->second] = 1;
  }
  std::vector<Bytes> to(ranks);
  for (std::size_t i = 0; i < state.particles.size(); ++i) {
    Packer p(to[even_part_of(total, ranks, share.order[i])]);
    p.put(std::uint8_t{1});  // a checkpoint particle
    p.put(share.order[i]);
    put_particle(p, state.particles[i]);
    p.put(escaped[i]);
    p.put(static_cast<std::uint32_t>(carried[i].size()));
    for (const ContactHistoryRecord* c : carried[i]) {
      p.put(c->kind);
      p.put(c->id_b);
      p.put(c->spring);
    }
  }
  for (std::size_t k = 0; k < s.owned; ++k) {
    Packer p(to[even_part_of(total, ranks, s.original[k])]);
    p.put(std::uint8_t{0});  // the scene's
    p.put(std::uint64_t{s.original[k]});
    p.put(s.id[k]);
    p.put(s.radius[k]);
    p.put(s.material[k]);
  }
  std::vector<Arrival> arrived;
  struct SceneParticle {
    std::uint64_t original;
    std::int64_t id;
    double radius;
    std::uint16_t material;
  };
  std::vector<SceneParticle> scene;
  for (const Bytes& block : comm.exchange(to)) {
    Unpacker u(block);
    while (!u.done()) {
      if (u.get<std::uint8_t>() == 0) {
        SceneParticle q{};
        u.get(q.original);
        u.get(q.id);
        u.get(q.radius);
        u.get(q.material);
        scene.push_back(q);
        continue;
      }
      Arrival a;
      u.get(a.original);
      a.particle = get_particle(u);
      u.get(a.escaped);
      const auto n = u.get<std::uint32_t>();
      for (std::uint32_t r = 0; r < n; ++r) {
        const auto kind = u.get<ContactHistoryRecord::Kind>();
        const auto id_b = u.get<std::int64_t>();
        const auto spring = u.get<TangentialSpring>();
        (kind == ContactHistoryRecord::Kind::kParticleBoundary ? a.walls : a.pairs).emplace_back(id_b, spring);
      }
      arrived.push_back(std::move(a));
    }
  }
  to.clear();

  // 2. This block: every index once (the parts' counts add up to the total, so an index is
  // missing only where another is twice), then each particle the scene's: the serial restore's
  // checks, in its order (a repeat, the earliest place, before any mismatch) and words.
  std::sort(arrived.begin(), arrived.end(), [](const Arrival& x, const Arrival& y) { return x.original < y.original; });
  std::sort(scene.begin(), scene.end(), [](const SceneParticle& x, const SceneParticle& y) { return x.original < y.original; });
  for (std::size_t k = 1; k < arrived.size(); ++k) {
    if (arrived[k].original == arrived[k - 1].original) {
      fail(arrived[k].original, "checkpoint part: construction index " + std::to_string(arrived[k].original) + " appears in two parts");
      break;
    }
  }
  // The scene's particles of this block: its indices below scene_particles (those above are
  // being inserted).
  const std::size_t in_scene = std::min(first + count, scene_particles) - std::min(first, scene_particles);
  bool covered = arrived.size() == count && scene.size() == in_scene;
  for (std::size_t k = 0; k < count && covered; ++k) covered = arrived[k].original == first + k;
  if (!covered) fail(total + first, "checkpoint part: the parts do not hold every construction index once");
  for (std::size_t k = 0; k < in_scene && covered; ++k) {
    const Particle& p = arrived[k].particle;
    if (p.id != scene[k].id || p.radius != scene[k].radius || p.material != scene[k].material) {
      fail(2 * total + first + k, "restore_state: particle " + std::to_string(first + k) + " (id " + std::to_string(p.id) +
                                        ") does not match the scene");
      break;
    }
  }
  // Every pair's partner is a particle of the checkpoint (the scene's ids are unique).
  std::vector<std::int64_t> ids, partners;
  for (const Arrival& a : arrived) {
    ids.push_back(a.particle.id);
    for (const auto& [id_b, spring] : a.pairs) partners.push_back(id_b);
  }
  if (const std::optional<std::int64_t> unknown = first_unknown_id(comm, ids, partners)) {
    fail(records_place, "restore_state: contact names unknown particle id " + std::to_string(*unknown));
  }
  throw_earliest_error(comm, failure);

  // 3. The block to the bricks (load_share's placing), each particle carrying its lower-id
  // histories and its boundary records in the order build_lists keeps.
  Particles block(count);
  History h;
  h.first.assign(count + 1, 0);
  h.record_first.assign(count + 1, 0);
  for (std::size_t k = 0; k < count; ++k) {
    Arrival& a = arrived[k];
    block[k] = a.particle;
    std::sort(a.pairs.begin(), a.pairs.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    for (const auto& [id_b, spring] : a.pairs) {
      h.partner_id.push_back(id_b);
      h.spring.push_back(spring);
    }
    h.first[k + 1] = static_cast<std::uint32_t>(h.partner_id.size());
    std::sort(a.walls.begin(), a.walls.end(), [](const auto& x, const auto& y) {
      return record_key(boundary_of_history_key(x.first), feature_of_history_key(x.first)) <
             record_key(boundary_of_history_key(y.first), feature_of_history_key(y.first));
    });
    for (const auto& [key, spring] : a.walls) {
      BoundaryRecord r;
      r.boundary = static_cast<std::uint32_t>(boundary_of_history_key(key));
      r.feature = feature_of_history_key(key);
      r.spring = spring;
      h.records.push_back(r);
    }
    h.record_first[k + 1] = static_cast<std::uint32_t>(h.records.size());
  }
  std::vector<std::uint8_t> block_escaped(count);
  for (std::size_t k = 0; k < count; ++k) block_escaped[k] = arrived[k].escaped;
  arrived.clear();
  arrived.shrink_to_fit();
  if (m.distributed()) {
    m.place_share(block, ParticleShare{&comm, first, total}, h, &block_escaped);
  } else {
    m.load_particles(block);  // one rank: the block is every particle, in this order
    s.escaped_via.assign(block_escaped.begin(), block_escaped.end());
  }
  m.restore_counters(state, static_cast<std::size_t>(comm.sum_over_ranks(static_cast<double>(state.escaped_ids.size()))));
  ++m.builds;
  m.out_valid = false;
  m.reset_lists();
  m.build_from(h);
  // A history whose pair the build does not list joins particles that are not neighbours.
  bool misplaced = !m.lost_terms.empty();
  m.lost_terms.clear();

  // 4. A pair whose higher-id particle is another rank's (a ghost here) keeps its history on
  // both sides (history_carry_over.cpp): the mirror goes to the ghost's owner.
  if (m.distributed() && s.friction) {
    std::vector<Bytes> mirrors(m.peers.size());
    std::vector<std::size_t> ghost_first(m.peers.size() + 1, s.owned);  // ghosts of peer r
    for (std::size_t r = 0; r < m.peers.size(); ++r) ghost_first[r + 1] = ghost_first[r] + m.halo_recv[r];
    for (std::size_t k = 0; k < s.owned; ++k) {
      for (std::uint32_t slot = s.first[k]; slot < s.first[k + 1]; ++slot) {
        const std::uint32_t j = s.partner[slot];
        if (j < s.owned || s.spring_of[slot] == kNoSpring || !(s.id[k] < s.id[j])) continue;
        const auto r = static_cast<std::size_t>(std::upper_bound(ghost_first.begin(), ghost_first.end(), j) - ghost_first.begin() - 1);
        Packer p(mirrors[r]);
        p.put(s.id[j]);
        p.put(s.id[k]);
        p.put(s.spring_at(s.spring_of[slot]).mirrored());
      }
    }
    std::unordered_map<std::int64_t, std::uint32_t> owned_at;
    for (std::size_t k = 0; k < s.owned; ++k) owned_at[s.id[k]] = static_cast<std::uint32_t>(k);
    for (const Bytes& block_in : comm.exchange_with(m.peers, mirrors)) {
      Unpacker u(block_in);
      while (!u.done()) {
        const auto self_id = u.get<std::int64_t>();
        const auto other_id = u.get<std::int64_t>();
        const auto spring = u.get<TangentialSpring>();
        const auto self = owned_at.find(self_id);
        if (self == owned_at.end()) {
          misplaced = true;
          continue;
        }
        const std::optional<std::uint32_t> slot = s.slot_of_partner(self->second, other_id);
        if (!slot) {
          misplaced = true;
          continue;
        }
        s.set_spring(*slot, spring);
      }
    }
  }
  if (m.distributed()) misplaced = comm.max_over_ranks(misplaced ? 1.0 : 0.0) > 0.0;
  if (misplaced) throw InputError("restore_state: a contact history joins particles that are not neighbours");
  m.finish_restore(state);
}

}  // namespace

}  // namespace ppohdem::dem::fast
