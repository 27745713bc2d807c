// The neighbour search's distance test, one and four members at a time (near_members.hpp).
#include "near_members.hpp"

#include <algorithm>
#include <initializer_list>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define PPOHDEM_X4 1
#endif

namespace ppohdem::dem::fast {

void ProbeColumns::resize(std::size_t members) {
  for (std::vector<double>* column : {&x, &y, &z, &r}) {
    column->resize(members + kPadding);
    std::fill(column->end() - static_cast<std::ptrdiff_t>(kPadding), column->end(), 0.0);
  }
}

std::size_t near_members(const ProbeColumns& probes, const MemberRun* runs, std::size_t run_count, const NearQuery& q,
                         std::uint32_t* kept) {
  std::size_t count = 0;
  for (std::size_t k = 0; k < run_count; ++k) {
    for (std::uint32_t m = runs[k].begin; m < runs[k].end; ++m) {
      const double dx = q.x - probes.x[m];
      const double dy = q.y - probes.y[m];
      const double dz = q.z - probes.z[m];
      const double reach = (q.radius + probes.r[m]) + q.skin;
      // Written always, kept by advancing the count (no branch: about a quarter of the
      // candidates pass, a coin toss for the branch predictor).
      kept[count] = m;
      count += static_cast<std::size_t>(((dx * dx + dy * dy) + dz * dz < reach * reach) & (m != q.self));
    }
  }
  return count;
}

#ifdef PPOHDEM_X4

namespace {

/// For each 4-bit mask of kept lanes: the kept lanes' offsets in ascending order (the rest
/// zero, written but not counted), and how many there are.
struct LaneTable {
  alignas(16) std::uint32_t offsets[16][4] = {};
  std::uint32_t count[16] = {};
  constexpr LaneTable() {
    for (unsigned mask = 0; mask < 16; ++mask) {
      for (unsigned lane = 0; lane < 4; ++lane) {
        if ((mask >> lane) & 1u) offsets[mask][count[mask]++] = lane;
      }
    }
  }
};
constexpr LaneTable kLanes;

}  // namespace

[[gnu::target("avx")]] std::size_t near_members_x4(const ProbeColumns& probes, const MemberRun* runs,
                                                     std::size_t run_count, const NearQuery& q, std::uint32_t* kept) {
  const __m256d cx = _mm256_set1_pd(q.x);
  const __m256d cy = _mm256_set1_pd(q.y);
  const __m256d cz = _mm256_set1_pd(q.z);
  const __m256d radius = _mm256_set1_pd(q.radius);
  const __m256d skin = _mm256_set1_pd(q.skin);
  const double* const px = probes.x.data();
  const double* const py = probes.y.data();
  const double* const pz = probes.z.data();
  const double* const pr = probes.r.data();
  std::size_t count = 0;
  for (std::size_t k = 0; k < run_count; ++k) {
    const std::uint32_t end = runs[k].end;
    for (std::uint32_t m = runs[k].begin; m < end; m += 4) {
      const __m256d dx = _mm256_sub_pd(cx, _mm256_loadu_pd(px + m));
      const __m256d dy = _mm256_sub_pd(cy, _mm256_loadu_pd(py + m));
      const __m256d dz = _mm256_sub_pd(cz, _mm256_loadu_pd(pz + m));
      const __m256d distance2 =
          _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)), _mm256_mul_pd(dz, dz));
      const __m256d reach = _mm256_add_pd(_mm256_add_pd(radius, _mm256_loadu_pd(pr + m)), skin);
      unsigned mask = static_cast<unsigned>(
          _mm256_movemask_pd(_mm256_cmp_pd(distance2, _mm256_mul_pd(reach, reach), _CMP_LT_OQ)));
      if (end - m < 4) mask &= (1u << (end - m)) - 1u;  // lanes past the run (padding or the next run)
      if (const std::uint32_t self = q.self - m; self < 4) mask &= ~(1u << self);
      // The kept members' indices as one 16-byte store (up to 3 more written, not counted).
      const __m128i lanes = _mm_load_si128(reinterpret_cast<const __m128i*>(kLanes.offsets[mask]));
      _mm_storeu_si128(reinterpret_cast<__m128i*>(kept + count), _mm_add_epi32(lanes, _mm_set1_epi32(static_cast<int>(m))));
      count += kLanes.count[mask];
    }
  }
  return count;
}

#else  // not x86-64 with GCC: never available, never called

std::size_t near_members_x4(const ProbeColumns& probes, const MemberRun* runs, std::size_t run_count, const NearQuery& q,
                            std::uint32_t* kept) {
  return near_members(probes, runs, run_count, q, kept);
}

#endif

}  // namespace ppohdem::dem::fast
