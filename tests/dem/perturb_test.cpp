// `--perturb-seed K` (dem/perturb.hpp): every coordinate moves by exactly one ulp, the same
// way for a given seed and particle id whatever the order, and the directions look random.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "ppohdem/dem/perturb.hpp"

namespace ppohdem::dem {
namespace {

Particles random_particles(std::size_t n) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  Particles p(n);
  for (std::size_t i = 0; i < n; ++i) {
    p[i].id = static_cast<std::int64_t>(i) + 1;
    p[i].position = Vec3(u(rng), u(rng), u(rng));
    p[i].radius = 0.01;
  }
  return p;
}

TEST(PerturbSeed, MovesEveryCoordinateByExactlyOneUlp) {
  const Particles before = random_particles(1000);
  Particles after = before;
  perturb_positions_by_one_ulp(after, 5);
  constexpr double inf = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < before.size(); ++i) {
    for (int a = 0; a < 3; ++a) {
      const double x = before[i].position[a], y = after[i].position[a];
      ASSERT_TRUE(y == std::nextafter(x, inf) || y == std::nextafter(x, -inf)) << "particle " << i << " axis " << a;
      ASSERT_NE(x, y);
    }
    EXPECT_EQ(before[i].velocity, after[i].velocity);
    EXPECT_EQ(before[i].radius, after[i].radius);
  }
}

TEST(PerturbSeed, SameSeedSameStateWhateverTheOrder) {
  Particles a = random_particles(500);
  Particles b = a;
  std::reverse(b.begin(), b.end());
  perturb_positions_by_one_ulp(a, 42);
  perturb_positions_by_one_ulp(b, 42);
  std::reverse(b.begin(), b.end());
  for (std::size_t i = 0; i < a.size(); ++i) ASSERT_EQ(a[i].position, b[i].position);
}

TEST(PerturbSeed, DirectionsAreBalancedAndDifferBetweenSeeds) {
  // 3,000 fair coin flips: 1,500 +- 27 (one standard deviation); +-150 is 5.5 sd.
  int up = 0, same_as_seed_2 = 0;
  for (std::int64_t id = 1; id <= 1000; ++id) {
    for (int axis = 0; axis < 3; ++axis) {
      up += perturbation_direction(1, id, axis) > 0 ? 1 : 0;
      same_as_seed_2 += perturbation_direction(1, id, axis) == perturbation_direction(2, id, axis) ? 1 : 0;
    }
  }
  EXPECT_NEAR(up, 1500, 150);
  EXPECT_NEAR(same_as_seed_2, 1500, 150);
}

TEST(PerturbSeed, ZeroMovesToTheSmallestSubnormal) {
  Particles p(1);
  p[0].id = 3;
  perturb_positions_by_one_ulp(p, 9);
  for (int a = 0; a < 3; ++a) EXPECT_EQ(std::abs(p[0].position[a]), std::numeric_limits<double>::denorm_min());
}

}  // namespace
}  // namespace ppohdem::dem
