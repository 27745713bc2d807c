// The fast engine: integration, cell sort and Verlet neighbour lists (fast_engine.hpp).
#include "ppohdem/dem/fast/fast_engine.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <tuple>
#include <unordered_map>

#include "fast_state.hpp"
#include "ppohdem/dem/cell_grid.hpp"
#include "ppohdem/error.hpp"

namespace ppohdem::dem::fast {

namespace {

using Grid = CellGrid;  // ppohdem/dem/cell_grid.hpp (shared with the reference's cell list)

Grid grid_for(const std::vector<Vec3>& x, double min_cell) { return cell_grid_for(x, min_cell); }

template <class T>
void permute(std::vector<T>& a, const std::vector<std::uint32_t>& order) {
  std::vector<T> b(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) b[k] = a[order[k]];
  a.swap(b);
}

TangentialSpring mirrored(const TangentialSpring& s) {
  TangentialSpring m;
  m.displacement = -s.displacement;
  m.stiffness = s.stiffness;
  m.branch_i = s.branch_j;
  m.branch_j = s.branch_i;
  return m;
}

template <class T>
std::size_t bytes(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}

}  // namespace

struct FastEngine::Impl {
  FastState s;
  std::unique_ptr<ForceKernel> kernel;
  Material material;
  double skin = 0.0;      ///< [m]
  double r_max = 0.0;     ///< [m]
  long steps = 0;
  long builds = 0;
  double elastic = 0.0;
  double dissipated = 0.0;
  double boundary_work = 0.0;
  double power = 0.0;  ///< P(n) of the last evaluation [W]
  std::vector<BoundaryLoad> loads;
  mutable Particles out;  ///< particles() in construction order
  mutable bool out_valid = false;

  void load_particles(const Particles& particles, const Material& mat) {
    const std::size_t n = particles.size();
    auto& q = s;
    q.id.resize(n);
    q.original.resize(n);
    q.x.resize(n);
    q.v.resize(n);
    q.w.resize(n);
    q.f.resize(n);
    q.t.resize(n);
    q.pv.resize(n);
    q.pw.resize(n);
    q.radius.resize(n);
    q.mass.resize(n);
    q.inertia.resize(n);
    q.escaped_via.assign(n, 0);
    q.elastic_p.assign(n, 0.0);
    q.dissipated_p.assign(n, 0.0);
    q.work_p.assign(n, 0.0);
    q.power_p.assign(n, 0.0);
    r_max = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const Particle& p = particles[i];
      q.id[i] = p.id;
      q.original[i] = static_cast<std::uint32_t>(i);
      q.x[i] = p.position;
      q.v[i] = p.velocity;
      q.w[i] = p.angular_velocity;
      q.f[i] = p.force;
      q.t[i] = p.torque;
      q.pv[i] = p.velocity;
      q.pw[i] = p.angular_velocity;
      q.radius[i] = p.radius;
      q.mass[i] = mat.mass(p.radius);
      q.inertia[i] = mat.moment_of_inertia(p.radius);
      r_max = std::max(r_max, p.radius);
    }
    q.first.assign(n + 1, 0);
    q.partner.clear();
    q.spring.clear();
    q.records.clear();
    q.record_first.assign(n + 1, 0);
    out_valid = false;
  }

  /// Sort the particles by cell and rebuild the full neighbour list (pairs closer than
  /// R_i + R_j + skin), each particle's partners in ascending id; carry the contact histories
  /// over by partner id.
  void build_lists() {
    ++builds;
    out_valid = false;
    const std::size_t n = s.size();
    if (n == 0) {
      s.x_build.clear();
      return;
    }
    const Grid grid = grid_for(s.x, 2.0 * r_max + skin);
    // Counting sort by cell (stable): order[new] = old.
    std::vector<std::uint32_t> cell(n);
    std::vector<std::uint32_t> start(grid.size() + 1, 0);
    for (std::size_t i = 0; i < n; ++i) {
      cell[i] = static_cast<std::uint32_t>(grid.linear(grid.index(s.x[i])));
      ++start[cell[i] + 1];
    }
    for (std::size_t c = 0; c < grid.size(); ++c) start[c + 1] += start[c];
    std::vector<std::uint32_t> order(n);
    {
      std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
      for (std::size_t i = 0; i < n; ++i) order[fill[cell[i]]++] = static_cast<std::uint32_t>(i);
    }
    std::vector<std::uint32_t> new_index(n);
    for (std::size_t k = 0; k < n; ++k) new_index[order[k]] = static_cast<std::uint32_t>(k);
    const std::vector<std::int64_t> old_id = s.id;
    permute(s.id, order);
    permute(s.original, order);
    permute(s.x, order);
    permute(s.v, order);
    permute(s.w, order);
    permute(s.f, order);
    permute(s.t, order);
    permute(s.pv, order);
    permute(s.pw, order);
    permute(s.radius, order);
    permute(s.mass, order);
    permute(s.inertia, order);
    permute(s.escaped_via, order);
    s.x_build = s.x;
    s.where.resize(n);
    for (std::size_t k = 0; k < n; ++k) s.where[s.original[k]] = static_cast<std::uint32_t>(k);

    // Neighbour search: two passes (count, fill), each particle independently.
    const double skin_ = skin;
    auto visit = [&](std::size_t i, auto&& emit) {
      const Index3 c = grid.index(s.x[i]);
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const Index3 nb = {c[0] + dx, c[1] + dy, c[2] + dz};
            if (nb[0] < 0 || nb[1] < 0 || nb[2] < 0 || nb[0] >= grid.dims[0] || nb[1] >= grid.dims[1] ||
                nb[2] >= grid.dims[2]) {
              continue;
            }
            const std::size_t cl = grid.linear(nb);
            for (std::uint32_t j = start[cl]; j < start[cl + 1]; ++j) {  // sorted: cell cl is [start, start+1)
              if (j == i) continue;
              const double reach = s.radius[i] + s.radius[j] + skin_;
              if ((s.x[i] - s.x[j]).squaredNorm() < reach * reach) emit(j);
            }
          }
    };
    std::vector<std::uint32_t> first(n + 1, 0);
    PPOHDEM_OMP(omp parallel for schedule(static) if (n >= kParallelMin))
    for (std::size_t i = 0; i < n; ++i) {
      std::uint32_t count = 0;
      visit(i, [&](std::uint32_t) { ++count; });
      first[i + 1] = count;
    }
    for (std::size_t i = 0; i < n; ++i) first[i + 1] += first[i];
    std::vector<std::uint32_t> partner(first[n]);
    PPOHDEM_OMP(omp parallel for schedule(dynamic, 256) if (n >= kParallelMin))
    for (std::size_t i = 0; i < n; ++i) {
      std::uint32_t slot = first[i];
      visit(i, [&](std::uint32_t j) { partner[slot++] = j; });
      std::sort(partner.begin() + first[i], partner.begin() + first[i + 1],
                [&](std::uint32_t a, std::uint32_t b) { return s.id[a] < s.id[b]; });
    }
    // Contact histories by partner id (both ranges ascending in id: a merge).
    if (s.friction) {
      std::vector<TangentialSpring> spring(partner.size());
      for (std::size_t k = 0; k < n; ++k) {
        const std::uint32_t o = order[k];
        std::uint32_t a = s.first.empty() ? 0 : s.first[o];
        const std::uint32_t a_end = s.first.empty() ? 0 : s.first[o + 1];
        for (std::uint32_t b = first[k]; b < first[k + 1]; ++b) {
          const std::int64_t want = s.id[partner[b]];
          for (; a < a_end && old_id[s.partner[a]] < want; ++a) lost(s.spring[a], s.id[k], old_id[s.partner[a]]);
          if (a < a_end && old_id[s.partner[a]] == want) spring[b] = s.spring[a++];
        }
        for (; a < a_end; ++a) lost(s.spring[a], s.id[k], old_id[s.partner[a]]);
      }
      s.spring.swap(spring);
    }
    s.first.swap(first);
    s.partner.swap(partner);
    // Boundary records follow their particle.
    for (BoundaryRecord& r : s.records) r.particle = new_index[r.particle];
    std::stable_sort(s.records.begin(), s.records.end(), [](const BoundaryRecord& a, const BoundaryRecord& b) {
      return a.particle < b.particle;
    });
    s.record_first.assign(n + 1, 0);
    for (const BoundaryRecord& r : s.records) ++s.record_first[r.particle + 1];
    for (std::size_t i = 0; i < n; ++i) s.record_first[i + 1] += s.record_first[i];
  }

  /// A history dropped from the list (the pair moved apart by more than the skin within one
  /// step): its stored energy is dissipated, booked once (lower id side).
  void lost(const TangentialSpring& spring, std::int64_t self, std::int64_t other) {
    if (self < other) dissipated += spring.stored_energy();
  }

  void evaluate_forces(double history_dt) {
    kernel->evaluate(s, static_cast<double>(steps) * s.dt, history_dt);
    // Sums in construction order: independent of the cell sort (so of restarts and, later,
    // of the decomposition) and of the thread count.
    double e = 0.0, d = 0.0, w = 0.0, p = 0.0;
    for (const std::uint32_t i : s.where) {
      e += s.elastic_p[i];
      d += s.dissipated_p[i];
      w += s.work_p[i];
      p += s.power_p[i];
    }
    elastic = e;
    dissipated += d;
    boundary_work += w;
    // W = (P(n) + P(n+1)) dt / 2 (contact_force.hpp "Moving boundaries"); the start-up
    // evaluation (dt = 0) records P(0).
    boundary_work += 0.5 * (power + p) * history_dt;
    power = p;
    loads.assign(s.boundaries.size(), BoundaryLoad{});
    std::vector<const BoundaryRecord*> by_original(s.records.size());
    for (std::size_t r = 0; r < s.records.size(); ++r) by_original[r] = &s.records[r];
    std::sort(by_original.begin(), by_original.end(), [&](const BoundaryRecord* a, const BoundaryRecord* b) {
      return std::pair(s.original[a->particle], a->boundary) < std::pair(s.original[b->particle], b->boundary);
    });
    for (const BoundaryRecord* rp : by_original) {
      const BoundaryRecord& r = *rp;
      loads[r.boundary].force -= r.force;
      loads[r.boundary].moment_about_origin += r.point.cross(-r.force);
    }
    out_valid = false;
  }

  void step() {
    const double dt = s.dt;
    const double half = 0.5 * dt;
    const Vec3 g = s.gravity;
    const std::size_t n = s.size();
    double largest = 0.0;  // max |x - x_build|^2 [m^2]
    // Half kick and drift (the reference's expressions, so the same bits).
    PPOHDEM_OMP(omp parallel for schedule(static) reduction(max : largest) if (n >= kParallelMin))
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 kick = half * (s.f[i] / s.mass[i] + g);
      const Vec3 spin_kick = half * s.t[i] / s.inertia[i];
      s.v[i] += kick;
      s.w[i] += spin_kick;
      s.x[i] += dt * s.v[i];
      s.pv[i] = s.v[i] + kick;
      s.pw[i] = s.w[i] + spin_kick;
      largest = std::max(largest, (s.x[i] - s.x_build[i]).squaredNorm());
    }
    ++steps;
    if (largest > 0.25 * skin * skin) build_lists();  // largest displacement > skin / 2
    evaluate_forces(dt);
    PPOHDEM_OMP(omp parallel for schedule(static) if (n >= kParallelMin))
    for (std::size_t i = 0; i < n; ++i) {
      s.v[i] += half * (s.f[i] / s.mass[i] + g);
      s.w[i] += half * s.t[i] / s.inertia[i];
    }
    out_valid = false;
  }

  std::size_t storage_index_of(std::int64_t id, const std::unordered_map<std::int64_t, std::uint32_t>& map) const {
    const auto it = map.find(id);
    if (it == map.end()) throw InputError("restore_state: contact names unknown particle id " + std::to_string(id));
    return it->second;
  }
};

FastEngine::FastEngine(const SimulationSetup& setup, FastOptions options) : impl_(std::make_unique<Impl>()) {
  validate_setup(setup);
  Impl& m = *impl_;
  m.s.dt = setup.dt;
  m.s.gravity = setup.gravity;
  m.s.boundaries = setup.boundaries;
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
  m.s.friction = std::visit([](const auto& law) { return law.friction() > 0.0; }, setup.law);
  m.kernel = make_force_kernel(setup);
  for (auto& p : setup.particles) m.r_max = std::max(m.r_max, p.radius);
  m.skin = options.skin_fraction * m.r_max;
  m.material = setup.material;
  m.load_particles(setup.particles, setup.material);
  std::fill(m.s.f.begin(), m.s.f.end(), Vec3::Zero());  // the first evaluation sets them
  std::fill(m.s.t.begin(), m.s.t.end(), Vec3::Zero());
  m.build_lists();
  m.evaluate_forces(0.0);  // a(0); no history increment at start-up
}

FastEngine::~FastEngine() = default;

std::unique_ptr<DemEngine> FastEngine::make(const SimulationSetup& setup) {
  return std::make_unique<FastEngine>(setup);
}

void FastEngine::step() { impl_->step(); }
long FastEngine::step_count() const { return impl_->steps; }
double FastEngine::time() const { return static_cast<double>(impl_->steps) * impl_->s.dt; }

const Particles& FastEngine::particles() const {
  Impl& m = *impl_;
  if (!m.out_valid) {
    const FastState& s = m.s;
    m.out.resize(s.size());
    for (std::size_t k = 0; k < s.size(); ++k) {
      Particle& p = m.out[s.original[k]];
      p.id = s.id[k];
      p.position = s.x[k];
      p.velocity = s.v[k];
      p.angular_velocity = s.w[k];
      p.radius = s.radius[k];
      p.force = s.f[k];
      p.torque = s.t[k];
    }
    m.out_valid = true;
  }
  return m.out;
}

Energies FastEngine::energies() const {
  const Impl& m = *impl_;
  const FastState& s = m.s;
  Energies e;
  for (const std::uint32_t i : s.where) {  // construction order (see evaluate_forces)
    e.kinetic += 0.5 * s.mass[i] * s.v[i].squaredNorm();
    e.rotational += 0.5 * s.inertia[i] * s.w[i].squaredNorm();
    e.gravitational -= s.mass[i] * s.gravity.dot(s.x[i]);
  }
  e.elastic = m.elastic;
  e.dissipated = m.dissipated;
  e.boundary_work = m.boundary_work;
  return e;
}

ContactCounts FastEngine::contact_counts() const {
  return {impl_->s.pair_contacts, impl_->s.boundary_contacts};
}

std::size_t FastEngine::escaped_count() const {
  return static_cast<std::size_t>(
      std::count_if(impl_->s.escaped_via.begin(), impl_->s.escaped_via.end(), [](std::int32_t e) { return e != 0; }));
}

std::vector<BoundaryLoad> FastEngine::boundary_loads() const { return impl_->loads; }

std::optional<LargestOverlap> FastEngine::largest_overlap() const {
  // The reference reports ratio 0 (no contact) as an empty record; so do we.
  return impl_->s.deepest.value_or(LargestOverlap{});
}

long FastEngine::neighbour_list_builds() const { return impl_->builds; }
double FastEngine::skin() const { return impl_->skin; }
std::size_t FastEngine::neighbour_slots() const { return impl_->s.partner.size(); }

std::size_t FastEngine::memory_bytes() const {
  const FastState& s = impl_->s;
  return bytes(s.id) + bytes(s.original) + bytes(s.where) + bytes(s.x) + bytes(s.v) + bytes(s.w) + bytes(s.f) + bytes(s.t) +
         bytes(s.pv) + bytes(s.pw) + bytes(s.x_build) + bytes(s.radius) + bytes(s.mass) + bytes(s.inertia) +
         bytes(s.escaped_via) + bytes(s.elastic_p) + bytes(s.dissipated_p) + bytes(s.work_p) + bytes(s.power_p) + bytes(s.first) +
         bytes(s.partner) + bytes(s.spring) + bytes(s.records) + bytes(s.record_first);
}

EngineState FastEngine::save_state() const {
  const Impl& m = *impl_;
  const FastState& s = m.s;
  EngineState state;
  state.engine = name();
  state.step = m.steps;
  state.dt = s.dt;
  state.particles = particles();
  if (s.friction) {
    for (std::size_t k = 0; k < s.size(); ++k) {
      for (std::uint32_t slot = s.first[k]; slot < s.first[k + 1]; ++slot) {
        const std::uint32_t j = s.partner[slot];
        const TangentialSpring& sp = s.spring[slot];
        if (s.id[k] < s.id[j] && (sp.stiffness != 0.0 || sp.branch_i != Vec3::Zero())) {
          state.contacts.push_back({ContactHistoryRecord::Kind::kParticlePair, s.id[k], s.id[j], sp});
        }
      }
    }
    for (const BoundaryRecord& r : s.records) {
      state.contacts.push_back({ContactHistoryRecord::Kind::kParticleBoundary, s.id[r.particle],
                                static_cast<std::int64_t>(r.boundary), r.spring});
    }
    std::sort(state.contacts.begin(), state.contacts.end(), [](const auto& a, const auto& b) {
      return std::tuple(a.kind, a.id_a, a.id_b) < std::tuple(b.kind, b.id_a, b.id_b);
    });
  }
  state.accumulators = energies();
  for (std::size_t k = 0; k < s.size(); ++k) {
    if (s.escaped_via[k] != 0) state.escaped_ids.push_back(s.id[k]);
  }
  std::sort(state.escaped_ids.begin(), state.escaped_ids.end());
  state.boundary_loads = m.loads;
  state.contact_counts = contact_counts();
  state.boundary_power = m.power;  // P(n), for the next trapezoid step of boundary_work
  return state;
}

void FastEngine::restore_state(const EngineState& state) {
  Impl& m = *impl_;
  FastState& s = m.s;
  const Particles& current = particles();
  if (state.dt != s.dt) throw InputError("restore_state: the checkpoint's dt differs from the scene's");
  if (state.particles.size() != current.size()) {
    throw InputError("restore_state: the checkpoint has " + std::to_string(state.particles.size()) +
                     " particles, the scene " + std::to_string(current.size()));
  }
  for (std::size_t i = 0; i < current.size(); ++i) {
    if (state.particles[i].id != current[i].id || state.particles[i].radius != current[i].radius) {
      throw InputError("restore_state: particle " + std::to_string(i) + " (id " +
                       std::to_string(state.particles[i].id) + ") does not match the scene");
    }
  }
  if (state.boundary_loads.size() != s.boundaries.size()) {
    throw InputError("restore_state: the checkpoint's boundary count differs from the scene's");
  }
  m.load_particles(state.particles, m.material);
  m.steps = state.step;
  m.elastic = state.accumulators.elastic;
  m.dissipated = state.accumulators.dissipated;
  m.boundary_work = state.accumulators.boundary_work;
  m.loads = state.boundary_loads;
  m.power = state.boundary_power;
  s.deepest.reset();  // of the evaluation before the checkpoint: not saved (as the reference)
  s.pair_contacts = state.contact_counts.particle_pairs;
  s.boundary_contacts = state.contact_counts.particle_boundary;
  m.build_lists();
  std::unordered_map<std::int64_t, std::uint32_t> where;
  for (std::size_t k = 0; k < s.size(); ++k) where[s.id[k]] = static_cast<std::uint32_t>(k);
  for (const std::int64_t id : state.escaped_ids) {
    s.escaped_via[m.storage_index_of(id, where)] = 1;  // the boundary is only used in the warning
  }
  std::vector<BoundaryRecord> records;
  for (const ContactHistoryRecord& c : state.contacts) {
    const std::size_t a = m.storage_index_of(c.id_a, where);
    if (c.kind == ContactHistoryRecord::Kind::kParticleBoundary) {
      if (c.id_b < 0 || static_cast<std::size_t>(c.id_b) >= s.boundaries.size()) {
        throw InputError("restore_state: boundary index " + std::to_string(c.id_b) + " out of range");
      }
      BoundaryRecord r;
      r.particle = static_cast<std::uint32_t>(a);
      r.boundary = static_cast<std::uint32_t>(c.id_b);
      r.spring = c.spring;
      records.push_back(r);
      continue;
    }
    if (!s.friction) continue;
    const std::size_t b = m.storage_index_of(c.id_b, where);
    auto install = [&](std::size_t self, std::size_t other, const TangentialSpring& spring) {
      const auto begin = s.partner.begin() + s.first[self];
      const auto end = s.partner.begin() + s.first[self + 1];
      const auto it = std::lower_bound(begin, end, s.id[other], [&](std::uint32_t j, std::int64_t id) { return s.id[j] < id; });
      if (it == end || *it != other) {
        throw InputError("restore_state: contact (" + std::to_string(c.id_a) + ", " + std::to_string(c.id_b) +
                         ") is not between neighbouring particles");
      }
      s.spring[static_cast<std::size_t>(it - s.partner.begin())] = spring;
    };
    install(a, b, c.spring);
    install(b, a, mirrored(c.spring));
  }
  std::sort(records.begin(), records.end(), [](const BoundaryRecord& x, const BoundaryRecord& y) {
    return std::pair(x.particle, x.boundary) < std::pair(y.particle, y.boundary);
  });
  s.records = std::move(records);
  s.record_first.assign(s.size() + 1, 0);
  for (const BoundaryRecord& r : s.records) ++s.record_first[r.particle + 1];
  for (std::size_t i = 0; i < s.size(); ++i) s.record_first[i + 1] += s.record_first[i];
  m.out_valid = false;
}

}  // namespace ppohdem::dem::fast
