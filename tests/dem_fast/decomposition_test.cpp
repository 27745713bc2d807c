// The bricks of the fast engine's domain decomposition (core/src/dem/fast/decomposition.hpp,
// recursive_bisection.hpp; docs/dem.md "Load balance"): the key order, the bisection's
// counts against their definition, owners inside their bricks, and the peers against
// brute-force oracles (every pair within the halo reach is seen by both owners).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "../../core/src/dem/fast/decomposition.hpp"  // internal

namespace fast = ppohdem::dem::fast;
using ppohdem::Vec3;

namespace {

struct Cloud {
  std::vector<Vec3> x;
  std::vector<std::int64_t> id;
};

/// n points in a column of 1 x 1 x 3: a dense layer (z in [0, 0.3]) under a dilute cloud, the
/// shape of a settling bed; ids unrelated to the order.
Cloud bed_cloud(std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Cloud c;
  for (std::size_t k = 0; k < n; ++k) {
    const double z = k % 5 == 0 ? 3.0 * u(rng) : 0.3 * u(rng);
    const double x = u(rng);
    c.x.emplace_back(x, u(rng), z);
    c.id.push_back(static_cast<std::int64_t>(7 * k + 3) * (k % 2 == 0 ? 1 : -1));
  }
  return c;
}

/// A lattice: whole layers share a coordinate, so cuts fall on planes of particles.
Cloud lattice(int nx, int ny, int nz) {
  Cloud c;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        c.x.emplace_back(0.1 * i, 0.1 * j, 0.1 * k);
        c.id.push_back(static_cast<std::int64_t>(c.id.size()) * 13 % 1000003);
      }
  return c;
}

std::vector<int> counts(const fast::Decomposition& d, const Cloud& c) {
  std::vector<int> n(static_cast<std::size_t>(d.ranks()), 0);
  for (std::size_t k = 0; k < c.x.size(); ++k) ++n[static_cast<std::size_t>(d.owner(c.x[k], c.id[k]))];
  return n;
}

/// The counts the definition gives: a node of n ranks and m particles gives its left half
/// round(m * floor(n / 2) / n) and recurses (the oracle knows nothing of the cuts).
void expected_counts(int first, int ranks, std::uint64_t m, std::vector<int>& out) {
  if (ranks == 1) {
    out[static_cast<std::size_t>(first)] = static_cast<int>(m);
    return;
  }
  const auto left = static_cast<std::uint64_t>(ranks / 2), all = static_cast<std::uint64_t>(ranks);
  const std::uint64_t to_left = (m * left + all / 2) / all;
  expected_counts(first, ranks / 2, to_left, out);
  expected_counts(first + ranks / 2, ranks - ranks / 2, m - to_left, out);
}

}  // namespace

TEST(Decomposition, OrderedKeysSortAsTheDoublesDo) {
  std::vector<double> v = {-std::numeric_limits<double>::infinity(), -1e300, -2.5, -1e-310, -0.0, 0.0, 1e-310,
                           std::numeric_limits<double>::min(), 0.5, 1.0, 3.0, 1e300,
                           std::numeric_limits<double>::infinity()};
  for (std::size_t i = 0; i < v.size(); ++i) {
    EXPECT_EQ(std::bit_cast<std::uint64_t>(fast::from_ordered_key(fast::ordered_key(v[i]))), std::bit_cast<std::uint64_t>(v[i]));
    if (i > 0) {
      EXPECT_LT(fast::ordered_key(v[i - 1]), fast::ordered_key(v[i])) << v[i - 1] << " < " << v[i];
    }
  }
  EXPECT_LT(fast::ordered_id(-5), fast::ordered_id(-4));
  EXPECT_LT(fast::ordered_id(-1), fast::ordered_id(0));
  EXPECT_LT(fast::ordered_id(std::numeric_limits<std::int64_t>::min()), fast::ordered_id(std::numeric_limits<std::int64_t>::max()));
}

// The bed: the equal bricks of its box leave the upper ranks almost empty; the bisection gives
// every rank the count of its definition exactly, for powers of two and others.
TEST(Decomposition, BisectionGivesEveryRankItsCountOnABed) {
  const Cloud c = bed_cloud(10007, 1);
  const ppohdem::SerialComm serial;
  for (const int ranks : {2, 3, 4, 5, 7, 8, 12}) {
    SCOPED_TRACE("ranks " + std::to_string(ranks));
    const auto d = fast::Decomposition::bisection(ranks, c.x, c.id, c.x.size(), serial);
    ASSERT_TRUE(d.bisected());
    std::vector<int> expected(static_cast<std::size_t>(ranks));
    expected_counts(0, ranks, c.x.size(), expected);
    EXPECT_EQ(counts(d, c), expected);
    const std::vector<int> equal = counts(fast::Decomposition(ranks, c.x), c);
    const double mean = static_cast<double>(c.x.size()) / ranks;
    if (ranks >= 4) {  // not vacuous: the equal bricks are far from balanced here
      EXPECT_GT(*std::max_element(equal.begin(), equal.end()) / mean, 1.3);
    }
  }
}

// On a lattice whole planes share a coordinate: the id splits them, so the counts are still
// exact (by coordinate alone a cut would move a whole plane of 100 particles).
TEST(Decomposition, BisectionSplitsALatticePlaneById) {
  const Cloud c = lattice(10, 10, 10);
  const ppohdem::SerialComm serial;
  for (const int ranks : {3, 6, 8}) {
    SCOPED_TRACE("ranks " + std::to_string(ranks));
    const auto d = fast::Decomposition::bisection(ranks, c.x, c.id, c.x.size(), serial);
    std::vector<int> expected(static_cast<std::size_t>(ranks));
    expected_counts(0, ranks, c.x.size(), expected);
    EXPECT_EQ(counts(d, c), expected);
  }
}

// What the halo and the migration rely on, by brute force over the pairs: every particle lies
// in its owner's brick; a particle within the reach of another rank's particle is within the
// reach of that rank's brick, and the two owners are peers (symmetrically).
TEST(Decomposition, PairsWithinReachAreSeenByBothOwnersAndTheirOwnersArePeers) {
  const Cloud c = bed_cloud(1500, 2);
  const ppohdem::SerialComm serial;
  const double reach = 0.08, slack = 1e-6 * reach;
  for (const bool bisected : {false, true}) {
    for (const int ranks : {4, 7, 8}) {
      SCOPED_TRACE(std::string(bisected ? "bisection, " : "equal bricks, ") + std::to_string(ranks) + " ranks");
      const auto d = bisected ? fast::Decomposition::bisection(ranks, c.x, c.id, c.x.size(), serial)
                              : fast::Decomposition(ranks, c.x);
      std::vector<std::vector<int>> peers;
      for (int r = 0; r < ranks; ++r) peers.push_back(d.peers(r, reach, slack));
      for (int r = 0; r < ranks; ++r) {
        for (const int q : peers[static_cast<std::size_t>(r)]) {
          const auto& back = peers[static_cast<std::size_t>(q)];
          EXPECT_TRUE(std::binary_search(back.begin(), back.end(), r)) << r << " and " << q;
        }
      }
      std::size_t across = 0;
      for (std::size_t i = 0; i < c.x.size(); ++i) {
        const int oi = d.owner(c.x[i], c.id[i]);
        EXPECT_LT(d.distance2(oi, c.x[i], slack), 1e-30);
        for (std::size_t j = 0; j < c.x.size(); ++j) {
          const int oj = d.owner(c.x[j], c.id[j]);
          if (oi == oj || (c.x[i] - c.x[j]).squaredNorm() >= reach * reach) continue;
          ++across;
          EXPECT_LT(d.distance2(oj, c.x[i], slack), reach * reach);
          EXPECT_TRUE(std::binary_search(peers[static_cast<std::size_t>(oi)].begin(),
                                         peers[static_cast<std::size_t>(oi)].end(), oj));
        }
      }
      EXPECT_GT(across, bisected ? 100u : 0u);  // not vacuous (the equal bricks cut the dense layer less)
      // Neighbour-only: some rank has fewer peers than all the others (4 or more bricks of a
      // tall column cannot all touch each other within a reach of 0.08).
      std::size_t fewest = static_cast<std::size_t>(ranks);
      for (const auto& p : peers) fewest = std::min(fewest, p.size());
      EXPECT_LT(fewest, static_cast<std::size_t>(ranks - 1));
    }
  }
}

// The equal bricks keep their definition: a 4 x 2 x 1 grid over a 4 x 2 x 1 box, and with a
// reach shorter than a brick the peers are exactly the bricks whose coordinates differ by at
// most one on every axis.
TEST(Decomposition, EqualBricksPeersAreTheAdjacentBricks) {
  const std::vector<Vec3> corners = {Vec3(0, 0, 0), Vec3(4, 2, 1)};
  const fast::Decomposition d(8, corners);
  EXPECT_EQ(d.dims(), (std::array<int, 3>{4, 2, 1}));
  EXPECT_EQ(d.owner(Vec3(2.5, 0.5, 0.5), 0), 2);
  EXPECT_EQ(d.owner(Vec3(3.5, 1.5, 0.5), 0), 7);
  EXPECT_EQ(d.owner(Vec3(-10, 10, 0.5), 0), 4);  // outer bricks extend to infinity
  for (int r = 0; r < 8; ++r) {
    std::vector<int> expected;
    for (int q = 0; q < 8; ++q) {
      if (q != r && std::abs(q % 4 - r % 4) <= 1 && std::abs(q / 4 - r / 4) <= 1) expected.push_back(q);
    }
    EXPECT_EQ(d.peers(r, 0.5, 1e-9), expected) << "rank " << r;
  }
}
