// Run diagnostics: the checks after every step (ppohdem/dem/run_diagnostics.hpp).
#include "ppohdem/dem/run_diagnostics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace ppohdem::dem {
namespace {

std::string format_vec(const Vec3& v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.6g, %.6g, %.6g)", v.x(), v.y(), v.z());
  return buf;
}

std::string where(const DemEngine& engine) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "step %ld (t = %.6g s)", engine.step_count(), engine.time());
  return buf;
}

const Particle* find_id(const Particles& particles, std::int64_t id) {
  for (const Particle& p : particles) {
    if (p.id == id) return &p;
  }
  return nullptr;
}

/// The largest overlap an ELASTIC collision reaches at approach speed v [m/s]: the delta with
/// U(delta) = m* v^2 / 2, U the law's elastic energy (Hertz: delta = (15 m* v^2 /
/// (16 E* sqrt(R*)))^(2/5), Johnson 1985 sec. 11.4; linear: v sqrt(m*/k_n)); by bisection
/// so that it holds for every law [m].
double elastic_overlap_at_speed(const ContactLaw& law, const PairProperties& pair, double v) {
  const double kinetic = 0.5 * pair.m_eff * v * v;  // [J]
  double lo = 0.0, hi = pair.r_eff;
  return std::visit(
      [&](const auto& l) {
        if (l.elastic_energy(hi, pair) < kinetic) return hi;  // more than R*: "> R*"
        for (int k = 0; k < 60; ++k) {
          const double mid = 0.5 * (lo + hi);
          (l.elastic_energy(mid, pair) < kinetic ? lo : hi) = mid;
        }
        return hi;
      },
      law);
}

}  // namespace

RunDiagnostics::RunDiagnostics(const SimulationSetup& setup, const RunChecks& checks, const Energies& initial,
                               double initial_overlap, std::optional<TimeStepLimit> limit)
    : setup_(setup),
      checks_(checks),
      initial_(initial),
      initial_overlap_(initial_overlap),
      limit_(limit ? *limit : time_step_limit(setup)) {}

std::string RunDiagnostics::time_step_note() const {
  char buf[200];
  std::snprintf(buf, sizeof buf, "dt = %.4g s is %.0f %% of the stability limit %.4g s", setup_.dt,
                100.0 * setup_.dt / limit_.limit, limit_.limit);
  return buf;
}

std::optional<std::string> RunDiagnostics::check(const DemEngine& engine, bool balance) {
  // Screening without a copy of the particle state (engine.particles() plus the per-particle
  // scans every step were a large part of a fast-engine step: docs/performance.md "Run checks
  // without a copy of the state"):
  // - the energy sums are not finite as soon as one position (m g.x: 0 * NaN and 0 * inf are
  //   NaN as well), velocity or angular velocity is not, and a non-finite force or torque enters
  //   the velocities at its kick (this step or the next), so the full scan runs only then and
  //   names the particle;
  // - both engines test Boundary::has_escaped for every particle in their force pass and count
  //   the escapes, so the per-particle escape scan runs only when that count has grown (and at
  //   every step when a [checks] box is set: the engines do not know it).
  // Between the balance checks the energies are not needed here: the engine's own screen
  // (DemEngine::motion_finite; the fast engine sums the energies of the state only when asked).
  std::optional<Energies> energies;
  if (setup_.energy_balance && balance) {
    energies = engine.energies();
    if (!std::isfinite(energies->kinetic + energies->rotational + energies->gravitational + energies->elastic)) {
      if (auto d = check_finite(engine)) return d;
    }
  } else if (!engine.motion_finite()) {
    if (auto d = check_finite(engine)) return d;
  }
  const std::size_t escaped = engine.escaped_count();
  if (escaped > escaped_seen_ || (checks_.domain_min && checks_.domain_max)) {
    if (auto d = check_domain(engine)) return d;
  }
  escaped_seen_ = escaped;
  if (auto d = check_overlap(engine)) return d;
  if (!energies) return std::nullopt;  // no energy balance to check
  return check_energy(engine, *energies);
}

std::optional<std::string> RunDiagnostics::check_finite(const DemEngine& engine) const {
  for (const Particle& p : engine.particles()) {
    const char* what = !p.position.allFinite()           ? "position"
                       : !p.velocity.allFinite()         ? "velocity"
                       : !p.angular_velocity.allFinite() ? "angular velocity"
                       : !p.force.allFinite()            ? "contact force"
                       : !p.torque.allFinite()           ? "contact torque"
                                                         : nullptr;
    if (what == nullptr) continue;
    std::ostringstream s;
    s << "run stopped at " << where(engine) << ": particle id " << p.id << ": the " << what
      << " is not finite (position " << format_vec(p.position) << ", velocity " << format_vec(p.velocity)
      << ", force " << format_vec(p.force) << "). Likely cause: ";
    if (setup_.dt > limit_.limit) {
      s << "the time step is above the stability limit (" << time_step_note()
        << ", accepted by --force): velocity Verlet diverges; reduce dt";
    } else {
      s << "a numerical instability (" << time_step_note()
        << "): reduce dt or the stiffness, or two particles placed at the same point";
    }
    return s.str();
  }
  return std::nullopt;
}

std::optional<std::string> RunDiagnostics::check_domain(const DemEngine& engine) const {
  if (!checks_.stop_on_escape) return std::nullopt;
  const double t = engine.time();
  for (const Particle& p : engine.particles()) {
    std::string through;
    for (const auto& boundary : setup_.boundaries) {
      if (boundary->has_escaped(p.position, t)) {
        through = "crossed " + boundary->describe();
        break;
      }
    }
    if (through.empty() && checks_.domain_min && checks_.domain_max &&
        ((p.position.array() < checks_.domain_min->array()).any() ||
         (p.position.array() > checks_.domain_max->array()).any())) {
      through = "left the box [checks] domain_min " + format_vec(*checks_.domain_min) + ", domain_max " +
                format_vec(*checks_.domain_max);
    }
    if (through.empty()) continue;
    const double speed = p.velocity.norm();
    const double per_step = speed * setup_.dt;  // distance moved per step [m]
    std::ostringstream s;
    s << "run stopped at " << where(engine) << ": particle id " << p.id << " left the domain: its centre "
      << format_vec(p.position) << " " << through << " (speed " << speed << " m/s, " << per_step
      << " m per step = " << 100.0 * per_step / p.radius << " % of its radius " << p.radius << " m). Likely cause: ";
    PairProperties pair;
    pair.m_eff = setup_.material_at(p.material).mass(p.radius);
    pair.r_eff = p.radius;
    const double delta = elastic_overlap_at_speed(setup_.law, pair, speed);
    if (per_step > 0.5 * p.radius) {
      s << "dt too large for this speed: the particle passes the wall between two force evaluations ("
        << time_step_note() << "); reduce dt";
    } else if (delta >= 0.5 * p.radius) {
      s << "the contact is too soft for this speed: an elastic impact at " << speed << " m/s overlaps by "
        << delta << " m (" << 100.0 * delta / p.radius << " % of the radius); raise the stiffness "
        << "(Young's modulus) or lower the speeds";
    } else {
      s << "the particle started outside the domain, or an instability elsewhere threw it out ("
        << time_step_note() << ")";
    }
    return s.str();
  }
  return std::nullopt;
}

std::optional<std::string> RunDiagnostics::check_overlap(const DemEngine& engine) {
  std::optional<LargestOverlap> deepest = engine.largest_overlap();
  if (!deepest) {
    // The engine does not report it: look at particle pairs (sort and sweep).
    const Particles& particles = engine.particles();
    for (const auto& [i, j] : overlapping_pairs(particles, checks_.max_overlap + initial_overlap_)) {
      const Particle& a = particles[i];
      const Particle& b = particles[j];
      const double overlap = a.radius + b.radius - (a.position - b.position).norm();
      const double ratio = overlap / std::min(a.radius, b.radius);
      if (!deepest || ratio > deepest->ratio) deepest = LargestOverlap{ratio, overlap, a.id, b.id, false};
    }
    if (!deepest) return std::nullopt;
  }
  margins_.overlap = std::max(margins_.overlap, deepest->ratio);
  const double limit_ratio = checks_.max_overlap + initial_overlap_;
  if (!(deepest->ratio > limit_ratio)) return std::nullopt;

  const Particle* a = find_id(engine.particles(), deepest->id_a);
  if (a == nullptr) return "run stopped at " + where(engine) + ": overlap beyond the limit (particle not found)";
  PairProperties pair;
  double approach = 0.0;  // normal approach speed [m/s]
  std::ostringstream s;
  s << "run stopped at " << where(engine) << ": particle id " << a->id;
  if (deepest->boundary) {
    const auto& boundary = *setup_.boundaries.at(static_cast<std::size_t>(deepest->id_b));
    s << " overlaps " << boundary.describe();
    pair.m_eff = setup_.material_at(a->material).mass(a->radius);
    pair.r_eff = a->radius;
    std::vector<FeatureContact> contacts;  // a mesh object may give several: the deepest
    boundary.contacts(a->position, a->radius, engine.time(), contacts);
    const BoundaryContact* c = nullptr;
    for (const FeatureContact& f : contacts) {
      if (c == nullptr || f.contact.overlap > c->overlap) c = &f.contact;
    }
    if (c != nullptr) approach = std::abs((a->velocity - c->surface_velocity).dot(c->normal));
  } else {
    const Particle* b = find_id(engine.particles(), deepest->id_b);
    s << " and particle id " << deepest->id_b << " overlap";
    if (b != nullptr) {
      const double ma = setup_.material_at(a->material).mass(a->radius);
      const double mb = setup_.material_at(b->material).mass(b->radius);
      pair.m_eff = ma * mb / (ma + mb);
      pair.r_eff = a->radius * b->radius / (a->radius + b->radius);
      const Vec3 n = (a->position - b->position).normalized();
      approach = std::abs((a->velocity - b->velocity).dot(n));
    }
  }
  s << " by " << deepest->overlap << " m = " << 100.0 * deepest->ratio << " % of the radius (limit "
    << 100.0 * checks_.max_overlap << " %, [checks] max_overlap";
  if (initial_overlap_ > 0.0) s << ", beyond the " << 100.0 * initial_overlap_ << " % of the initial state";
  s << "). Likely cause: ";
  const double radius = deepest->overlap / deepest->ratio;
  const double limit = limit_ratio * radius;  // [m]
  const double per_step = approach * setup_.dt;       // approach per step at this speed [m]
  const double delta = pair.m_eff > 0.0 ? elastic_overlap_at_speed(setup_.law, pair, approach) : 0.0;
  if (per_step > 0.5 * limit) {
    // (The speed after the step includes the kick of the deep overlap itself.)
    s << "dt too large: the bodies move " << per_step << " m per step relative to each other at the normal "
      << "speed " << approach << " m/s, so the contact is resolved by too few steps (" << time_step_note()
      << "); reduce dt";
  } else if (delta > limit) {
    s << "the contact is too soft for the impact speed: an elastic impact at the normal speed " << approach
      << " m/s overlaps by " << delta << " m (" << 100.0 * delta / radius
      << " % of the radius); raise the stiffness (Young's modulus) or lower the speeds";
  } else {
    s << "a load pressing the bodies together (a moving wall or object, the weight above) that the "
      << "contact stiffness cannot carry: raise the stiffness; or dt too large (" << time_step_note()
      << "; an elastic impact at the normal speed " << approach << " m/s would overlap by only " << delta
      << " m)";
  }
  return s.str();
}

std::optional<std::string> RunDiagnostics::check_energy(const DemEngine& engine, const Energies& e) {
  if (!setup_.energy_balance) return std::nullopt;  // [simulation] energy_balance = false: no balance
  Energies e0 = initial_;  // with the inserted particles' energy as if present from the start
  e0.kinetic += input_.kinetic;
  e0.rotational += input_.rotational;
  e0.gravitational += input_.gravitational;
  const double scale = e0.kinetic + e0.rotational + e0.elastic + e.kinetic + e.rotational + e.elastic +
                       std::abs(e.dissipated) + std::abs(e.boundary_work) +
                       std::abs(e.gravitational - e0.gravitational) +
                       1e-10 * (std::abs(e.gravitational) + std::abs(e0.gravitational));  // rounding floor
  const double growth = e.total() - e0.total();  // [J]
  if (!(scale > 0.0)) return std::nullopt;
  const double ratio = growth / scale;
  margins_.energy_growth = std::max(margins_.energy_growth, ratio);
  if (!(ratio > checks_.max_energy_growth)) return std::nullopt;
  // The fastest particle is where the energy went.
  const Particles& particles = engine.particles();
  const Particle* fastest = particles.empty() ? nullptr : &particles.front();
  for (const Particle& p : particles) {
    if (p.velocity.squaredNorm() > fastest->velocity.squaredNorm()) fastest = &p;
  }
  std::ostringstream s;
  s << "run stopped at " << where(engine) << ": the energy grew without input: the balance "
    << "(kinetic + rotational + gravitational + elastic + dissipated - boundary work) rose by " << growth
    << " J since step 0, " << 100.0 * ratio << " % of the energy in play " << scale << " J (limit "
    << 100.0 * checks_.max_energy_growth << " %, [checks] max_energy_growth)";
  if (fastest != nullptr) {
    s << "; fastest particle id " << fastest->id << " at " << fastest->velocity.norm() << " m/s";
  }
  s << ". Likely cause: dt too large for the stiffness (" << time_step_note()
    << "; Verlet gains energy when contacts are resolved by too few steps), or a rigid object's "
    << "distance grid too coarse for the particles (docs/objects.md)";
  return s.str();
}

}  // namespace ppohdem::dem
