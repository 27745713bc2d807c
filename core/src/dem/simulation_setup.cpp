#include "ppohdem/dem/simulation_setup.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <optional>
#include <unordered_set>

#include "checks_over_ranks.hpp"
#include "ppohdem/comm/comm.hpp"
#include "ppohdem/error.hpp"
#include "ppohdem/units.hpp"

namespace ppohdem::dem {
namespace {

std::string seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g s", s);
  return buf;
}

/// The materials of a setup, their pair rules and the boundaries' materials.
void validate_materials(const SimulationSetup& setup) {
  const std::string& where = setup.source;
  auto fail = [&](const std::string& what) { throw InputError(where, 0, what); };
  // E and nu enter Hertz-Mindlin and hooke (E*), not the constant-stiffness linear law.
  const auto* linear = std::get_if<LinearSpringDashpot>(&setup.law);
  const bool elastic = !linear || linear->per_contact_stiffness();
  const std::size_t count = setup.material_count();
  if (count == 1) {
    validate(setup.material, elastic, where);
  } else {
    if (count > kMaxMaterials) {
      fail(std::to_string(count) + " materials; at most " + std::to_string(kMaxMaterials) + " are supported");
    }
    for (std::size_t k = 0; k < count; ++k) {
      try {
        validate(setup.material_at(k), elastic, where);
      } catch (const InputError& e) {
        fail(setup.material_label(k) + ": " + e.message());
      }
    }
  }
  if (!setup.material_names.empty() && setup.material_names.size() != count) {
    fail(std::to_string(setup.material_names.size()) + " material names for " + std::to_string(count) +
         " materials");
  }
  for (const MaterialPairRule& r : setup.material_pairs) {
    const std::string what = "material pair (" + std::to_string(r.a) + ", " + std::to_string(r.b) + "): ";
    if (r.a >= count || r.b >= count) fail(what + "unknown material index");
    if (r.a == r.b) fail(what + "a pair of one material is given by the material itself");
    if (r.restitution && !(*r.restitution > 0.0 && *r.restitution <= 1.0)) {
      fail(what + "restitution must be in (0, 1], got " + std::to_string(*r.restitution));
    }
    if (r.friction && (!(*r.friction >= 0.0) || !std::isfinite(*r.friction))) {
      fail(what + "friction must be >= 0, got " + std::to_string(*r.friction));
    }
  }
  if (setup.boundary_materials.size() > setup.boundaries.size()) {
    fail("more boundary materials than boundaries");
  }
  for (const std::int32_t m : setup.boundary_materials) {
    if (m < -1 || (m >= 0 && static_cast<std::size_t>(m) >= count)) {
      fail("boundary material index " + std::to_string(m) + " out of range");
    }
  }
}

/// Hooke: 0.2 pi sqrt(m*/k_n) minimised over the pairs of the smallest particle of each
/// material with each other, with itself and with a boundary (R* = R, m* = m, each boundary
/// material). For one density and E*, k_n/m* ~ m*^{-4/5} R*^{2/5} is largest for the two
/// smallest spheres; across materials these candidates give the stiffest contacts.
TimeStepLimit hooke_time_step_limit(const SimulationSetup& setup, const LinearSpringDashpot& law) {
  const std::size_t count = setup.material_count();
  std::vector<double> r_min(count, std::numeric_limits<double>::infinity());
  for (const Particle& p : setup.particles) {
    const std::size_t k = p.material < count ? p.material : 0;
    r_min[k] = std::min(r_min[k], p.radius);
  }
  if (setup.shared()) {  // the minima over all the shares (exact: minima)
    for (double& r : r_min) r = -r;
    r_min = setup.share.comm->max_each_over_ranks(std::move(r_min));
    for (double& r : r_min) r = -r;
  }
  double half_period = std::numeric_limits<double>::infinity();
  auto consider = [&](std::size_t a, std::size_t b, const PairProperties& pair) {
    const LinearSpringDashpot l = law.for_pair(setup.material_at(a), setup.material_at(b), 1.0, 0.0);
    half_period = std::min(half_period, units::kPi * std::sqrt(pair.m_eff / l.stiffness(pair)));
  };
  for (std::size_t a = 0; a < count; ++a) {
    if (!std::isfinite(r_min[a])) continue;
    const double m_a = setup.material_at(a).mass(r_min[a]);
    for (std::size_t b = a; b < count; ++b) {
      if (!std::isfinite(r_min[b])) continue;
      const double m_b = setup.material_at(b).mass(r_min[b]);
      consider(a, b, {harmonic_pair(m_a, m_b), harmonic_pair(r_min[a], r_min[b])});
    }
    if (!setup.boundaries.empty()) {
      consider(a, a, {m_a, r_min[a]});
      for (const std::int32_t w : setup.boundary_materials) {
        if (w >= 0 && static_cast<std::size_t>(w) < count) consider(a, static_cast<std::size_t>(w), {m_a, r_min[a]});
      }
    }
  }
  return {0.2 * half_period, "0.2 * pi sqrt(m*/k_n) = 0.2 * " + seconds(half_period) +
                                 " (hooke: undamped half period of the stiffest contact)"};
}

}  // namespace

double rayleigh_time(double radius, const Material& material) {
  // T_R = pi R sqrt(rho / G) / (0.1631 nu + 0.8766)  [s]
  return units::kPi * radius * std::sqrt(material.density / material.shear_modulus()) /
         (0.1631 * material.poisson + 0.8766);
}

std::string SimulationSetup::material_label(std::size_t k) const {
  std::string label = "material ";
  if (k < material_names.size()) label += "'" + material_names[k] + "' (" + std::to_string(k) + ")";
  else label += std::to_string(k);
  return label;
}

TimeStepLimit time_step_limit(const SimulationSetup& setup) {
  if (!setup.insert_probes.empty()) {  // the particles to come count as well
    SimulationSetup all = setup;
    all.particles.insert(all.particles.end(), setup.insert_probes.begin(), setup.insert_probes.end());
    all.insert_probes.clear();
    return time_step_limit(all);
  }
  // A shared setup: each rank's minima, then the minima over the ranks (exact: the same as
  // over all the particles on one rank).
  const Comm* comm = setup.shared() ? setup.share.comm : nullptr;
  auto min_over_ranks = [comm](double v) { return comm != nullptr ? -comm->max_over_ranks(-v) : v; };
  const bool none = comm != nullptr ? comm->max_over_ranks(setup.particles.empty() ? 0.0 : 1.0) == 0.0
                                    : setup.particles.empty();
  if (none) return {std::numeric_limits<double>::infinity(), "no particles"};
  // Mass and Rayleigh time grow monotonically with R (also in floating point: products and
  // quotients of positive numbers), so with one material these minima are those of R_min.
  const auto material_of = [&](const Particle& p) -> const Material& {
    return setup.material_at(p.material < setup.material_count() ? p.material : 0);
  };
  const auto* linear = std::get_if<LinearSpringDashpot>(&setup.law);
  if (linear && linear->per_contact_stiffness()) return hooke_time_step_limit(setup, *linear);
  if (linear) {
    double m_min = std::numeric_limits<double>::infinity();
    for (const Particle& p : setup.particles) m_min = std::min(m_min, material_of(p).mass(p.radius));
    m_min = min_over_ranks(m_min);
    const double m_eff = m_min / 2.0;  // lightest pair, m* = m/2
    const double half_period = units::kPi * std::sqrt(m_eff / linear->normal_stiffness());
    return {0.2 * half_period, "0.2 * pi sqrt(m*/k_n) = 0.2 * " + seconds(half_period) +
                                   " (undamped half period of the lightest pair)"};
  }
  double t_r = std::numeric_limits<double>::infinity();
  for (const Particle& p : setup.particles) t_r = std::min(t_r, rayleigh_time(p.radius, material_of(p)));
  t_r = min_over_ranks(t_r);
  return {0.2 * t_r, "0.2 * Rayleigh time " + seconds(t_r) +
                         (setup.material_count() > 1 ? " of the fastest particle (size and material)"
                                                     : " of the smallest particle")};
}

void validate_setup(const SimulationSetup& setup) {
  const std::string& where = setup.source;
  auto fail = [&](const std::string& what) { throw InputError(where, 0, what); };
  if (!(setup.dt > 0.0) || !std::isfinite(setup.dt)) {
    fail("[simulation] dt must be > 0 s, got " + std::to_string(setup.dt));
  }
  if (!setup.gravity.allFinite()) fail("[simulation] gravity must be finite");
  validate_materials(setup);
  // The first bad particle in file order; of a shared setup, over all the shares (every rank
  // throws the same error).
  const std::size_t first = setup.shared() ? setup.share.first : 0;
  const std::size_t repeat = setup.shared() ? first_repeated_id(*setup.share.comm, setup.particles, first) : kNoRepeat;
  std::unordered_set<std::int64_t> ids;
  std::optional<PlacedError> bad;
  for (std::size_t i = 0; i < setup.particles.size() && !bad; ++i) {
    const Particle& p = setup.particles[i];
    const std::string record = "particle " + std::to_string(first + i) + " (id " + std::to_string(p.id) + "): ";
    std::string what;
    if (!(p.radius > 0.0) || !std::isfinite(p.radius)) {
      what = "radius must be > 0 m, got " + std::to_string(p.radius);
    } else if (!p.position.allFinite() || !p.velocity.allFinite() || !p.angular_velocity.allFinite()) {
      what = "position, velocity and angular velocity must be finite";
    } else if (setup.shared() ? first + i == repeat : !ids.insert(p.id).second) {
      what = "id repeated";
    } else if (p.material >= setup.material_count()) {
      what = "material index " + std::to_string(p.material) + ", the scene has " +
             std::to_string(setup.material_count()) + " material(s)";
    }
    if (!what.empty()) bad = PlacedError{first + i, InputError(where, 0, record + what)};
  }
  if (setup.shared()) throw_earliest_error(*setup.share.comm, bad);
  if (bad) throw bad->error;
  const TimeStepLimit limit = time_step_limit(setup);
  if (setup.dt > limit.limit && !setup.force_time_step) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.4g s", limit.limit);
    fail("[simulation] dt = " + seconds(setup.dt) + " is above the stability limit " + buf +
         " (" + limit.reason + "); use a smaller dt, or --force to run anyway");
  }
  if (!setup.allow_initial_overlap && !setup.shared()) {  // shared: the engine checks, once it has placed them
    const auto pairs = overlapping_pairs(setup.particles, 0.01);
    if (!pairs.empty()) {
      // The pair with the smallest ids (as over ranks: fast/initial_overlaps.cpp).
      auto ids_of = [&](const std::pair<std::size_t, std::size_t>& q) {
        const std::int64_t a = setup.particles[q.first].id, b = setup.particles[q.second].id;
        return std::pair(std::min(a, b), std::max(a, b));
      };
      const auto example = *std::min_element(pairs.begin(), pairs.end(), [&](const auto& x, const auto& y) {
        return ids_of(x) < ids_of(y);
      });
      const Particle& a = setup.particles[example.first];
      const Particle& b = setup.particles[example.second];
      throw a.id < b.id ? overlap_error(where, pairs.size(), a, b) : overlap_error(where, pairs.size(), b, a);
    }
  }
}

InputError overlap_error(const std::string& source, std::size_t count, const Particle& a, const Particle& b) {
  const double overlap = a.radius + b.radius - (a.position - b.position).norm();
  return InputError(source, 0, std::to_string(count) + " particle pair(s) overlap by more than 1% of the "
                    "smaller radius, e.g. ids " + std::to_string(a.id) + " and " + std::to_string(b.id) +
                    " by " + std::to_string(overlap) + " m; set [particles] allow_overlap = true to accept");
}

}  // namespace ppohdem::dem
