#pragma once
/// \file rolling_resistance.hpp
/// Rolling resistance: a torque at each contact that opposes the relative rolling of the two
/// bodies (docs/dem.md, "Rolling resistance"). Scene keys: `[contact] rolling = "none" |
/// "cdt" | "epsd2"` and `rolling_friction = mu_r` [-] in [material] / [[material_pair]].
///
/// Kinematics (body i against body j; j may be a wall or a rigid object, whose spin is that of
/// its material at the contact):
///   w_rel = w_i - w_j                                relative spin [rad/s]
///   w_t   = w_rel - (w_rel . n) n                    its rolling part (twisting removed)
///   dth_t = w_t(n+1/2) dt                            relative rolling rotation of the step [rad]
///
/// CONSTANT DIRECTIONAL TORQUE (CDT; Zhou et al. 1999, Physica A 269:536; Ai, Chen, Rotter &
/// Ooi 2011, Powder Technol. 206:269, model A):
///   M_i = -mu_r R* |F_n| w_t / |w_t|   (0 when w_t = 0)                      [N m]
///   dissipated  D = -M_i . w_t dt = mu_r R* |F_n| |w_t| dt >= 0 (booked at the evaluation
///               time with the predicted spin, the rule of the normal dashpot, contact_force.hpp)
///   A sphere rolling without slip on a plane decelerates at (5/7) mu_r g: m a = F_t,
///   I dw/dt = -R F_t - mu_r R m g with v = w R and I = (2/5) m R^2.
///
/// ELASTIC-PLASTIC SPRING (EPSD2, as LIGGGHTS `rolling_friction epsd2`; Ai et al. 2011,
/// model C without its viscous part; Iwashita & Oda 1998, J. Eng. Mech. 124:285):
///   k_r = k_t R*^2   (k_t the law's tangential stiffness now)                [N m/rad]
///   S~  = the stored spring torque rotated onto the current tangent plane, length kept
///   S   = S~ + k_r dth_t,  capped at |S| <= mu_r R* |F_n|  (full mobilisation)   [N m]
///   M_i = -S,  M_j = +S
///   elastic     E_r = |S|^2 / (2 k_r)                                           [J]
///   dissipated  W - dE_r with the trapezoid work W = (S(n) + S) . dth_t / 2 that the two
///               bodies do on the spring (Verlet's rule, contact_force.hpp): 0 while the
///               spring holds at constant k_r, >= 0 when it slips.
///   At rest under an applied torque below mu_r R* |F_n| the spring holds: a sphere on a slope
///   of angle theta stays at rest if tan(theta) <= mu_r (elastic rotation S / k_r only).
///
/// History: S and k_r live in the contact's TangentialSpring (contact_force.hpp), so a scene
/// with rolling resistance keeps histories even without sliding friction.
#include <cmath>

#include "ppohdem/geometry/vector.hpp"

namespace ppohdem::dem {

enum class RollingModel { kNone, kCdt, kEpsd2 };

/// The rolling resistance of one pair of materials (pair_laws.hpp).
struct RollingParameters {
  RollingModel model = RollingModel::kNone;
  double friction = 0.0;  ///< mu_r [-]
  bool active() const { return model != RollingModel::kNone; }
};

/// What the rolling resistance of one contact adds.
struct RollingTorque {
  Vec3 on_i = Vec3::Zero();  ///< torque on body i; body j receives -on_i [N m]
  double elastic = 0.0;      ///< E_r stored now [J]
  double dissipated = 0.0;   ///< removed during this step [J]
};

/// The rolling spring of a contact (EPSD2): stored torque S [N m] and stiffness k_r [N m/rad].
struct RollingSpring {
  Vec3 torque = Vec3::Zero();
  double stiffness = 0.0;
  double stored_energy() const {  ///< |S|^2 / (2 k_r) [J]
    return stiffness > 0.0 ? 0.5 * torque.squaredNorm() / stiffness : 0.0;
  }
};

/// The rolling torque of one contact. `spin` is w_i - w_j at the evaluation time (predicted),
/// `rotation` the step's w_i - w_j at mid-step times dt, `f_n` the normal force [N], `k_t` the
/// law's tangential stiffness now [N/m], `normal` unit from j to i. Odd in (normal, spin,
/// rotation, spring.torque), bitwise: the partner's evaluation is the exact mirror.
inline RollingTorque rolling_torque(const RollingParameters& p, double r_eff, double f_n, double k_t,
                                    const Vec3& normal, const Vec3& spin, const Vec3& rotation,
                                    RollingSpring& spring, double dt) {
  RollingTorque out;
  const double limit = p.friction * r_eff * std::abs(f_n);  // mu_r R* |F_n| [N m]
  if (p.model == RollingModel::kCdt) {
    const Vec3 w_t = spin - spin.dot(normal) * normal;
    const double w = w_t.norm();
    if (w > 0.0) {
      out.on_i = -(limit / w) * w_t;
      out.dissipated = limit * w * dt;
    }
    return out;
  }
  // EPSD2: rotate the stored torque onto the tangent plane, add the step, cap it.
  Vec3& s = spring.torque;
  const Vec3 s_previous = s;
  const double length = s.norm();
  s -= s.dot(normal) * normal;
  const double projected = s.norm();
  if (projected > 0.0) s *= length / projected;
  const double energy_before = spring.stored_energy();
  const Vec3 rotation_t = rotation - rotation.dot(normal) * normal;
  const double k_r = k_t * r_eff * r_eff;
  s += k_r * rotation_t;
  spring.stiffness = k_r;
  const double magnitude = s.norm();
  if (magnitude > limit) s *= limit / magnitude;
  out.on_i = -s;
  out.elastic = spring.stored_energy();
  // W - dE_r, with W by the trapezoid rule along the whole step rotation (the previous torque
  // acted in the previous tangent plane).
  out.dissipated = 0.5 * (s_previous + s).dot(rotation) - (out.elastic - energy_before);
  return out;
}

}  // namespace ppohdem::dem
