// The projection of the fast engine's decomposition and halo to P ranks (ppohdem/dem/fast/
// halo_projection.hpp; docs/performance.md "Projection to many nodes") against a brute-force
// oracle that knows nothing of the engine's code: the bisection's bricks recomputed by sorting
// (the definition in docs/dem.md "Load balance": each node of n ranks and m particles cut
// across the longest extent of its particles' box so that the left part holds round(m
// floor(n/2) / n) of them), and the ghosts by testing every particle against every other
// rank's brick (distance below the reach 2 R_max + skin, bricks 1e-6 reach larger: the halo
// rule of docs/dem.md "Domain decomposition").
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <numeric>
#include <random>
#include <set>
#include <vector>

#include "ppohdem/dem/fast/halo_projection.hpp"

namespace fast = ppohdem::dem::fast;
using ppohdem::Vec3;

namespace {

struct Box {
  std::array<double, 3> lo, hi;
};

/// A dense layer under a dilute cloud (a settling bed), 1 x 0.6 x 2; every coordinate distinct.
void cloud(std::size_t n, std::vector<Vec3>& x, std::vector<std::int64_t>& id) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (std::size_t k = 0; k < n; ++k) {
    const double z = k % 4 == 0 ? 2.0 * u(rng) : 0.3 * u(rng);
    const double a = u(rng);
    x.emplace_back(a, 0.6 * u(rng), z);
    id.push_back(static_cast<std::int64_t>(n - k) * 7);
  }
}

/// The bisection by its definition: the leaves' boxes and every particle's rank.
void bisect(const std::vector<Vec3>& x, std::vector<std::size_t> members, int first, int ranks, Box box,
            std::vector<Box>& boxes, std::vector<int>& owner) {
  if (ranks == 1) {
    boxes[static_cast<std::size_t>(first)] = box;
    for (const std::size_t k : members) owner[k] = first;
    return;
  }
  std::array<double, 3> lo, hi;
  lo.fill(std::numeric_limits<double>::infinity());
  hi.fill(-std::numeric_limits<double>::infinity());
  for (const std::size_t k : members) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], x[k][a]);
      hi[a] = std::max(hi[a], x[k][a]);
    }
  }
  int axis = 0;
  for (int a = 1; a < 3; ++a) {
    if (hi[a] - lo[a] > hi[axis] - lo[axis]) axis = a;
  }
  std::sort(members.begin(), members.end(), [&](std::size_t p, std::size_t q) { return x[p][axis] < x[q][axis]; });
  const std::size_t m = members.size(), left = static_cast<std::size_t>(ranks / 2), all = static_cast<std::size_t>(ranks);
  const std::size_t to_left = (m * left + all / 2) / all;
  ASSERT_GT(to_left, 0u);  // the oracle's beds give every rank particles
  const double cut = x[members[to_left - 1]][axis];
  Box l = box, r = box;
  l.hi[axis] = cut;
  r.lo[axis] = cut;
  bisect(x, std::vector<std::size_t>(members.begin(), members.begin() + static_cast<std::ptrdiff_t>(to_left)), first,
         ranks / 2, l, boxes, owner);
  bisect(x, std::vector<std::size_t>(members.begin() + static_cast<std::ptrdiff_t>(to_left), members.end()),
         first + ranks / 2, ranks - ranks / 2, r, boxes, owner);
}

double distance2(const Box& b, const Vec3& p, double slack) {
  double d2 = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double g = std::max({0.0, (b.lo[a] - slack) - p[a], p[a] - (b.hi[a] + slack)});
    d2 += g * g;
  }
  return d2;
}

}  // namespace

TEST(HaloProjection, MatchesABruteForceCountOverEveryParticleAndRank) {
  std::vector<Vec3> x;
  std::vector<std::int64_t> id;
  cloud(3000, x, id);
  const double r_max = 0.02;
  fast::FastOptions options;  // skin 0.2 R_max, bisection
  const double reach = 2.0 * r_max + 0.2 * r_max, slack = 1e-6 * reach;
  for (const int ranks : {1, 2, 3, 4, 5, 8, 13, 16, 32}) {
    SCOPED_TRACE(ranks);
    const double inf = std::numeric_limits<double>::infinity();
    std::vector<Box> boxes(static_cast<std::size_t>(ranks));
    std::vector<int> owner(x.size(), -1);
    std::vector<std::size_t> all(x.size());
    std::iota(all.begin(), all.end(), 0);
    bisect(x, all, 0, ranks, Box{{-inf, -inf, -inf}, {inf, inf, inf}}, boxes, owner);
    std::vector<std::size_t> owned(boxes.size(), 0), in(boxes.size(), 0), out(boxes.size(), 0), interior(boxes.size(), 0);
    std::vector<std::set<int>> sends_to(boxes.size()), receives_from(boxes.size());
    for (std::size_t k = 0; k < x.size(); ++k) {
      const auto o = static_cast<std::size_t>(owner[k]);
      ++owned[o];
      ++interior[o];  // until another rank's brick is found within reach
      bool layer = false;
      for (int r = 0; r < ranks; ++r) {
        if (r == owner[k] || distance2(boxes[static_cast<std::size_t>(r)], x[k], slack) >= reach * reach) continue;
        if (!layer) --interior[o];
        layer = true;
        ++in[static_cast<std::size_t>(r)];
        ++out[o];
        sends_to[o].insert(r);
        receives_from[static_cast<std::size_t>(r)].insert(owner[k]);
      }
    }
    const fast::HaloProjection h = fast::project_halo(ranks, x, id, r_max, options);
    ASSERT_EQ(h.rank.size(), boxes.size());
    EXPECT_DOUBLE_EQ(h.reach, reach);
    std::size_t ghosts = 0;
    for (std::size_t r = 0; r < boxes.size(); ++r) {
      SCOPED_TRACE(r);
      EXPECT_EQ(h.rank[r].owned, owned[r]);
      EXPECT_EQ(h.rank[r].interior, interior[r]);
      EXPECT_EQ(h.rank[r].ghosts_in, in[r]);
      EXPECT_EQ(h.rank[r].ghosts_out, out[r]);
      EXPECT_EQ(h.rank[r].messages_out, static_cast<int>(sends_to[r].size()));
      EXPECT_EQ(h.rank[r].messages_in, static_cast<int>(receives_from[r].size()));
      EXPECT_GE(h.rank[r].peers, h.rank[r].messages_out);  // a rank sends to peers only
      ghosts += in[r];
    }
    if (ranks > 1) {
      EXPECT_GT(ghosts, 0u);  // the bed is not trivially split
      EXPECT_LT(h.rank[0].interior, h.rank[0].owned);
    }
  }
}

TEST(HaloProjection, MessageSizesAreTheEnginesFields) {
  // The refresh carries x, v, omega and the two cached half kicks (fast_state.hpp,
  // for_each_moving_array): 5 vectors of 3 doubles. A ghost's creation carries every
  // per-particle field, more than that.
  std::vector<Vec3> x = {Vec3(0, 0, 0), Vec3(1, 0, 0)};
  std::vector<std::int64_t> id = {1, 2};
  const fast::HaloProjection h = fast::project_halo(2, x, id, 0.6, fast::FastOptions{});
  EXPECT_EQ(h.refresh_bytes, 2u * 3u * sizeof(double));  // the half kick: dv, domega
  EXPECT_GT(h.creation_bytes, h.refresh_bytes);
  // Two particles 1 apart, reach 1.32: each is a ghost of the other's rank.
  ASSERT_EQ(h.rank.size(), 2u);
  EXPECT_EQ(h.rank[0].ghosts_in, 1u);
  EXPECT_EQ(h.rank[1].ghosts_in, 1u);
}

TEST(HaloProjection, RejectsBadArguments) {
  std::vector<Vec3> x = {Vec3(0, 0, 0)};
  std::vector<std::int64_t> id = {1, 2};
  EXPECT_THROW(fast::project_halo(2, x, id, 0.5, fast::FastOptions{}), std::invalid_argument);
  id.pop_back();
  EXPECT_THROW(fast::project_halo(0, x, id, 0.5, fast::FastOptions{}), std::invalid_argument);
}
