# YADE reference run: normal impact of two identical spheres (Hertz-Mindlin, e = 0.5).
#     yade -n -x validation/yade/two_spheres.py [OUT_DIR]      (default OUT_DIR: fixtures/yade)
# The scene of DESIGN.md's peer comparison: R = 0.5 mm, 2500 kg/m^3, E = 1e7 Pa, nu = 0.3,
# e = 0.5 (measured), approach 0.1 m/s, no gravity; started 1 um apart so the contact begins
# after 10 steps. dt = 1e-7 s (~1786 steps per contact), and again with dt/2 so the comparison
# can estimate YADE's time-step error (Richardson). ppohdem's twin scene:
# validation/yade/scenes/two_spheres.toml. Writes
#   yade_two_spheres_series.csv   time [s], overlap [m], normal force on sphere 1 [N]
#                                 (dt = 1e-7 s, every 4th step, while the spheres are < 1 um apart)
#   yade_two_spheres_summary.csv  quantity, value (dt), value_half_dt (dt/2): max overlap [m],
#                                 max force [N], duration [s], restitution
import os, sys
sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))  # __file__ is not set by yade -x
import yade_common as yc
from yade import O, utils

R, RHO, E, NU, E_REST, MU = 0.5e-3, 2500.0, 1.0e7, 0.3, 0.5, 0.5
V_REL, GAP, DT, T_END = 0.1, 1.0e-6, 1.0e-7, 2.4e-4


def run(dt):
    O.reset()
    mat = yc.material(RHO, E, NU, MU)
    yc.setup_engines(E_REST)
    a = O.bodies.append(utils.sphere((-(R + GAP / 2), 0, 0), R, material=mat))
    b = O.bodies.append(utils.sphere((+(R + GAP / 2), 0, 0), R, material=mat))
    O.bodies[a].state.vel = (+V_REL / 2, 0, 0)
    O.bodies[b].state.vel = (-V_REL / 2, 0, 0)
    O.dt = dt
    rows = []
    for n in range(int(round(T_END / dt))):
        pa, pb = O.bodies[a].state.pos, O.bodies[b].state.pos
        overlap = 2 * R - (pb - pa).norm()      # at x(n)
        t = O.time
        O.step()                                # forces at x(n), then leapfrog to x(n+1)
        force = -O.forces.f(a)[0]               # normal force pushing sphere a back (+ = repulsive)
        rows.append((t, overlap, force))
    v_out = O.bodies[b].state.vel[0] - O.bodies[a].state.vel[0]

    def crossing(i):  # time where the overlap crosses 0 between rows i and i+1 (linear)
        (t0, d0, _), (t1, d1, _) = rows[i], rows[i + 1]
        return t0 + (t1 - t0) * d0 / (d0 - d1)
    inside = [i for i, r in enumerate(rows) if r[1] > 0]
    summary = {'max_overlap_m': max(r[1] for r in rows),
               'max_force_N': max(r[2] for r in rows),
               'duration_s': crossing(inside[-1]) - crossing(inside[0] - 1),
               'restitution': v_out / V_REL}
    return rows, summary


rows, s1 = run(DT)
_, s2 = run(DT / 2)
out = yc.out_dir()
yc.write_csv(os.path.join(out, 'yade_two_spheres_series.csv'), sys.argv[0],
             ['time', 'overlap', 'force'],
             [r for i, r in enumerate(rows) if r[1] > -1e-6 and i % 4 == 0])
yc.write_csv(os.path.join(out, 'yade_two_spheres_summary.csv'), sys.argv[0],
             ['quantity', 'value', 'value_half_dt'], [(k, s1[k], s2[k]) for k in s1],
             'dt = %g s and dt/2; betan = alpha(e)/sqrt(6), betas = 0 (docs/yade.md)' % DT)
for k in s1:
    print('%s %.9g %.9g' % (k, s1[k], s2[k]))
