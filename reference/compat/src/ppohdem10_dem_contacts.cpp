// The original DEM's contact forces (ppohDEM_calcforce, calc_force_ij_DEM, calc_force_wall_DEM);
// see ppohdem10_dem.hpp. Linear spring-dashpot (Cundall & Strack 1979, Geotechnique 29(1)
// 47-65) as the original codes it:
//   overlap  delta = r_i + r_j - |x_j - x_i| [m],  n = (x_j - x_i) / |x_j - x_i|
//   contact velocity  v_c = (v_j - v_i) - (r'_j omega_j + r'_i omega_i) x n,  r' = r - delta/2
//   normal   F_n = (-Kn delta + En (v_c . n)) n                       [N]
//   spring   s = s_old + (n_old x n) x s_old + Kt dt (v_c - (v_c . n) n)   (new contact: s_old = 0)
//   force on i  F = F_n + s + Et v_c,   rforce_i += n x (s + Et v_c)
// Walls: the same with the wall as a partner at rest (no rotation of the spring), and the
// Coulomb cap |s + Et v_c| <= mu |F_n . n| only for a contact that persists from the last step.
#include <string>

#include "ppohdem/error.hpp"
#include "ppohdem/compat/ppohdem10_dem.hpp"

namespace ppohdem::compat {
namespace {

using C = Ppohdem10DemConstants;

struct PairForce {
  Rvec3 force;
  Rvec3 rforce;
};

void push_contact(std::vector<Ppohdem10Contact>& list, std::size_t capacity, const Ppohdem10Contact& c,
                  std::size_t particle, const Ppohdem10Particles& p, long itime, const char* what) {
  if (list.size() >= capacity) {
    // The original writes past its fixed-size list (undefined behaviour): refused.
    throw InputError("--compat ppohdem-1.0: step " + std::to_string(itime + 1) + ": particle id " +
                     std::to_string(p.id[particle]) + " has more than " + std::to_string(capacity) + " " + what +
                     " contacts (the original's list overflows)");
  }
  list.push_back(c);
}

/// calc_force_ij_DEM: the force of particle j on particle i (1-based i1, j1), recording the
/// contact in i's new list and looking its spring up in i's old list.
PairForce force_ij(Ppohdem10Particles& p, std::size_t i1, std::size_t j1,
                   const std::vector<Ppohdem10Contact>& old_contact_list, long itime) {
  PairForce out;  // zero unless in contact (the original adds these zeros too)
  if (i1 == j1) return out;
  const std::size_t i = i1 - 1;
  const std::size_t j = j1 - 1;
  Rvec3 dn = sub_rvec3(p.pos[j], p.pos[i]);
  const double a = length_rvec3(dn);
  const double value_dis = p.radius[i] + p.radius[j] - a;  // overlap [m]
  if (!((value_dis > 0) && (a != 0))) return out;
  const double b = 1. / a;
  dn = mulc_rvec3(dn, b);  // unit normal i -> j, as n * (1/a), not n / a
  push_contact(p.contact_list[i], C::kContactListSize, {static_cast<int>(j1), {}, dn}, i, p, itime, "particle");
  Ppohdem10Contact& stored = p.contact_list[i].back();

  // normal force
  const double rihun_i = p.radius[i] - 0.5 * value_dis;  // distance centre -> contact point [m]
  const double rihun_j = p.radius[j] - 0.5 * value_dis;
  Rvec3 ff = add_rvec3(mulc_rvec3(p.omega[j], rihun_j), mulc_rvec3(p.omega[i], rihun_i));
  const Rvec3 vc = sub_rvec3(sub_rvec3(p.vel[j], p.vel[i]), cross_rvec3(ff, dn));  // [m/s]
  const double nv = dot_rvec3(vc, dn);
  const Rvec3 vt = sub_rvec3(vc, mulc_rvec3(dn, nv));
  const double fnn = -C::kNormalStiffness * value_dis + C::kNormalDamping * nv;  // [N], < 0 pushes i away
  out.force = mulc_rvec3(dn, fnn);

  // tangential force. Q5: README "a tangential spring with history that is rotated by
  // dn_old x dn": s_old + (dn_old x dn) x s_old, a first-order rotation that is not
  // renormalised. The dashpot term Et v_c acts on the FULL contact velocity (normal part
  // included), and there is NO Coulomb cap between particles ("missing particle-particle
  // friction cap"): the spring grows without bound while the contact lasts.
  ff = mulc_rvec3(vt, C::kTangentialStiffness * C::kTimeStep);
  for (std::size_t k = 1; k <= old_contact_list.size() + 1; ++k) {
    if (k == old_contact_list.size() + 1) {  // a new contact: spring from zero
      stored.tforce = ff;
      ff = add_rvec3(ff, mulc_rvec3(vc, C::kTangentialDamping));
      out.force = add_rvec3(out.force, ff);
      out.rforce = cross_rvec3(dn, ff);
      break;
    }
    const Ppohdem10Contact& old = old_contact_list[k - 1];
    if (old.pid == static_cast<int>(j1)) {  // the contact persists (by index: see Q4)
      const Rvec3 ff2 = cross_rvec3(old.dn, dn);
      const Rvec3 ff3 = add_rvec3(old.tforce, cross_rvec3(ff2, old.tforce));
      ff = add_rvec3(ff3, ff);
      stored.tforce = ff;
      ff = add_rvec3(ff, mulc_rvec3(vc, C::kTangentialDamping));
      out.force = add_rvec3(out.force, ff);
      out.rforce = cross_rvec3(dn, ff);
      break;
    }
  }
  return out;
}

/// calc_force_wall_DEM: the force of wall w (1-based) on particle i.
PairForce force_wall(Ppohdem10Particles& p, std::size_t i, const std::vector<Ppohdem10Wall>& walls, int w,
                     const std::vector<Ppohdem10Contact>& old_contact_list_wall, long itime) {
  PairForce out;
  const Ppohdem10Wall& wall = walls[static_cast<std::size_t>(w - 1)];
  const Rvec3 dr = sub_rvec3(wall.point, p.pos[i]);
  const Rvec3 dn = negative_rvec3(wall.nvec);  // unit normal particle -> wall
  const double rihun_i = dot_rvec3(dr, dn);    // distance centre -> wall [m]
  const double value_dis = p.radius[i] - rihun_i;
  // The original also tests `a .ne. 0` with `a` never set in this routine (an uninitialised
  // local). The sample's wall contacts all act (582 at the end), so the test evidently passed;
  // it is taken as true here.
  if (!(value_dis > 0)) return out;
  push_contact(p.contact_list_wall[i], C::kWallContactListSize, {w, {}, dn}, i, p, itime, "wall");
  Ppohdem10Contact& stored = p.contact_list_wall[i].back();

  // normal force
  Rvec3 ff = mulc_rvec3(p.omega[i], rihun_i);
  const Rvec3 vc = negative_rvec3(add_rvec3(p.vel[i], cross_rvec3(ff, dn)));
  const double nv = dot_rvec3(vc, dn);
  const double fnn = -C::kNormalStiffness * value_dis + C::kNormalDamping * nv;
  out.force = mulc_rvec3(dn, fnn);

  // tangential force: no rotation of the wall spring (the wall normal is fixed).
  ff = mulc_rvec3(sub_rvec3(vc, mulc_rvec3(dn, nv)), C::kTangentialStiffness * C::kTimeStep);
  for (std::size_t k = 1; k <= old_contact_list_wall.size() + 1; ++k) {
    if (k == old_contact_list_wall.size() + 1) {
      // Q5: README "friction limit 0.5774 on the wall tangential force only" — and only on
      // PERSISTING wall contacts: a new wall contact gets spring + dashpot uncapped.
      stored.tforce = ff;
      ff = add_rvec3(ff, mulc_rvec3(vc, C::kTangentialDamping));
      out.force = add_rvec3(out.force, ff);
      out.rforce = cross_rvec3(dn, ff);
      break;
    }
    const Ppohdem10Contact& old = old_contact_list_wall[k - 1];
    if (old.pid == w) {
      Rvec3 ff3 = add_rvec3(old.tforce, ff);
      stored.tforce = ff3;  // the stored spring is never capped
      ff3 = add_rvec3(ff3, mulc_rvec3(vc, C::kTangentialDamping));
      const double f1 = length_rvec3(ff3);
      const double f2 = std::abs(fnn);
      if (f1 > f2 * C::kFriction) {
        const double f3 = f2 * C::kFriction / f1;  // (f2 mu) / f1
        ff3 = mulc_rvec3(ff3, f3);
      }
      out.force = add_rvec3(out.force, ff3);
      out.rforce = cross_rvec3(dn, ff3);
      break;
    }
  }
  return out;
}

}  // namespace

void ppohdem10_calcforce(Ppohdem10Particles& p, const Ppohdem10Cells& cells, const std::vector<Ppohdem10Wall>& walls,
                         long itime) {
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.force[i] = Rvec3{};
    p.rforce[i] = Rvec3{};

    // particles: prepare_contactlist moves i's list aside and starts an empty one.
    const std::vector<Ppohdem10Contact> old_contact_list = std::move(p.contact_list[i]);
    p.contact_list[i].clear();
    // Q3: p.cellindex[i] is the stale (pre-sort order) cell number, as in the original.
    const auto own_cell = static_cast<std::size_t>(p.cellindex[i] - 1);
    for (std::size_t cn = 0; cn < 27; ++cn) {
      const auto nei_cell = static_cast<std::size_t>(cells.nei_cellindex[27 * own_cell + cn] - 1);
      for (int j = cells.start_partindex[nei_cell]; j <= cells.end_partindex[nei_cell]; ++j) {
        const PairForce f = force_ij(p, i + 1, static_cast<std::size_t>(j), old_contact_list, itime);
        p.force[i] = add_rvec3(p.force[i], f.force);
        p.rforce[i] = add_rvec3(p.rforce[i], f.rforce);
      }
    }

    // walls
    const std::vector<Ppohdem10Contact> old_contact_list_wall = std::move(p.contact_list_wall[i]);
    p.contact_list_wall[i].clear();
    for (int w = 1; w <= static_cast<int>(walls.size()); ++w) {
      const PairForce f = force_wall(p, i, walls, w, old_contact_list_wall, itime);
      p.force[i] = add_rvec3(p.force[i], f.force);
      p.rforce[i] = add_rvec3(p.rforce[i], f.rforce);
    }
  }
}

}  // namespace ppohdem::compat
