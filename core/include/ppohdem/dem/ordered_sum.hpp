#pragma once
/// \file ordered_sum.hpp
/// Sums over the particles of a system (kinetic energy, contact energy terms) in ONE fixed
/// order that serial and parallel code both reproduce bit for bit.
///
/// Floating-point addition is not associative, so "the sum" depends on the order of the
/// additions. The order fixed here: the construction indices 0 .. n-1 are cut into blocks of
/// kSumBlock consecutive indices; each block is summed left to right starting from zero, then
/// the block sums are added left to right starting from zero. Blocks are independent, so
/// threads can sum them concurrently and the result does not depend on how many threads did.
/// For n <= kSumBlock this is the plain running sum. Blocked summation also has the smaller
/// error bound: about (kSumBlock + n / kSumBlock) eps sum|x_i| instead of n eps sum|x_i|
/// (Higham, "Accuracy and Stability of Numerical Algorithms", 2nd ed. 2002, section 4.2).
#include <algorithm>
#include <array>
#include <cstddef>
#include <vector>

namespace ppohdem::dem {

inline constexpr std::size_t kSumBlock = 1024;

/// K running sums of term(i) over i in [begin, end), left to right from zero.
/// `term(i)` returns std::array<double, K>.
template <std::size_t K, class Term>
std::array<double, K> sum_range(std::size_t begin, std::size_t end, const Term& term) {
  std::array<double, K> sums{};
  for (std::size_t i = begin; i < end; ++i) {
    const std::array<double, K> t = term(i);
    for (std::size_t c = 0; c < K; ++c) sums[c] += t[c];
  }
  return sums;
}

/// Number of blocks for n terms.
inline std::size_t sum_blocks(std::size_t n) { return (n + kSumBlock - 1) / kSumBlock; }

/// The block sums added left to right from zero.
template <std::size_t K>
std::array<double, K> add_blocks(const std::vector<std::array<double, K>>& blocks) {
  std::array<double, K> sums{};
  for (const auto& b : blocks) {
    for (std::size_t c = 0; c < K; ++c) sums[c] += b[c];
  }
  return sums;
}

/// The ordered sum of term(0) .. term(n-1), serially. Parallel code computes block b as
/// sum_range<K>(b * kSumBlock, min(n, (b + 1) * kSumBlock), term) and calls add_blocks.
template <std::size_t K, class Term>
std::array<double, K> ordered_sum(std::size_t n, const Term& term) {
  std::vector<std::array<double, K>> blocks(sum_blocks(n));
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    blocks[b] = sum_range<K>(b * kSumBlock, std::min(n, (b + 1) * kSumBlock), term);
  }
  return add_blocks(blocks);
}

}  // namespace ppohdem::dem
