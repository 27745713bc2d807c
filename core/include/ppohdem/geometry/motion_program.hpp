#pragma once
/// \file motion_program.hpp
/// A motion program: the prescribed rigid motion of an object as a sequence of segments, each
/// with a start time t_k [s] (LIGGGHTS' chained `move/mesh` styles; docs/objects.md "Motion
/// programs"). Segment k acts on [t_k, t_{k+1}) (the last one for ever); before t_0 the
/// object rests at the identity pose (its field's frame is the world frame).
///
/// Within segment k, with s = t - t_k, the motion relative to the pose P_k = P(t_k) is
///
///   M_k(s): x -> R(s) (x - c_k) + c_k + d(s),    R(s) = exp([r(s)]x)                    (1)
///   P(t) = M_k(s) o P_k
///
/// where c_k [m] is a point on the rotation axis at t_k (it moves with the translation),
/// d(s) [m] the translation and r(s) [rad] the rotation vector, each one of
///
///   none:    d = 0                             r = 0
///   linear:  d = v s                           r = omega s            (omega = axis * rate)
///   sine:    d = A (sin(w s + phi) - sin phi)  r = Theta axis (sin(w s + phi) - sin phi)
///
/// All three vanish at s = 0, so M_k(0) is the identity: the pose is continuous at every
/// switch (each segment starts where the previous one ended) and exact at any time (closed
/// form per segment, composed once with P_k, which is computed when the program is built).
/// The velocity of the object's material at world point x, and its angular velocity:
///
///   u(x, t) = d'(s) + r'(s) x (x - (c_k + d(s))),     Omega(t) = r'(s)                     (2)
///
/// A reference point q (the object's "centroid", where its torques are taken) is carried by
/// the motion: q(t) = (c_k + d(s)) + R(s) (q_k - c_k).
#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "ppohdem/geometry/rigid_motion.hpp"

namespace ppohdem {

/// How one part (translation or rotation) of a segment depends on s = t - t_k.
enum class MotionProfile { none, linear, sine };

/// One part of a segment: d(s) [m] for the translation, r(s) [rad] for the rotation (1).
struct MotionPart {
  MotionProfile profile = MotionProfile::none;
  /// linear: the rate (v [m/s] or omega [rad/s], axis times rate); sine: the amplitude
  /// (A [m], or Theta times the unit axis [rad]).
  Vec3 vector = Vec3::Zero();
  double angular_frequency = 0.0;  ///< sine: w = 2 pi f [rad/s]
  double phase = 0.0;              ///< sine: phi [rad]

  Vec3 value(double s) const;  ///< d(s) [m] or r(s) [rad]
  Vec3 rate(double s) const;   ///< d'(s) [m/s] or r'(s) [rad/s]
};

/// One segment of a program: from `start` [s] until the next segment's start.
struct MotionSegment {
  double start = 0.0;  ///< t_k [s]
  MotionPart translation;
  MotionPart rotation;
  /// c_k: a point on the rotation axis at t_k, world frame [m]. Empty: where the motion so far
  /// has carried the program's reference point (the object's centroid).
  std::optional<Vec3> point;
};

class MotionProgram {
 public:
  /// `segments` in strictly increasing start times; `reference_point` q [m] in the object frame
  /// (= world at rest). Throws std::invalid_argument naming the segment (0-based) if a start is
  /// not finite or not increasing, a vector is not finite, or a sine part has w <= 0 or a
  /// non-finite phase.
  MotionProgram(std::vector<MotionSegment> segments, const Vec3& reference_point);
  /// The single constant motion of rigid_motion.hpp between start and stop (rest before and
  /// after): a translation + rotation segment about the motion's centroid from `start`, then a
  /// rest segment from `stop` (none for stop = infinity). Bitwise the poses of
  /// RigidMotion::pose_at(min(max(t, start), stop) - start).
  static MotionProgram single(const RigidMotion& motion, double start = 0.0,
                              double stop = std::numeric_limits<double>::infinity());

  /// P(t): object frame -> world [m].
  RigidTransform pose_at(double time) const;
  /// q(t): the reference point in the world [m].
  Vec3 reference_point_at(double time) const;
  /// u(x, t) of (2) [m/s]; zero before the first segment.
  Vec3 point_velocity(const Vec3& x, double time) const;
  /// Omega(t) of (2) [rad/s]; zero before the first segment.
  Vec3 angular_velocity_at(double time) const;

  const std::vector<MotionSegment>& segments() const { return segments_; }
  const Vec3& reference_point() const { return reference_; }
  /// c_k resolved (the given point or the carried reference point) [m].
  const Vec3& segment_point(std::size_t k) const { return point_[k]; }

 private:
  static constexpr std::size_t kBeforeStart = std::numeric_limits<std::size_t>::max();
  std::size_t segment_at(double time) const;  ///< the k with t_k <= t < t_{k+1}, or kBeforeStart
  RigidTransform relative_pose(std::size_t k, double s) const;  ///< M_k(s)
  RigidTransform composed(std::size_t k, const RigidTransform& step) const;  ///< step o P_k

  std::vector<MotionSegment> segments_;
  Vec3 reference_;
  std::vector<Vec3> point_;                 ///< c_k [m]
  std::vector<RigidTransform> start_pose_;  ///< P_k = P(t_k)
  std::vector<bool> start_at_identity_;     ///< P_k is exactly the identity (no composition)
  std::vector<Vec3> start_reference_;       ///< q_k = q(t_k) [m]
};

}  // namespace ppohdem
