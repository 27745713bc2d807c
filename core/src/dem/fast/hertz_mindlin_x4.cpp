// Hertz-Mindlin contacts four (AVX, or AVX-512VL's encoding of it) or eight (AVX-512F) at a
// time (see hertz_mindlin_x4.hpp). The law itself is hertz_mindlin_lanes.inc, included once per
// width and encoding; every function that holds a lane value carries its target and is inlined
// into hertz_mindlin_avx, hertz_mindlin_avx512vl or hertz_mindlin_avx512, called only after the
// CPU check: the rest of the program stays SSE2-only. Built with -ffp-contract=off: AVX-512F
// has FMA, which would fuse a * b + c and change the bits (core/src/dem/CMakeLists.txt).
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
static_assert(offsetof(PairResult, torque_summed) == offsetof(PairResult, force) + 3 * sizeof(double));

/// Four lanes (AVX): a group of four contacts.
namespace lanes4 {
#define PPOHDEM_LANES [[gnu::target("avx"), gnu::always_inline]] inline
#include "hertz_mindlin_lanes4.inc"
#undef PPOHDEM_LANES
}  // namespace lanes4

/// Four lanes encoded with AVX-512VL, for the CPUs whose DEM lanes are four although they run
/// AVX-512 (dem_four_lanes_avx512vl): 32 registers instead of 16, so the law spills less, and
/// its selections take mask registers.
namespace lanes4vl {
#define PPOHDEM_LANES [[gnu::target("avx512f,avx512vl"), gnu::always_inline]] inline
#include "hertz_mindlin_lanes4.inc"
#undef PPOHDEM_LANES
}  // namespace lanes4vl

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

/// The same in four lanes with AVX-512VL's encoding (lanes4vl).
template <bool kEnergy>
[[gnu::target("avx512f,avx512vl"), gnu::flatten]] void hertz_mindlin_avx512vl(const HertzMindlin& law, FastState& s,
                                                                             PairEntry* entries, std::size_t count,
                                                                             double dt, OwnSums* sums) {
  const lanes4vl::LawLanes law4 = lanes4vl::law_lanes(law, dt);
  lanes4vl::EqualParticles equal;
  for (std::size_t first = 0; first < count; first += 4) {
    lanes4vl::evaluate_group<kEnergy>(law4, s, entries, first, count, equal, sums);
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

bool x4_contacts_in_avx512vl() { return dem_four_lanes_avx512vl(); }

template <bool kEnergy>
void hertz_mindlin_x4(const HertzMindlin& law, FastState& s, PairEntry* entries, std::size_t count, double dt,
                      OwnSums* sums) {
  static const bool eight = x8_contacts_available();  // the level is fixed for the process
  static const bool four_vl = x4_contacts_in_avx512vl();
  if (eight) {
    hertz_mindlin_avx512<kEnergy>(law, s, entries, count, dt, sums);
  } else if (four_vl) {
    hertz_mindlin_avx512vl<kEnergy>(law, s, entries, count, dt, sums);
  } else {
    hertz_mindlin_avx<kEnergy>(law, s, entries, count, dt, sums);
  }
}

#else  // not x86-64 with GCC: never available, never called

bool x4_contacts_available() { return false; }
bool x8_contacts_available() { return false; }
bool x4_contacts_in_avx512vl() { return false; }

template <bool kEnergy>
void hertz_mindlin_x4(const HertzMindlin&, FastState&, PairEntry*, std::size_t, double, OwnSums*) {}

#endif

template void hertz_mindlin_x4<true>(const HertzMindlin&, FastState&, PairEntry*, std::size_t, double, OwnSums*);
template void hertz_mindlin_x4<false>(const HertzMindlin&, FastState&, PairEntry*, std::size_t, double, OwnSums*);

}  // namespace ppohdem::dem::fast
