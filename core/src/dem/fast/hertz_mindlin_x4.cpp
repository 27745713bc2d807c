// Hertz-Mindlin contacts four at a time (see hertz_mindlin_x4.hpp). Every function that holds
// a 4-lane value carries target("avx") and is inlined into hertz_mindlin_x4_avx, which is
// called only after the CPU check: the rest of the program stays SSE2-only. Each formula below
// names its scalar original; the order of operations is the original's, lane by lane.
#include "hertz_mindlin_x4.hpp"

#include <cstddef>
#include <cstdint>

#include "ppohdem/simd_level.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define PPOHDEM_X4 1
#endif

namespace ppohdem::dem::fast {

#ifdef PPOHDEM_X4
namespace {

// The wide stores below rely on these layouts (checked here, where they are used).
static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 is three packed doubles");
static_assert(offsetof(TangentialSpring, stiffness) == offsetof(TangentialSpring, displacement) + 3 * sizeof(double));
static_assert(offsetof(TangentialSpring, branch_i) == offsetof(TangentialSpring, stiffness) + sizeof(double));
static_assert(offsetof(TangentialSpring, branch_j) == offsetof(TangentialSpring, branch_i) + 3 * sizeof(double));
static_assert(offsetof(PairResult, torque_i) == offsetof(PairResult, force) + 3 * sizeof(double));
static_assert(offsetof(PairResult, torque_j) == offsetof(PairResult, torque_i) + 3 * sizeof(double));

using D4 = double __attribute__((vector_size(32)));  ///< four lanes, one contact each
struct V4 {                                           ///< four 3-vectors, one per lane
  D4 x, y, z;
};

#define PPOHDEM_LANES [[gnu::target("avx"), gnu::always_inline]] inline

PPOHDEM_LANES D4 broadcast(double a) { return D4{a, a, a, a}; }
PPOHDEM_LANES D4 sqrt4(D4 a) { return reinterpret_cast<D4>(_mm256_sqrt_pd(reinterpret_cast<__m256d>(a))); }
/// `condition ? a : b` per lane, `condition` a lane comparison (all bits set where true).
template <class Mask>
PPOHDEM_LANES D4 select(Mask condition, D4 a, D4 b) {
  return condition ? a : b;
}

PPOHDEM_LANES V4 operator+(const V4& a, const V4& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
PPOHDEM_LANES V4 operator-(const V4& a, const V4& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
PPOHDEM_LANES V4 operator*(D4 a, const V4& b) { return {a * b.x, a * b.y, a * b.z}; }  // Eigen: scalar * vector
PPOHDEM_LANES V4 operator/(const V4& a, D4 b) { return {a.x / b, a.y / b, a.z / b}; }  // Eigen: vector / scalar
/// Eigen's dot and squaredNorm of 3-vectors: (a0 b0 + a1 b1) + a2 b2.
PPOHDEM_LANES D4 dot(const V4& a, const V4& b) { return (a.x * b.x + a.y * b.y) + a.z * b.z; }
/// Eigen's cross product of 3-vectors: (a1 b2 - a2 b1, a2 b0 - a0 b2, a0 b1 - a1 b0).
PPOHDEM_LANES V4 cross(const V4& a, const V4& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

/// Lane l = base[index[l]].
PPOHDEM_LANES D4 gather(const std::vector<double>& base, const std::uint32_t* index) {
  return D4{base[index[0]], base[index[1]], base[index[2]], base[index[3]]};
}
PPOHDEM_LANES V4 gather(const Vec3* const* p) {
  return {D4{p[0]->x(), p[1]->x(), p[2]->x(), p[3]->x()}, D4{p[0]->y(), p[1]->y(), p[2]->y(), p[3]->y()},
          D4{p[0]->z(), p[1]->z(), p[2]->z(), p[3]->z()}};
}
PPOHDEM_LANES V4 gather(const std::vector<Vec3>& base, const std::uint32_t* index) {
  const Vec3* p[4] = {&base[index[0]], &base[index[1]], &base[index[2]], &base[index[3]]};
  return gather(p);
}
/// The four lanes of a, b, c, d as four rows: row l = (a[l], b[l], c[l], d[l]).
PPOHDEM_LANES void transpose(D4 a, D4 b, D4 c, D4 d, D4 row[4]) {
  const __m256d ab_even = _mm256_unpacklo_pd(reinterpret_cast<__m256d>(a), reinterpret_cast<__m256d>(b));  // a0 b0 a2 b2
  const __m256d ab_odd = _mm256_unpackhi_pd(reinterpret_cast<__m256d>(a), reinterpret_cast<__m256d>(b));   // a1 b1 a3 b3
  const __m256d cd_even = _mm256_unpacklo_pd(reinterpret_cast<__m256d>(c), reinterpret_cast<__m256d>(d));
  const __m256d cd_odd = _mm256_unpackhi_pd(reinterpret_cast<__m256d>(c), reinterpret_cast<__m256d>(d));
  row[0] = reinterpret_cast<D4>(_mm256_permute2f128_pd(ab_even, cd_even, 0x20));
  row[1] = reinterpret_cast<D4>(_mm256_permute2f128_pd(ab_odd, cd_odd, 0x20));
  row[2] = reinterpret_cast<D4>(_mm256_permute2f128_pd(ab_even, cd_even, 0x31));
  row[3] = reinterpret_cast<D4>(_mm256_permute2f128_pd(ab_odd, cd_odd, 0x31));
}
/// Four consecutive doubles at `to` := row (one unaligned 32-byte store).
PPOHDEM_LANES void store4(double* to, D4 row) { _mm256_storeu_pd(to, reinterpret_cast<__m256d>(row)); }

/// Four contacts of the list, first to first + 3; a short last group repeats its last contact
/// (same inputs, same outputs written twice).
struct Group {
  PairEntry* entry[4];
  std::uint32_t i[4], j[4];
  TangentialSpring* spring[4];
  PairResult* result[4];
};
PPOHDEM_LANES Group group_at(FastState& s, PairEntry* entries, const std::uint32_t* contacts, std::size_t first,
                             std::size_t count) {
  Group g;
  for (std::size_t l = 0; l < 4; ++l) {
    const std::size_t k = first + l < count ? first + l : count - 1;
    g.entry[l] = &entries[contacts != nullptr ? contacts[k] : k];
    g.i[l] = g.entry[l]->i;
    g.j[l] = g.entry[l]->j;
    g.spring[l] = &s.spring_at(g.entry[l]->code);
    g.result[l] = &s.result_at(g.entry[l]->code);
  }
  return g;
}

/// The law's constants, each the scalar code's first product (contact_law.hpp), and the step.
struct Law4 {
  D4 hertz_factor;    ///< 4/3 E* [Pa]; K = this sqrt(R*)
  D4 mindlin_factor;  ///< 8 G* [Pa]; k_t = this sqrt(R* delta)
  D4 alpha;           ///< Tsuji's alpha(e) [-]
  D4 mu;              ///< [-]
  D4 step;            ///< dt [s]
};

/// A group's kinematics (force_pairs.hpp, pair_kinematics, and the step's displacement).
struct Kinematics4 {
  D4 ri, rj, mi, mj;
  V4 n;                  ///< unit normal, j -> i
  D4 overlap;            ///< delta [m]
  V4 r_i, r_j;           ///< branch vectors [m]
  V4 vi, vj, wi, wj;     ///< the step's velocities
  V4 relative_velocity;  ///< at the evaluation time [m/s]
  V4 displacement;       ///< ds [m]
};
PPOHDEM_LANES Kinematics4 kinematics4(const FastState& s, const Group& g, const Law4& law) {
  const D4 half = broadcast(0.5);
  Kinematics4 k;
  k.ri = gather(s.radius, g.i);
  k.rj = gather(s.radius, g.j);
  const V4 d = gather(s.x, g.i) - gather(s.x, g.j);  // from j to i [m]
  const D4 distance = sqrt4(dot(d, d));              // d.norm()
  k.n = d / distance;
  k.overlap = (k.ri + k.rj) - distance;
  k.r_i = -(k.ri - half * k.overlap) * k.n;
  k.r_j = (k.rj - half * k.overlap) * k.n;
  k.wi = gather(s.w, g.i);
  k.wj = gather(s.w, g.j);
  k.relative_velocity = (gather(s.pv, g.i) + cross(gather(s.pw, g.i), k.r_i)) - (gather(s.pv, g.j) + cross(gather(s.pw, g.j), k.r_j));
  k.vi = gather(s.v, g.i);
  k.vj = gather(s.v, g.j);
  k.displacement = law.step * ((k.vi + cross(k.wi, k.r_i)) - (k.vj + cross(k.wj, k.r_j)));
  k.mi = gather(s.mass, g.i);
  k.mj = gather(s.mass, g.j);
  return k;
}

/// A group's R* [m], Hertz constant K [N/m^1.5] and normal damping eta.
struct PairConstants4 {
  D4 r_eff, stiffness, eta;
};
/// Equal particles: a group whose eight particles all have the radius and mass of the last
/// such group reuses that group's R*, K and eta instead of computing them again (the same
/// operations on the same inputs: the same bits). This saves 2 of the 7 divisions and 2 of the
/// 9 square roots of a contact, which share one divider unit: docs/performance.md "Equal
/// particles". Mixed sizes take the general path.
struct EqualParticles {
  double radius = -1.0, mass = -1.0;  // no group seen yet (radii and masses are > 0)
  PairConstants4 constants{};
};
PPOHDEM_LANES PairConstants4 pair_constants4(const Kinematics4& k, const Law4& law, EqualParticles& equal_group) {
  const double r0 = k.ri[0], m0 = k.mi[0];
  const auto same = (k.ri == broadcast(r0)) & (k.rj == broadcast(r0)) & (k.mi == broadcast(m0)) & (k.mj == broadcast(m0));
  const bool equal = same[0] & same[1] & same[2] & same[3];
  if (equal && !(r0 == equal_group.radius && m0 == equal_group.mass)) {
    const D4 r = broadcast(r0), m = broadcast(m0);
    PairConstants4& c = equal_group.constants;
    c.r_eff = r * r / (r + r);
    c.stiffness = law.hertz_factor * sqrt4(c.r_eff);
    c.eta = law.alpha * sqrt4(m * m / (m + m) * c.stiffness);
    equal_group.radius = r0;
    equal_group.mass = m0;
  }
  if (equal) return equal_group.constants;
  PairConstants4 c;
  const D4 m_eff = k.mi * k.mj / (k.mi + k.mj);  // pair_value [kg]
  c.r_eff = k.ri * k.rj / (k.ri + k.rj);         // [m]
  c.stiffness = law.hertz_factor * sqrt4(c.r_eff);  // hertz_constant K [N/m^1.5]
  c.eta = law.alpha * sqrt4(m_eff * c.stiffness);
  return c;
}

/// What the law gives for a group: the force on i, the new spring, the energy terms.
struct Contact4 {
  V4 force;           ///< out.on_i [N]
  V4 xi_new;          ///< the spring's new displacement [m]
  D4 k_t;             ///< its new stiffness [N/m]
  D4 elastic{};       ///< kEnergy [J]
  D4 dissipated{};    ///< kEnergy [J]
};
/// normal_contact_force with HertzMindlin::normal_force / elastic_force / elastic_energy, then
/// frictional_contact_force, on the group's springs.
template <bool kEnergy>
PPOHDEM_LANES Contact4 contact4(const Law4& law, const Group& g, const Kinematics4& k, const PairConstants4& c) {
  const D4 zero = broadcast(0.0);
  const D4 half = broadcast(0.5);
  const V4& n = k.n;
  const D4 overlap = k.overlap;
  // The springs.
  const Vec3* xi_p[4];
  const Vec3* bi_p[4];
  const Vec3* bj_p[4];
  for (int l = 0; l < 4; ++l) {
    xi_p[l] = &g.spring[l]->displacement;
    bi_p[l] = &g.spring[l]->branch_i;
    bj_p[l] = &g.spring[l]->branch_j;
  }
  const V4 xi_previous = gather(xi_p);
  const D4 k_old = D4{g.spring[0]->stiffness, g.spring[1]->stiffness, g.spring[2]->stiffness, g.spring[3]->stiffness};
  V4 displacement_previous_arms{};
  if constexpr (kEnergy) {
    displacement_previous_arms = law.step * ((k.vi + cross(k.wi, gather(bi_p))) - (k.vj + cross(k.wj, gather(bj_p))));
  }

  // The normal force.
  Contact4 out;
  const D4 delta_dot = -dot(k.relative_velocity, n);  // approach speed [m/s]
  const D4 root_delta = sqrt4(overlap);
  const D4 f = c.stiffness * overlap * root_delta + c.eta * sqrt4(root_delta) * delta_dot;
  const D4 f_n = select(f > zero, f, zero);  // no attraction [N]
  const D4 f_elastic = c.stiffness * overlap * root_delta;
  V4 force = f_n * n;
  if constexpr (kEnergy) {
    out.elastic = broadcast(0.4) * c.stiffness * overlap * overlap * root_delta;
    out.dissipated = (f_n - f_elastic) * delta_dot * law.step;
  }

  // frictional_contact_force: 1. rotate the history onto the tangent plane.
  const D4 f_normal = dot(force, n);
  const D4 length = sqrt4(dot(xi_previous, xi_previous));
  const V4 projected_xi = xi_previous - dot(xi_previous, n) * n;
  const D4 projected = sqrt4(dot(projected_xi, projected_xi));
  const D4 rescale = length / projected;  // 0/0 in lanes with projected = 0: not selected
  const auto rotate = projected > zero;
  const V4 xi_rotated{select(rotate, projected_xi.x * rescale, projected_xi.x),
                      select(rotate, projected_xi.y * rescale, projected_xi.y),
                      select(rotate, projected_xi.z * rescale, projected_xi.z)};
  // 2. Trial state and Mindlin stiffness.
  const V4 sliding = k.displacement - dot(k.displacement, n) * n;  // ds_t
  const V4 xi_trial = xi_rotated + sliding;
  const D4 k_t = law.mindlin_factor * sqrt4(c.r_eff * overlap);
  // 3. Spring force and Coulomb cap.
  V4 f_t = -k_t * xi_trial;
  const D4 cap = law.mu * select(f_normal > zero, f_normal, zero);
  const D4 f_t_norm = sqrt4(dot(f_t, f_t));
  const auto slip = f_t_norm > cap;
  const D4 scale = cap / f_t_norm;
  f_t = V4{select(slip, f_t.x * scale, f_t.x), select(slip, f_t.y * scale, f_t.y), select(slip, f_t.z * scale, f_t.z)};
  const V4 xi_new{select(slip, xi_trial.x * scale, xi_trial.x), select(slip, xi_trial.y * scale, xi_trial.y),
                  select(slip, xi_trial.z * scale, xi_trial.z)};
  if constexpr (kEnergy) {
    out.dissipated = out.dissipated + -half * (k_t - k_old) * dot(xi_rotated, xi_trial);
    out.dissipated = out.dissipated + half * k_t * dot(xi_trial - xi_new, xi_rotated + xi_new);
    out.dissipated = out.dissipated + half * k_old * (dot(xi_previous, displacement_previous_arms) - dot(xi_rotated, k.displacement));
  }
  out.force = force + f_t;
  if constexpr (kEnergy) out.elastic = out.elastic + half * k_t * dot(xi_new, xi_new);  // spring.stored_energy()
  out.xi_new = xi_new;
  out.k_t = k_t;
  return out;
}

/// Stores: the spring, the pair result, the entry. Each lane's spring and result as rows of
/// four consecutive doubles (the layouts checked at the top of the file): four 32-byte stores
/// and three scalar ones per contact instead of 19 scalar ones (docs/performance.md, "What the
/// law's stores cost"). The branch vectors only with kEnergy: nothing else reads them
/// (save_state writes them from the positions; docs/performance.md "Fewer loads and stores per
/// contact and per particle"). The entry's overlap only for the booking (`booking`).
template <bool kEnergy>
PPOHDEM_LANES void store_group(const Group& g, const Kinematics4& k, const Contact4& c, const V4& torque_i,
                               const V4& torque_j, bool booking) {
  D4 rows[4];
  transpose(c.xi_new.x, c.xi_new.y, c.xi_new.z, c.k_t, rows);  // displacement, stiffness
  for (int l = 0; l < 4; ++l) store4(g.spring[l]->displacement.data(), rows[l]);
  if constexpr (kEnergy) {
    transpose(k.r_i.x, k.r_i.y, k.r_i.z, k.r_j.x, rows);  // branch_i, branch_j.x
    for (int l = 0; l < 4; ++l) store4(g.spring[l]->branch_i.data(), rows[l]);
  }
  transpose(c.force.x, c.force.y, c.force.z, torque_i.x, rows);  // force, torque_i.x
  for (int l = 0; l < 4; ++l) store4(g.result[l]->force.data(), rows[l]);
  transpose(torque_i.y, torque_i.z, torque_j.x, torque_j.y, rows);  // torque_i.y, .z, torque_j.x, .y
  for (int l = 0; l < 4; ++l) store4(g.result[l]->torque_i.data() + 1, rows[l]);
  for (int l = 0; l < 4; ++l) {
    g.result[l]->torque_j.z() = torque_j.z[l];
    if constexpr (kEnergy) {
      g.spring[l]->branch_j.y() = k.r_j.y[l];
      g.spring[l]->branch_j.z() = k.r_j.z[l];
      g.entry[l]->elastic = c.elastic[l];
      g.entry[l]->dissipated = c.dissipated[l];
    }
    if (booking) g.entry[l]->overlap = k.overlap[l];
  }
}

/// OwnSums (hertz_mindlin_x4.hpp): each upper contact of the group that starts at list
/// position `first` of `count` (a repeated last lane is not added again) into its particle's
/// sums, counted and offered as the deepest. The booking's ratio (force_pairs.hpp): overlap / std::min(r_i, r_j), four
/// divisions in one instruction.
PPOHDEM_LANES void add_own_sums(FastState& s, const Group& g, const Kinematics4& k, const V4& force, const V4& torque_i,
                                std::size_t first, std::size_t count, OwnSums& sums) {
  const D4 ratio = k.overlap / select(k.rj < k.ri, k.rj, k.ri);
  for (std::size_t l = 0; l < 4 && first + l < count; ++l) {
    if (g.entry[l]->kind != PairEntry::kContactUpper) continue;  // a lower-id ghost's: the sum pass adds it
    Vec3& force_sum = s.f[g.i[l]];
    force_sum.x() += force.x[l];
    force_sum.y() += force.y[l];
    force_sum.z() += force.z[l];
    Vec3& torque_sum = s.t[g.i[l]];
    torque_sum.x() += torque_i.x[l];
    torque_sum.y() += torque_i.y[l];
    torque_sum.z() += torque_i.z[l];
    ++sums.pairs;
    std::optional<LargestOverlap>& deepest = *sums.deepest;
    if (!deepest || ratio[l] >= deepest->ratio) {
      keep_deeper(deepest, LargestOverlap{ratio[l], k.overlap[l], s.id[g.i[l]], s.id[g.j[l]], false});
    }
  }
}

template <bool kEnergy>
[[gnu::target("avx"), gnu::flatten]] void hertz_mindlin_x4_avx(const HertzMindlin& law, FastState& s, PairEntry* entries,
                                                                const std::uint32_t* contacts, std::size_t count, double dt,
                                                                OwnSums* sums) {
  const Law4 law4{broadcast(4.0 / 3.0 * law.effective_young()), broadcast(8.0 * law.effective_shear()),
                  broadcast(law.damping_ratio()), broadcast(law.friction()), broadcast(dt)};
  EqualParticles equal;
  for (std::size_t first = 0; first < count; first += 4) {
    const Group g = group_at(s, entries, contacts, first, count);
    const Kinematics4 k = kinematics4(s, g, law4);
    const PairConstants4 constants = pair_constants4(k, law4, equal);
    const Contact4 c = contact4<kEnergy>(law4, g, k, constants);
    const V4 torque_i = cross(k.r_i, c.force);
    const V4 torque_j = cross(k.r_j, c.force);
    store_group<kEnergy>(g, k, c, torque_i, torque_j, sums == nullptr);
    if (sums != nullptr) add_own_sums(s, g, k, c.force, torque_i, first, count, *sums);
  }
}

}  // namespace

bool x4_contacts_available() { return simd_level() >= SimdLevel::avx; }  // the CPU's, or PPOHDEM_SIMD's

template <bool kEnergy>
void hertz_mindlin_x4(const HertzMindlin& law, FastState& s, PairEntry* entries, const std::uint32_t* contacts,
                      std::size_t count, double dt, OwnSums* sums) {
  hertz_mindlin_x4_avx<kEnergy>(law, s, entries, contacts, count, dt, sums);
}

#else  // not x86-64 with GCC: never available, never called

bool x4_contacts_available() { return false; }

template <bool kEnergy>
void hertz_mindlin_x4(const HertzMindlin&, FastState&, PairEntry*, const std::uint32_t*, std::size_t, double, OwnSums*) {}

#endif

template void hertz_mindlin_x4<true>(const HertzMindlin&, FastState&, PairEntry*, const std::uint32_t*, std::size_t,
                                     double, OwnSums*);
template void hertz_mindlin_x4<false>(const HertzMindlin&, FastState&, PairEntry*, const std::uint32_t*, std::size_t,
                                      double, OwnSums*);

}  // namespace ppohdem::dem::fast
