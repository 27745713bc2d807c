// ExactSum and add_terms (ppohdem/dem/exact_sum.hpp) against independent answers: cases whose
// exact sum is known by reasoning, random sums against Python's rational arithmetic
// (exact_sum_oracle.py), and the property the engines rely on: any order and any split into
// merged parts give the same bits, one term at a time or in lanes.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "ppohdem/dem/exact_sum.hpp"

namespace {

using ppohdem::dem::ExactSum;

double exact(const std::vector<double>& terms) {
  ExactSum s;
  for (const double t : terms) s.add(t);
  return s.value();
}

// add_terms' value; add_terms_overwriting (on a copy) must give the same bits, else NaN.
double in_lanes(const std::vector<double>& terms) {
  ExactSum s, t;
  ppohdem::dem::add_terms(s, terms);
  std::vector<double> scratch = terms;
  ppohdem::dem::add_terms_overwriting(t, scratch);
  if (std::bit_cast<std::uint64_t>(s.value()) != std::bit_cast<std::uint64_t>(t.value())) return std::nan("");
  return s.value();
}

std::uint64_t bits(double x) { return std::bit_cast<std::uint64_t>(x); }

constexpr double kMax = std::numeric_limits<double>::max();
constexpr double kTiny = std::numeric_limits<double>::denorm_min();  // 2^-1074
constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(ExactSum, CasesKnownByReasoning) {
  const double u = std::ldexp(1.0, -53);  // half an ulp of 1
  EXPECT_EQ(bits(exact({})), bits(0.0));
  EXPECT_EQ(bits(exact({-0.0, -0.0})), bits(0.0)) << "the exact sum of zeros is +0";
  EXPECT_EQ(exact({1e16, 1.0, -1e16}), 1.0) << "cancellation: a running sum gives 0";
  EXPECT_EQ(exact({1.0, u, u}), 1.0 + 2 * u) << "a running sum gives 1";
  EXPECT_EQ(exact({1.0, u}), 1.0) << "a tie rounds to the even neighbour 1";
  EXPECT_EQ(exact({1.0 + 2 * u, u}), 1.0 + 4 * u) << "a tie rounds to the even neighbour 1 + 2^-51";
  EXPECT_EQ(exact({1.0, u, kTiny}), 1.0 + 2 * u) << "just above a tie rounds up";
  EXPECT_EQ(exact({1.0, u, -kTiny}), 1.0) << "just below a tie rounds down";
  EXPECT_EQ(exact({-1.0, u}), -(1.0 - u)) << "1 - 2^-53 is a double";
  EXPECT_EQ(exact({kTiny, kTiny}), 2 * kTiny);
  EXPECT_EQ(exact({std::numeric_limits<double>::min(), -kTiny}), std::nextafter(std::numeric_limits<double>::min(), 0.0));
  EXPECT_EQ(exact({kMax, kMax, -kMax}), kMax) << "no overflow in between";
  EXPECT_EQ(exact({kMax, kMax}), kInf);
  EXPECT_EQ(exact({-kMax, -kMax}), -kInf);
  EXPECT_EQ(exact({kMax, std::ldexp(1.0, 969)}), kMax) << "below half an ulp of DBL_MAX";
  EXPECT_EQ(exact({kMax, std::ldexp(1.0, 970)}), kInf) << "a tie above DBL_MAX (odd) rounds to 2^1024";
  EXPECT_EQ(exact({kInf, 1.0}), kInf);
  EXPECT_EQ(exact({-kInf, kMax, kMax}), -kInf);
  EXPECT_TRUE(std::isnan(exact({kInf, -kInf})));
  EXPECT_TRUE(std::isnan(exact({1.0, std::numeric_limits<double>::quiet_NaN()})));
}

TEST(ExactSum, ManyTermsCarryWithoutOverflow) {
  // 100,000 x DBL_MAX - 100,000 x DBL_MAX + 1: the carries of far more terms than
  // kTermsBetweenCarries, above the double range in between.
  ExactSum s;
  for (int i = 0; i < 100000; ++i) s.add(kMax);
  for (int i = 0; i < 100000; ++i) s.add(-kMax);
  s.add(1.0);
  EXPECT_EQ(s.value(), 1.0);
  ExactSum ones;
  for (int i = 0; i < (1 << 20); ++i) ones.add(1.0);
  EXPECT_EQ(ones.value(), 1048576.0);
  ExactSum tenths;  // 10^6 x 0.1 (the double) = 100000.0000000000055511151231257827 exactly
  for (int i = 0; i < 1000000; ++i) tenths.add(0.1);
  EXPECT_EQ(tenths.value(), 100000.0);
}

// Random terms over the whole range: mixed magnitudes, subnormals, cancelling pairs, near ties.
std::vector<std::vector<double>> random_cases(std::mt19937_64& rng) {
  std::vector<std::vector<double>> cases;
  std::uniform_int_distribution<int> exponent(-1074, 1023), small(-60, 60), count(1, 40);
  std::uniform_real_distribution<double> mantissa(1.0, 2.0);
  auto any = [&](int e) { return (rng() & 1 ? -1.0 : 1.0) * std::ldexp(mantissa(rng), e - 1); };
  for (int c = 0; c < 300; ++c) {
    std::vector<double> terms;
    const int n = count(rng);
    switch (c % 5) {
      case 0:  // anywhere in the range
        for (int i = 0; i < n; ++i) terms.push_back(any(exponent(rng)));
        break;
      case 1:  // magnitudes within 2^120 of each other: much rounding in a running sum
        for (int i = 0; i < n; ++i) terms.push_back(any(small(rng)));
        break;
      case 2:  // cancelling pairs and a small remainder
        for (int i = 0; i < n; ++i) {
          const double x = any(small(rng));
          terms.push_back(x);
          terms.push_back(-x);
        }
        terms.push_back(any(small(rng) - 100));
        std::shuffle(terms.begin(), terms.end(), rng);
        break;
      case 3:  // subnormals and the smallest normals
        for (int i = 0; i < n; ++i) terms.push_back((rng() & 1 ? -1.0 : 1.0) * kTiny * static_cast<double>(rng() >> 11));
        break;
      default:  // x plus half an ulp of x, nudged: ties and near ties
        {
          const double x = any(small(rng));
          const double half_ulp = std::ldexp(std::abs(x) - std::abs(std::nextafter(x, 0.0)), -1);
          terms = {x, half_ulp};
          if (c % 3 == 1) terms.push_back(std::ldexp(half_ulp, -60));
          if (c % 3 == 2) terms.push_back(-std::ldexp(half_ulp, -60));
        }
    }
    cases.push_back(terms);
  }
  return cases;
}

TEST(ExactSum, MatchesPythonRationalArithmetic) {
  std::mt19937_64 rng(20261205);
  const auto cases = random_cases(rng);
  const auto dir = std::filesystem::temp_directory_path();
  const auto in = dir / ("exact_sum_cases_" + std::to_string(::getpid()) + ".txt");
  const auto out = dir / ("exact_sum_oracle_" + std::to_string(::getpid()) + ".txt");
  {
    std::FILE* f = std::fopen(in.c_str(), "w");
    ASSERT_NE(f, nullptr);
    for (const auto& terms : cases) {
      for (const double t : terms) std::fprintf(f, "%a ", t);
      std::fprintf(f, "\n");
    }
    std::fclose(f);
  }
  const std::string command = std::string("/usr/bin/python3 ") + PPOHDEM_SOURCE_DIR + "/tests/dem/exact_sum_oracle.py < " +
                              in.string() + " > " + out.string();
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  std::ifstream answers(out);
  std::size_t checked = 0;
  for (const auto& terms : cases) {
    std::string hex;
    ASSERT_TRUE(answers >> hex) << "the oracle gave fewer answers than cases";
    const double want = hex == "inf" ? kInf : hex == "-inf" ? -kInf : std::strtod(hex.c_str(), nullptr);
    EXPECT_EQ(bits(exact(terms)), bits(want)) << "case " << checked << ": want " << hex;
    EXPECT_EQ(bits(in_lanes(terms)), bits(want)) << "in lanes, case " << checked << ": want " << hex;
    ++checked;
  }
  EXPECT_EQ(checked, cases.size());
  std::filesystem::remove(in);
  std::filesystem::remove(out);
}

}  // namespace

// Any order of the terms, and any split into parts summed apart and then merged (threads) or
// added word by word (ranks: Comm::sum_over_ranks), gives the same bits.
RC_GTEST_PROP(ExactSumProperty, OrderAndSplitDoNotChangeTheBits, ()) {
  const auto raw = *rc::gen::container<std::vector<std::uint64_t>>(rc::gen::arbitrary<std::uint64_t>());
  std::vector<double> terms;
  for (const std::uint64_t b : raw) {
    const double x = std::bit_cast<double>(b);
    if (std::isfinite(x)) terms.push_back(x);
  }
  const double whole = exact(terms);
  std::vector<double> shuffled = terms;
  std::mt19937_64 rng(*rc::gen::arbitrary<std::uint64_t>());
  std::shuffle(shuffled.begin(), shuffled.end(), rng);
  RC_ASSERT(bits(exact(shuffled)) == bits(whole));
  const std::size_t parts = *rc::gen::inRange<std::size_t>(1, 6);
  std::vector<ExactSum> part(parts);
  for (std::size_t i = 0; i < shuffled.size(); ++i) part[rng() % parts].add(shuffled[i]);
  ExactSum merged;
  for (std::size_t p = parts; p-- > 0;) merged.merge(part[p]);
  RC_ASSERT(bits(merged.value()) == bits(whole));
  std::array<std::int64_t, ExactSum::kWords> words{};
  for (ExactSum& p : part) {
    const auto w = p.words();
    for (std::size_t k = 0; k < ExactSum::kWords; ++k) words[k] += w[k];
  }
  RC_ASSERT(bits(ExactSum::from_words(words).value()) == bits(whole));
}

namespace {

// The words of adding each term to an empty sum (what add_terms must give).
std::array<std::int64_t, ExactSum::kWords> words_one_by_one(const std::vector<double>& terms) {
  ExactSum s;
  for (const double t : terms) s.add(t);
  std::array<std::int64_t, ExactSum::kWords> w{};
  std::copy_n(s.words().begin(), ExactSum::kWords, w.begin());
  return w;
}

// add_terms' words; add_terms_overwriting (on a copy) must give the same, else the answer is
// {-1, 0, ...}, which is no sum's words (the limbs below the last are in [0, 2^32)).
std::array<std::int64_t, ExactSum::kWords> words_in_lanes(const std::vector<double>& terms) {
  ExactSum s, t;
  ppohdem::dem::add_terms(s, terms);
  std::vector<double> scratch = terms;
  ppohdem::dem::add_terms_overwriting(t, scratch);
  std::array<std::int64_t, ExactSum::kWords> w{}, v{};
  std::copy_n(s.words().begin(), ExactSum::kWords, w.begin());
  std::copy_n(t.words().begin(), ExactSum::kWords, v.begin());
  if (v != w) return {-1};
  return w;
}

TEST(AddTerms, FullPiecesAtTheLevelsBound) {
  // 1,024 terms just below 2^e, one sign: the level's sum reaches its bound sigma; then with
  // mixed signs, a term of another level, and pieces beyond the first.
  for (const int e : {-1000, -1021, -60, 0, 52, 1000, 1013, 1014, 1023}) {
    const double top = std::nextafter(std::ldexp(1.0, e), 0.0);
    std::vector<double> terms(1024, top);
    EXPECT_EQ(words_in_lanes(terms), words_one_by_one(terms)) << "2^" << e;
    for (std::size_t i = 0; i < terms.size(); i += 3) terms[i] = -terms[i];
    terms.push_back(std::ldexp(1.5, e - 200));
    terms.push_back(kTiny);
    terms.insert(terms.end(), 2000, std::ldexp(top, -7));
    EXPECT_EQ(words_in_lanes(terms), words_one_by_one(terms)) << "mixed, 2^" << e;
  }
  // Known by reasoning (as for ExactSum above): many pieces, and terms beyond the lemma's range.
  EXPECT_EQ(in_lanes(std::vector<double>(1000000, 0.1)), 100000.0);
  std::vector<double> huge(100000, kMax);
  huge.insert(huge.end(), 100000, -kMax);
  huge.push_back(1.0);
  EXPECT_EQ(in_lanes(huge), 1.0);
  EXPECT_EQ(words_in_lanes({}), words_one_by_one({}));
  EXPECT_EQ(words_in_lanes({0.0, -0.0}), words_one_by_one({0.0, -0.0}));
  EXPECT_EQ(words_in_lanes({kMax, kMax, -kMax, kInf, 1.0}), words_one_by_one({kMax, kMax, -kMax, kInf, 1.0}));
}

}  // namespace

// add_terms gives the words of one add a term, for terms anywhere (infinities and NaNs
// included), and for many terms within a window of exponents (several pieces and levels).
RC_GTEST_PROP(AddTermsProperty, GivesTheWordsOfOneAddATerm, ()) {
  std::vector<double> terms;
  if (*rc::gen::inRange(0, 3) == 0) {
    for (const std::uint64_t b : *rc::gen::container<std::vector<std::uint64_t>>(rc::gen::arbitrary<std::uint64_t>())) {
      terms.push_back(std::bit_cast<double>(b));
    }
  } else {
    const int low = *rc::gen::inRange(-1074, 1024);
    const int width = *rc::gen::inRange(0, 300);
    const std::size_t n = *rc::gen::inRange<std::size_t>(0, 3000);
    std::mt19937_64 rng(*rc::gen::arbitrary<std::uint64_t>());
    for (std::size_t i = 0; i < n; ++i) {
      const int e = std::min(low + static_cast<int>(rng() % static_cast<std::uint64_t>(width + 1)), 1023);
      const std::uint64_t mantissa = rng() >> (rng() % 64 < 8 ? 12 + rng() % 52 : 12);  // some short mantissas
      double x = std::ldexp(static_cast<double>(mantissa | (std::uint64_t{1} << 52)), std::max(e, -1022) - 52);
      if (e < -1022) x = std::ldexp(x, e + 1022);  // subnormal (rounded: any double will do)
      if (rng() % 8 == 0) x = 0.0;
      terms.push_back(rng() & 1 ? -x : x);
    }
  }
  RC_ASSERT(words_in_lanes(terms) == words_one_by_one(terms));
}
