// The opening half kick and drift of a block of particles (fast_state.hpp, kicks_and_drifts):
// where the kick is the cached one of the last closing kick, eight particles at a time with
// AVX-512F where the CPU has it, four with AVX; else kick_and_drift one at a time. Each lane does
// kick_and_drift's operations in its order, and the squared displacements are summed per
// particle in Eigen's order, (x^2 + y^2) + z^2, so the same bits and the same largest value
// (docs/performance.md "Eight drifts at a time"). Built with -ffp-contract=off
// (core/src/dem/CMakeLists.txt).
#include <algorithm>
#include <cstddef>

#include "fast_state.hpp"
#include "ppohdem/simd_level.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define PPOHDEM_DRIFT_LANES 1
#endif

namespace ppohdem::dem::fast {

namespace {

double kicks_and_drifts_one_by_one(FastState& s, std::size_t begin, std::size_t end, bool cached) {
  double largest = 0.0;
  for (std::size_t i = begin; i < end; ++i) {
    kick_and_drift(s, i, first_half_kick(s, i, cached));
    largest = std::max(largest, (s.x[i] - s.x_build[i]).squaredNorm());
  }
  return largest;
}

#ifdef PPOHDEM_DRIFT_LANES
static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 is three packed doubles: 8 particles are 3 registers");

/// The cached kick (pv, pw): eight particles' Vec3 fields are 24 consecutive doubles, three
/// registers, each lane one component of one particle. Whole blocks of eight from `begin`;
/// returns where they end, the largest squared displacement in `largest`. It calls nothing
/// and ends with vzeroupper: with the registers' upper halves dirty, Intel cores add a merge
/// to every later SSE instruction of the step (GCC left them dirty before the tail's call
/// here; docs/portability.md "Upper register state").
[[gnu::target("avx512f")]] std::size_t kicks_and_drifts_avx512(FastState& s, std::size_t begin, std::size_t end, double& largest) {
  const __m512d dt = _mm512_set1_pd(s.dt);
  std::size_t i = begin;
  for (; i + 8 <= end; i += 8) {
    double squares[24];
    for (int k = 0; k < 3; ++k) {
      const std::size_t at = 8 * static_cast<std::size_t>(k);
      // kick_and_drift: v += kv, w += kw, x += dt v, pv = v + kv, pw = w + kw.
      const __m512d kv = _mm512_loadu_pd(s.pv[i].data() + at);
      const __m512d kw = _mm512_loadu_pd(s.pw[i].data() + at);
      const __m512d v = _mm512_add_pd(_mm512_loadu_pd(s.v[i].data() + at), kv);
      const __m512d w = _mm512_add_pd(_mm512_loadu_pd(s.w[i].data() + at), kw);
      const __m512d x = _mm512_add_pd(_mm512_loadu_pd(s.x[i].data() + at), _mm512_mul_pd(dt, v));
      _mm512_storeu_pd(s.v[i].data() + at, v);
      _mm512_storeu_pd(s.w[i].data() + at, w);
      _mm512_storeu_pd(s.x[i].data() + at, x);
      _mm512_storeu_pd(s.pv[i].data() + at, _mm512_add_pd(v, kv));
      _mm512_storeu_pd(s.pw[i].data() + at, _mm512_add_pd(w, kw));
      const __m512d d = _mm512_sub_pd(x, _mm512_loadu_pd(s.x_build[i].data() + at));
      _mm512_storeu_pd(squares + at, _mm512_mul_pd(d, d));
    }
    for (int p = 0; p < 8; ++p) largest = std::max(largest, (squares[3 * p] + squares[3 * p + 1]) + squares[3 * p + 2]);
  }
  _mm256_zeroupper();
  return i;
}

/// The same with AVX: four particles' Vec3 fields are 12 doubles, three registers.
[[gnu::target("avx")]] std::size_t kicks_and_drifts_avx(FastState& s, std::size_t begin, std::size_t end, double& largest) {
  const __m256d dt = _mm256_set1_pd(s.dt);
  std::size_t i = begin;
  for (; i + 4 <= end; i += 4) {
    double squares[12];
    for (int k = 0; k < 3; ++k) {
      const std::size_t at = 4 * static_cast<std::size_t>(k);
      // kick_and_drift: v += kv, w += kw, x += dt v, pv = v + kv, pw = w + kw.
      const __m256d kv = _mm256_loadu_pd(s.pv[i].data() + at);
      const __m256d kw = _mm256_loadu_pd(s.pw[i].data() + at);
      const __m256d v = _mm256_add_pd(_mm256_loadu_pd(s.v[i].data() + at), kv);
      const __m256d w = _mm256_add_pd(_mm256_loadu_pd(s.w[i].data() + at), kw);
      const __m256d x = _mm256_add_pd(_mm256_loadu_pd(s.x[i].data() + at), _mm256_mul_pd(dt, v));
      _mm256_storeu_pd(s.v[i].data() + at, v);
      _mm256_storeu_pd(s.w[i].data() + at, w);
      _mm256_storeu_pd(s.x[i].data() + at, x);
      _mm256_storeu_pd(s.pv[i].data() + at, _mm256_add_pd(v, kv));
      _mm256_storeu_pd(s.pw[i].data() + at, _mm256_add_pd(w, kw));
      const __m256d d = _mm256_sub_pd(x, _mm256_loadu_pd(s.x_build[i].data() + at));
      _mm256_storeu_pd(squares + at, _mm256_mul_pd(d, d));
    }
    for (int p = 0; p < 4; ++p) largest = std::max(largest, (squares[3 * p] + squares[3 * p + 1]) + squares[3 * p + 2]);
  }
  _mm256_zeroupper();
  return i;
}
#endif

}  // namespace

double kicks_and_drifts(FastState& s, std::size_t begin, std::size_t end, bool cached) {
#ifdef PPOHDEM_DRIFT_LANES
  static const SimdLevel level = dem_simd_level();  // fixed for the process
  if (cached && level >= SimdLevel::avx) {
    double largest = 0.0;
    const std::size_t tail = level >= SimdLevel::avx512 ? kicks_and_drifts_avx512(s, begin, end, largest)
                                                        : kicks_and_drifts_avx(s, begin, end, largest);
    return std::max(largest, kicks_and_drifts_one_by_one(s, tail, end, true));
  }
#endif
  return kicks_and_drifts_one_by_one(s, begin, end, cached);
}

}  // namespace ppohdem::dem::fast
