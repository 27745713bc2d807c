// The prescribed motion of an object as the engine sees it (pose, centroid, surface velocity).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "object_fields.hpp"
#include "ppohdem/dem/distance_field_object.hpp"
#include "ppohdem/error.hpp"
#include "ppohdem/units.hpp"

namespace ppohdem::dem::test {
namespace {

DistanceFieldObject spinning_ball(const RigidMotion& motion, double start = 0.0,
                                  double stop = std::numeric_limits<double>::infinity()) {
  const GridSpec grid{Vec3::Constant(-2.0), Vec3::Constant(0.25), {17, 17, 17}};
  return DistanceFieldObject(ball_field(grid, Vec3(0.3, -0.2, 0.1), 1.0), motion, "ball", start, stop);
}

TEST(ObjectMotion, AfterAFullTurnTheObjectIsBackToRoundOff) {
  RigidMotion motion;
  motion.angular_velocity = Vec3(1.0, -2.0, 0.5).normalized() * 7.0;  // rad/s
  motion.centroid = Vec3(0.3, 0.1, -0.4);
  const DistanceFieldObject object = spinning_ball(motion);
  const double turn = 2.0 * units::kPi / 7.0;  // s
  const RigidTransform pose = object.pose_at(turn);
  // The rotation by 2 pi is -identity as a quaternion (q and -q are the same rotation); check
  // the map on points: |P(x) - x| for points ~1 m from the centroid, a few ulps of pi * |x|.
  for (const Vec3& x : {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(-0.7, 0.4, 1.3)}) {
    EXPECT_LT((pose.apply(x) - x).norm(), 1e-14);
  }
  // And the contact it offers at t = T is the one at t = 0.
  const Vec3 probe(1.4, -0.2, 0.3);
  const auto c0 = object.contact(probe, 0.2, 0.0);
  const auto c1 = object.contact(probe, 0.2, turn);
  ASSERT_TRUE(c0 && c1);
  EXPECT_NEAR(c1->overlap, c0->overlap, 1e-13);
  EXPECT_LT((c1->normal - c0->normal).norm(), 1e-12);
}

TEST(ObjectMotion, QuaternionStaysUnitOverOneMillionSteps) {
  // The object's pose at every step time t = n dt of a 1e6-step run (the seed's sample rate:
  // pi/1200 rad per frame of 500 steps, here faster, 1e-3 rad per step, 159 turns). The pose
  // is the closed form of rigid_motion.hpp, not a composition, so nothing accumulates: each
  // quaternion is (cos, sin * unit axis) rounded once, |q| = 1 within a few eps (bound 4 eps,
  // as RigidMotion.QuaternionStaysUnitOverOneMillionSteps for the composed pose). The last pose
  // also maps a point as the analytic rotation by 1000 rad does (Rodrigues, Eigen AngleAxis).
  RigidMotion motion;
  motion.angular_velocity = Vec3(0.3, -0.7, 1.1).normalized();  // 1 rad/s
  motion.centroid = Vec3(0.3, 0.1, -0.4);
  const DistanceFieldObject object = spinning_ball(motion);
  constexpr long kSteps = 1000000;
  constexpr double kDt = 1e-3;  // s
  double worst = 0.0;
  for (long n = 0; n <= kSteps; ++n) {
    worst = std::max(worst, std::abs(object.pose_at(static_cast<double>(n) * kDt).rotation.norm() - 1.0));
  }
  constexpr double kEps = std::numeric_limits<double>::epsilon();
  EXPECT_LT(worst, 4 * kEps);
  const Vec3 x(1.0, 0.5, -0.2);
  const Eigen::AngleAxisd exact(1000.0, motion.angular_velocity);
  const Vec3 expected = exact * (x - motion.centroid) + motion.centroid;
  // The angle 1000 rad itself carries ~eps * 1000 of round-off in t = n dt and in sin/cos of
  // it: ~1e-13 m at |x - c| ~ 1 m; bound 1e-12.
  EXPECT_LT((object.pose_at(static_cast<double>(kSteps) * kDt).apply(x) - expected).norm(), 1e-12);
}

TEST(ObjectMotion, HalfTurnMapsThePointToItsMirrorAboutTheAxis) {
  // Hand-computed: rotation by pi about z through c = (1, 0, 0): (2, 0, 0) -> (0, 0, 0),
  // plus a translation v t = (0, 0, 1) pi.
  RigidMotion motion;
  motion.angular_velocity = Vec3(0, 0, 1.0);
  motion.centroid = Vec3(1, 0, 0);
  motion.velocity = Vec3(0, 0, 1);
  const DistanceFieldObject object = spinning_ball(motion);
  EXPECT_LT((object.pose_at(units::kPi).apply(Vec3(2, 0, 0)) - Vec3(0, 0, units::kPi)).norm(), 1e-15);
  EXPECT_LT((object.centroid_at(units::kPi) - Vec3(1, 0, units::kPi)).norm(), 1e-15);
}

TEST(ObjectMotion, ObjectRestsOutsideItsStartStopInterval) {
  RigidMotion motion;
  motion.velocity = Vec3(1, 0, 0);
  motion.angular_velocity = Vec3(0, 0, 2);
  const DistanceFieldObject object = spinning_ball(motion, 1.0, 3.0);
  EXPECT_EQ(object.pose_at(0.5).translation, Vec3::Zero());  // not started: identity
  EXPECT_EQ(object.point_velocity(Vec3(1, 1, 1), 0.5), Vec3::Zero());
  // Moving in [1, 3): centroid c0 + v (t - start).
  EXPECT_LT((object.centroid_at(2.0) - Vec3(1, 0, 0)).norm(), 1e-15);
  EXPECT_LT((object.point_velocity(Vec3(2, 1, 0), 2.0) - Vec3(1 - 2, 2, 0)).norm(), 1e-15);
  // Stopped: frozen at the pose of t = stop, no velocity.
  EXPECT_LT((object.centroid_at(10.0) - Vec3(2, 0, 0)).norm(), 1e-15);
  EXPECT_EQ(object.point_velocity(Vec3(1, 1, 1), 3.0), Vec3::Zero());
}

TEST(ObjectMotion, RejectsStopBeforeStartAndNonFiniteValues) {
  RigidMotion motion;
  EXPECT_THROW(spinning_ball(motion, 2.0, 1.0), InputError);
  motion.velocity = Vec3(std::nan(""), 0, 0);
  EXPECT_THROW(spinning_ball(motion), InputError);
}

}  // namespace
}  // namespace ppohdem::dem::test
