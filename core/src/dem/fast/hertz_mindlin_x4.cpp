// Hertz-Mindlin contacts four (AVX) or eight (AVX-512F) at a time (see hertz_mindlin_x4.hpp).
// The law itself is hertz_mindlin_lanes.inc, included once per width; every function that holds
// a lane value carries its width's target and is inlined into hertz_mindlin_avx or
// hertz_mindlin_avx512, called only after the CPU check: the rest of the program stays
// SSE2-only. Built with -ffp-contract=off: AVX-512F has FMA, which would fuse a * b + c and
// change the bits (core/src/dem/CMakeLists.txt).
#include "hertz_mindlin_x4.hpp"

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

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
static_assert(offsetof(SpringCore, stiffness) == offsetof(SpringCore, displacement) + 3 * sizeof(double));
static_assert(offsetof(SpringArms, branch_j) == offsetof(SpringArms, branch_i) + 3 * sizeof(double));
static_assert(offsetof(PairResult, torque_i) == offsetof(PairResult, force) + 3 * sizeof(double));
static_assert(offsetof(PairResult, torque_j) == offsetof(PairResult, torque_i) + 3 * sizeof(double));

/// Four lanes (AVX): a group of four contacts.
namespace lanes4 {
using D = double __attribute__((vector_size(32)));
constexpr std::size_t kWidth = 4;
#define PPOHDEM_LANES [[gnu::target("avx"), gnu::always_inline]] inline
PPOHDEM_LANES D sqrt_lanes(D a) { return reinterpret_cast<D>(_mm256_sqrt_pd(reinterpret_cast<__m256d>(a))); }
/// Row l = (a[l], b[l], c[l], d[l]) to the four doubles at to[l]: a 4 x 4 transpose and four
/// unaligned 32-byte stores.
PPOHDEM_LANES void store_rows(D a, D b, D c, D d, double* const* to) {
  const __m256d ab_even = _mm256_unpacklo_pd(reinterpret_cast<__m256d>(a), reinterpret_cast<__m256d>(b));  // a0 b0 a2 b2
  const __m256d ab_odd = _mm256_unpackhi_pd(reinterpret_cast<__m256d>(a), reinterpret_cast<__m256d>(b));   // a1 b1 a3 b3
  const __m256d cd_even = _mm256_unpacklo_pd(reinterpret_cast<__m256d>(c), reinterpret_cast<__m256d>(d));
  const __m256d cd_odd = _mm256_unpackhi_pd(reinterpret_cast<__m256d>(c), reinterpret_cast<__m256d>(d));
  _mm256_storeu_pd(to[0], _mm256_permute2f128_pd(ab_even, cd_even, 0x20));
  _mm256_storeu_pd(to[1], _mm256_permute2f128_pd(ab_odd, cd_odd, 0x20));
  _mm256_storeu_pd(to[2], _mm256_permute2f128_pd(ab_even, cd_even, 0x31));
  _mm256_storeu_pd(to[3], _mm256_permute2f128_pd(ab_odd, cd_odd, 0x31));
}
/// The transpose of store_rows: a[l], b[l], c[l], d[l] = the four doubles at from[l].
PPOHDEM_LANES void load_rows(const double* const* from, D& a, D& b, D& c, D& d) {
  const __m256d r0 = _mm256_loadu_pd(from[0]), r1 = _mm256_loadu_pd(from[1]);
  const __m256d r2 = _mm256_loadu_pd(from[2]), r3 = _mm256_loadu_pd(from[3]);
  const __m256d ac01 = _mm256_unpacklo_pd(r0, r1);  // a0 a1 c0 c1
  const __m256d bd01 = _mm256_unpackhi_pd(r0, r1);  // b0 b1 d0 d1
  const __m256d ac23 = _mm256_unpacklo_pd(r2, r3);
  const __m256d bd23 = _mm256_unpackhi_pd(r2, r3);
  a = reinterpret_cast<D>(_mm256_permute2f128_pd(ac01, ac23, 0x20));
  b = reinterpret_cast<D>(_mm256_permute2f128_pd(bd01, bd23, 0x20));
  c = reinterpret_cast<D>(_mm256_permute2f128_pd(ac01, ac23, 0x31));
  d = reinterpret_cast<D>(_mm256_permute2f128_pd(bd01, bd23, 0x31));
}
/// Pair l = (a[l], b[l]) to the two doubles at to[l]: two unpacks and four 16-byte stores.
PPOHDEM_LANES void store_pairs(D a, D b, double* const* to) {
  const __m256d even = _mm256_unpacklo_pd(reinterpret_cast<__m256d>(a), reinterpret_cast<__m256d>(b));  // a0 b0 a2 b2
  const __m256d odd = _mm256_unpackhi_pd(reinterpret_cast<__m256d>(a), reinterpret_cast<__m256d>(b));   // a1 b1 a3 b3
  _mm_storeu_pd(to[0], _mm256_castpd256_pd128(even));
  _mm_storeu_pd(to[1], _mm256_castpd256_pd128(odd));
  _mm_storeu_pd(to[2], _mm256_extractf128_pd(even, 1));
  _mm_storeu_pd(to[3], _mm256_extractf128_pd(odd, 1));
}
/// The transpose of store_pairs: a[l], b[l] = the two doubles at from[l].
PPOHDEM_LANES void load_pairs(const double* const* from, D& a, D& b) {
  const __m256d even = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(from[0])), _mm_loadu_pd(from[2]), 1);
  const __m256d odd = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(from[1])), _mm_loadu_pd(from[3]), 1);
  a = reinterpret_cast<D>(_mm256_unpacklo_pd(even, odd));
  b = reinterpret_cast<D>(_mm256_unpackhi_pd(even, odd));
}
#include "hertz_mindlin_lanes.inc"
#undef PPOHDEM_LANES
}  // namespace lanes4

/// Eight lanes (AVX-512F): a group of eight contacts. Its square roots and divisions, most of
/// the law's time, take one instruction for eight contacts instead of two (docs/performance.md
/// "Eight contacts at a time").
namespace lanes8 {
using D = double __attribute__((vector_size(64)));
constexpr std::size_t kWidth = 8;
#define PPOHDEM_LANES [[gnu::target("avx512f"), gnu::always_inline]] inline
// maskz_ forms with every lane: GCC 12's plain forms read an undefined register (a false
// -Wmaybe-uninitialized); the results are the same.
PPOHDEM_LANES D sqrt_lanes(D a) { return reinterpret_cast<D>(_mm512_maskz_sqrt_pd(0xFF, reinterpret_cast<__m512d>(a))); }
PPOHDEM_LANES lanes4::D low(D v) {
  return reinterpret_cast<lanes4::D>(_mm512_maskz_extractf64x4_pd(0xF, reinterpret_cast<__m512d>(v), 0));
}
PPOHDEM_LANES lanes4::D high(D v) {
  return reinterpret_cast<lanes4::D>(_mm512_maskz_extractf64x4_pd(0xF, reinterpret_cast<__m512d>(v), 1));
}
/// As lanes4::store_rows, for lanes 0-3 and 4-7.
PPOHDEM_LANES void store_rows(D a, D b, D c, D d, double* const* to) {
  lanes4::store_rows(low(a), low(b), low(c), low(d), to);
  lanes4::store_rows(high(a), high(b), high(c), high(d), to + 4);
}
PPOHDEM_LANES D join(lanes4::D low_half, lanes4::D high_half) {
  const __m512d low_only = _mm512_maskz_insertf64x4(0xFF, _mm512_setzero_pd(), reinterpret_cast<__m256d>(low_half), 0);
  return reinterpret_cast<D>(_mm512_maskz_insertf64x4(0xFF, low_only, reinterpret_cast<__m256d>(high_half), 1));
}
/// As lanes4::load_rows, for lanes 0-3 and 4-7.
PPOHDEM_LANES void load_rows(const double* const* from, D& a, D& b, D& c, D& d) {
  lanes4::D a0, b0, c0, d0, a1, b1, c1, d1;
  lanes4::load_rows(from, a0, b0, c0, d0);
  lanes4::load_rows(from + 4, a1, b1, c1, d1);
  a = join(a0, a1);
  b = join(b0, b1);
  c = join(c0, c1);
  d = join(d0, d1);
}
/// As lanes4::store_pairs and load_pairs, for lanes 0-3 and 4-7.
PPOHDEM_LANES void store_pairs(D a, D b, double* const* to) {
  lanes4::store_pairs(low(a), low(b), to);
  lanes4::store_pairs(high(a), high(b), to + 4);
}
PPOHDEM_LANES void load_pairs(const double* const* from, D& a, D& b) {
  lanes4::D a0, b0, a1, b1;
  lanes4::load_pairs(from, a0, b0);
  lanes4::load_pairs(from + 4, a1, b1);
  a = join(a0, a1);
  b = join(b0, b1);
}
#include "hertz_mindlin_lanes.inc"
#undef PPOHDEM_LANES
}  // namespace lanes8

template <bool kEnergy>
[[gnu::target("avx"), gnu::flatten]] void hertz_mindlin_avx(const HertzMindlin& law, FastState& s, PairEntry* entries,
                                                             std::size_t count, double dt, OwnSums* sums) {
  const lanes4::LawLanes law4 = lanes4::law_lanes(law, dt);
  lanes4::EqualParticles equal;
  for (std::size_t first = 0; first < count; first += 4) {
    lanes4::evaluate_group<kEnergy>(law4, s, entries, first, count, equal, sums);
  }
}

/// Groups of eight; a rest of at most four contacts goes as one group of four (fewer repeated
/// lanes at the end of a chunk's list).
template <bool kEnergy>
[[gnu::target("avx512f"), gnu::flatten]] void hertz_mindlin_avx512(const HertzMindlin& law, FastState& s,
                                                                   PairEntry* entries, std::size_t count, double dt,
                                                                   OwnSums* sums) {
  const lanes8::LawLanes law8 = lanes8::law_lanes(law, dt);
  lanes8::EqualParticles equal8;
  std::size_t first = 0;
  for (; first + 4 < count; first += 8) {
    lanes8::evaluate_group<kEnergy>(law8, s, entries, first, count, equal8, sums);
  }
  if (first < count) {
    const lanes4::LawLanes law4 = lanes4::law_lanes(law, dt);
    lanes4::EqualParticles equal4;
    lanes4::evaluate_group<kEnergy>(law4, s, entries, first, count, equal4, sums);
  }
}

}  // namespace

bool x4_contacts_available() { return dem_simd_level() >= SimdLevel::avx; }  // simd_level.hpp

bool x8_contacts_available() { return dem_simd_level() >= SimdLevel::avx512; }

template <bool kEnergy>
void hertz_mindlin_x4(const HertzMindlin& law, FastState& s, PairEntry* entries, std::size_t count, double dt,
                      OwnSums* sums) {
  static const bool eight = x8_contacts_available();  // the level is fixed for the process
  if (eight) {
    hertz_mindlin_avx512<kEnergy>(law, s, entries, count, dt, sums);
  } else {
    hertz_mindlin_avx<kEnergy>(law, s, entries, count, dt, sums);
  }
}

#else  // not x86-64 with GCC: never available, never called

bool x4_contacts_available() { return false; }
bool x8_contacts_available() { return false; }

template <bool kEnergy>
void hertz_mindlin_x4(const HertzMindlin&, FastState&, PairEntry*, std::size_t, double, OwnSums*) {}

#endif

template void hertz_mindlin_x4<true>(const HertzMindlin&, FastState&, PairEntry*, std::size_t, double, OwnSums*);
template void hertz_mindlin_x4<false>(const HertzMindlin&, FastState&, PairEntry*, std::size_t, double, OwnSums*);

}  // namespace ppohdem::dem::fast
