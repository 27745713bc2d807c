# YADE reference run: 1,000 spheres settling from a jittered lattice into an open-top box.
#     yade -n -x validation/yade/settling_bed.py [OUT_DIR] [SEED ...]    (default seeds 1 2 3)
# Initial state: fixtures/yade/bed_seed<S>.csv (make_bed.py: R = 1 mm on a 10x10x10 lattice of
# pitch 1.05 d, jitter 0.04 R, at rest) in a 21 mm x 21 mm box (plane walls x, y = 0 and
# 21 mm, floor z = 0). R = 1 mm, 2500 kg/m^3, E = 1e7 Pa, nu = 0.3, e = 0.5, mu = 0.5, g = 9.81.
# dt = 1e-5 s (58% of 0.2 T_R), 20,000 steps = 0.2 s (the top layer lands at ~0.07 s; the bed
# is at rest, kinetic energy < 1e-3 of the potential energy released, by 0.2 s).
# ppohdem's twin: validation/yade/scenes/settling_bed.toml (particle file replaced per seed).
# Writes yade_bed_seed<S>_final.csv (ppohdem particle CSV: id,x,y,z,vx,vy,vz,wx,wy,wz,radius)
# and yade_bed_seed<S>_summary.csv (seed, kinetic energy [J], sphere-sphere contacts, wall
# contacts, wall time [s]).
import os, sys, time
sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))  # __file__ is not set by yade -x
import yade_common as yc
from yade import O, utils, Sphere

RHO, E, NU, E_REST, MU, G = 2500.0, 1.0e7, 0.3, 0.5, 0.5, 9.81
L, DT, STEPS = 0.021, 1.0e-5, 20000
seeds = [int(s) for s in sys.argv[2:]] or [1, 2, 3]
out = yc.out_dir()
for seed in seeds:
    O.reset()
    mat = yc.material(RHO, E, NU, MU)
    yc.setup_engines(E_REST, gravity=(0, 0, -G), walls=True)
    for axis, pos, sense in ((2, 0.0, 1), (0, 0.0, 1), (0, L, -1), (1, 0.0, 1), (1, L, -1)):
        O.bodies.append(utils.wall(pos, axis=axis, sense=sense, material=mat))
    ids = {}
    with open(os.path.join(yc.REPO, 'fixtures', 'yade', 'bed_seed%d.csv' % seed)) as f:
        for line in f:
            if line.startswith('#') or line.startswith('id'):
                continue
            v = [float(x) for x in line.split(',')]
            ids[int(v[0])] = O.bodies.append(utils.sphere(v[1:4], v[10], material=mat))
    O.dt = DT
    t0 = time.time()
    O.run(STEPS, True)
    wall = time.time() - t0
    rows, ke = [], 0.0
    for pid, b in sorted(ids.items()):
        s = O.bodies[b].state
        ke += 0.5 * s.mass * s.vel.squaredNorm()
        rows.append((pid, s.pos[0], s.pos[1], s.pos[2], s.vel[0], s.vel[1], s.vel[2],
                     s.angVel[0], s.angVel[1], s.angVel[2], O.bodies[b].shape.radius))
    pp = sum(1 for i in O.interactions if i.isReal and isinstance(O.bodies[i.id1].shape, Sphere)
             and isinstance(O.bodies[i.id2].shape, Sphere))
    pw = sum(1 for i in O.interactions if i.isReal) - pp
    yc.write_csv(os.path.join(out, 'yade_bed_seed%d_final.csv' % seed), sys.argv[0],
                 ['id', 'x', 'y', 'z', 'vx', 'vy', 'vz', 'wx', 'wy', 'wz', 'radius'], rows,
                 'seed %d after %d steps of dt %g s' % (seed, STEPS, DT))
    summary = (seed, ke, pp, pw, wall)
    print('seed %d: kinetic %.4g J, %d sphere-sphere and %d wall contacts, %.1f s' % summary)
    yc.write_csv(os.path.join(out, 'yade_bed_seed%d_summary.csv' % seed), sys.argv[0],
                 ['seed', 'kinetic_J', 'pp_contacts', 'pw_contacts', 'wall_s'], [summary])
