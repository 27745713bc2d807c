// Motion programs (issue 38, item 1): the pose, velocity, spin and centroid of a program of
// segments against the analytic motion computed here independently (Eigen AngleAxis
// matrices, the segments' own parameters, nothing taken from MotionProgram), continuity at
// the switches, the single motion as a program bit for bit, and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <vector>

#include "ppohdem/geometry/motion_program.hpp"
#include "ppohdem/units.hpp"

namespace ppohdem::test {
namespace {

using Mat3 = Eigen::Matrix3d;

// ---- the program under test: every kind of segment, with given and carried axis points ----
const Vec3 kReference(0.1, 0.2, 0.3);           // q0 [m]
const Vec3 kV0(0.3, -0.2, 0.1);                 // translate [m/s]
const Vec3 kAxis1 = Vec3::UnitZ();              // rotate about z ...
constexpr double kRate1 = 5.0;                  // ... at 5 rad/s ...
const Vec3 kPoint1(1.0, 0.5, 0.0);              // ... through this point [m]
const Vec3 kAmp2(0.01, 0.02, -0.03);            // vibrate_translate: A [m]
constexpr double kF2 = 3.0, kPhase2 = 0.4;      // f [Hz], phi [rad]
const Vec3 kAxis3 = Vec3(1, 1, 0).normalized();  // vibrate_rotate about the carried q
constexpr double kTheta3 = 0.3, kF3 = 2.0, kPhase3 = -0.7;
const Vec3 kV4(0.0, 0.0, 0.5);                  // translate_rotate: v [m/s] ...
const Vec3 kAxis4 = Vec3::UnitY();              // ... and -1.5 rad/s about y ...
constexpr double kRate4 = -1.5;
const Vec3 kPoint4(0.2, 0.3, 0.4);              // ... through this point (moving with v)
const std::vector<double> kStarts = {0.5, 1.5, 2.25, 3.0, 4.0, 5.0};  // the last: rest

MotionProgram program() {
  std::vector<MotionSegment> s(6);
  for (std::size_t k = 0; k < s.size(); ++k) s[k].start = kStarts[k];
  s[0].translation = {MotionProfile::linear, kV0};
  s[1].rotation = {MotionProfile::linear, kAxis1 * kRate1};
  s[1].point = kPoint1;
  s[2].translation = {MotionProfile::sine, kAmp2, 2 * units::kPi * kF2, kPhase2};
  s[3].rotation = {MotionProfile::sine, kAxis3 * kTheta3, 2 * units::kPi * kF3, kPhase3};
  s[4].translation = {MotionProfile::linear, kV4};
  s[4].rotation = {MotionProfile::linear, kAxis4 * kRate4};
  s[4].point = kPoint4;
  return MotionProgram(s, kReference);
}

// ---- the analytic motion: a world map x -> R (x - c) + c + d per segment ----
struct Map {
  Mat3 r = Mat3::Identity();
  Vec3 c = Vec3::Zero();
  Vec3 d = Vec3::Zero();
  Vec3 operator()(const Vec3& x) const { return r * (x - c) + c + d; }
};

Mat3 turn(const Vec3& unit_axis, double angle) { return Eigen::AngleAxisd(angle, unit_axis).toRotationMatrix(); }
double wave(double f, double phase, double s) { return std::sin(2 * units::kPi * f * s + phase) - std::sin(phase); }

/// Segment k's map after s seconds; `q` is where the reference point is at the segment's start
/// (the axis point of a segment without one).
Map segment_map(std::size_t k, double s, const Vec3& q) {
  Map m;
  switch (k) {
    case 0: m.d = kV0 * s; break;
    case 1: m.r = turn(kAxis1, kRate1 * s); m.c = kPoint1; break;
    case 2: m.d = kAmp2 * wave(kF2, kPhase2, s); break;
    case 3: m.r = turn(kAxis3, kTheta3 * wave(kF3, kPhase3, s)); m.c = q; break;
    case 4: m.r = turn(kAxis4, kRate4 * s); m.c = kPoint4; m.d = kV4 * s; break;
    default: break;  // rest
  }
  return m;
}

/// Where the material point at x0 (object frame) is at time t.
Vec3 analytic_position(const Vec3& x0, double t) {
  Vec3 x = x0, q = kReference;
  for (std::size_t k = 0; k < kStarts.size() && t >= kStarts[k]; ++k) {
    const double end = k + 1 < kStarts.size() ? std::min(t, kStarts[k + 1]) : t;
    const Map m = segment_map(k, end - kStarts[k], q);
    x = m(x);
    q = m(q);
  }
  return x;
}

const std::vector<Vec3> kProbes = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(-0.7, 0.4, 1.3)};

std::vector<double> sample_times() {
  std::vector<double> times;
  for (int n = 0; n <= 1200; ++n) times.push_back(-0.1 + 6.0 * n / 1200.0);
  for (const double t : kStarts) {  // at and next to every switch
    for (const double e : {-1e-9, 0.0, 1e-9}) times.push_back(t + e);
  }
  return times;
}

TEST(MotionProgram, PoseFollowsTheAnalyticMotionAcrossEverySwitch) {
  // Each pose is one closed form composed with the pose at its segment's start (a few products
  // of unit quaternions and O(1) vectors): round-off ~1e-15 m; bound 1e-13 m for |x| <= 1.5 m.
  const MotionProgram p = program();
  double worst = 0.0;
  for (const double t : sample_times()) {
    const RigidTransform pose = p.pose_at(t);
    for (const Vec3& x0 : kProbes) worst = std::max(worst, (pose.apply(x0) - analytic_position(x0, t)).norm());
    EXPECT_LT(std::abs(pose.rotation.norm() - 1.0), 4 * std::numeric_limits<double>::epsilon()) << "t = " << t;
  }
  EXPECT_LT(worst, 1e-13);
  // Not vacuous: the program moved the probes by O(0.1-1) m.
  EXPECT_GT((p.pose_at(4.6).apply(kProbes[4]) - kProbes[4]).norm(), 0.3);
}

TEST(MotionProgram, HandComputedPointsAtTheSwitches) {
  // At t = 1.5 s the translation has moved everything by v (1.5 - 0.5) s = (0.3, -0.2, 0.1).
  // Then half a turn about z through (1, 0.5, 0) takes pi/5 s: the origin, now at
  // (0.3, -0.2, 0.1), goes to 2 (1, 0.5) - (0.3, -0.2) = (1.7, 1.2), z unchanged.
  const MotionProgram p = program();
  EXPECT_LT((p.pose_at(1.5).apply(Vec3(1, 0, 0)) - Vec3(1.3, -0.2, 0.1)).norm(), 1e-15);
  const double half_turn = 1.5 + units::kPi / 5.0;  // s, still inside segment 1 (ends at 2.25)
  EXPECT_LT((p.pose_at(half_turn).apply(Vec3::Zero()) - Vec3(1.7, 1.2, 0.1)).norm(), 1e-14);
  // Before the first segment: identity; after the last (rest): frozen.
  EXPECT_EQ(p.pose_at(0.25).apply(Vec3(0.3, 0.4, 0.5)), Vec3(0.3, 0.4, 0.5));
  EXPECT_EQ(p.pose_at(5.0).apply(kProbes[4]), p.pose_at(123.0).apply(kProbes[4]));
  EXPECT_EQ(p.point_velocity(kProbes[4], 7.0), Vec3::Zero());
  EXPECT_EQ(p.angular_velocity_at(7.0), Vec3::Zero());
}

TEST(MotionProgram, PoseIsContinuousAtTheSwitches) {
  // Just before a switch the pose is the previous segment's closed form, at it the next
  // segment's start: they differ by the motion over e ~ 1e-12 s, u e (u the velocity just
  // before), plus round-off ~1e-15 m; the second-order term a e^2 is ~1e-22 m. Bound 1e-13 m,
  // against a jump of O(1) m if a segment started from the wrong pose.
  const MotionProgram p = program();
  for (std::size_t k = 1; k < kStarts.size(); ++k) {
    const double t = kStarts[k];
    const double before = t - 1e-12;
    const double e = t - before;  // the step as represented [s]
    for (const Vec3& x0 : kProbes) {
      const Vec3 x = p.pose_at(before).apply(x0);
      const Vec3 predicted = x + p.point_velocity(x, before) * e;
      EXPECT_LT((p.pose_at(t).apply(x0) - predicted).norm(), 1e-13) << "switch " << k;
    }
  }
}

TEST(MotionProgram, VelocityAndSpinAreTheTimeDerivativesOfThePose) {
  // Central differences of the analytic motion with h = 1e-5 s: truncation h^2 |x'''| / 6
  // < 1e-10 * 1e3 m/s^3 (the 3 Hz vibration: A w^3 ~ 0.04 * 19^3), round-off eps |x| / h ~ 1e-11;
  // bound 1e-7 m/s and rad/s. Times closer than h to a switch are skipped (one-sided there).
  const MotionProgram p = program();
  constexpr double h = 1e-5;
  int checked = 0;
  for (const double t : sample_times()) {
    bool near_switch = false;
    for (const double s : kStarts) near_switch = near_switch || std::abs(t - s) < 2 * h;
    if (near_switch || t < 0) continue;
    for (const Vec3& x0 : kProbes) {
      const Vec3 x = analytic_position(x0, t);
      const Vec3 fd = (analytic_position(x0, t + h) - analytic_position(x0, t - h)) / (2 * h);
      EXPECT_LT((p.point_velocity(x, t) - fd).norm(), 1e-7) << "t = " << t;
    }
    // Spin: R(t + h) R(t - h)^T is a turn by 2 h Omega.
    const Quat dq = p.pose_at(t + h).rotation * p.pose_at(t - h).rotation.conjugate();
    const Eigen::AngleAxisd aa(dq);
    EXPECT_LT((p.angular_velocity_at(t) - aa.axis() * aa.angle() / (2 * h)).norm(), 1e-7) << "t = " << t;
    ++checked;
  }
  EXPECT_GT(checked, 1000);
}

TEST(MotionProgram, ReferencePointIsCarriedAsAMaterialPoint) {
  // q(t) = P(t) q0: the torques' point moves with the body. Bound as for the pose.
  const MotionProgram p = program();
  for (const double t : sample_times()) {
    EXPECT_LT((p.reference_point_at(t) - analytic_position(kReference, t)).norm(), 1e-13) << "t = " << t;
  }
  // The vibrate_rotate segment (3) turns about where q was at t = 3 s: q is on its axis.
  EXPECT_LT((p.segment_point(3) - analytic_position(kReference, 3.0)).norm(), 1e-15);
}

bool same_bits(const Vec3& a, const Vec3& b) { return std::memcmp(a.data(), b.data(), 3 * sizeof(double)) == 0; }

TEST(MotionProgram, SingleMotionIsTheOldClosedFormBitForBit) {
  // MotionProgram::single must reproduce RigidMotion at tau = min(max(t, start), stop) - start
  // exactly (existing scenes keep their bits): tolerance zero.
  RigidMotion m;
  m.velocity = Vec3(0.01, -0.02, 0.03);
  m.angular_velocity = Vec3(0.3, -0.7, 1.1).normalized() * 5.0;
  m.centroid = Vec3(0.05, 0.04, -0.02);
  const double start = 0.013, stop = 0.41;
  const MotionProgram p = MotionProgram::single(m, start, stop);
  const Vec3 x(0.061, 0.033, 0.007);
  for (int n = 0; n <= 600; ++n) {
    const double t = 0.5 * n / 600.0;
    const double tau = std::min(std::max(t, start), stop) - start;
    const RigidTransform want = m.pose_at(tau);
    const RigidTransform got = p.pose_at(t);
    EXPECT_TRUE(same_bits(got.translation, want.translation)) << "t = " << t;
    EXPECT_EQ(std::memcmp(got.rotation.coeffs().data(), want.rotation.coeffs().data(), 4 * sizeof(double)), 0)
        << "t = " << t;
    EXPECT_TRUE(same_bits(p.reference_point_at(t), m.centroid_at(tau))) << "t = " << t;
    const Vec3 v = t < start || t >= stop ? Vec3::Zero() : m.point_velocity(x, tau);
    EXPECT_TRUE(same_bits(p.point_velocity(x, t), v)) << "t = " << t;
  }
}

TEST(MotionProgram, RejectsUnorderedStartsAndBadNumbers) {
  auto seg = [](double start) {
    MotionSegment s;
    s.start = start;
    s.translation = {MotionProfile::linear, Vec3(1, 0, 0)};
    return s;
  };
  EXPECT_NO_THROW(MotionProgram({seg(0.0), seg(1.0)}, Vec3::Zero()));
  EXPECT_THROW(MotionProgram({seg(1.0), seg(1.0)}, Vec3::Zero()), std::invalid_argument);
  EXPECT_THROW(MotionProgram({seg(1.0), seg(0.5)}, Vec3::Zero()), std::invalid_argument);
  EXPECT_THROW(MotionProgram({seg(std::nan(""))}, Vec3::Zero()), std::invalid_argument);
  MotionSegment sine = seg(0.0);
  sine.translation = {MotionProfile::sine, Vec3(1, 0, 0), 0.0, 0.0};  // w = 0
  EXPECT_THROW(MotionProgram({sine}, Vec3::Zero()), std::invalid_argument);
  MotionSegment inf = seg(0.0);
  inf.rotation = {MotionProfile::linear, Vec3(std::numeric_limits<double>::infinity(), 0, 0)};
  EXPECT_THROW(MotionProgram({inf}, Vec3::Zero()), std::invalid_argument);
}

}  // namespace
}  // namespace ppohdem::test
