#pragma once
/// \file contact_force.hpp
/// The force of one contact, for any law of contact_law.hpp, shared by every engine and by
/// particle-particle and particle-boundary contacts alike.
///
/// Kinematics (body i against body j, where j may be a wall or a rigid object):
///   n        unit normal pointing from j towards i
///   delta    overlap [m] > 0
///   v_rel    velocity of i's material at the contact point minus j's [m/s]:
///            v_rel = (v_i + w_i x r_i) - (v_j + w_j x r_j),  r = branch vectors to the point,
///            at the time of the force evaluation (dashpot); in velocity Verlet this is the
///            prediction v(n+1/2) + a(n) dt/2, which keeps the dissipated-energy integral
///            second order (with v(n+1/2) it would be first order in dt)
///   ds       relative displacement of the contact points over the last step [m]
///            = (v_rel computed with v(n+1/2), w(n+1/2)) dt: the exact increment of the
///            positions, so the spring stores exactly the work the particles lose
///   delta_dot = -v_rel . n            (approach speed)          [m/s]
///   ds_t      = ds - (ds . n) n        (sliding displacement)    [m]
/// Normal force on i: F_n n with F_n from the law (>= 0 for Hertz).
/// Tangential spring (only with friction, by construction: two kernels, no runtime branch):
///   xi   accumulated tangential displacement (the contact history) [m]
///   1. rotate xi onto the current tangent plane: xi <- |xi| (xi - (xi.n)n)/|xi - (xi.n)n|
///      (keeps the stored energy when the contact plane turns; as LIGGGHTS)
///   2. xi <- xi + ds_t
///   3. F_t = -k_t(delta) xi; if |F_t| > mu F_n: F_t <- mu F_n F_t/|F_t| and xi <- -F_t/k_t
///      (Coulomb slip; the spring energy lost is friction work)
/// Energy book-keeping per contact and step (so that kinetic + rotational + gravitational +
/// elastic + dissipated stays constant up to the integrator's O(dt^2) error):
///   elastic     U_n(delta) + k_t |xi|^2 / 2                                   [J]
///   dissipated  (F_n - F_n,elastic) delta_dot dt      (dashpot, and the Hertz clamp)  [J]
///             + k_t (|xi_trial|^2 - |xi|^2) / 2       (Coulomb slip)
///             - (k_t,new - k_t,old) |xi|^2 / 2        (Mindlin: the stiffness changes with
///                                                      delta; the model adds this energy)
#include "ppohdem/dem/contact_law.hpp"
#include "ppohdem/geometry/vector.hpp"

namespace ppohdem::dem {

struct ContactKinematics {
  Vec3 normal = Vec3::UnitZ();           ///< n, unit, from j towards i
  double overlap = 0.0;                  ///< delta [m]
  Vec3 relative_velocity = Vec3::Zero();  ///< v_rel at the evaluation time [m/s]
  Vec3 relative_displacement = Vec3::Zero();  ///< ds over the last step [m]
  PairProperties pair;
};

/// The history of one frictional contact (the seed's contact_list entry).
struct TangentialSpring {
  Vec3 displacement = Vec3::Zero();  ///< xi [m]
  double stiffness = 0.0;            ///< k_t at the last update [N/m]
  double stored_energy() const { return 0.5 * stiffness * displacement.squaredNorm(); }  ///< [J]
};

struct ContactForce {
  Vec3 on_i = Vec3::Zero();     ///< force on body i; body j receives -on_i [N]
  double elastic_energy = 0.0;  ///< stored in the contact's springs now [J]
  double dissipated = 0.0;      ///< energy removed during this step [J]
};

/// Frictionless contact: normal force only, no history.
template <class Law>
ContactForce normal_contact_force(const Law& law, const ContactKinematics& c, double dt) {
  const double delta_dot = -c.relative_velocity.dot(c.normal);
  const double f_n = law.normal_force(c.overlap, delta_dot, c.pair);
  const double f_el = law.elastic_force(c.overlap, c.pair);
  ContactForce out;
  out.on_i = f_n * c.normal;
  out.elastic_energy = law.elastic_energy(c.overlap, c.pair);
  out.dissipated = (f_n - f_el) * delta_dot * dt;
  return out;
}

/// Frictional contact: normal force plus the tangential spring `spring` (updated in place).
template <class Law>
ContactForce frictional_contact_force(const Law& law, const ContactKinematics& c,
                                      TangentialSpring& spring, double dt) {
  ContactForce out = normal_contact_force(law, c, dt);
  const Vec3& n = c.normal;
  const double f_n = out.on_i.dot(n);

  // 1. Rotate the history onto the current tangent plane, keeping its length.
  Vec3& xi = spring.displacement;
  const double length = xi.norm();
  xi -= xi.dot(n) * n;
  const double projected = xi.norm();
  if (projected > 0.0) xi *= length / projected;

  // Mindlin: k_t follows delta; the model adds (k_new - k_old)|xi|^2/2 to the stored energy.
  const double k_t = law.tangential_stiffness(c.overlap, c.pair);
  out.dissipated -= 0.5 * (k_t - spring.stiffness) * xi.squaredNorm();
  spring.stiffness = k_t;

  // 2. Accumulate the sliding displacement of this step.
  xi += c.relative_displacement - c.relative_displacement.dot(n) * n;

  // 3. Spring force and Coulomb cap.
  Vec3 f_t = -k_t * xi;
  const double cap = law.friction() * f_n;
  const double f_t_norm = f_t.norm();
  if (f_t_norm > cap) {
    const double before = spring.stored_energy();
    f_t *= (f_t_norm > 0.0 ? cap / f_t_norm : 0.0);
    xi = k_t > 0.0 ? Vec3(-f_t / k_t) : Vec3(Vec3::Zero());
    out.dissipated += before - spring.stored_energy();
  }
  out.on_i += f_t;
  out.elastic_energy += spring.stored_energy();
  return out;
}

}  // namespace ppohdem::dem
