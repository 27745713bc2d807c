#pragma once
// What a step of the fast engine needs from every rank, in ONE record of fixed size combined
// by one allreduce (Comm::combine_over_ranks; docs/dem.md "One collective a step"): the
// counts, the screen, the energy rates, the deepest contact and the largest displacement of
// the next drift. Each part has its own operation, all commutative and associative, so the
// ranks' records combine in any order to the same bits.
#include <bit>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "fast_state.hpp"
#include "ppohdem/dem/exact_sum.hpp"

namespace ppohdem::dem::fast {

/// The record, in 64-bit words:
///   [0]                 the number of summed words after it (the same on every rank; kept)
///   [1, 1 + summed)     summed as integers: pair contacts, boundary contacts, escaped
///                       particles, ranks whose screen is not finite; then, energies tracked,
///                       the words of the rates' exact sums (dissipated, work, power)
///   [1 + summed]        the maximum: the next drift's largest squared displacement, a double
///                       >= 0 (never NaN: the maxima start at 0 and std::max drops NaN terms)
///   then 6 words        the deepest contact, by keep_deeper (a total order): present flag,
///                       ratio and overlap (double bits), id_a, id_b, boundary flag
class StepRecord {
 public:
  static constexpr std::size_t kCounts = 4;
  static constexpr std::size_t kRates = 3;  ///< dissipated, boundary work, power
  static constexpr std::size_t kDeepestWords = 6;

  explicit StepRecord(bool rates) : words_(1 + kCounts + (rates ? kRates * ExactSum::kWords : 0) + 1 + kDeepestWords, 0) {
    words_[0] = static_cast<std::int64_t>(summed());
  }

  std::vector<std::int64_t>& words() { return words_; }
  const std::vector<std::int64_t>& words() const { return words_; }
  std::size_t bytes() const { return words_.size() * sizeof(std::int64_t); }

  void set_counts(std::size_t pairs, std::size_t boundaries, std::size_t escaped, bool screen_finite) {
    words_[1] = static_cast<std::int64_t>(pairs);
    words_[2] = static_cast<std::int64_t>(boundaries);
    words_[3] = static_cast<std::int64_t>(escaped);
    words_[4] = screen_finite ? 0 : 1;
  }
  std::size_t pair_contacts() const { return static_cast<std::size_t>(words_[1]); }
  std::size_t boundary_contacts() const { return static_cast<std::size_t>(words_[2]); }
  std::size_t escaped() const { return static_cast<std::size_t>(words_[3]); }
  bool screens_finite() const { return words_[4] == 0; }

  /// rates[0..kRates): this rank's exact sums of the rates (energies tracked only).
  void set_rates(ExactSum* rates) {  // non-const: words() propagates the carries first
    for (std::size_t c = 0; c < kRates; ++c) {
      const auto w = rates[c].words();
      std::copy(w.begin(), w.end(), words_.begin() + static_cast<std::ptrdiff_t>(1 + kCounts + c * ExactSum::kWords));
    }
  }
  ExactSum rate(std::size_t c) const {
    return ExactSum::from_words(
        std::span<const std::int64_t, ExactSum::kWords>(words_.data() + 1 + kCounts + c * ExactSum::kWords, ExactSum::kWords));
  }

  void set_drift(double largest) { words_[1 + summed()] = std::bit_cast<std::int64_t>(largest); }
  double drift() const { return std::bit_cast<double>(words_[1 + summed()]); }

  void set_deepest(const std::optional<LargestOverlap>& d) { write_deepest(words_.data() + words_.size() - kDeepestWords, d); }
  std::optional<LargestOverlap> deepest() const { return deepest_of(words_.data(), words_.size()); }

  /// The operation of the allreduce (CombineWords): inout := in combined with inout.
  static void combine(const std::int64_t* in, std::int64_t* inout, std::size_t words) {
    const auto summed = static_cast<std::size_t>(in[0]);
    for (std::size_t k = 1; k <= summed; ++k) {  // wrapping, as MPI_SUM does: exact for exact sums' words
      inout[k] = static_cast<std::int64_t>(static_cast<std::uint64_t>(inout[k]) + static_cast<std::uint64_t>(in[k]));
    }
    const double drift = std::bit_cast<double>(in[1 + summed]);
    if (drift > std::bit_cast<double>(inout[1 + summed])) inout[1 + summed] = in[1 + summed];
    if (const auto other = deepest_of(in, words)) {
      std::optional<LargestOverlap> deepest = deepest_of(inout, words);
      keep_deeper(deepest, *other);
      write_deepest(inout + words - kDeepestWords, deepest);
    }
  }

 private:
  std::size_t summed() const { return words_.size() - 2 - kDeepestWords; }
  static void write_deepest(std::int64_t* w, const std::optional<LargestOverlap>& d) {
    w[0] = d ? 1 : 0;
    if (!d) return;
    w[1] = std::bit_cast<std::int64_t>(d->ratio);
    w[2] = std::bit_cast<std::int64_t>(d->overlap);
    w[3] = d->id_a;
    w[4] = d->id_b;
    w[5] = d->boundary ? 1 : 0;
  }
  static std::optional<LargestOverlap> deepest_of(const std::int64_t* all, std::size_t words) {
    const std::int64_t* w = all + words - kDeepestWords;
    if (w[0] == 0) return std::nullopt;
    return LargestOverlap{std::bit_cast<double>(w[1]), std::bit_cast<double>(w[2]), w[3], w[4], w[5] != 0};
  }

  std::vector<std::int64_t> words_;
};

}  // namespace ppohdem::dem::fast
