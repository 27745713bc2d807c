#pragma once
/// \file exact_sum.hpp
/// Sums of doubles that stay EXACT until one final rounding, so that partial sums made on any
/// threads and ranks combine, in any order, to the same bits. The value of a sum is defined as
/// the real (exact) sum of its terms rounded once to the nearest double, ties to even
/// (docs/dem.md "Sums over particles").
///
/// Method: a fixed-point long accumulator (Kulisch & Miranker, "Computer Arithmetic in Theory
/// and Practice", 1981), laid out as Neal's "small superaccumulator" (R. M. Neal, "Fast exact
/// summation using small and large superaccumulators", arXiv:1505.05571, 2015). Every finite
/// double is
///     x = (-1)^sign  m  2^(s - 1074),   m integer in [0, 2^53),  s integer in [0, 2045]
/// (s = biased exponent - 1 and m with its hidden bit for normals; s = 0 for subnormals). The
/// accumulator holds signed 64-bit limbs c_k for the integer value
///     A = sum_k c_k 2^(32 k)          (the sum is A 2^-1074),
/// and a term adds m 2^(s mod 32) into limbs s/32 and s/32 + 1: the low 32 bits to the first,
/// the rest (< 2^53) to the second. A limb so grows by less than 2^53 per term; after
/// kTermsBetweenCarries terms the carries are propagated (each limb but the last brought to
/// [0, 2^32)), long before a limb could overflow. Integer additions are associative: the
/// order of the terms and of the merges cannot change A.
/// Infinities and NaNs are counted apart; the sum is NaN if there is a NaN or both infinities,
/// else the infinity if there is one (what any order of IEEE additions gives, up to the NaN's
/// payload). A sum of zeros is +0. Why by hand: no Debian package has an exact summation whose
/// partial sums travel in an MPI message (words() below).
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>

namespace ppohdem::dem {

class ExactSum {
 public:
  /// 64 limbs reach bit 32 * 64 > 1074 + 1024 (the largest double's top bit); 3 more take the
  /// carries of up to 2^60 terms of the largest magnitude.
  static constexpr std::size_t kLimbs = 67;
  /// Limbs plus the counts of +inf, -inf and NaN terms: what merge() and the ranks add.
  static constexpr std::size_t kWords = kLimbs + 3;
  /// After a carry propagation a limb is below 2^32 + 2^53 per term since: 2^9 terms keep it
  /// far below 2^63.
  static constexpr unsigned kTermsBetweenCarries = 512;

  void add(double x) {
    const auto bits = std::bit_cast<std::uint64_t>(x);
    const unsigned biased = static_cast<unsigned>(bits >> 52) & 0x7ffu;
    const std::uint64_t fraction = bits & ((std::uint64_t{1} << 52) - 1);
    if ((bits << 1) == 0) return;  // +0 or -0 adds nothing
    nonzero_ = true;
    if (biased == 0x7ffu) {  // inf or NaN
      ++words_[kLimbs + (fraction != 0 ? 2 : (bits >> 63))];
      return;
    }
    const std::uint64_t m = biased != 0 ? fraction | (std::uint64_t{1} << 52) : fraction;
    const unsigned s = biased != 0 ? biased - 1 : 0;
    const unsigned k = s / 32;
    const unsigned shift = s % 32;
    // m 2^shift = low + high 2^32 with low < 2^32, high < 2^53; (v ^ sign) - sign negates v
    // when sign = -1 (a negative term) and keeps it when sign = 0.
    const auto low = static_cast<std::int64_t>((m << shift) & 0xffffffffu);
    const auto high = static_cast<std::int64_t>(m >> (32 - shift));
    const auto sign = -static_cast<std::int64_t>(bits >> 63);
    words_[k] += (low ^ sign) - sign;
    words_[k + 1] += (high ^ sign) - sign;
    if (++terms_ == kTermsBetweenCarries) propagate_carries();
  }

  /// Adds another sum's terms (exact: the result does not depend on the order of merges).
  void merge(const ExactSum& other) {
    if (!other.nonzero_) return;  // nothing to add (most of a step's load sums)
    ExactSum carried = other;
    carried.propagate_carries();
    propagate_carries();
    for (std::size_t k = 0; k < kWords; ++k) words_[k] += carried.words_[k];
    terms_ = 2;  // each limb is now below 2^33 < 2 * 2^53
    nonzero_ = true;
  }

  /// Back to the empty sum (cheap if nothing was added).
  void reset() {
    if (nonzero_) *this = ExactSum{};
  }

  /// The limbs with their carries propagated (each but the last in [0, 2^32)) and the counts:
  /// summing the words of several sums elementwise (MPI_Allreduce, MPI_SUM) gives the words
  /// of their merge, for fewer than 2^31 sums.
  std::span<std::int64_t, kWords> words() {
    propagate_carries();
    return words_;
  }

  /// The sum of the words of other sums (words() of each, added elementwise).
  static ExactSum from_words(std::span<const std::int64_t, kWords> words) {
    ExactSum sum;
    for (std::size_t k = 0; k < kWords; ++k) {
      sum.words_[k] = words[k];
      sum.nonzero_ = sum.nonzero_ || words[k] != 0;
    }
    sum.terms_ = kTermsBetweenCarries - 1;  // unknown history: propagate at the next add
    return sum;
  }

  /// The exact sum rounded to the nearest double, ties to even (+-inf beyond the range).
  double value() const {
    if (!nonzero_) return 0.0;
    const std::int64_t plus_inf = words_[kLimbs], minus_inf = words_[kLimbs + 1], nan = words_[kLimbs + 2];
    if (nan != 0 || (plus_inf != 0 && minus_inf != 0)) return std::numeric_limits<double>::quiet_NaN();
    if (plus_inf != 0) return std::numeric_limits<double>::infinity();
    if (minus_inf != 0) return -std::numeric_limits<double>::infinity();
    ExactSum a = *this;
    a.propagate_carries();  // A = sum c_k 2^(32k), limbs below the last in [0, 2^32)
    const bool negative = a.words_[kLimbs - 1] < 0;
    if (negative) {  // |A| = -A: negate every limb, then bring them back to [0, 2^32)
      for (std::size_t k = 0; k < kLimbs; ++k) a.words_[k] = -a.words_[k];
      a.propagate_carries();
    }
    const double magnitude = a.rounded_magnitude();
    return negative ? -magnitude : magnitude;
  }

 private:
  void propagate_carries() {
    for (std::size_t k = 0; k + 1 < kLimbs; ++k) {
      const std::int64_t carry = words_[k] >> 32;  // floor(c_k / 2^32): arithmetic shift
      words_[k] -= carry * (std::int64_t{1} << 32);
      words_[k + 1] += carry;
    }
    terms_ = 0;
  }

  /// A 2^-1074 rounded to nearest, ties to even, for A >= 0 with every limb in [0, 2^32).
  double rounded_magnitude() const {
    std::size_t top = kLimbs;  // the highest nonzero limb
    while (top > 0 && words_[top - 1] == 0) --top;
    if (top == 0) return 0.0;
    --top;
    const auto digit = [&](std::size_t k) { return static_cast<std::uint64_t>(words_[k]); };
    // b: the bit length of A; window: A's 64 bits [b - 64, b) (A shifted up if b < 64);
    // sticky: some bit of A below the window is set.
    const int b = static_cast<int>(32 * top) + static_cast<int>(std::bit_width(digit(top)));
    std::uint64_t window = 0;
    bool sticky = false;
    if (b <= 64) {
      const std::uint64_t value = top == 0 ? digit(0) : digit(0) | (digit(1) << 32);
      if (b <= 53) return std::ldexp(static_cast<double>(value), -1074);  // exact
      window = value << (64 - b);
    } else {
      const auto lowest = static_cast<std::size_t>(b - 64);  // the window's lowest bit
      const std::size_t k = lowest / 32;
      const unsigned shift = lowest % 32;
      const std::uint64_t two = digit(k) | (digit(k + 1) << 32);  // bits [32k, 32k + 64)
      window = two >> shift;
      if (shift != 0 && k + 2 <= top) window |= digit(k + 2) << (64 - shift);
      sticky = (digit(k) & ((std::uint64_t{1} << shift) - 1)) != 0;
      for (std::size_t j = 0; j < k && !sticky; ++j) sticky = words_[j] != 0;
    }
    // The top 53 bits, and the 11 below them against half a unit in the last place.
    std::uint64_t q = window >> 11;
    const std::uint64_t rest = window & 0x7ffu;
    constexpr std::uint64_t kHalf = 0x400u;
    if (rest > kHalf || (rest == kHalf && (sticky || (q & 1u) != 0))) ++q;  // q may become 2^53: still exact
    return std::ldexp(static_cast<double>(q), b - 53 - 1074);  // normal (b > 53), inf beyond the range
  }

  std::array<std::int64_t, kWords> words_{};
  unsigned terms_ = 0;  ///< terms added since the last carry propagation
  bool nonzero_ = false;  ///< some term was not zero (else the words are all zero)
};

/// Adds every term to `sum`: the same words as sum.add(t) for each t, in lanes. Each piece of
/// up to 1,024 terms is split level by level with Rump's error-free extraction (q = (sigma + x)
/// - sigma, x - q exact; Rump, Ogita & Oishi, "Accurate floating-point summation part I",
/// SIAM J. Sci. Comput. 31(1), 2008, Lemma 3.3): the q of a level are multiples of one unit
/// and their sum is below sigma, so it is exact in doubles, in any order, and goes into `sum`
/// as one term (docs/dem.md "Sums over particles"). Terms too small or too large for a normal
/// sigma, infinities and NaNs are added one by one.
void add_terms(ExactSum& sum, std::span<const double> terms);
/// add_terms for terms that may be overwritten (scratch arrays): the same words, without
/// copying the terms to scratch of its own; `terms` holds garbage afterwards.
void add_terms_overwriting(ExactSum& sum, std::span<double> terms);

/// K exact sums side by side (e.g. the energy terms of the particles).
template <std::size_t K>
struct ExactSums {
  std::array<ExactSum, K> sum;
  void add(const std::array<double, K>& terms) {
    for (std::size_t c = 0; c < K; ++c) sum[c].add(terms[c]);
  }
  void merge(const ExactSums& other) {
    for (std::size_t c = 0; c < K; ++c) sum[c].merge(other.sum[c]);
  }
  std::array<double, K> values() const {
    std::array<double, K> v{};
    for (std::size_t c = 0; c < K; ++c) v[c] = sum[c].value();
    return v;
  }
};

}  // namespace ppohdem::dem
