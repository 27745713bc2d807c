# YADE reference run: a sphere resting on a floor that translates at V = 0.1 m/s along +x
# (a conveyor belt). Friction drags the sphere until it rolls without slipping; rigid-body
# theory (impulse about the contact point) gives v -> 2V/7 and omega_y -> -5V/(7R) after
# t_roll = 2V/(7 mu g). Material as the settling scenes: R = 1 mm, 2500 kg/m^3, E = 1e7 Pa,
# nu = 0.3, e = 0.5, mu = 0.5; g = 9.81 m/s^2; dt = 1e-6 s, 12,000 steps (0.012 s).
#     yade -n -x validation/yade/moving_wall.py [OUT_DIR]
# ppohdem's twin: validation/yade/scenes/moving_wall.toml ([[wall]] velocity).
# Runs with dt and dt/2 (time-step error estimate). Writes yade_moving_wall.csv:
# dt [s], time [s], vx [m/s], omega_y [rad/s], z [m] every 0.02 ms.
import math, os, sys
sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))  # __file__ is not set by yade -x
import yade_common as yc
from yade import O, utils

R, RHO, E, NU, E_REST, MU = 1.0e-3, 2500.0, 1.0e7, 0.3, 0.5, 0.5
V_BELT, G, DT, STEPS, EVERY = 0.1, 9.81, 1.0e-6, 12000, 20

rows = []
for dt, steps, every in ((DT, STEPS, EVERY), (DT / 2, 2 * STEPS, 2 * EVERY)):
    O.reset()
    mat = yc.material(RHO, E, NU, MU)
    yc.setup_engines(E_REST, gravity=(0, 0, -G), walls=True)
    w = O.bodies.append(utils.wall(0.0, axis=2, sense=1, material=mat))
    O.bodies[w].state.vel = (V_BELT, 0, 0)   # kinematic body: NewtonIntegrator moves it
    s = O.bodies.append(utils.sphere((0, 0, R), R, material=mat))   # touching, at rest
    O.dt = dt
    for n in range(steps + 1):
        if n % every == 0:
            st = O.bodies[s].state
            rows.append((dt, O.time, st.vel[0], st.angVel[1], st.pos[2]))
        if n < steps:
            O.step()
yc.write_csv(os.path.join(yc.out_dir(), 'yade_moving_wall.csv'), sys.argv[0],
             ['dt', 'time', 'vx', 'omega_y', 'z'], rows, 'wall velocity (0.1, 0, 0) m/s')
print('final vx %.7g omega_y %.7g (theory %.7g, %.7g)' % (rows[-1][2], rows[-1][3],
      2 * V_BELT / 7, -5 * V_BELT / (7 * R)))
