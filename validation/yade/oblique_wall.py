# YADE reference run: oblique impact of a sphere on a plane wall with friction (Chung & Ooi
# 2011 test 4 material: alumina R = 2.55 mm, 4000 kg/m^3, E = 380 GPa, nu = 0.23, mu = 0.092,
# elastic e = 1), speed 3.9 m/s at incidence angles 5..80 degrees from the wall normal.
#     yade -n -x validation/yade/oblique_wall.py [OUT_DIR] [ANGLES]   (ANGLES: "5,45", default all)
# The wall has the sphere's material (as in ppohdem, docs/dem.md) and, with hertzian=True, a
# curvature radius 1e8 R (R* = R (1 - 1e-8)). dt = 1e-9 s (> 8000 steps per contact), and
# dt/2 for the time-step error estimate (Richardson).
# ppohdem's twin: validation/yade/scenes/oblique_wall.toml (velocity set per angle by the check).
# Writes yade_oblique_wall.csv: angle_deg, dt [s], vt_in, vn_in [m/s], vt_out, vn_out [m/s] (centre
# velocity after the contact; t along +x, n along +z), omega_out [rad/s] (spin about +y),
# duration [s] (time with a real interaction).
import math, os, sys
sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))  # __file__ is not set by yade -x
import yade_common as yc
from yade import O, utils

R, RHO, E, NU, E_REST, MU = 2.55e-3, 4000.0, 3.8e11, 0.23, 1.0, 0.092
SPEED, GAP, DT = 3.9, 1.0e-7, 1.0e-9
ANGLES = [5.0, 10.0, 20.0, 30.0, 45.0, 60.0, 80.0]
if len(sys.argv) > 2:
    ANGLES = [float(a) for a in sys.argv[2].split(',')]

rows = []
for angle, dt in [(a, d) for a in ANGLES for d in (DT, DT / 2)]:
    O.reset()
    mat = yc.material(RHO, E, NU, MU)
    yc.setup_engines(E_REST, walls=True)
    O.bodies.append(utils.wall(0.0, axis=2, sense=1, material=mat))
    s = O.bodies.append(utils.sphere((0, 0, R + GAP), R, material=mat))
    th = math.radians(angle)
    vt, vn = SPEED * math.sin(th), -SPEED * math.cos(th)
    O.bodies[s].state.vel = (vt, 0, vn)
    O.dt = dt
    steps_in_contact, touched = 0, False
    for n in range(200000):
        O.step()
        real = any(i.isReal for i in O.interactions)
        if real:
            touched = True
            steps_in_contact += 1
        elif touched:
            break
    st = O.bodies[s].state
    rows.append((angle, dt, vt, vn, st.vel[0], st.vel[2], st.angVel[1], steps_in_contact * dt))
    print('angle %g dt %g vt_out %.7g vn_out %.7g omega %.7g' % (angle, dt, st.vel[0], st.vel[2], st.angVel[1]))
yc.write_csv(os.path.join(yc.out_dir(), 'yade_oblique_wall.csv'), sys.argv[0],
             ['angle_deg', 'dt', 'vt_in', 'vn_in', 'vt_out', 'vn_out', 'omega_out', 'duration'], rows,
             'wall: Ig2_Wall_Sphere_ScGeom(hertzian=True); betan = betas = 0 (e = 1)')
