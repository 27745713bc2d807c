// The fast engine behind the DemEngine interface (fast_engine.hpp); its concepts live in the
// files listed in engine_impl.hpp.
#include <algorithm>
#include <bit>

#include "engine_impl.hpp"
#include "ppohdem/simd_level.hpp"

namespace ppohdem::dem::fast {

FastEngine::FastEngine(const SimulationSetup& setup, FastOptions options) : impl_(std::make_unique<Impl>()) {
  validate_setup(setup);
  (void)simd_level();  // a bad PPOHDEM_SIMD is reported here, not inside the parallel loops
  Impl& m = *impl_;
  if (options.comm != nullptr) m.comm = options.comm;
  if (setup.shared() && setup.share.comm != options.comm) {
    throw std::invalid_argument("FastEngine: a setup shared over ranks needs FastOptions::comm = its share's comm");
  }
  m.s.dt = setup.dt;
  m.energy_balance = setup.energy_balance;
  m.s.gravity = setup.gravity;
  m.s.boundaries = setup.boundaries;
  m.s.rolling = setup.rolling != RollingModel::kNone;
  m.s.walls.resize(setup.boundaries.size());
  m.s.is_wall.assign(setup.boundaries.size(), false);
  for (std::size_t b = 0; b < setup.boundaries.size(); ++b) {
    if (const auto* wall = dynamic_cast<const PlaneWall*>(setup.boundaries[b].get())) {
      m.s.is_wall[b] = true;
      m.s.walls[b].point0 = wall->point_at(0.0);
      m.s.walls[b].normal = wall->normal();
      m.s.walls[b].velocity = wall->velocity();
    }
  }
  // Histories if any pair of materials has friction (pair_laws.hpp).
  m.s.friction = std::visit([&](const auto& law) { return PairLaws(setup, law).any_friction(); }, setup.law);
  m.kernel = make_force_kernel(setup, options.vector_contacts);
  for (auto& p : setup.particles) m.r_max = std::max(m.r_max, p.radius);
  if (setup.shared()) m.r_max = m.comm->max_over_ranks(m.r_max);  // exact: a maximum
  m.skin = options.skin_fraction * m.r_max;
  m.skip_far_objects = options.skip_far_objects;
  m.skip_apart_slots = options.skip_apart_slots;
  m.skin_fraction = options.skin_fraction;
  m.balance = options.balance;
  if (!(options.balance_threshold >= 1.0)) {
    throw InputError("balance threshold: expected >= 1 (max/mean particles per rank), got " +
                     std::to_string(options.balance_threshold));
  }
  m.balance_threshold = options.balance_threshold;
  // Only the materials are kept (a copy of the setup would hold a second copy of the particles).
  for (std::size_t k = 0; k < setup.material_count(); ++k) m.materials.push_back(setup.material_at(k));
  if (setup.shared()) m.load_share(setup.particles, setup.share);
  else m.load_particles(setup.particles);
  std::fill(m.s.f.begin(), m.s.f.end(), Vec3::Zero());  // the first evaluation sets them
  std::fill(m.s.t.begin(), m.s.t.end(), Vec3::Zero());
  m.build_lists();
  // A shared setup's overlaps span the shares: checked once the owners hold their ghosts.
  if (setup.shared() && !setup.allow_initial_overlap) m.check_initial_overlaps(setup.source);
  m.evaluate_forces(0.0);  // a(0); no history increment at start-up
}

FastEngine::~FastEngine() = default;

std::unique_ptr<DemEngine> FastEngine::make(const SimulationSetup& setup) {
  return std::make_unique<FastEngine>(setup);
}

void FastEngine::step() { impl_->step(); }
long FastEngine::step_count() const { return impl_->steps; }
double FastEngine::time() const { return static_cast<double>(impl_->steps) * impl_->s.dt; }
int FastEngine::ranks() const { return impl_->comm->size(); }
std::array<int, 3> FastEngine::rank_grid() const { return impl_->decomposition.dims(); }
LoadReport FastEngine::load_report() const { return impl_->load_report(); }
std::size_t FastEngine::owned_count() const { return impl_->s.owned; }
std::size_t FastEngine::ghost_count() const { return impl_->s.size() - impl_->s.owned; }
std::size_t FastEngine::interior_count() const { return impl_->s.n_interior; }
std::size_t FastEngine::interior_near_ghosts() const {
  const FastState& s = impl_->s;
  std::size_t near = 0;
  for (std::size_t i = 0; i < s.n_interior; ++i) {
    bool found = false;
    for (std::uint32_t slot = s.first[i]; slot < s.first[i + 1]; ++slot) found = found || s.partner[slot] >= s.owned;
    for (std::size_t g = s.owned; g < s.size(); ++g) {
      const double reach = s.radius[i] + s.radius[g] + impl_->skin;
      found = found || (s.x_build[i] - s.x_build[g]).squaredNorm() < reach * reach;  // at the build
    }
    near += found ? 1 : 0;
  }
  return near;
}

namespace {

/// The particle record of storage index k (the fields a Particle carries).
Particle particle_at(const FastState& s, std::size_t k) {
  Particle p;
  p.id = s.id[k];
  p.position = s.x[k];
  p.velocity = s.v[k];
  p.angular_velocity = s.w[k];
  p.radius = s.radius[k];
  p.material = s.material[k];
  p.force = s.f[k];
  p.torque = s.t[k];
  return p;
}

}  // namespace

Particles FastEngine::owned_particles() const {
  const FastState& s = impl_->s;
  std::vector<std::uint32_t> by_original(s.owned);  // storage indices in construction order
  for (std::uint32_t k = 0; k < s.owned; ++k) by_original[k] = k;
  std::sort(by_original.begin(), by_original.end(), [&](std::uint32_t a, std::uint32_t b) { return s.original[a] < s.original[b]; });
  Particles owned(s.owned);
  for (std::size_t i = 0; i < owned.size(); ++i) {
    owned[i] = particle_at(s, by_original[i]);
  }
  return owned;
}

namespace {

// An owned particle with its construction index, for a gather of particles().
void pack_output(Packer& pk, const FastState& s, std::size_t k) {
  pk.put(s.original[k]);
  put_particle(pk, particle_at(s, k));
}

// pack_output's records in `block`, each given to put(construction index, particle).
template <class Put>
void unpack_outputs(const Bytes& block, Put&& put) {
  Unpacker u(block);
  while (!u.done()) {
    const auto o = u.get<std::uint32_t>();
    put(o, get_particle(u));
  }
}

}  // namespace

const Particles& FastEngine::particles() const {
  Impl& m = *impl_;
  if (!m.out_valid) {
    const FastState& s = m.s;
    m.out.resize(m.total);
    auto fill = [&](std::uint32_t o, const Particle& p) { m.out[o] = p; };
    if (!m.distributed()) {
      for (std::size_t k = 0; k < s.owned; ++k) fill(s.original[k], particle_at(s, k));
    } else {
      Bytes mine;
      Packer pk(mine);
      for (std::size_t k = 0; k < s.owned; ++k) pack_output(pk, s, k);
      for (const Bytes& block : m.comm->allgather(mine)) unpack_outputs(block, fill);
    }
    m.out_valid = true;
  }
  return m.out;
}

DemEngine::OrderedPart FastEngine::ordered_part() const {
  const Impl& m = *impl_;
  if (!m.distributed() || m.out_valid) {  // (gathered already: cut from it)
    const Particles& all = particles();
    const auto ranks = static_cast<std::size_t>(m.comm->size()), me = static_cast<std::size_t>(m.comm->rank());
    const std::size_t first = even_part_first(all.size(), ranks, me);
    const std::size_t count = even_part_first(all.size(), ranks, me + 1) - first;
    return {Particles(all.begin() + static_cast<std::ptrdiff_t>(first), all.begin() + static_cast<std::ptrdiff_t>(first + count)),
            first, all.size()};
  }
  const FastState& s = m.s;
  const auto ranks = static_cast<std::size_t>(m.comm->size()), me = static_cast<std::size_t>(m.comm->rank());
  auto first_of = [&](std::size_t r) { return even_part_first(m.total, ranks, r); };
  std::vector<Bytes> to(ranks);
  for (std::size_t k = 0; k < s.owned; ++k) {
    Packer pk(to[even_part_of(m.total, ranks, s.original[k])]);
    pack_output(pk, s, k);
  }
  OrderedPart part;
  part.first = first_of(me);
  part.total = m.total;
  part.particles.resize(first_of(me + 1) - part.first);
  for (const Bytes& block : m.comm->exchange(to)) {
    unpack_outputs(block, [&](std::uint32_t o, const Particle& p) { part.particles[o - part.first] = p; });
  }
  return part;
}

std::size_t FastEngine::particle_count() const { return impl_->total; }

DemEngine::Extent FastEngine::particle_extent() const {
  const Impl& m = *impl_;
  const FastState& s = m.s;
  // Radii are > 0, so their bit patterns order as the values do: both maxima in one reduction.
  std::int64_t words[2] = {0, 0};
  for (std::size_t k = 0; k < s.owned; ++k) {
    words[0] = std::max(words[0], s.id[k]);
    words[1] = std::max(words[1], std::bit_cast<std::int64_t>(s.radius[k]));
  }
  if (m.distributed()) {
    m.comm->combine_over_ranks(words, [](const std::int64_t* in, std::int64_t* inout, std::size_t count) {
      for (std::size_t w = 0; w < count; ++w) inout[w] = std::max(inout[w], in[w]);
    });
  }
  return {words[0], std::bit_cast<double>(words[1])};
}

Particles FastEngine::particles_in(const std::vector<CentreBox>& boxes) const {
  const Impl& m = *impl_;
  const FastState& s = m.s;
  auto in_a_box = [&](std::size_t k) {
    return std::any_of(boxes.begin(), boxes.end(), [&](const CentreBox& b) { return b.holds(s.x[k]); });
  };
  std::vector<std::pair<std::uint32_t, Particle>> found;  // (construction index, particle)
  if (!m.distributed()) {
    for (std::size_t k = 0; k < s.owned; ++k) {
      if (in_a_box(k)) found.emplace_back(s.original[k], particle_at(s, k));
    }
  } else {
    Bytes mine;
    Packer pk(mine);
    for (std::size_t k = 0; k < s.owned; ++k) {
      if (in_a_box(k)) pack_output(pk, s, k);
    }
    for (const Bytes& block : m.comm->allgather(mine)) {
      unpack_outputs(block, [&](std::uint32_t o, const Particle& p) { found.emplace_back(o, p); });
    }
  }
  std::sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  Particles in;
  in.reserve(found.size());
  for (auto& [o, p] : found) in.push_back(std::move(p));
  return in;
}

Energies FastEngine::energies() const {
  // The reference's terms, summed exactly and rounded once (exact_sum.hpp): the same bits
  // for the motion terms and the loads.
  return impl_->sum_energies();
}

ContactCounts FastEngine::contact_counts() const {
  return {impl_->s.pair_contacts, impl_->s.boundary_contacts};
}

std::size_t FastEngine::escaped_count() const {
  const Impl& m = *impl_;
  return m.lazy_sums() ? m.count_escaped() : m.escaped;
}

std::vector<BoundaryLoad> FastEngine::boundary_loads() const {
  if (impl_->loads_stale) impl_->sum_loads();
  return impl_->loads;
}

bool FastEngine::motion_finite() const {
  const Impl& m = *impl_;
  // The screen of the last closing kick (after a (re)load there is none yet: the energies'),
  // with several ranks every rank's, gathered with the evaluation's counts.
  if (m.kick_cached) return m.distributed() ? m.screens_finite : std::isfinite(m.s.screen);
  return DemEngine::motion_finite();
}

bool FastEngine::state_finite() const {
  const Impl& m = *impl_;
  const FastState& s = m.s;
  bool finite = true;
  for (std::size_t k = 0; k < s.owned && finite; ++k) {
    finite = s.x[k].allFinite() && s.v[k].allFinite() && s.w[k].allFinite() && s.f[k].allFinite() && s.t[k].allFinite();
  }
  return m.distributed() ? m.comm->max_over_ranks(finite ? 0.0 : 1.0) == 0.0 : finite;
}

std::optional<LargestOverlap> FastEngine::largest_overlap() const {
  // The reference reports ratio 0 (no contact) as an empty record; so do we.
  return impl_->s.deepest.value_or(LargestOverlap{});
}

long FastEngine::neighbour_list_builds() const { return impl_->builds; }

std::size_t FastEngine::skipped_screens() const {
  std::size_t skipped = 0;
  for (const ThreadOutput& range : impl_->s.threads) skipped += range.skipped_screens;
  return skipped;
}
double FastEngine::skin() const { return impl_->skin; }
std::size_t FastEngine::neighbour_slots() const { return impl_->s.partner.size(); }
const ThreadSpeeds& FastEngine::thread_speeds() const { return impl_->s.thread_speeds; }

std::size_t FastEngine::memory_bytes() const {
  const FastState& s = impl_->s;
  std::size_t pool_bytes = bytes(s.spring_pools) + bytes(s.result_pools) + bytes(s.mirror) + bytes(s.upper_first) + bytes(s.lower_ghost);
  for (const SpringPool& pool : s.spring_pools) pool_bytes += pool.bytes();
  for (const auto& pool : s.result_pools) pool_bytes += bytes(pool);
  pool_bytes += bytes(impl_->search_buffers) + bytes(impl_->search_probes.x) + bytes(impl_->search_probes.y) + bytes(impl_->search_probes.z) +
                bytes(impl_->search_probes.r);  // the engine's reused work buffers
  for (const auto& buffer : impl_->search_buffers) pool_bytes += bytes(buffer);
  const History& h = impl_->history;  // kept between list builds
  pool_bytes += bytes(h.first) + bytes(h.partner_id) + bytes(h.spring) + bytes(h.record_first) + bytes(h.records);
  return bytes(s.id) + bytes(s.original) + bytes(s.where) + bytes(s.x) + bytes(s.v) + bytes(s.w) + bytes(s.f) + bytes(s.t) +
         bytes(s.pv) + bytes(s.pw) + bytes(s.x_build) + bytes(s.radius) + bytes(s.mass) + bytes(s.inertia) + bytes(s.material) +
         bytes(s.escaped_via) + bytes(s.terms) + bytes(s.first) +
         bytes(s.partner) + bytes(s.spring_of) + bytes(s.lower_code) + pool_bytes + bytes(s.records) + bytes(s.record_first) +
         bytes(s.next_records) + bytes(s.next_record_first) + bytes(s.near_boundaries);
}

}  // namespace ppohdem::dem::fast
