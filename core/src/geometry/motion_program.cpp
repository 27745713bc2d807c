// Motion programs: piecewise closed-form rigid motion (formulas in motion_program.hpp).
#include "ppohdem/geometry/motion_program.hpp"

#include <cmath>
#include <stdexcept>

namespace ppohdem {

Vec3 MotionPart::value(double s) const {
  switch (profile) {
    case MotionProfile::none: return Vec3::Zero();
    case MotionProfile::linear: return vector * s;
    case MotionProfile::sine: return vector * (std::sin(angular_frequency * s + phase) - std::sin(phase));
  }
  return Vec3::Zero();
}

Vec3 MotionPart::rate(double s) const {
  switch (profile) {
    case MotionProfile::none: return Vec3::Zero();
    case MotionProfile::linear: return vector;
    case MotionProfile::sine: return vector * (angular_frequency * std::cos(angular_frequency * s + phase));
  }
  return Vec3::Zero();
}

namespace {

void check_part(const MotionPart& part, std::size_t k, const char* which) {
  const std::string where = "motion segment " + std::to_string(k) + " " + which;
  if (!part.vector.allFinite()) throw std::invalid_argument(where + ": expected finite numbers");
  if (part.profile == MotionProfile::sine &&
      (!(part.angular_frequency > 0.0) || !std::isfinite(part.angular_frequency) || !std::isfinite(part.phase))) {
    throw std::invalid_argument(where + ": expected a finite frequency > 0 and a finite phase");
  }
}

bool is_identity(const RigidTransform& p) {
  return p.rotation.coeffs() == Quat::Identity().coeffs() && p.translation == Vec3::Zero();
}

}  // namespace

MotionProgram::MotionProgram(std::vector<MotionSegment> segments, const Vec3& reference_point)
    : segments_(std::move(segments)), reference_(reference_point) {
  if (!reference_.allFinite()) throw std::invalid_argument("motion program: expected a finite reference point");
  RigidTransform pose = RigidTransform::identity();
  Vec3 reference = reference_;
  for (std::size_t k = 0; k < segments_.size(); ++k) {
    const MotionSegment& seg = segments_[k];
    if (!std::isfinite(seg.start)) {
      throw std::invalid_argument("motion segment " + std::to_string(k) + ": expected a finite start time");
    }
    if (k > 0 && !(seg.start > segments_[k - 1].start)) {
      throw std::invalid_argument("motion segment " + std::to_string(k) + ": start must be after the previous segment's start");
    }
    check_part(seg.translation, k, "translation");
    check_part(seg.rotation, k, "rotation");
    if (seg.point && !seg.point->allFinite()) {
      throw std::invalid_argument("motion segment " + std::to_string(k) + ": expected a finite point");
    }
    // P_k and q_k: where the previous segment ended (identity and q before the first).
    if (k > 0) {
      const double length = seg.start - segments_[k - 1].start;  // s at the switch [s]
      const RigidTransform step = relative_pose(k - 1, length);
      const MotionSegment& prev = segments_[k - 1];
      reference = (point_[k - 1] + prev.translation.value(length)) + step.rotation * (reference - point_[k - 1]);
      pose = composed(k - 1, step);
    }
    start_pose_.push_back(pose);
    start_at_identity_.push_back(is_identity(pose));
    start_reference_.push_back(reference);
    point_.push_back(seg.point.value_or(reference));
  }
}

MotionProgram MotionProgram::single(const RigidMotion& motion, double start, double stop) {
  MotionSegment moving;
  moving.start = start;
  moving.translation = {MotionProfile::linear, motion.velocity};
  moving.rotation = {MotionProfile::linear, motion.angular_velocity};
  moving.point = motion.centroid;
  std::vector<MotionSegment> segments;
  if (stop > start) segments.push_back(moving);
  if (stop < std::numeric_limits<double>::infinity()) {
    MotionSegment rest;
    rest.start = stop;
    segments.push_back(rest);
  }
  return MotionProgram(std::move(segments), motion.centroid);
}

std::size_t MotionProgram::segment_at(double time) const {
  // Few segments: a linear scan from the end finds the last start <= t.
  for (std::size_t k = segments_.size(); k-- > 0;) {
    if (segments_[k].start <= time) return k;
  }
  return kBeforeStart;
}

RigidTransform MotionProgram::relative_pose(std::size_t k, double s) const {
  // (1): x -> R (x - c) + c + d, so translation = c + d - R c (the order of RigidMotion::pose_at).
  const MotionSegment& seg = segments_[k];
  const Quat r = quaternion_from_rotation_vector(seg.rotation.value(s));
  const Vec3& c = point_[k];
  return {r, c + seg.translation.value(s) - r * c};
}

RigidTransform MotionProgram::composed(std::size_t k, const RigidTransform& step) const {
  // M_k(s) o P_k; no composition with an identity (then() renormalises the quaternion), so a
  // single motion's poses are those of RigidMotion::pose_at bit for bit.
  if (start_at_identity_[k]) return step;
  if (is_identity(step)) return start_pose_[k];
  return start_pose_[k].then(step);
}

RigidTransform MotionProgram::pose_at(double time) const {
  const std::size_t k = segment_at(time);
  if (k == kBeforeStart) return RigidTransform::identity();
  return composed(k, relative_pose(k, time - segments_[k].start));
}

Vec3 MotionProgram::reference_point_at(double time) const {
  const std::size_t k = segment_at(time);
  if (k == kBeforeStart) return reference_;
  const MotionSegment& seg = segments_[k];
  const double s = time - seg.start;
  const Vec3 moved_point = point_[k] + seg.translation.value(s);  // c_k + d(s)
  if (seg.rotation.profile == MotionProfile::none) return moved_point + (start_reference_[k] - point_[k]);
  const Quat r = quaternion_from_rotation_vector(seg.rotation.value(s));
  return moved_point + r * (start_reference_[k] - point_[k]);
}

Vec3 MotionProgram::point_velocity(const Vec3& x, double time) const {
  const std::size_t k = segment_at(time);
  if (k == kBeforeStart) return Vec3::Zero();
  const MotionSegment& seg = segments_[k];
  if (seg.translation.profile == MotionProfile::none && seg.rotation.profile == MotionProfile::none) return Vec3::Zero();
  const double s = time - seg.start;
  // (2), in RigidMotion::point_velocity's order: v + omega x (x - c(t)).
  return seg.translation.rate(s) + seg.rotation.rate(s).cross(x - (point_[k] + seg.translation.value(s)));
}

Vec3 MotionProgram::angular_velocity_at(double time) const {
  const std::size_t k = segment_at(time);
  if (k == kBeforeStart) return Vec3::Zero();
  return segments_[k].rotation.rate(time - segments_[k].start);
}

}  // namespace ppohdem
