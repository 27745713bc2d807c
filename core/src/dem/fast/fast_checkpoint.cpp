// Checkpoints of the fast engine: the whole system's state in the reference's layout, so a run
// restarts with either engine and at any rank count (docs/reliability.md).
#include "engine_impl.hpp"

namespace ppohdem::dem::fast {

namespace {

// This rank's contact histories: pairs from the lower-id side, which is owned here, and the
// boundary records of its particles (every record on exactly one rank).
std::vector<ContactHistoryRecord> own_contact_records(const FastState& s) {
  std::vector<ContactHistoryRecord> records;
  if (!s.friction) return records;
  for (std::size_t k = 0; k < s.owned; ++k) {
    for (std::uint32_t slot = s.first[k]; slot < s.first[k + 1]; ++slot) {
      const std::uint32_t j = s.partner[slot];
      if (s.spring_of[slot] == kNoSpring || s.id[k] > s.id[j]) continue;
      // A slot keeps a spring only while its pair touched at the last evaluation, whose
      // positions these still are; the branch vectors are the ones it computed (the same
      // expressions, pair_geometry), which the kernel stores only when the energies are
      // tracked (their only other use): the checkpoint is the same either way.
      TangentialSpring sp = s.spring_at(s.spring_of[slot]);
      const PairGeometry g = pair_geometry(s, k, j, s.x[k] - s.x[j]);
      sp.branch_i = g.r_i;
      sp.branch_j = g.r_j;
      if (sp.stiffness != 0.0 || sp.branch_i != Vec3::Zero()) {
        records.push_back({ContactHistoryRecord::Kind::kParticlePair, s.id[k], s.id[j], sp});
      }
    }
  }
  for (const BoundaryRecord& r : s.records) {
    records.push_back({ContactHistoryRecord::Kind::kParticleBoundary, s.id[r.particle],
                       boundary_history_key(r.boundary, r.feature), r.spring});
  }
  return records;
}

std::vector<std::int64_t> own_escaped_ids(const FastState& s) {
  std::vector<std::int64_t> ids;
  for (std::size_t k = 0; k < s.owned; ++k) {
    if (s.escaped_via[k] != 0) ids.push_back(s.id[k]);
  }
  return ids;
}

void sort_contact_records(std::vector<ContactHistoryRecord>& records) {
  std::sort(records.begin(), records.end(), [](const auto& a, const auto& b) {
    return std::tuple(a.kind, a.id_a, a.id_b) < std::tuple(b.kind, b.id_a, b.id_b);
  });
}

// The fields that are the same on every rank (collective sums), without the three lists.
EngineState global_state(const FastEngine& engine, const FastEngine::Impl& m) {
  EngineState state;
  state.engine = engine.name();
  state.step = m.steps;
  state.dt = m.s.dt;
  state.accumulators = engine.energies();
  if (m.loads_stale) m.sum_loads();
  state.boundary_loads = m.loads;
  state.contact_counts = engine.contact_counts();
  state.boundary_power = m.power;  // P(n), for the next trapezoid step of boundary_work
  return state;
}

}  // namespace

EngineState FastEngine::save_state() const {
  const Impl& m = *impl_;
  const FastState& s = m.s;
  EngineState state = global_state(*this, m);
  state.particles = particles();  // whole system (gathered)
  if (s.friction) {
    Bytes mine;
    Packer pk(mine);
    for (const ContactHistoryRecord& c : own_contact_records(s)) {
      pk.put(c.kind);
      pk.put(c.id_a);
      pk.put(c.id_b);
      pk.put(c.spring);
    }
    for (const Bytes& block : m.comm->allgather(mine)) {
      Unpacker u(block);
      while (!u.done()) {
        ContactHistoryRecord c;
        u.get(c.kind);
        u.get(c.id_a);
        u.get(c.id_b);
        u.get(c.spring);
        state.contacts.push_back(c);
      }
    }
    sort_contact_records(state.contacts);
  }
  {
    Bytes mine;
    Packer pk(mine);
    for (const std::int64_t id : own_escaped_ids(s)) pk.put(id);
    for (const Bytes& block : m.comm->allgather(mine)) {
      Unpacker u(block);
      while (!u.done()) state.escaped_ids.push_back(u.get<std::int64_t>());
    }
  }
  std::sort(state.escaped_ids.begin(), state.escaped_ids.end());
  return state;
}

// No gather: this rank's particles (construction order), histories and escaped ids.
EngineStateShare FastEngine::save_state_share() const {
  const Impl& m = *impl_;
  const FastState& s = m.s;
  EngineStateShare share;
  share.state = global_state(*this, m);
  share.total = m.total;
  share.state.particles = owned_particles();
  share.order.reserve(s.owned);
  for (std::size_t k = 0; k < s.owned; ++k) share.order.push_back(s.original[k]);
  std::sort(share.order.begin(), share.order.end());  // owned_particles() is in this order
  share.state.contacts = own_contact_records(s);
  sort_contact_records(share.state.contacts);
  share.state.escaped_ids = own_escaped_ids(s);
  std::sort(share.state.escaped_ids.begin(), share.state.escaped_ids.end());
  return share;
}

void FastEngine::restore_state(const EngineState& state) {
  Impl& m = *impl_;
  FastState& s = m.s;
  const Particles& current = particles();  // whole system (collective)
  if (state.dt != s.dt) throw InputError("restore_state: the checkpoint's dt differs from the scene's");
  if (state.particles.size() != current.size()) {
    throw InputError("checkpoint: " + std::to_string(state.particles.size()) + " particles, the scene has " +
                     std::to_string(current.size()));  // the reference engine's words
  }
  for (std::size_t i = 0; i < current.size(); ++i) {
    if (state.particles[i].id != current[i].id || state.particles[i].radius != current[i].radius ||
        state.particles[i].material != current[i].material) {
      throw InputError("restore_state: particle " + std::to_string(i) + " (id " +
                       std::to_string(state.particles[i].id) + ") does not match the scene");
    }
  }
  if (state.boundary_loads.size() != s.boundaries.size()) {
    throw InputError("restore_state: the checkpoint's boundary count differs from the scene's");
  }
  // Validate the records against the whole system on every rank (so that every rank throws
  // or none does), then install each on the rank owning its particle.
  std::unordered_map<std::int64_t, std::uint32_t> index_of;  // id -> construction index
  for (std::size_t i = 0; i < state.particles.size(); ++i) index_of[state.particles[i].id] = static_cast<std::uint32_t>(i);
  auto known = [&](std::int64_t id) {
    if (!index_of.count(id)) throw InputError("restore_state: contact names unknown particle id " + std::to_string(id));
  };
  for (const std::int64_t id : state.escaped_ids) known(id);
  for (const ContactHistoryRecord& c : state.contacts) {
    known(c.id_a);
    if (c.kind == ContactHistoryRecord::Kind::kParticleBoundary) {
      if (c.id_b < 0 || boundary_of_history_key(c.id_b) >= s.boundaries.size()) {
        throw InputError("restore_state: boundary index " + std::to_string(boundary_of_history_key(c.id_b)) + " out of range");
      }
    } else {
      known(c.id_b);
    }
  }
  m.load_particles(state.particles);
  m.restore_counters(state, state.escaped_ids.size());
  m.build_lists();
  std::unordered_map<std::int64_t, std::uint32_t> where;  // id -> storage index (owned and ghosts)
  for (std::size_t k = 0; k < s.size(); ++k) where[s.id[k]] = static_cast<std::uint32_t>(k);
  auto owned_index = [&](std::int64_t id) -> std::optional<std::size_t> {
    const auto it = where.find(id);
    if (it == where.end() || it->second >= s.owned) return std::nullopt;
    return it->second;
  };
  for (const std::int64_t id : state.escaped_ids) {
    if (const auto k = owned_index(id)) s.escaped_via[*k] = 1;  // the boundary is only used in the warning
  }
  std::vector<BoundaryRecord> records;
  bool misplaced = false;  // a pair record between particles that are not neighbours
  for (const ContactHistoryRecord& c : state.contacts) {
    if (c.kind == ContactHistoryRecord::Kind::kParticleBoundary) {
      if (const auto a = owned_index(c.id_a)) {
        BoundaryRecord r;
        r.particle = static_cast<std::uint32_t>(*a);
        r.boundary = static_cast<std::uint32_t>(boundary_of_history_key(c.id_b));
        r.feature = feature_of_history_key(c.id_b);
        r.spring = c.spring;
        records.push_back(r);
      }
      continue;
    }
    if (!s.friction) continue;
    auto install = [&](std::int64_t self_id, std::int64_t other_id, const TangentialSpring& spring) {
      const auto self = owned_index(self_id);
      if (!self) return;
      const std::optional<std::uint32_t> slot = s.slot_of_partner(*self, other_id);
      if (!slot) {
        misplaced = true;
        return;
      }
      if (s.partner[*slot] < s.owned && other_id < self_id) return;  // kept by the owned lower-id side
      s.set_spring(*slot, spring);
    };
    install(c.id_a, c.id_b, c.spring);
    install(c.id_b, c.id_a, c.spring.mirrored());
  }
  if (m.distributed()) misplaced = m.comm->max_over_ranks(misplaced ? 1.0 : 0.0) > 0.0;
  if (misplaced) throw InputError("restore_state: a contact history joins particles that are not neighbours");
  std::sort(records.begin(), records.end(), [](const BoundaryRecord& x, const BoundaryRecord& y) {
    return std::pair(x.particle, record_key(x)) < std::pair(y.particle, record_key(y));
  });
  s.records = std::move(records);
  s.record_first.assign(s.owned + 1, 0);
  for (const BoundaryRecord& r : s.records) ++s.record_first[r.particle + 1];
  for (std::size_t i = 0; i < s.owned; ++i) s.record_first[i + 1] += s.record_first[i];
  m.finish_restore(state);
}

void FastEngine::Impl::restore_counters(const EngineState& state, std::size_t escaped_total) {
  steps = state.step;
  dissipated = state.accumulators.dissipated;
  boundary_work = state.accumulators.boundary_work;
  loads = state.boundary_loads;
  loads_stale = false;
  power = state.boundary_power;
  escaped = escaped_total;
  s.deepest.reset();  // of the evaluation before the checkpoint: not saved (as the reference)
}

void FastEngine::Impl::finish_restore(const EngineState& state) {
  s.pair_contacts = state.contact_counts.particle_pairs;
  s.boundary_contacts = state.contact_counts.particle_boundary;
  out_valid = false;
  energies_cache.reset();
  restored_elastic = state.accumulators.elastic;  // the particles' records start at zero
}

}  // namespace ppohdem::dem::fast
