// The four- and eight-lane Hertz-Mindlin contacts (core/src/dem/fast/hertz_mindlin_x4.hpp; eight
// where the CPU has AVX-512, four under PPOHDEM_SIMD=avx: ctest runs both) against their
// oracle, the scalar contact law of ppohdem/dem/contact_force.hpp: for random contacts, each
// lane's spring, pair result, energies and overlap must be the very bits of the scalar
// evaluation, including the cases that are selections in the lanes (a new contact with an
// empty history, a history parallel to the normal, Coulomb slip, a separating contact whose
// damped force is clamped to zero) and short last groups (counts not a multiple of 4 or 8: a
// rest of 5-7 goes as a group of eight with repeated lanes, of 1-4 as a group of four).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <optional>
#include <random>
#include <utility>

#include "ppohdem/dem/contact_force.hpp"
#include "ppohdem/dem/material.hpp"
#include "ppohdem/error.hpp"
#include "../../core/src/dem/fast/hertz_mindlin_x4.hpp"  // internal

namespace ppohdem::dem::test {
namespace {

using fast::FastState;
using fast::PairEntry;
using fast::PairResult;

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool same_bits(const Vec3& a, const Vec3& b) {
  return same_bits(a.x(), b.x()) && same_bits(a.y(), b.y()) && same_bits(a.z(), b.z());
}

/// The scalar evaluation of one pair, written from contact_force.hpp as the reference engine
/// does it (reference/src/dem/force_passes.hpp): kinematics, frictional_contact_force, arms.
struct Scalar {
  TangentialSpring spring;
  Vec3 torque_i, torque_j;  ///< r_i x F, r_j x F [N m]
  ContactForce force;
  double overlap = 0.0;
};
Scalar scalar_contact(const HertzMindlin& law, const FastState& s, std::size_t i, std::size_t j, TangentialSpring spring,
                      double dt) {
  const Vec3 d = s.x[i] - s.x[j];
  const double distance = d.norm();
  ContactKinematics k;
  k.normal = d / distance;
  k.overlap = s.radius[i] + s.radius[j] - distance;
  const Vec3 r_i = -(s.radius[i] - 0.5 * k.overlap) * k.normal;
  const Vec3 r_j = (s.radius[j] - 0.5 * k.overlap) * k.normal;
  k.relative_velocity = (s.pv[i] + s.pw[i].cross(r_i)) - (s.pv[j] + s.pw[j].cross(r_j));
  k.relative_displacement = dt * ((s.v[i] + s.w[i].cross(r_i)) - (s.v[j] + s.w[j].cross(r_j)));
  k.relative_displacement_previous_arms =
      dt * ((s.v[i] + s.w[i].cross(spring.branch_i)) - (s.v[j] + s.w[j].cross(spring.branch_j)));
  k.pair.m_eff = s.mass[i] * s.mass[j] / (s.mass[i] + s.mass[j]);
  k.pair.r_eff = s.radius[i] * s.radius[j] / (s.radius[i] + s.radius[j]);
  Scalar out;
  out.force = frictional_contact_force(law, k, spring, dt);
  spring.branch_i = r_i;
  spring.branch_j = r_j;
  out.spring = spring;
  out.torque_i = r_i.cross(out.force.on_i);
  out.torque_j = r_j.cross(out.force.on_i);
  out.overlap = k.overlap;
  return out;
}

/// `pairs` random touching pairs (particles 2p, 2p + 1) of radii 0.3-0.7 mm with overlaps up
/// to 5 % of the smaller radius, velocities up to 1 m/s, spins up to 1000 rad/s, and histories
/// of the listed kinds; pair p's spring has code p in pool 0. `equal_blocks`: pairs come in
/// blocks of 8 whose 16 particles have one radius (0.5 mm, 0.45 mm, then a block of random
/// radii, and again), so whole groups of four contacts take the lanes' equal-particle path and
/// its cached constants change between blocks.
FastState random_pairs(std::size_t pairs, std::mt19937_64& rng, bool equal_blocks = false) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  FastState s;
  const std::size_t n = 2 * pairs;
  s.owned = n;
  s.x.resize(n);
  s.v.resize(n);
  s.w.resize(n);
  s.pv.resize(n);
  s.pw.resize(n);
  s.radius.resize(n);
  s.mass.resize(n);
  s.id.resize(n);
  s.f.assign(n, Vec3::Zero());
  s.t.assign(n, Vec3::Zero());
  s.terms.assign(n, FastState::ParticleTerms{});
  s.spring_pools.assign(1, fast::SpringPool{});
  s.spring_pools[0].resize(pairs);
  s.result_pools.assign(1, std::vector<PairResult>(pairs));
  s.pool_shift = 31;
  for (std::size_t p = 0; p < pairs; ++p) {
    const std::size_t i = 2 * p, j = i + 1;
    for (const std::size_t q : {i, j}) {
      s.radius[q] = 0.5e-3 * (1.0 + 0.4 * u(rng));               // [m]
      if (equal_blocks && (p / 8) % 3 != 2) s.radius[q] = (p / 8) % 3 == 0 ? 0.5e-3 : 0.45e-3;
      s.mass[q] = 2500.0 * 4.18879 * std::pow(s.radius[q], 3);   // [kg]
      s.v[q] = Vec3(u(rng), u(rng), u(rng));                     // [m/s]
      s.pv[q] = s.v[q] + 0.01 * Vec3(u(rng), u(rng), u(rng));
      s.w[q] = 1000.0 * Vec3(u(rng), u(rng), u(rng));            // [rad/s]
      s.pw[q] = s.w[q] + 10.0 * Vec3(u(rng), u(rng), u(rng));
    }
    const Vec3 normal = Vec3(u(rng), u(rng), u(rng)).normalized();
    const double overlap = 0.05 * std::min(s.radius[i], s.radius[j]) * unit(rng);
    s.x[j] = 1e-3 * Vec3(u(rng), u(rng), u(rng));
    s.x[i] = s.x[j] + (s.radius[i] + s.radius[j] - overlap) * normal;
    TangentialSpring spring;
    // Not a field of a pair spring (boundaries only): the law must leave it as it is.
    spring.surface_velocity = Vec3(u(rng), u(rng), u(rng));
    switch (p % 5) {
      case 0:  // a new contact: empty history
        break;
      case 1:  // a history in the tangent plane, small (sticking)
      case 2:  // large (slipping)
        spring.displacement = (p % 5 == 1 ? 1e-9 : 1e-4) * Vec3(u(rng), u(rng), u(rng));
        spring.stiffness = 1e3 * unit(rng);
        spring.branch_i = -s.radius[i] * normal + 1e-6 * Vec3(u(rng), u(rng), u(rng));
        spring.branch_j = s.radius[j] * normal;
        break;
      case 3:  // a history exactly along the normal: no tangential part to rotate
        spring.displacement = 1e-7 * normal;
        spring.stiffness = 500.0;
        break;
      default:  // separating fast: the damped normal force is clamped to 0
        s.pv[i] += 50.0 * normal;
        s.v[i] += 50.0 * normal;
        spring.displacement = 1e-6 * Vec3(u(rng), u(rng), u(rng));
        spring.stiffness = 800.0;
        break;
    }
    s.spring_pools[0].set(p, spring);
  }
  return s;
}

class ContactsX4 : public ::testing::TestWithParam<std::size_t> {};

/// False where the lanes never run: no AVX, or a forced PPOHDEM_SIMD this CPU lacks (refused).
bool lanes_run() {
  try {
    return fast::x4_contacts_available();
  } catch (const InputError&) {
    return false;
  }
}

TEST_P(ContactsX4, EveryLaneIsBitwiseTheScalarContact) {
  if (!lanes_run()) GTEST_SKIP() << "this CPU runs no AVX lanes (or not the level forced)";
  RecordProperty("lanes", fast::x8_contacts_available() ? 8 : 4);
  const std::size_t pairs = GetParam();
  std::mt19937_64 rng(2026 + pairs);
  Material m;
  m.density = 2500.0;
  m.young = 1.0e7;
  m.poisson = 0.3;
  m.restitution = 0.5;
  m.friction = 0.5;
  const HertzMindlin law = HertzMindlin::from_material(m);
  const double dt = 8.65e-6;  // [s]
  struct Mode {
    bool energy, equal_blocks, own_sums;
  };
  for (const Mode mode : {Mode{true, false, false}, Mode{false, false, false}, Mode{true, true, false},
                          Mode{true, false, true}, Mode{false, true, true}}) {
    const bool energy = mode.energy;
    FastState s = random_pairs(pairs, rng, mode.equal_blocks);
    std::vector<TangentialSpring> before;
    for (std::size_t p = 0; p < pairs; ++p) before.push_back(s.spring_pools[0].get(p));
    // Entries listed in reverse order of the pairs (not the storage order of the springs).
    // Every sixth a lower-id ghost's pair (kContact): its result keeps i's torque, and the
    // law's own sums leave it to the sum pass.
    std::vector<PairEntry> entries(pairs + 1);
    std::size_t upper = 0;
    for (std::size_t p = pairs; p-- > 0;) {
      PairEntry& e = entries[pairs - 1 - p];
      e.i = static_cast<std::uint32_t>(2 * p);
      e.j = static_cast<std::uint32_t>(2 * p + 1);
      e.code = static_cast<std::uint32_t>(p);
      e.kind = p % 6 == 5 ? PairEntry::kContact : PairEntry::kContactUpper;
      upper += e.kind == PairEntry::kContactUpper;
    }
    std::optional<LargestOverlap> deepest;
    std::vector<double> elastic(2 * pairs, 0.0), dissipated(2 * pairs, 0.0);  // the "chunk" is every particle
    fast::OwnSums own{&deepest, 0, 0, elastic.data(), dissipated.data()};
    fast::OwnSums* const sums = mode.own_sums ? &own : nullptr;
    if (energy) {
      fast::hertz_mindlin_x4<true>(law, s, entries.data(), pairs, dt, sums);
    } else {
      fast::hertz_mindlin_x4<false>(law, s, entries.data(), pairs, dt, sums);
    }
    if (mode.own_sums) {
      EXPECT_EQ(own.pairs, upper);  // each upper contact counted once, repeated lanes not
    }
    std::size_t slipping = 0, clamped = 0, differing = 0;
    for (std::size_t p = 0; p < pairs; ++p) {
      const Scalar want = scalar_contact(law, s, 2 * p, 2 * p + 1, before[p], dt);
      const TangentialSpring got = s.spring_pools[0].get(p);
      const PairResult& result = s.result_pools[0][p];
      const PairEntry& entry = entries[pairs - 1 - p];
      // The branch vectors are kept only with the energies (their one reader); else untouched.
      const TangentialSpring& branches = energy ? want.spring : before[p];
      bool same = same_bits(got.displacement, want.spring.displacement) && same_bits(got.stiffness, want.spring.stiffness) &&
                  same_bits(got.branch_i, branches.branch_i) && same_bits(got.branch_j, branches.branch_j) &&
                  same_bits(result.force, want.force.on_i) && same_bits(got.surface_velocity, before[p].surface_velocity);
      const bool lower_ghost = entry.kind == PairEntry::kContact;
      same = same && same_bits(result.torque_summed, lower_ghost ? want.torque_i : want.torque_j);
      if (mode.own_sums && lower_ghost) {  // nothing added: the sum pass adds it
        same = same && s.f[2 * p] == Vec3::Zero() && s.t[2 * p] == Vec3::Zero() &&
               (!energy || (elastic[2 * p] == 0.0 && dissipated[2 * p] == 0.0));
      } else if (mode.own_sums) {
        // The particle's one contact added to its zeroed sums: +0 + x is x (== also takes a
        // -0 term, whose sum is +0).
        same = same && s.f[2 * p] == want.force.on_i && s.t[2 * p] == want.torque_i;
        if (energy) {  // on i's side only
          same = same && elastic[2 * p] == want.force.elastic_energy && dissipated[2 * p] == want.force.dissipated &&
                 elastic[2 * p + 1] == 0.0 && dissipated[2 * p + 1] == 0.0;
        }
      } else {
        same = same && same_bits(entry.overlap, want.overlap);
        if (energy) same = same && same_bits(entry.elastic, want.force.elastic_energy) && same_bits(entry.dissipated, want.force.dissipated);
      }
      if (!same && differing++ == 0) {
        ADD_FAILURE() << "pair " << p << " of " << pairs << " (energy " << energy << ", equal blocks " << mode.equal_blocks
                      << ", own sums " << mode.own_sums << ") differs";
      }
      const Vec3 n = (s.x[2 * p] - s.x[2 * p + 1]).normalized();
      if (want.force.on_i.dot(n) == 0.0) ++clamped;
      // Slip: the tangential force sits on the Coulomb cap mu F_n (to round-off, 1e-9).
      const double f_n = want.force.on_i.dot(n);
      const double f_t = (want.force.on_i - f_n * n).norm();
      if (f_n > 0.0 && std::abs(f_t - 0.5 * f_n) <= 1e-9 * f_n) ++slipping;
    }
    EXPECT_EQ(differing, 0u);
    if (pairs >= 40) {  // not vacuous: the selections were exercised
      EXPECT_GT(clamped, 0u);
      EXPECT_GT(slipping, 0u);
    }
  }
}

// 1, 3 and 7 contacts: a short group only, and short last groups; 1000: many of each kind.
INSTANTIATE_TEST_SUITE_P(Counts, ContactsX4, ::testing::Values(1u, 3u, 7u, 9u, 12u, 13u, 1000u));

}  // namespace
}  // namespace ppohdem::dem::test
