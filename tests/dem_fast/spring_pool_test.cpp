// SpringPool (core/src/dem/fast/spring_pool.hpp): a spring stored in its three arrays comes
// back with every field bit for bit; the parts the lane law writes are the spring's fields;
// new entries are empty springs; a core part never straddles two cache lines.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>

#include "../../core/src/dem/fast/spring_pool.hpp"  // internal

namespace ppohdem::dem::test {
namespace {

using fast::SpringPool;

/// A spring whose 17 doubles are all different (k + 1, ..., k + 17).
TangentialSpring distinct_spring(double k) {
  TangentialSpring s;
  s.displacement = Vec3(k + 1, k + 2, k + 3);
  s.stiffness = k + 4;
  s.branch_i = Vec3(k + 5, k + 6, k + 7);
  s.branch_j = Vec3(k + 8, k + 9, k + 10);
  s.surface_velocity = Vec3(k + 11, k + 12, k + 13);
  s.rolling.torque = Vec3(k + 14, k + 15, k + 16);
  s.rolling.stiffness = k + 17;
  return s;
}

/// Every field of a and b has the same bits (the fields in for_each_field's order).
bool same_bits(const TangentialSpring& a, const TangentialSpring& b) {
  bool same = true;
  auto eq = [&](const Vec3& u, const Vec3& v) { same = same && std::memcmp(u.data(), v.data(), sizeof(double) * 3) == 0; };
  eq(a.displacement, b.displacement);
  eq(a.branch_i, b.branch_i);
  eq(a.branch_j, b.branch_j);
  eq(a.surface_velocity, b.surface_velocity);
  eq(a.rolling.torque, b.rolling.torque);
  same = same && std::memcmp(&a.stiffness, &b.stiffness, sizeof(double)) == 0;
  same = same && std::memcmp(&a.rolling.stiffness, &b.rolling.stiffness, sizeof(double)) == 0;
  return same;
}

TEST(SpringPool, EverySpringFieldComesBackBitForBit) {
  SpringPool pool;
  pool.push_back(distinct_spring(0.0));
  pool.resize(3);
  pool.set(2, distinct_spring(100.0));
  ASSERT_EQ(pool.size(), 3u);
  EXPECT_TRUE(same_bits(pool.get(0), distinct_spring(0.0)));
  EXPECT_TRUE(same_bits(pool.get(2), distinct_spring(100.0)));
  EXPECT_TRUE(same_bits(pool.get(1), TangentialSpring{}));  // a new entry is an empty spring
  EXPECT_FALSE(pool.get(1).holds_history());
  const TangentialSpring negative_zero = [] {
    TangentialSpring s;
    s.displacement = Vec3(-0.0, 0.0, -0.0);  // signs of zero kept too
    return s;
  }();
  pool.set(1, negative_zero);
  EXPECT_TRUE(same_bits(pool.get(1), negative_zero));
  pool.clear();
  EXPECT_TRUE(pool.empty());
}

TEST(SpringPool, TheLawsPartsAreTheSpringsFields) {
  SpringPool pool;
  for (int k = 0; k < 9; ++k) pool.push_back(distinct_spring(20.0 * k));
  for (std::size_t k = 0; k < pool.size(); ++k) {
    // Whole cache lines hold whole cores: the lane law's one 32-byte load and store a contact.
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(&pool.core(k)) % 32, 0u) << k;
  }
  pool.core(4).displacement = Vec3(-1, -2, -3);
  pool.core(4).stiffness = -4;
  pool.arms(4).branch_i = Vec3(-5, -6, -7);
  pool.arms(4).branch_j = Vec3(-8, -9, -10);
  TangentialSpring want = distinct_spring(80.0);
  want.displacement = Vec3(-1, -2, -3);
  want.stiffness = -4;
  want.branch_i = Vec3(-5, -6, -7);
  want.branch_j = Vec3(-8, -9, -10);
  EXPECT_TRUE(same_bits(pool.get(4), want));
  EXPECT_TRUE(same_bits(pool.get(3), distinct_spring(60.0)));  // its neighbours untouched
  EXPECT_TRUE(same_bits(pool.get(5), distinct_spring(100.0)));
}

}  // namespace
}  // namespace ppohdem::dem::test
