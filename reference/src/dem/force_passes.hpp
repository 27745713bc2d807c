#pragma once
// The force passes of the reference engine, one class template per interaction kind and
// instantiated per (law, friction) at construction: a frictionless scene runs the kernel
// without any tangential history code, a scene without walls has no boundary pass at all.
//
// Geometry of a contact between spheres i and j (docs/dem.md):
//   d = x_i - x_j,  n = d / |d|          unit normal from j towards i
//   delta = R_i + R_j - |d| > 0          overlap [m]
//   r_i = -(R_i - delta/2) n,  r_j = (R_j - delta/2) n   branch vectors to the contact point
//   v_rel = (v_i + w_i x r_i) - (v_j + w_j x r_j)       relative velocity there [m/s]
//   m* = m_i m_j / (m_i + m_j),  R* = R_i R_j / (R_i + R_j)   [kg], [m]
// A boundary is a body j of infinite mass and radius: m* = m_i, R* = R_i, and v_j + w_j x r_j
// is the velocity of its material at the contact point.
// The force laws (contact_law.hpp): Hertz 1882 normal elasticity F_n = (4/3) E* sqrt(R*)
// delta^{3/2}; Tsuji, Tanaka & Ishida 1992 damping ~ delta^{1/4} delta_dot; Mindlin &
// Deresiewicz 1953 tangential stiffness k_t = 8 G* sqrt(R* delta) with the Coulomb cap
// |F_t| <= mu F_n (contact_force.hpp); or the linear spring-dashpot of Cundall & Strack 1979.
// Rolling resistance (CDT or EPSD2) adds a torque M on i and -M on j (rolling_resistance.hpp).
// Newton's third law: F on i, -F on j; torques r_i x F (+ M) on i, r_j x (-F) (- M) on j.
#include <algorithm>
#include <array>
#include <cstdio>
#include <map>
#include <string>
#include <set>
#include <utility>
#include <vector>

#include "ppohdem/dem/boundary.hpp"
#include "ppohdem/dem/contact_force.hpp"
#include "ppohdem/dem/material.hpp"
#include "ppohdem/dem/pair_laws.hpp"
#include "ppohdem/error.hpp"
#include "ppohdem/dem/reference/cell_list.hpp"
#include "ppohdem/dem/reference/reference_engine.hpp"

namespace ppohdem::dem::reference {

using ppohdem::dem::ContactForce;
using ppohdem::dem::ContactKinematics;
using ppohdem::dem::harmonic_pair;
using ppohdem::dem::Particle;
using ppohdem::dem::TangentialSpring;

/// A contact that ended (k_t' = 0) loses the energy left in its tangential spring:
/// D_k = k |xi|^2 / 2 (contact_force.hpp) [J].
inline double ended(const TangentialSpring& spring) { return spring.stored_energy(); }

/// Frictionless contacts keep no history: the kernel calls normal_contact_force only.
/// With friction, the spring of each contact lives in `history` between steps.
/// The law of a contact is that of the two particles' materials (pair_laws.hpp).
template <class Law, bool kFriction>
class PairForces final : public ForcePass {
 public:
  explicit PairForces(ppohdem::dem::PairLaws<Law> laws) : laws_(std::move(laws)) {}

  void add_forces(ForceContext& c) override {
    Particles& p = c.particles;
    auto pairs = touching_pairs(p);  // (i, j) with id_i < id_j
    active_ = pairs.size();
    std::sort(pairs.begin(), pairs.end(), [&](const auto& a, const auto& b) {
      return visited_before(Key(p[a.first].id, p[a.second].id), Key(p[b.first].id, p[b.second].id));
    });
    // Both `pairs` and `history_` are in visit order: the old spring of a contact is found by
    // walking a cursor through the old history (a merge), and entries the cursor skips are
    // contacts that ended.
    History next_history;
    auto old = history_.begin();
    for (const auto& [i, j] : pairs) {
      Particle& a = p[i];
      Particle& b = p[j];
      // Normal, overlap and branch vectors to the contact point in the middle of the overlap.
      const ppohdem::dem::SpherePairGeometry g = ppohdem::dem::sphere_pair_geometry(a.position - b.position, a.radius, b.radius);
      ContactKinematics k;
      k.normal = g.normal;
      k.overlap = g.overlap;
      const Vec3& r_a = g.r_i;
      const Vec3& r_b = g.r_j;
      k.relative_velocity = (c.velocity[i] + c.angular_velocity[i].cross(r_a)) -
                            (c.velocity[j] + c.angular_velocity[j].cross(r_b));
      k.relative_displacement = c.dt * ((a.velocity + a.angular_velocity.cross(r_a)) -
                                        (b.velocity + b.angular_velocity.cross(r_b)));
      k.pair.m_eff = harmonic_pair(c.mass[i], c.mass[j]);  // m* = m_i m_j / (m_i + m_j)
      k.pair.r_eff = harmonic_pair(a.radius, b.radius);    // R* = R_i R_j / (R_i + R_j)
      c.note_overlap(k.overlap, std::min(a.radius, b.radius), a.id, b.id, false);
      const Law& law = laws_.pair(a.material, b.material);
      if (law.rolling().active()) {  // rolling_resistance.hpp
        k.relative_spin = c.angular_velocity[i] - c.angular_velocity[j];
        k.relative_rotation = c.dt * (a.angular_velocity - b.angular_velocity);
      }
      ContactForce f;
      if constexpr (kFriction) {
        const Key key(a.id, b.id);
        for (; old != history_.end() && visited_before(old->first, key); ++old) c.dissipated.add(ended(old->second));
        TangentialSpring spring;  // a new contact starts with xi = 0, k_t = 0
        if (old != history_.end() && old->first == key) spring = (old++)->second;
        k.relative_displacement_previous_arms =
            c.dt * ((a.velocity + a.angular_velocity.cross(spring.branch_i)) -
                    (b.velocity + b.angular_velocity.cross(spring.branch_j)));
        f = ppohdem::dem::frictional_contact_force(law, k, spring, c.dt);
        spring.branch_i = r_a;
        spring.branch_j = r_b;
        next_history.emplace_back(key, spring);
      } else {
        f = ppohdem::dem::normal_contact_force(law, k, c.dt);
      }
      // Newton's third law: equal and opposite forces at the contact point.
      a.force += f.on_i;
      b.force -= f.on_i;
      if (law.rolling().active()) {  // the rolling torque acts on i, its opposite on j
        a.torque += r_a.cross(f.on_i) + f.rolling_torque;
        b.torque += -(r_b.cross(f.on_i) + f.rolling_torque);
      } else {
        a.torque += r_a.cross(f.on_i);
        b.torque += r_b.cross(-f.on_i);
      }
      c.elastic.add(f.elastic_energy);
      c.dissipated.add(f.dissipated);
    }
    if constexpr (kFriction) {
      for (; old != history_.end(); ++old) c.dissipated.add(ended(old->second));
      history_ = std::move(next_history);
    }
  }
  std::size_t active_contacts() const override { return active_; }

  void save(EngineState& state) const override {
    state.contact_counts.particle_pairs = active_;
    if constexpr (kFriction) {
      History sorted = history_;  // checkpoints list them by (id_a, id_b)
      std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
      for (const auto& [key, spring] : sorted) {
        state.contacts.push_back({Record::Kind::kParticlePair, key.first, key.second, spring});
      }
    }
  }
  void restore(const EngineState& state) override {
    active_ = state.contact_counts.particle_pairs;
    History history;
    for (const Record& r : state.contacts) {
      if (r.kind != Record::Kind::kParticlePair) continue;
      if (!kFriction) {
        throw InputError("checkpoint: a particle-pair friction history, but this scene is frictionless");
      }
      const Key key(r.id_a, r.id_b);
      if (r.id_a >= r.id_b || (!history.empty() && !(history.back().first < key))) {
        throw InputError("checkpoint: particle-pair histories are not sorted by (id_a < id_b)");
      }
      history.emplace_back(key, r.spring);
    }
    std::sort(history.begin(), history.end(), [](const auto& a, const auto& b) { return visited_before(a.first, b.first); });
    history_ = std::move(history);
  }

 private:
  using Record = ppohdem::dem::ContactHistoryRecord;
  ppohdem::dem::PairLaws<Law> laws_;
  std::size_t active_ = 0;
  using Key = std::pair<std::int64_t, std::int64_t>;  // (id_i, id_j), id_i < id_j
  using History = std::vector<std::pair<Key, TangentialSpring>>;
  /// The order in which the pass visits the pairs: by the lower id DEScending, then by the
  /// higher id ascending. WHY this order: floating-point sums depend on their order, and this
  /// one is the order in which the parallel fast engine can add each particle's contacts
  /// without atomics, so both engines give the same bits. With Newton's third law applied at
  /// each pair, every particle receives its contacts with higher-id partners (ascending id)
  /// first and those with lower-id partners (descending id) after them, before the boundary
  /// pass adds its boundaries: the fast engine adds the first part in its pass over the
  /// contacts each particle evaluates, the rest in its pass over the partners' results
  /// (docs/dem.md, "Reproducibility argument").
  static bool visited_before(const Key& a, const Key& b) {
    return a.first != b.first ? a.first > b.first : a.second < b.second;
  }
  History history_;  // in visit order; the seed's contact_list
};

/// Particle-boundary contacts: the boundary is body j with infinite mass and radius, so
/// m* = m_i, R* = R_i, and the boundary material moves with surface_velocity. The law is that
/// of the particle's material with the boundary's (its own if the boundary has none).
template <class Law, bool kFriction>
class BoundaryForces final : public ForcePass {
 public:
  BoundaryForces(ppohdem::dem::PairLaws<Law> laws, ppohdem::dem::BoundaryList boundaries)
      : laws_(std::move(laws)), boundaries_(std::move(boundaries)) {}

  void add_forces(ForceContext& c) override {
    Particles& p = c.particles;
    active_ = 0;
    load_sums_.assign(boundaries_.size(), {});
    std::map<std::pair<std::int64_t, std::int64_t>, TangentialSpring> next_history;
    ppohdem::dem::ExactSum power_sum;  // P(n+1) = sum of (F_i - F_d) . v_s over the contacts [W]
    for (std::size_t i = 0; i < p.size(); ++i) {
      Particle& a = p[i];
      for (std::size_t w = 0; w < boundaries_.size(); ++w) {
        const auto& boundary = *boundaries_[w];
        if (boundary.has_escaped(a.position, c.time)) {
          if (escaped_.insert(a.id).second) {
            std::fprintf(stderr, "warning: particle id %lld left the domain through %s at t = %g s\n",
                         static_cast<long long>(a.id), boundary.describe().c_str(), c.time);
          }
          continue;
        }
        boundary.contacts(a.position, a.radius, c.time, touching_);  // by feature (boundary.hpp)
        for (const ppohdem::dem::FeatureContact& touching : touching_) {
          const auto* contact = &touching.contact;
          ++active_;
          c.note_overlap(contact->overlap, a.radius, a.id, static_cast<std::int64_t>(w), true);
          ContactKinematics k;
          k.normal = contact->normal;
          k.overlap = contact->overlap;
          const Vec3 r_a = contact->point - a.position;  // branch vector to the contact point [m]
          k.relative_velocity =
              c.velocity[i] + c.angular_velocity[i].cross(r_a) - contact->surface_velocity;
          k.pair.m_eff = c.mass[i];
          k.pair.r_eff = a.radius;
          const Law& law = laws_.boundary(a.material, w);
          if (law.rolling().active()) {  // the boundary's spin is that of its material
            k.relative_spin = c.angular_velocity[i] - contact->surface_spin;
            k.relative_rotation = c.dt * (a.angular_velocity - contact->surface_spin);
          }
          ContactForce f;
          if constexpr (kFriction) {
            const auto key = std::pair(a.id, ppohdem::dem::boundary_history_key(w, touching.feature));
            TangentialSpring spring;
            const auto it = history_.find(key);
            if (it != history_.end()) spring = it->second;
            // The boundary's material moved by (v_s(n) + v_s(n+1)) dt / 2 during the step (the
            // trapezoid rule of Verlet; contact_force.hpp "Moving boundaries") [m/s].
            const Vec3 v_s = ppohdem::dem::boundary_step_velocity(spring, it != history_.end(),
                                                                  contact->surface_velocity);
            k.relative_displacement = c.dt * (a.velocity + a.angular_velocity.cross(r_a) - v_s);
            k.relative_displacement_previous_arms =
                c.dt * (a.velocity + a.angular_velocity.cross(spring.branch_i) - v_s);
            f = ppohdem::dem::frictional_contact_force(law, k, spring, c.dt);
            spring.branch_i = r_a;
            next_history.emplace(key, spring);
          } else {
            f = ppohdem::dem::normal_contact_force(law, k, c.dt);
          }
          a.force += f.on_i;
          if (law.rolling().active()) {
            a.torque += r_a.cross(f.on_i) + f.rolling_torque;
          } else {
            a.torque += r_a.cross(f.on_i);
          }
          // Reaction on the boundary (Newton's third law), at the contact point.
          // The terms summed exactly (exact_sum.hpp): -F, p x (-F) and -M [N, N m].
          const Vec3 moment = contact->point.cross(-f.on_i);
          for (int x = 0; x < 3; ++x) {
            load_sums_[w][x].add(-f.on_i[x]);
            load_sums_[w][3 + x].add(moment[x]);
            if (law.rolling().active()) load_sums_[w][3 + x].add(-f.rolling_torque[x]);
          }
          c.elastic.add(f.elastic_energy);
          c.dissipated.add(f.dissipated);
          // Work of the boundary on the particle (contact_force.hpp "Moving boundaries"): the
          // dashpot's share now, F_d . v_s dt, as its dissipation; the rest below [J].
          c.boundary_work.add(f.dashpot.dot(contact->surface_velocity) * c.dt);
          power_sum.add((f.on_i - f.dashpot).dot(contact->surface_velocity));
        }
      }
    }
    // The rest by the trapezoid rule, as Verlet books the kinetic energy:
    // W = (P(n) + P(n+1)) dt / 2 [J]. The start-up evaluation has dt = 0: it records P(0).
    const double power = power_sum.value();
    c.boundary_work.add(0.5 * (power_ + power) * c.dt);
    power_ = power;
    loads_.resize(boundaries_.size());
    for (std::size_t w = 0; w < boundaries_.size(); ++w) {
      loads_[w].force = Vec3(load_sums_[w][0].value(), load_sums_[w][1].value(), load_sums_[w][2].value());
      loads_[w].moment_about_origin = Vec3(load_sums_[w][3].value(), load_sums_[w][4].value(), load_sums_[w][5].value());
    }
    if constexpr (kFriction) {
      for (const auto& [key, spring] : history_) {
        if (!next_history.count(key)) c.dissipated.add(ended(spring));
      }
      history_ = std::move(next_history);
    }
  }
  std::size_t active_contacts() const override { return active_; }
  std::size_t escaped() const override { return escaped_.size(); }
  std::vector<ppohdem::dem::BoundaryLoad> loads() const override { return loads_; }

  void save(EngineState& state) const override {
    state.contact_counts.particle_boundary = active_;
    state.boundary_power = power_;
    state.boundary_loads = loads_;
    state.escaped_ids.assign(escaped_.begin(), escaped_.end());
    for (const auto& [key, spring] : history_) {
      state.contacts.push_back({Record::Kind::kParticleBoundary, key.first, key.second, spring});
    }
  }
  void restore(const EngineState& state) override {
    if (state.boundary_loads.size() != boundaries_.size()) {
      throw InputError("checkpoint: " + std::to_string(state.boundary_loads.size()) +
                       " boundaries, the scene has " + std::to_string(boundaries_.size()));
    }
    decltype(history_) history;
    for (const Record& r : state.contacts) {
      if (r.kind != Record::Kind::kParticleBoundary) continue;
      if (!kFriction) {
        throw InputError("checkpoint: a particle-boundary friction history, but this scene is frictionless");
      }
      if (r.id_b < 0 || ppohdem::dem::boundary_of_history_key(r.id_b) >= boundaries_.size()) {
        throw InputError("checkpoint: a contact history with boundary " +
                         std::to_string(ppohdem::dem::boundary_of_history_key(r.id_b)) + ", the scene has " +
                         std::to_string(boundaries_.size()));
      }
      history.emplace(std::pair(r.id_a, r.id_b), r.spring);
    }
    history_ = std::move(history);
    escaped_ = std::set<std::int64_t>(state.escaped_ids.begin(), state.escaped_ids.end());
    loads_ = state.boundary_loads;
    active_ = state.contact_counts.particle_boundary;
    power_ = state.boundary_power;
  }

 private:
  using Record = ppohdem::dem::ContactHistoryRecord;
  ppohdem::dem::PairLaws<Law> laws_;
  ppohdem::dem::BoundaryList boundaries_;
  std::vector<ppohdem::dem::BoundaryLoad> loads_;  ///< per boundary, last evaluation
  /// Per boundary the exact sums of the last evaluation's load terms: force x, y, z, then
  /// moment about the origin x, y, z (rounded into loads_).
  std::vector<std::array<ppohdem::dem::ExactSum, 6>> load_sums_;
  std::size_t active_ = 0;
  double power_ = 0.0;  ///< P(n) of the last evaluation, without the dashpots' share [W]
  std::set<std::int64_t> escaped_;
  /// (particle id, boundary_history_key(boundary, feature)) -> spring; seed: contact_list_wall
  std::map<std::pair<std::int64_t, std::int64_t>, TangentialSpring> history_;
  std::vector<ppohdem::dem::FeatureContact> touching_;  ///< scratch: one boundary's contacts
};

}  // namespace ppohdem::dem::reference
