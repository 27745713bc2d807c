// The ensemble consistency test's statistics (validation/port/ensemble.hpp) on synthetic
// ensembles whose answers are known: the fit members' PC scores are white by construction,
// the mean passes, a shift of many standard deviations fails, files round-trip.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <random>

#include "ensemble.hpp"

namespace ppohdem::port {
namespace {

/// Members of 6 observables: 4 independent N(0, s_k) and 2 correlated with the first.
std::vector<Observables> synthetic(int count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<Observables> members;
  for (int i = 0; i < count; ++i) {
    Observables o;
    o.names = {"a", "b", "c", "d", "e", "f"};
    const double a = n(rng);
    o.values = {10.0 + a, 2.0 * n(rng), -3.0 + 0.5 * n(rng), n(rng), 2.0 * a + 0.3 * n(rng), -a + 0.1 * n(rng)};
    members.push_back(o);
  }
  return members;
}

TEST(EnsembleTest, FitMembersScoreWhite) {
  const auto members = synthetic(200, 1);
  EnsembleRule rule;
  rule.variance_kept = 1.0;  // every PC
  const Baseline b = fit_baseline("synthetic", members, rule);
  ASSERT_EQ(b.eigenvalues.size(), 6);
  Eigen::MatrixXd s(200, 6);
  for (int i = 0; i < 200; ++i) s.row(i) = pc_scores(b, members[static_cast<std::size_t>(i)]).transpose();
  // Exact in exact arithmetic: scores are the whitened data (mean 0, identity covariance);
  // 1e-9 allows the eigen-solver's round-off.
  const Eigen::MatrixXd centred = s.rowwise() - s.colwise().mean();
  const Eigen::MatrixXd cov = centred.transpose() * centred / 199.0;
  EXPECT_LT((cov - Eigen::MatrixXd::Identity(6, 6)).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT(s.colwise().mean().cwiseAbs().maxCoeff(), 1e-9);
}

TEST(EnsembleTest, KeepsTheLeadingPcsOfTheVarianceShare) {
  const Baseline b = fit_baseline("synthetic", synthetic(200, 2), EnsembleRule{});
  const double kept = b.eigenvalues.sum() / 6.0;  // the correlation matrix's trace is 6
  EXPECT_GE(kept, 0.95);
  EXPECT_LT(b.eigenvalues.size(), 6);  // a, e and f are nearly one direction
}

TEST(EnsembleTest, MeanPassesAndAShiftFails) {
  const Baseline b = fit_baseline("synthetic", synthetic(200, 3), EnsembleRule{});
  Observables mean;
  mean.names = b.names;
  mean.values.assign(b.mean.data(), b.mean.data() + b.mean.size());
  EXPECT_TRUE(judge(b, {mean, mean, mean}).pass);
  Observables shifted = mean;
  shifted.values[3] += 10.0 * b.stddev(3);  // observable d, 10 sd off
  EXPECT_FALSE(judge(b, {shifted, shifted, mean}).pass);
  EXPECT_TRUE(judge(b, {shifted, mean, mean}).pass);  // one run of three is not enough
}

TEST(EnsembleTest, StandardisedNamesTheShiftedObservable) {
  const Baseline b = fit_baseline("synthetic", synthetic(200, 4), EnsembleRule{});
  Observables run;
  run.names = b.names;
  run.values.assign(b.mean.data(), b.mean.data() + b.mean.size());
  run.values[1] += 4.0 * b.stddev(1);  // observable b, 4 sd up
  std::reverse(run.names.begin(), run.names.end());  // found by name, not by position
  std::reverse(run.values.begin(), run.values.end());
  Eigen::VectorXd z = standardised(b, run);
  // (mean + 4 sd - mean) / sd: exact up to the round-off of two operations (1e-12).
  EXPECT_NEAR(z(1), 4.0, 1e-12);
  z(1) = 0.0;
  EXPECT_LT(z.cwiseAbs().maxCoeff(), 1e-12);
}

TEST(EnsembleTest, FalsePositiveRateOfFreshMembersIsSmall) {
  // Held-out members from the same distribution: with 2.5 sigma in 2 of 3 runs per PC and
  // about 4 PCs, a Gaussian triple fails with probability ~4 x 3 x 0.0124^2 = 0.2 %.
  const Baseline b = fit_baseline("synthetic", synthetic(200, 4), EnsembleRule{});
  const auto [rate, triples] = false_positive_rate(b, synthetic(40, 5));
  EXPECT_EQ(triples, 9880U);
  EXPECT_LT(rate, 0.02);
}

TEST(EnsembleTest, BaselineFileRoundTrips) {
  Baseline b = fit_baseline("synthetic", synthetic(50, 6), EnsembleRule{});
  b.particle_count = 12;
  b.radius_sum = 0.123;
  const auto dir = std::filesystem::temp_directory_path() / "ppohdem-ensemble-test";
  std::filesystem::create_directories(dir);
  write_baseline(dir, b);
  const Baseline r = read_baseline(dir / "synthetic.baseline.csv");
  EXPECT_EQ(r.names, b.names);
  EXPECT_EQ(r.mean, b.mean);
  EXPECT_EQ(r.loadings, b.loadings);
  EXPECT_EQ(r.eigenvalues, b.eigenvalues);
  EXPECT_EQ(r.particle_count, 12U);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ppohdem::port
