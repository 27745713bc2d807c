// The closing half kick of a block of particles (fast_state.hpp, close_kicks): eight particles
// at a time with AVX-512F where the CPU has it, four with AVX, else close_kick one at a time.
// The kick's six divisions a particle (f / m, (dt/2 t) / I: the reference's expressions, kept
// for the same bits) take one vdivpd for 8/3 (4/3) particles instead of one divsd each
// (docs/performance.md "Eight kicks at a time"). Built with -ffp-contract=off
// (core/src/dem/CMakeLists.txt).
#include <cstddef>

#include "fast_state.hpp"
#include "ppohdem/simd_level.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define PPOHDEM_KICK_LANES 1
#endif

namespace ppohdem::dem::fast {

namespace {

double close_kicks_one_by_one(FastState& s, std::size_t begin, std::size_t end) {
  double screen = 0.0;
  for (std::size_t i = begin; i < end; ++i) screen += close_kick(s, i);
  return screen;
}

#ifdef PPOHDEM_KICK_LANES
static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 is three packed doubles: 8 particles are 3 registers");

/// Eight particles' Vec3 fields are 24 consecutive doubles, three registers; lane l of register
/// k belongs to particle (8 k + l) / 3 of the eight and to component (8 k + l) % 3. (maskz_
/// forms with every lane: GCC 12's plain permute reads an undefined register, a false
/// -Wmaybe-uninitialized.)
[[gnu::target("avx512f")]] double close_kicks_avx512(FastState& s, std::size_t begin, std::size_t end) {
  const double half = 0.5 * s.dt;
  const Vec3 g = s.gravity;
  const __m512d h = _mm512_set1_pd(half);
  const __m512i owner[3] = {_mm512_setr_epi64(0, 0, 0, 1, 1, 1, 2, 2), _mm512_setr_epi64(2, 3, 3, 3, 4, 4, 4, 5),
                            _mm512_setr_epi64(5, 5, 6, 6, 6, 7, 7, 7)};
  const __m512d gravity[3] = {_mm512_setr_pd(g.x(), g.y(), g.z(), g.x(), g.y(), g.z(), g.x(), g.y()),
                              _mm512_setr_pd(g.z(), g.x(), g.y(), g.z(), g.x(), g.y(), g.z(), g.x()),
                              _mm512_setr_pd(g.y(), g.z(), g.x(), g.y(), g.z(), g.x(), g.y(), g.z())};
  __m512d screen = _mm512_setzero_pd();
  std::size_t i = begin;
  for (; i + 8 <= end; i += 8) {
    const __m512d mass = _mm512_loadu_pd(&s.mass[i]);
    const __m512d inertia = _mm512_loadu_pd(&s.inertia[i]);
    for (int k = 0; k < 3; ++k) {
      const std::size_t at = 8 * static_cast<std::size_t>(k);
      // pv = dt/2 (f / m + g), pw = (dt/2 t) / I, per component (close_kick).
      const __m512d pv = _mm512_mul_pd(
          h, _mm512_add_pd(_mm512_div_pd(_mm512_loadu_pd(s.f[i].data() + at), _mm512_maskz_permutexvar_pd(0xFF, owner[k], mass)),
                           gravity[k]));
      const __m512d pw =
          _mm512_div_pd(_mm512_mul_pd(h, _mm512_loadu_pd(s.t[i].data() + at)), _mm512_maskz_permutexvar_pd(0xFF, owner[k], inertia));
      const __m512d v = _mm512_add_pd(_mm512_loadu_pd(s.v[i].data() + at), pv);
      const __m512d w = _mm512_add_pd(_mm512_loadu_pd(s.w[i].data() + at), pw);
      _mm512_storeu_pd(s.pv[i].data() + at, pv);
      _mm512_storeu_pd(s.pw[i].data() + at, pw);
      _mm512_storeu_pd(s.v[i].data() + at, v);
      _mm512_storeu_pd(s.w[i].data() + at, w);
      // The screen only tells finite from not: its order is free.
      screen = _mm512_add_pd(screen, _mm512_add_pd(_mm512_mul_pd(v, v), _mm512_mul_pd(w, w)));
    }
  }
  double lanes[8];
  _mm512_storeu_pd(lanes, screen);
  double total = close_kicks_one_by_one(s, i, end);
  for (const double lane : lanes) total += lane;
  return total;
}

/// Four particles' values (a0, a1, a2, a3) spread over the lanes of their Vec3 fields' three
/// registers: (a0, a0, a0, a1), (a1, a1, a2, a2), (a2, a3, a3, a3).
[[gnu::target("avx"), gnu::always_inline]] inline void lane_owners(__m256d a, __m256d out[3]) {
  out[0] = _mm256_permute_pd(_mm256_permute2f128_pd(a, a, 0x00), 0b1000);
  out[1] = _mm256_permute_pd(a, 0b0011);
  out[2] = _mm256_permute_pd(_mm256_permute2f128_pd(a, a, 0x11), 0b1110);
}

/// The same with AVX: four particles' Vec3 fields are 12 doubles, three registers; lane l of
/// register k belongs to particle (4 k + l) / 3 of the four. Each particle's mass and moment
/// of inertia reach its lanes by in-lane permutes (AVX has no cross-lane one for doubles).
/// Ends with vzeroupper (docs/portability.md "Upper register state").
[[gnu::target("avx")]] double close_kicks_avx(FastState& s, std::size_t begin, std::size_t end) {
  const double half = 0.5 * s.dt;
  const Vec3 g = s.gravity;
  const __m256d h = _mm256_set1_pd(half);
  const __m256d gravity[3] = {_mm256_setr_pd(g.x(), g.y(), g.z(), g.x()), _mm256_setr_pd(g.y(), g.z(), g.x(), g.y()),
                              _mm256_setr_pd(g.z(), g.x(), g.y(), g.z())};
  __m256d screen = _mm256_setzero_pd();
  std::size_t i = begin;
  for (; i + 4 <= end; i += 4) {
    __m256d mass[3], inertia[3];
    lane_owners(_mm256_loadu_pd(&s.mass[i]), mass);
    lane_owners(_mm256_loadu_pd(&s.inertia[i]), inertia);
    for (int k = 0; k < 3; ++k) {
      const std::size_t at = 4 * static_cast<std::size_t>(k);
      // pv = dt/2 (f / m + g), pw = (dt/2 t) / I, per component (close_kick).
      const __m256d pv =
          _mm256_mul_pd(h, _mm256_add_pd(_mm256_div_pd(_mm256_loadu_pd(s.f[i].data() + at), mass[k]), gravity[k]));
      const __m256d pw = _mm256_div_pd(_mm256_mul_pd(h, _mm256_loadu_pd(s.t[i].data() + at)), inertia[k]);
      const __m256d v = _mm256_add_pd(_mm256_loadu_pd(s.v[i].data() + at), pv);
      const __m256d w = _mm256_add_pd(_mm256_loadu_pd(s.w[i].data() + at), pw);
      _mm256_storeu_pd(s.pv[i].data() + at, pv);
      _mm256_storeu_pd(s.pw[i].data() + at, pw);
      _mm256_storeu_pd(s.v[i].data() + at, v);
      _mm256_storeu_pd(s.w[i].data() + at, w);
      // The screen only tells finite from not: its order is free.
      screen = _mm256_add_pd(screen, _mm256_add_pd(_mm256_mul_pd(v, v), _mm256_mul_pd(w, w)));
    }
  }
  double lanes[4];
  _mm256_storeu_pd(lanes, screen);
  _mm256_zeroupper();
  double total = close_kicks_one_by_one(s, i, end);
  for (const double lane : lanes) total += lane;
  return total;
}
#endif

}  // namespace

double close_kicks(FastState& s, std::size_t begin, std::size_t end) {
#ifdef PPOHDEM_KICK_LANES
  static const SimdLevel level = dem_simd_level();  // fixed for the process
  if (level >= SimdLevel::avx512) return close_kicks_avx512(s, begin, end);
  if (level == SimdLevel::avx) return close_kicks_avx(s, begin, end);
#endif
  return close_kicks_one_by_one(s, begin, end);
}

}  // namespace ppohdem::dem::fast
