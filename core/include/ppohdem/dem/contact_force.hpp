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
///   1. rotate xi onto the current tangent plane: xi~ = |xi| (xi - (xi.n)n)/|xi - (xi.n)n|
///      (keeps the stored energy when the contact plane turns; as LIGGGHTS)
///   2. trial: xi_tr = xi~ + ds_t,  k' = k_t(delta) (Mindlin: k_t changes with the overlap)
///   3. F_t = -k' xi_tr; if |F_t| > mu max(F_n, 0): xi' = c xi_tr with c = mu F_n/(k'|xi_tr|)
///      (Coulomb slip), else xi' = xi_tr. With the tangential dashpot the cap applies to
///      -k' xi_tr - gamma_t v_t instead (tangential_dashpot below).
/// Energy book-keeping per contact and step. Velocity Verlet changes the kinetic energy by
/// the TRAPEZOID rule of the contact forces along the step's displacement (docs/dem.md):
///   dKE = (F(n) + F(n+1))/2 . (x(n+1) - x(n)) + (dt^2/8) m (|a(n+1)|^2 - |a(n)|^2)
/// (the last term telescopes and vanishes when contacts end). The dissipated energy of the
/// tangential spring is therefore DEFINED as the trapezoid work the particles do on it minus
/// what it stores, W_t - dE_t with W_t = (k xi~ + k' xi') . ds_t / 2 and
/// dE_t = k'|xi'|^2/2 - k|xi~|^2/2. Split by mechanism, this identity is (exactly):
///   stiffness   D_k    = -(k' - k) xi~ . xi_tr / 2   (Mindlin: E_t = k_t|xi|^2/2 changes with
///                       delta at fixed xi although no force does that work; the model adds
///                       or removes this energy; can have either sign)          [J]
///   slip        D_slip = k' (xi_tr - xi') . (xi~ + xi') / 2 >= 0   (Coulomb: the slipped
///                       displacement times the mean spring force)              [J]
/// (The rectangle forms k'(|xi_tr|^2 - |xi'|^2)/2 and (k' - k)|xi~|^2/2 differ from these by
/// k'|ds_t|^2/2 and (k' - k) xi~.ds_t/2 per step: first order in dt in total, which is what
/// made the balance drift in a slowly sliding pile: docs/dem.md "Energy balance".)
/// In total:
///   elastic     U_n(delta) + k' |xi'|^2 / 2                                      [J]
///   dissipated  (F_n - F_n,elastic) delta_dot dt   (dashpot with the predicted v(n+1),
///                                                   and the Hertz clamp)         [J]
///             + D_k + D_slip
/// When a contact ends (k' = 0) the engine adds D_k = k|xi~|^2/2 (+ k xi~.ds_t/2, which is
/// O(dt^{5/2}) there because |k xi| <= mu F_n -> 0 and is left out): the stored energy.
///
/// Moving boundaries (j = a wall or rigid object of prescribed motion, velocity v_s(t) of its
/// material at the contact point). The engine's force on i integrates the kinetic energy with
/// the trapezoid rule, so the balance closes only if the boundary's share of ds and the
/// boundary's work are booked with the same rule (Hairer, Lubich & Wanner 2006, Geometric
/// Numerical Integration, sec. I.1.4: Stoermer-Verlet is the trapezoid rule in the forces):
///   ds  = (v_i(n+1/2) + w_i(n+1/2) x r_i) dt - d_s,
///   d_s = (v_s(n) + v_s(n+1)) dt / 2         [m], boundary_step_velocity() times dt
///         (v_s(n) at the contact point of the previous evaluation, kept in the spring;
///          a new contact has no v_s(n) and uses v_s(n+1) dt)
///   W   = (P(n) + P(n+1)) dt / 2 + F_d(n+1) . v_s(n+1) dt               work of j [J]
///         P = (F_i - F_d) . v_s summed over the contacts [W], F_d = ContactForce::dashpot
/// The dashpot's share is booked at the evaluation time, the rule of its dissipation D_n above:
/// booking it by the trapezoid would leave D_n's end term (F_d delta_dot dt / 2) in the
/// balance wherever v_s jumps under a loaded contact (a plate starting to move under a
/// resting particle: 4e-5 relative in PowerBalance.Translating*).
/// With these, d(K + U + E_t) + D - W is O(dt^3) per step (the tangential remainder is
/// -(F_t(n+1) - F_t(n)).(v_s(n+1) - v_s(n)) dt / 4 per contact), so the balance converges at
/// second order. Taking v_s(n+1) dt for d_s and F(n+1).v_s(n+1) dt for all of W (the
/// rectangle rule) leaves sum_n (F(n+1) - F(n)).v_s(n+1) dt / 2, which telescopes for a
/// translating wall but is FIRST order on a rotating surface, where v_s at the moving contact
/// point changes (docs/objects.md "Power balance").
#include "ppohdem/dem/contact_law.hpp"
#include "ppohdem/dem/rolling_resistance.hpp"
#include "ppohdem/geometry/vector.hpp"

namespace ppohdem::dem {

struct ContactKinematics {
  Vec3 normal = Vec3::UnitZ();           ///< n, unit, from j towards i
  double overlap = 0.0;                  ///< delta [m]
  Vec3 relative_velocity = Vec3::Zero();  ///< v_rel at the evaluation time [m/s]
  Vec3 relative_displacement = Vec3::Zero();  ///< ds over the last step [m]
  /// ds over the last step computed with the branch vectors of the PREVIOUS evaluation, the
  /// lever arms through which the previous tangential force's torque acted during the step
  /// (frictional contacts only; equals ds when the branch vectors did not change) [m]
  Vec3 relative_displacement_previous_arms = Vec3::Zero();
  /// Rolling resistance only (rolling_resistance.hpp): w_i - w_j at the evaluation time, and
  /// the step's relative rotation (w_i - w_j at mid-step) dt [rad/s], [rad].
  Vec3 relative_spin = Vec3::Zero();
  Vec3 relative_rotation = Vec3::Zero();
  PairProperties pair;
};

/// The history of one contact (the seed's contact_list entry), kept by every law with sliding
/// friction or rolling resistance. The rules about history are stated here once:
///   - holds_history(): an entry with any nonzero field is a history (checkpointed, carried
///     over, its stored energy lost when the contact ends); a new contact starts from {};
///   - mirrored() (fast engine): the partner's view negates the vectors that are odd in the
///     normal (displacement, rolling torque) and swaps the branch vectors;
///   - a checkpoint and the fast engine's messages store every field, in the order of
///     for_each_field below (checkpoint.cpp, fast/pack.hpp).
struct TangentialSpring {
  Vec3 displacement = Vec3::Zero();  ///< xi [m]
  double stiffness = 0.0;            ///< k_t at the last update [N/m]
  Vec3 branch_i = Vec3::Zero();      ///< r_i at the last update (centre of i to contact) [m]
  Vec3 branch_j = Vec3::Zero();      ///< r_j at the last update (zero for a boundary) [m]
  /// Velocity of j's material at the contact point at the last update, v_s(n) (boundaries
  /// only: it gives the trapezoid surface displacement of the next step) [m/s]
  Vec3 surface_velocity = Vec3::Zero();
  RollingSpring rolling;  ///< EPSD2 rolling resistance only (rolling_resistance.hpp)
  /// Energy stored in the springs [J]; lost when the contact ends.
  double stored_energy() const {
    const double tangential = 0.5 * stiffness * displacement.squaredNorm();
    return rolling.stiffness > 0.0 ? tangential + rolling.stored_energy() : tangential;
  }
  /// Whether this entry carries anything a later step needs (see above).
  bool holds_history() const {
    return stiffness != 0.0 || branch_i != Vec3::Zero() || displacement != Vec3::Zero() ||
           rolling.stiffness != 0.0 || rolling.torque != Vec3::Zero();
  }
  /// The partner's view of a pair history: bitwise what the partner's own evaluation stores
  /// (the update is odd in the normal and the displacements, even in the scalars).
  TangentialSpring mirrored() const {
    TangentialSpring m;
    m.displacement = -displacement;
    m.stiffness = stiffness;
    m.branch_i = branch_j;
    m.branch_j = branch_i;
    m.rolling.torque = -rolling.torque;
    m.rolling.stiffness = rolling.stiffness;
    return m;
  }
  /// Calls f on every field (Vec3 or double), in the stored order.
  template <class Spring, class F>
  static void for_each_field(Spring& s, F&& f) {
    f(s.displacement);
    f(s.stiffness);
    f(s.branch_i);
    f(s.branch_j);
    f(s.surface_velocity);
    f(s.rolling.torque);
    f(s.rolling.stiffness);
  }
};

struct ContactForce {
  Vec3 on_i = Vec3::Zero();     ///< force on body i; body j receives -on_i [N]
  /// Torque on body i besides r_i x on_i (rolling resistance); j receives -rolling_torque [N m]
  Vec3 rolling_torque = Vec3::Zero();
  /// The dashpot's share of on_i, (F_n - F_n,elastic) n [N]: its work is booked at the
  /// evaluation time (the rectangle rule, as its dissipation), see "Moving boundaries".
  Vec3 dashpot = Vec3::Zero();
  double elastic_energy = 0.0;  ///< stored in the contact's springs now [J]
  double dissipated = 0.0;      ///< energy removed during this step [J]
};

/// The geometry of two touching spheres i, j with d = x_i - x_j (docs/dem.md), written once
/// for both engines: n = d / |d| (from j towards i), delta = R_i + R_j - |d| [m], and the
/// branch vectors to the contact point in the middle of the overlap,
/// r_i = -(R_i - delta/2) n, r_j = (R_j - delta/2) n [m].
struct SpherePairGeometry {
  Vec3 normal;
  double overlap;
  Vec3 r_i, r_j;
};
inline SpherePairGeometry sphere_pair_geometry(const Vec3& d, double radius_i, double radius_j) {
  const double distance = d.norm();
  SpherePairGeometry g;
  g.normal = d / distance;
  g.overlap = radius_i + radius_j - distance;
  g.r_i = -(radius_i - 0.5 * g.overlap) * g.normal;
  g.r_j = (radius_j - 0.5 * g.overlap) * g.normal;
  return g;
}

/// Mean velocity of a moving boundary's material at the contact over the last step [m/s], so
/// that d_s = dt * (result): the trapezoid rule (v_s(n) + v_s(n+1)) / 2 for a contact that
/// existed at step n (`continuing`; v_s(n) = spring.surface_velocity), v_s(n+1) for a new one.
/// Stores v_s(n+1) in the spring for the next step. For a constant v_s it returns v_s exactly
/// (0.5 (a + a) = a in floating point), so translating walls are unchanged bit for bit.
inline Vec3 boundary_step_velocity(TangentialSpring& spring, bool continuing,
                                   const Vec3& surface_velocity_now) {
  const Vec3 mean = continuing ? Vec3(0.5 * (spring.surface_velocity + surface_velocity_now))
                               : surface_velocity_now;
  spring.surface_velocity = surface_velocity_now;
  return mean;
}

/// Frictionless contact: normal force only, no history.
template <class Law>
ContactForce normal_contact_force(const Law& law, const ContactKinematics& c, double dt) {
  const double delta_dot = -c.relative_velocity.dot(c.normal);
  const double f_n = law.normal_force(c.overlap, delta_dot, c.pair);
  const double f_el = law.elastic_force(c.overlap, c.pair);
  ContactForce out;
  out.on_i = f_n * c.normal;
  out.dashpot = (f_n - f_el) * c.normal;
  out.elastic_energy = law.elastic_energy(c.overlap, c.pair);
  out.dissipated = (f_n - f_el) * delta_dot * dt;
  return out;
}

/// The tangential dashpot (contact_law.hpp, `tangential_damping`) and the Coulomb cap, given
/// the trial spring state xi = xi_tr and f_t = -k' xi_tr:
///   F_t = -k' xi_tr - gamma_t v_t,  v_t = v_rel - (v_rel . n) n  (at the evaluation time)
///   sticking  |F_t| <= mu F_n: xi' = xi_tr; the dashpot dissipates gamma_t |v_t|^2 dt, booked
///             like the normal dashpot (with the predicted velocity) and, as that one, part of
///             ContactForce::dashpot;
///   sliding   F_t scaled to |F_t| = mu F_n and carried by the spring alone, xi' = -F_t / k'
///             (LIGGGHTS resets the spring the same way), no dashpot force; the spring's D_k
///             and D_slip (frictional_contact_force) book the energy, an identity for any xi'.
/// LIGGGHTS instead caps the spring force alone and adds the dashpot only while it sticks, so
/// its sticking |F_t| can exceed mu F_n by up to gamma_t |v_t|; here Coulomb's law holds
/// always (docs/dem.md "Tangential dashpot"). Odd in (n, v_rel, xi): the mirror is exact.
template <class Law>
void tangential_dashpot(const Law& law, const ContactKinematics& c, double k_t, double cap, double dt,
                        Vec3& xi, Vec3& f_t, ContactForce& out) {
  const Vec3& n = c.normal;
  const Vec3 v_t = c.relative_velocity - c.relative_velocity.dot(n) * n;  // [m/s]
  const Vec3 f_d = -law.tangential_damping_coefficient(c.overlap, c.pair) * v_t;  // [N]
  const Vec3 total = f_t + f_d;
  const double total_norm = total.norm();
  if (total_norm > cap) {
    f_t = (cap / total_norm) * total;
    xi = k_t > 0.0 ? Vec3(f_t / -k_t) : Vec3(Vec3::Zero());
  } else {
    f_t = total;
    out.dashpot += f_d;
    out.dissipated -= f_d.dot(v_t) * dt;  // gamma_t |v_t|^2 dt >= 0 [J]
  }
}

/// Frictional contact: normal force plus the tangential spring `spring` (updated in place).
template <class Law>
ContactForce frictional_contact_force(const Law& law, const ContactKinematics& c,
                                      TangentialSpring& spring, double dt) {
  ContactForce out = normal_contact_force(law, c, dt);
  const Vec3& n = c.normal;
  const double f_n = out.on_i.dot(n);

  // 1. Rotate the history onto the current tangent plane, keeping its length: xi~.
  Vec3& xi = spring.displacement;
  const Vec3 xi_previous = xi;
  const double length = xi.norm();
  xi -= xi.dot(n) * n;
  const double projected = xi.norm();
  if (projected > 0.0) xi *= length / projected;
  const Vec3 xi_rotated = xi;
  const double k_old = spring.stiffness;  // k [N/m]

  // 2. Trial state: add the sliding displacement of this step; Mindlin k' = k_t(delta).
  const Vec3 ds_t = c.relative_displacement - c.relative_displacement.dot(n) * n;
  const Vec3 xi_trial = xi_rotated + ds_t;
  const double k_t = law.tangential_stiffness(c.overlap, c.pair);
  xi = xi_trial;
  spring.stiffness = k_t;

  // 3. Spring force and Coulomb cap |F_t| <= mu F_n (F_n < 0 is possible with the unclamped
  // linear law near separation: then the cap is 0).
  Vec3 f_t = -k_t * xi;
  const double cap = law.friction() * (f_n > 0.0 ? f_n : 0.0);
  if (law.tangential_damping()) {  // a runtime test: scenes without it pay one branch
    tangential_dashpot(law, c, k_t, cap, dt, xi, f_t, out);
  } else {
    const double f_t_norm = f_t.norm();
    if (f_t_norm > cap) {
      const double scale = cap / f_t_norm;  // c in [0, 1)
      f_t *= scale;
      xi *= scale;
    }
  }
  // Energy the trapezoid-rule work puts into the spring but it does not store [J]:
  // D_k = -(k' - k) xi~.xi_tr / 2 and D_slip = k' (xi_tr - xi').(xi~ + xi') / 2.
  out.dissipated += -0.5 * (k_t - k_old) * xi_rotated.dot(xi_trial);
  out.dissipated += 0.5 * k_t * (xi_trial - xi).dot(xi_rotated + xi);
  // D_frame: the previous force F_t(n) = -k xi(n) acted in the previous tangent plane and
  // through the previous lever arms; the trapezoid work above used xi~ and the new arms.
  out.dissipated += 0.5 * k_old *
                    (xi_previous.dot(c.relative_displacement_previous_arms) -
                     xi_rotated.dot(c.relative_displacement));
  out.on_i += f_t;
  out.elastic_energy += 0.5 * spring.stiffness * spring.displacement.squaredNorm();
  if (law.rolling().active()) {  // a runtime test: laws without it pay one predicted branch
    const RollingTorque m = rolling_torque(law.rolling(), c.pair.r_eff, f_n, k_t, n, c.relative_spin,
                                           c.relative_rotation, spring.rolling, dt);
    out.rolling_torque = m.on_i;
    out.elastic_energy += m.elastic;
    out.dissipated += m.dissipated;
  }
  return out;
}

}  // namespace ppohdem::dem
