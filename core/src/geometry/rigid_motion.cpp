// Rigid transforms and constant-velocity rigid motion (see rigid_motion.hpp for the formulas).
#include "ppohdem/geometry/rigid_motion.hpp"

#include <cmath>

namespace ppohdem {

Quat quaternion_from_rotation_vector(const Vec3& rotation_vector) {
  // q = (cos(theta/2), sin(theta/2) n), theta = |r| [rad], n = r / |r|  (Shoemake 1985).
  const double theta = rotation_vector.norm();
  if (theta == 0.0) return Quat::Identity();
  const Vec3 axis = rotation_vector / theta;
  return Quat(Eigen::AngleAxisd(theta, axis));
}

RigidTransform RigidTransform::inverse() const {
  // x = R^T (x' - t)  =>  rotation R^T, translation -R^T t.
  const Quat r_inv = rotation.conjugate();
  return {r_inv, -(r_inv * translation)};
}

RigidTransform RigidTransform::then(const RigidTransform& second) const {
  // second(first(x)) = R2 (R1 x + t1) + t2 = (R2 R1) x + (R2 t1 + t2).
  Quat r = second.rotation * rotation;
  r.normalize();
  return {r, second.rotation * translation + second.translation};
}

RigidTransform RigidMotion::pose_at(double t) const {
  // Equation (1): x -> R(t) (x - c0) + c0 + v t, so translation = c0 + v t - R(t) c0.
  const Quat r = quaternion_from_rotation_vector(angular_velocity * t);
  return {r, centroid + velocity * t - r * centroid};
}

RigidTransform RigidMotion::advance(const RigidTransform& pose, double dt) const {
  // One step: rotate by omega dt about the *current* centroid c = pose(c0), then translate by
  // v dt. Composing these increments reproduces (1) because omega is constant.
  const Vec3 c = pose.apply(centroid);
  const Quat dr = quaternion_from_rotation_vector(angular_velocity * dt);
  const RigidTransform step{dr, c + velocity * dt - dr * c};
  return pose.then(step);
}

Vec3 RigidMotion::point_velocity(const Vec3& x, double t) const {
  // Rigid-body kinematics: v_P = v + omega x (x - c(t))  [m/s].
  return velocity + angular_velocity.cross(x - centroid_at(t));
}

}  // namespace ppohdem
