#pragma once
/// \file rigid_motion.hpp
/// Rigid transforms and the prescribed motion of a rigid object (the seed's objects_update):
/// a translation velocity plus a rotation with constant angular velocity about a centroid that
/// moves with the body.
///
///   pose(t):  x  ->  R(t) (x - c0) + c0 + v t,     R(t) = exp(t [omega]x)     (1)
///
/// where c0 [m] is the centroid at t = 0, v [m/s] the translation velocity and omega [rad/s]
/// the angular velocity vector (axis * rate). The velocity of a material point at world
/// position x is  v + omega x (x - c(t)),  c(t) = c0 + v t.
/// Quaternion exponential: q = (cos(|w| dt / 2), sin(|w| dt / 2) w/|w|)  (Shoemake 1985).
#include "ppohdem/geometry/vector.hpp"

namespace ppohdem {

/// x' = rotation * x + translation. Composition and inverse are exact up to round-off.
struct RigidTransform {
  Quat rotation = Quat::Identity();
  Vec3 translation = Vec3::Zero();  ///< [m]

  static RigidTransform identity() { return {}; }
  Vec3 apply(const Vec3& x) const { return rotation * x + translation; }
  Vec3 rotate(const Vec3& direction) const { return rotation * direction; }
  /// The transform that undoes this one: x = R^T (x' - t).
  RigidTransform inverse() const;
  /// `first.then(second)` applies `first`, then `second`.
  RigidTransform then(const RigidTransform& second) const;
};

/// A constant-velocity rigid motion (translation + rotation about a moving centroid).
struct RigidMotion {
  Vec3 velocity = Vec3::Zero();          ///< v [m/s]
  Vec3 angular_velocity = Vec3::Zero();  ///< omega [rad/s], axis times rate
  Vec3 centroid = Vec3::Zero();          ///< c0 [m], centre of rotation at t = 0

  /// Closed form (1): the pose after time t [s] from the start.
  RigidTransform pose_at(double t) const;
  /// The pose after one more step of dt [s], composed incrementally from `pose` (what an
  /// engine does every step); the quaternion is renormalised so it stays unit over 1e6 steps.
  RigidTransform advance(const RigidTransform& pose, double dt) const;
  /// Centroid at time t: c0 + v t [m].
  Vec3 centroid_at(double t) const { return centroid + velocity * t; }
  /// Velocity [m/s] of the material point at world position x at time t.
  Vec3 point_velocity(const Vec3& x, double t) const;
};

/// Unit quaternion rotating by |rotation_vector| radians about rotation_vector's direction
/// (identity for a zero vector).
Quat quaternion_from_rotation_vector(const Vec3& rotation_vector);

}  // namespace ppohdem
