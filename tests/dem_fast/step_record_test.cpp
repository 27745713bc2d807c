// StepRecord (core/src/dem/fast/step_record.hpp), the one allreduce of a fast-engine step:
// the ranks' records combined in any order give the same words, and each part is what a
// direct computation over the ranks' values gives (sums of the counts, the exact sum of all
// the rates' terms, the largest drift, keep_deeper over the deepest contacts).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
#include <random>
#include <tuple>
#include <vector>

#include "../../core/src/dem/fast/step_record.hpp"  // internal

namespace {

using ppohdem::dem::ExactSum;
using ppohdem::dem::LargestOverlap;
using ppohdem::dem::fast::StepRecord;

struct RankValues {
  std::size_t pairs = 0, boundaries = 0, escaped = 0;
  bool finite = true;
  std::vector<std::vector<double>> rate_terms = std::vector<std::vector<double>>(StepRecord::kRates);
  double drift = 0.0;
  std::optional<LargestOverlap> deepest;
};

StepRecord record_of(const RankValues& v, bool rates) {
  StepRecord r(rates);
  r.set_counts(v.pairs, v.boundaries, v.escaped, v.finite);
  if (rates) {
    ExactSum sums[StepRecord::kRates];
    for (std::size_t c = 0; c < StepRecord::kRates; ++c) {
      for (const double x : v.rate_terms[c]) sums[c].add(x);
    }
    r.set_rates(sums);
  }
  r.set_drift(v.drift);
  r.set_deepest(v.deepest);
  return r;
}

/// Combines the records in the given order, as a chain of the operation.
std::vector<std::int64_t> combined(const std::vector<StepRecord>& records, const std::vector<std::size_t>& order) {
  std::vector<std::int64_t> acc = records[order[0]].words();
  for (std::size_t k = 1; k < order.size(); ++k) {
    const std::vector<std::int64_t>& in = records[order[k]].words();
    StepRecord::combine(in.data(), acc.data(), acc.size());
  }
  return acc;
}

TEST(StepRecord, CombinesInAnyOrderToTheDirectValues) {
  std::mt19937_64 rng(37);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (const bool rates : {true, false}) {
    for (int trial = 0; trial < 50; ++trial) {
      const int ranks = 2 + trial % 7;
      std::vector<RankValues> values(static_cast<std::size_t>(ranks));
      for (RankValues& v : values) {
        v.pairs = rng() % 1000;
        v.boundaries = rng() % 100;
        v.escaped = rng() % 3;
        v.finite = rng() % 5 != 0;
        for (auto& terms : v.rate_terms) {
          for (int t = 0; t < 20; ++t) terms.push_back((u(rng) - 0.3) * std::pow(10.0, 20.0 * u(rng) - 10.0));
        }
        v.drift = rng() % 4 == 0 ? 0.0 : u(rng) * 1e-8;
        if (rng() % 3 != 0) {
          // Few distinct ratios, so that ties (broken by boundary, id_a, id_b) occur.
          v.deepest = LargestOverlap{0.01 * static_cast<double>(rng() % 3), u(rng), static_cast<std::int64_t>(rng() % 5),
                                     static_cast<std::int64_t>(rng() % 5), rng() % 2 == 0};
        }
      }
      std::vector<StepRecord> records;
      for (const RankValues& v : values) records.push_back(record_of(v, rates));
      std::vector<std::size_t> order(values.size());
      std::iota(order.begin(), order.end(), 0);
      const std::vector<std::int64_t> first = combined(records, order);
      for (int shuffle = 0; shuffle < 5; ++shuffle) {
        std::shuffle(order.begin(), order.end(), rng);
        EXPECT_EQ(combined(records, order), first);
      }
      // A tree (pairs, then pairs of pairs), as a recursive-doubling allreduce combines.
      std::vector<std::vector<std::int64_t>> level;
      for (StepRecord& r : records) level.push_back(r.words());
      while (level.size() > 1) {
        std::vector<std::vector<std::int64_t>> next;
        for (std::size_t k = 0; k + 1 < level.size(); k += 2) {
          StepRecord::combine(level[k].data(), level[k + 1].data(), level[k + 1].size());
          next.push_back(level[k + 1]);
        }
        if (level.size() % 2 == 1) next.push_back(level.back());
        level.swap(next);
      }
      EXPECT_EQ(level[0], first);

      // The direct values.
      StepRecord result(rates);
      result.words() = first;
      std::size_t pairs = 0, boundaries = 0, escaped = 0;
      bool finite = true;
      double drift = 0.0;
      std::optional<LargestOverlap> deepest;
      ExactSum all[StepRecord::kRates];
      for (const RankValues& v : values) {
        pairs += v.pairs;
        boundaries += v.boundaries;
        escaped += v.escaped;
        finite = finite && v.finite;
        drift = std::max(drift, v.drift);
        if (v.deepest) {
          // keep_deeper's rule written out: larger ratio, ties to the smaller (boundary, id_a, id_b).
          const LargestOverlap& c = *v.deepest;
          if (!deepest || c.ratio > deepest->ratio ||
              (c.ratio == deepest->ratio && std::tie(c.boundary, c.id_a, c.id_b) < std::tie(deepest->boundary, deepest->id_a, deepest->id_b))) {
            deepest = c;
          }
        }
        for (std::size_t c = 0; c < StepRecord::kRates; ++c) {
          for (const double x : v.rate_terms[c]) all[c].add(x);
        }
      }
      EXPECT_EQ(result.pair_contacts(), pairs);
      EXPECT_EQ(result.boundary_contacts(), boundaries);
      EXPECT_EQ(result.escaped(), escaped);
      EXPECT_EQ(result.screens_finite(), finite);
      EXPECT_EQ(result.drift(), drift);
      ASSERT_EQ(result.deepest().has_value(), deepest.has_value());
      if (deepest) {
        EXPECT_EQ(result.deepest()->ratio, deepest->ratio);
        EXPECT_EQ(result.deepest()->overlap, deepest->overlap);
        EXPECT_EQ(result.deepest()->id_a, deepest->id_a);
        EXPECT_EQ(result.deepest()->id_b, deepest->id_b);
        EXPECT_EQ(result.deepest()->boundary, deepest->boundary);
      }
      if (rates) {
        for (std::size_t c = 0; c < StepRecord::kRates; ++c) EXPECT_EQ(result.rate(c).value(), all[c].value()) << c;
      }
    }
  }
}

TEST(StepRecord, HasAFixedSizeWhateverTheRanks) {
  // The bytes of the allreduce: 1 + 4 counts + 3 exact sums of ExactSum::kWords + 1 + 6 words.
  EXPECT_EQ(StepRecord(true).bytes(), 8 * (1 + 4 + 3 * ExactSum::kWords + 1 + 6));
  EXPECT_EQ(StepRecord(false).bytes(), 8u * 12u);
}

}  // namespace
