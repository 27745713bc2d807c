// The neighbour search's distance test (core/src/dem/fast/near_members.hpp) against its oracle,
// the engine's former one-candidate loop written with Eigen (d.squaredNorm() < reach^2 and not
// itself): the one-at-a-time and the four-lane versions must keep exactly the oracle's members
// in the oracle's order, including the cases that are masks in the lanes: runs whose length is
// not a multiple of 4 (lanes past the run, in the padding or in the next run), the particle
// itself inside a group, a member exactly at the reach (not kept) and one ulp inside it (kept),
// and a NaN centre (never kept).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "ppohdem/geometry/vector.hpp"
#include "../../core/src/dem/fast/hertz_mindlin_x4.hpp"  // internal: x4_contacts_available
#include "../../core/src/dem/fast/near_members.hpp"      // internal

namespace ppohdem::dem::test {
namespace {

using fast::MemberRun;
using fast::NearQuery;
using fast::ProbeColumns;

/// The oracle: the search's loop before near_members, one candidate at a time with Eigen.
std::vector<std::uint32_t> oracle(const ProbeColumns& p, const std::vector<MemberRun>& runs, const NearQuery& q) {
  std::vector<std::uint32_t> kept;
  const Vec3 centre(q.x, q.y, q.z);
  for (const MemberRun& run : runs) {
    for (std::uint32_t m = run.begin; m < run.end; ++m) {
      const double reach = q.radius + p.r[m] + q.skin;
      const Vec3 d = centre - Vec3(p.x[m], p.y[m], p.z[m]);
      if (d.squaredNorm() < reach * reach && m != q.self) kept.push_back(m);
    }
  }
  return kept;
}

using NearFunction = std::size_t (*)(const ProbeColumns&, const MemberRun*, std::size_t, const NearQuery&, std::uint32_t*);

std::vector<std::uint32_t> run_version(NearFunction f, const ProbeColumns& p, const std::vector<MemberRun>& runs,
                                       const NearQuery& q) {
  std::size_t total = 0;
  for (const MemberRun& run : runs) total += run.end - run.begin;
  std::vector<std::uint32_t> kept(total + ProbeColumns::kPadding, 0xdeadbeefu);
  kept.resize(f(p, runs.data(), runs.size(), q, kept.data()));
  return kept;
}

/// Every version available on this CPU against the oracle.
void expect_oracle(const ProbeColumns& p, const std::vector<MemberRun>& runs, const NearQuery& q) {
  const std::vector<std::uint32_t> expected = oracle(p, runs, q);
  EXPECT_EQ(run_version(fast::near_members, p, runs, q), expected) << "one at a time";
  if (fast::x4_contacts_available()) {
    EXPECT_EQ(run_version(fast::near_members_x4, p, runs, q), expected) << "four lanes";
  }
}

TEST(NearMembers, RandomBedsKeepTheOraclesMembersInOrder) {
  std::mt19937_64 rng(20261203);
  std::uniform_real_distribution<double> coordinate(0.0, 0.01);   // a 1 cm box [m]
  std::uniform_real_distribution<double> radius(0.0004, 0.0006);  // about the bench's 0.5 mm [m]
  std::uniform_int_distribution<std::uint32_t> run_length(0, 9);  // every tail of a group of 4
  std::size_t kept_total = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const std::size_t members = 60;
    ProbeColumns p;
    p.resize(members);
    for (std::size_t m = 0; m < members; ++m) {
      p.x[m] = coordinate(rng);
      p.y[m] = coordinate(rng);
      p.z[m] = coordinate(rng);
      p.r[m] = radius(rng);
    }
    // Up to 9 runs, some back to back (the next run's members follow a run's end) and some
    // ending at the last member (the padding follows).
    std::vector<MemberRun> runs;
    std::uint32_t at = std::uniform_int_distribution<std::uint32_t>(0, 5)(rng);
    for (int k = 0; k < 9 && at < members; ++k) {
      const std::uint32_t end = std::min<std::uint32_t>(at + run_length(rng), members);
      runs.push_back({at, end});
      at = end + std::uniform_int_distribution<std::uint32_t>(0, 2)(rng);
    }
    const std::uint32_t self = std::uniform_int_distribution<std::uint32_t>(0, members - 1)(rng);
    // The query is a member (self), as in the search, with a skin that keeps about half.
    const NearQuery q{p.x[self], p.y[self], p.z[self], p.r[self], 0.004, self};
    expect_oracle(p, runs, q);
    kept_total += oracle(p, runs, q).size();
  }
  EXPECT_GT(kept_total, 2000u);  // the trials keep members, not only reject them
}

TEST(NearMembers, TheReachItselfIsOutAndOneUlpInsideIsIn) {
  // Centre at the origin, R = 0.5, r = 0.25, skin = 0.25: the reach is exactly 1 and so is its
  // square, as are the squared distances below.
  ProbeColumns p;
  p.resize(6);
  const double inside = std::nextafter(1.0, 0.0);
  const double xs[6] = {1.0, inside, -1.0, 0.0, 0.0, 0.0};
  const double ys[6] = {0.0, 0.0, 0.0, -inside, 0.0, 0.0};
  const double zs[6] = {0.0, 0.0, 0.0, 0.0, 1.0, std::numeric_limits<double>::quiet_NaN()};
  for (std::size_t m = 0; m < 6; ++m) {
    p.x[m] = xs[m];
    p.y[m] = ys[m];
    p.z[m] = zs[m];
    p.r[m] = 0.25;
  }
  const NearQuery q{0.0, 0.0, 0.0, 0.5, 0.25, 99};
  const std::vector<MemberRun> runs{{0, 6}};
  const std::vector<std::uint32_t> expected{1, 3};  // one ulp inside; at the reach and NaN: out
  EXPECT_EQ(oracle(p, runs, q), expected);
  expect_oracle(p, runs, q);
}

TEST(NearMembers, ItselfIsNeverKeptInAnyLane) {
  ProbeColumns p;
  p.resize(8);
  for (std::size_t m = 0; m < 8; ++m) {
    p.x[m] = 1e-4 * static_cast<double>(m);  // all within reach of each other
    p.r[m] = 5e-4;
  }
  for (std::uint32_t self = 0; self < 8; ++self) {
    const NearQuery q{p.x[self], 0.0, 0.0, 5e-4, 1e-4, self};
    const std::vector<MemberRun> runs{{0, 3}, {3, 8}};  // back to back: groups that start mid-way
    std::vector<std::uint32_t> expected;
    for (std::uint32_t m = 0; m < 8; ++m) {
      if (m != self) expected.push_back(m);
    }
    EXPECT_EQ(oracle(p, runs, q), expected);
    expect_oracle(p, runs, q);
  }
}

}  // namespace
}  // namespace ppohdem::dem::test
