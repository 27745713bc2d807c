// Rigid transforms and motions: properties that hold for every rotation and translation.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <limits>

#include "ppohdem/geometry/rigid_motion.hpp"
#include "ppohdem/units.hpp"

namespace ppohdem {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

// Bounded random doubles and vectors for the properties (magnitudes up to 1e3 so that the
// round-off bounds below, written relative to the magnitude, stay meaningful).
rc::Gen<double> bounded(double limit) {
  return rc::gen::map(rc::gen::inRange(-1000000, 1000001),
                      [limit](int n) { return limit * n / 1.0e6; });
}
rc::Gen<Vec3> vec3(double limit) {
  return rc::gen::apply([](double x, double y, double z) { return Vec3(x, y, z); }, bounded(limit),
                        bounded(limit), bounded(limit));
}

RigidTransform random_transform(const Vec3& rotation_vector, const Vec3& translation) {
  return {quaternion_from_rotation_vector(rotation_vector), translation};
}

RC_GTEST_PROP(RigidTransform, RotationKeepsLengthsAndUnitNorm, ()) {
  const Vec3 r = *vec3(10.0);
  const Vec3 x = *vec3(1000.0);
  const Quat q = quaternion_from_rotation_vector(r);
  // A product of a few correctly rounded operations: |q| = 1 to a few ulps.
  RC_ASSERT(std::abs(q.norm() - 1.0) <= 4 * kEps);
  // |R x| = |x|: each component of R x carries ~10 roundings of size eps |x|.
  RC_ASSERT(std::abs((q * x).norm() - x.norm()) <= 16 * kEps * (1.0 + x.norm()));
}

RC_GTEST_PROP(RigidTransform, ComposingWithInverseIsIdentity, ()) {
  const RigidTransform a = random_transform(*vec3(10.0), *vec3(1000.0));
  const Vec3 x = *vec3(1000.0);
  const Vec3 back = a.then(a.inverse()).apply(x);
  const Vec3 back2 = a.inverse().then(a).apply(x);
  // Error ~ eps * (|x| + |t|) per rotation and translation, a handful of them.
  const double tol = 64 * kEps * (1.0 + x.norm() + a.translation.norm());
  RC_ASSERT((back - x).norm() <= tol);
  RC_ASSERT((back2 - x).norm() <= tol);
}

RC_GTEST_PROP(RigidTransform, ThenAppliesFirstThenSecond, ()) {
  const RigidTransform a = random_transform(*vec3(10.0), *vec3(100.0));
  const RigidTransform b = random_transform(*vec3(10.0), *vec3(100.0));
  const Vec3 x = *vec3(100.0);
  const double tol = 64 * kEps * (1.0 + x.norm() + a.translation.norm() + b.translation.norm());
  RC_ASSERT((a.then(b).apply(x) - b.apply(a.apply(x))).norm() <= tol);
}

TEST(RigidTransform, QuarterTurnAboutZMapsXToY) {
  // Hand-computed: +90 degrees about +z maps (1,0,0) to (0,1,0) (right-hand rule).
  const Quat q = quaternion_from_rotation_vector(Vec3(0, 0, units::kPi / 2));
  const Vec3 y = q * Vec3(1, 0, 0);
  EXPECT_NEAR(y.x(), 0.0, 1e-15);
  EXPECT_NEAR(y.y(), 1.0, 1e-15);
  EXPECT_NEAR(y.z(), 0.0, 1e-15);
}

TEST(RigidMotion, CentroidMovesWithVelocityAndStaysFixedUnderRotation) {
  RigidMotion m;
  m.velocity = Vec3(0.1, -0.2, 0.3);
  m.angular_velocity = Vec3(1.0, 2.0, -0.5);
  m.centroid = Vec3(5, 6, 7);
  for (double t : {0.0, 0.5, 3.0}) {
    const Vec3 c = m.pose_at(t).apply(m.centroid);
    EXPECT_LT((c - (m.centroid + m.velocity * t)).norm(), 1e-13) << "t = " << t;
  }
}

TEST(RigidMotion, FullTurnReturnsToStart) {
  // omega = 2 pi / T about an oblique axis through a centroid away from the origin.
  RigidMotion m;
  m.angular_velocity = Vec3(1, 2, 2).normalized() * (2 * units::kPi / 4.0);
  m.centroid = Vec3(22, 22, 11);
  const int steps = 40000;
  const double dt = 4.0 / steps;
  RigidTransform pose;
  for (int s = 0; s < steps; ++s) pose = m.advance(pose, dt);
  const Vec3 corner(25, 19, 13);
  // 4e4 composed steps, each adding ~eps * |x| (|x| ~ 40) of round-off, random-walk or worse:
  // bound by steps * 4 eps * |x| ~ 1.4e-9.
  EXPECT_LT((pose.apply(corner) - corner).norm(), steps * 4 * kEps * corner.norm());
  EXPECT_LT((m.pose_at(4.0).apply(corner) - corner).norm(), 1e-12);
}

TEST(RigidMotion, IncrementalPoseMatchesClosedForm) {
  RigidMotion m;
  m.velocity = Vec3(0, 0, 0.005);
  m.angular_velocity = Vec3(0, 0, -units::kPi / 1200.0);
  m.centroid = Vec3(22, 22, 11);
  RigidTransform pose;
  const int steps = 10000;
  const double dt = 0.37;
  for (int s = 0; s < steps; ++s) pose = m.advance(pose, dt);
  const RigidTransform exact = m.pose_at(steps * dt);
  const Vec3 x(20, 24, 12);
  // Same per-step round-off argument as FullTurnReturnsToStart.
  EXPECT_LT((pose.apply(x) - exact.apply(x)).norm(), steps * 4 * kEps * 40.0);
}

TEST(RigidMotion, QuaternionStaysUnitOverOneMillionSteps) {
  RigidMotion m;
  m.angular_velocity = Vec3(0.3, -0.7, 1.1);
  RigidTransform pose;
  for (int s = 0; s < 1000000; ++s) pose = m.advance(pose, 1e-3);
  // `then` renormalises each step, so the norm error cannot accumulate beyond one rounding.
  EXPECT_LT(std::abs(pose.rotation.norm() - 1.0), 4 * kEps);
}

TEST(RigidMotion, PointVelocityIsTheTimeDerivativeOfThePose) {
  RigidMotion m;
  m.velocity = Vec3(0.1, 0.2, -0.3);
  m.angular_velocity = Vec3(0.5, -1.0, 0.25);
  m.centroid = Vec3(1, 2, 3);
  const Vec3 x0(2.5, 1.0, 4.0);
  const double t = 0.8, h = 1e-5;
  const Vec3 x_t = m.pose_at(t).apply(x0);
  // Central difference: truncation O(h^2 |omega|^3 |r|) ~ 1e-10, round-off ~ eps |x| / h ~ 1e-11.
  const Vec3 fd = (m.pose_at(t + h).apply(x0) - m.pose_at(t - h).apply(x0)) / (2 * h);
  EXPECT_LT((fd - m.point_velocity(x_t, t)).norm(), 1e-9);
}

}  // namespace
}  // namespace ppohdem
