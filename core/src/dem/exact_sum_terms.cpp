// ExactSum's add of many terms in lanes (add_terms, ppohdem/dem/exact_sum.hpp): pieces of
// 1,024 terms split by Rump's error-free extraction, each level's share summed exactly in
// doubles (docs/dem.md "Sums over particles"). Built once for AVX-512F and once for the
// baseline (and in four lanes for AVX); all give the words of the term-by-term add.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "ppohdem/dem/exact_sum.hpp"
#include "ppohdem/simd_level.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

// The helpers below are always inlined into the function built for their width, so the
// compilers' note that a 64-byte vector passes differently without AVX-512F does not apply.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace ppohdem::dem {
namespace {

constexpr std::size_t kPiece = 1024;  ///< n <= 2^kLevelBits terms a piece: see add_piece
constexpr int kLevelBits = 10;
constexpr std::size_t kLanes = 8;  ///< the widest W below: pieces are padded to it
constexpr std::uint64_t kMagnitude = ~(std::uint64_t{1} << 63);

// W lanes as GCC/Clang vector types: eight in one AVX-512F register, four in an AVX one, two
// in an SSE2 one (the loops are written in lanes: GCC vectorises per-lane arrays across the
// terms instead).
// (Spelled out per width: GCC drops vector_size on an alias template with a dependent size.)
template <std::size_t W>
struct LaneTypes;
template <>
struct LaneTypes<2> {
  typedef double Lanes __attribute__((vector_size(16)));
  typedef std::uint64_t Bits __attribute__((vector_size(16)));
};
template <>
struct LaneTypes<4> {
  typedef double Lanes __attribute__((vector_size(32)));
  typedef std::uint64_t Bits __attribute__((vector_size(32)));
};
template <>
struct LaneTypes<8> {
  typedef double Lanes __attribute__((vector_size(64)));
  typedef std::uint64_t Bits __attribute__((vector_size(64)));
};
template <std::size_t W>
using Lanes = typename LaneTypes<W>::Lanes;
template <std::size_t W>
using Bits = typename LaneTypes<W>::Bits;
template <std::size_t W>
[[gnu::always_inline]] inline Lanes<W> load(const double* p) {
  Lanes<W> v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
template <std::size_t W>
[[gnu::always_inline]] inline void store(double* p, Lanes<W> v) { std::memcpy(p, &v, sizeof v); }

/// Adds r[0, n) (n <= kPiece, padded with zeros to a multiple of kLanes) to `sum`; r is
/// overwritten. With |x| <= 2^e for every term and sigma = 2^(e + kLevelBits), Lemma 3.3 of
/// Rump et al. splits each x into q + r' exactly, q a multiple of u = 2^-53 sigma and
/// |q| <= 2^-kLevelBits sigma, |r'| <= u: so every partial sum of the n q's is a multiple of u
/// below sigma, a double, whatever the order of the adds. The next level splits the r' with
/// e := log2 u. sigma stays a normal double (the lemma's setting); what is left below that,
/// or above the range, is added term by term.
template <std::size_t W>
[[gnu::always_inline]] inline void add_piece(ExactSum& sum, double* r, std::size_t n) {
  // The largest |x| (max in lanes: SSE2 has no 64-bit integer max), and x - x, which is 0 for
  // a finite x and NaN for an infinity or a NaN.
  Lanes<W> top_lanes{};
  Lanes<W> finite{};
  for (std::size_t i = 0; i < n; i += W) {
    const Lanes<W> x = load<W>(r + i);
    const Lanes<W> magnitude = std::bit_cast<Lanes<W>>(std::bit_cast<Bits<W>>(x) & kMagnitude);
    top_lanes = top_lanes > magnitude ? top_lanes : magnitude;
    finite += x - x;
  }
  double top_value = 0.0, screen = 0.0;
  for (std::size_t l = 0; l < W; ++l) {
    top_value = std::max(top_value, top_lanes[l]);
    screen += finite[l];
  }
  if (screen != 0.0) {  // NaN: an infinity or a NaN among the terms, counted one by one
    for (std::size_t i = 0; i < n; ++i) sum.add(r[i]);
    return;
  }
  const std::uint64_t top = std::bit_cast<std::uint64_t>(top_value);
  if (top == 0) return;  // zeros only
  int e = std::max(static_cast<int>(top >> 52), 1) - 1022;  // |x| < 2^e
  while (true) {
    const int level = e + kLevelBits;  // sigma = 2^level
    if (level > 1023 || level - 53 < -1022) {
      for (std::size_t i = 0; i < n; ++i) sum.add(r[i]);  // outside the lemma's range: one by one
      return;
    }
    const Lanes<W> sigma = Lanes<W>{} + std::ldexp(1.0, level);
    Lanes<W> share{};
    Bits<W> left{};
    for (std::size_t i = 0; i < n; i += W) {
      Lanes<W> x = load<W>(r + i);
      const Lanes<W> q = (sigma + x) - sigma;
      x -= q;
      store<W>(r + i, x);
      share += q;
      left |= std::bit_cast<Bits<W>>(x) << 1;  // -0 counts as nothing left
    }
    double level_sum = 0.0;  // exact, in any order (see above)
    std::uint64_t any = 0;
    for (std::size_t l = 0; l < W; ++l) {
      level_sum += share[l];
      any |= left[l];
    }
    sum.add(level_sum);
    if (any == 0) return;
    e = level - 53;  // |r'| <= u = 2^(level - 53)
  }
}

// Whole pieces of kLanes-multiples in place when the terms may be overwritten (T = double),
// else each piece copied to scratch first; the last few terms padded with zeros in scratch.
template <std::size_t W, class T>
[[gnu::always_inline]] inline void add_all(ExactSum& sum, std::span<T> terms) {
  alignas(64) double r[kPiece];
  for (std::size_t at = 0; at < terms.size();) {
    std::size_t n = std::min(kPiece, terms.size() - at);
    if constexpr (!std::is_const_v<T>) {
      if (n >= kLanes) {
        n = n / kLanes * kLanes;
        add_piece<W>(sum, terms.data() + at, n);
        at += n;
        continue;
      }
    }
    std::copy_n(terms.data() + at, n, r);
    const std::size_t padded = (n + kLanes - 1) / kLanes * kLanes;
    std::fill(r + n, r + padded, 0.0);
    add_piece<W>(sum, r, padded);
    at += n;
  }
}

// One function a width and a constness of the terms (T: const double or double).
template <class T>
void add_all_baseline(ExactSum& sum, std::span<T> terms) {
  add_all<2>(sum, terms);
}

#if defined(__x86_64__) && defined(__GNUC__)
// Each ends with vzeroupper on every path, the empty one too (docs/portability.md "Upper
// register state"). Four lanes: the DEM's lanes are four on Intel CPUs with AVX-512
// (docs/portability.md "DEM lane width").
template <class T>
[[gnu::target("avx512f")]] void add_all_avx512(ExactSum& sum, std::span<T> terms) {
  add_all<8>(sum, terms);
  _mm256_zeroupper();
}
template <class T>
[[gnu::target("avx")]] void add_all_avx(ExactSum& sum, std::span<T> terms) {
  add_all<4>(sum, terms);
  _mm256_zeroupper();
}
#endif

template <class T>
void add_terms_at_level(ExactSum& sum, std::span<T> terms) {
#if defined(__x86_64__) && defined(__GNUC__)
  static const SimdLevel level = dem_simd_level();  // fixed for the process
  if (level >= SimdLevel::avx512) return add_all_avx512(sum, terms);
  if (level == SimdLevel::avx) return add_all_avx(sum, terms);
#endif
  add_all_baseline(sum, terms);
}

}  // namespace

void add_terms(ExactSum& sum, std::span<const double> terms) { add_terms_at_level(sum, terms); }
void add_terms_overwriting(ExactSum& sum, std::span<double> terms) { add_terms_at_level(sum, terms); }

}  // namespace ppohdem::dem
