#!/usr/bin/python3
"""The object benchmark of issue 38 item 4 (ci/bench-objects.sh; docs/performance.md "Objects").

A settled bed of 1,355 spheres (R = 2 mm, 2500 kg/m^3, E = 2e7 Pa, nu = 0.3, e = 0.5, mu = 0.5,
Hertz-Mindlin) in an 80 x 56 mm box, and the scoop of fixtures/scenes/scoop (30 x 14 x 24 mm, a
tenth of the box's length) driven through it as one motion program: a translation at
(-0.06, 0, -0.13) m/s for the first STEPS_T steps (down and back into the bed), then a rotation
at 1.4 rad/s about +y through its back-bottom edge for STEPS_R steps (it lifts particles).
dt = 1.5e-5 s (61 % of the stability limit).

  make_scoop_bench.py settle OUT            OUT/settle.toml: the bed falls and settles (8000 steps)
  make_scoop_bench.py bench FINAL OUT STEPS_T STEPS_R [--untracked]
      OUT/particles.csv (the settled FINAL), OUT/particles.data (the same for LIGGGHTS: atoms and
      velocities), OUT/scene.toml (ppohdem) and OUT/liggghts.vars (the deck's variables for
      validation/peers/liggghts/in.scoop); --untracked: [simulation] energy_balance = false.
"""
import math
import os
import shutil
import sys

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..'))
STL = os.path.join(ROOT, 'fixtures', 'scenes', 'scoop', 'scoop.stl')
R, RHO, DT = 2.0e-3, 2500.0, 1.5e-5
N = 1355
BOX = ((0.0, 0.08), (-0.014, 0.042), (0.0, 0.1))  # x, y, z [m]; the scoop's width is centred in y
VELOCITY = (-0.1, 0.0, -0.16)  # m/s
OMEGA = 2.5  # rad/s about +y
CENTROID = (0.075, 0.014, 0.045)  # the scoop's back-bottom edge at rest [m]

COMMON = '''[material]
density = 2500.0
young = 2.0e7
poisson = 0.3
restitution = 0.5
friction = 0.5

[contact]
model = "hertz-mindlin"
'''


def walls():
    (x0, x1), (y0, y1), _ = BOX
    out = ''
    for p, n in (((0, 0, 0), (0, 0, 1)), ((x0, 0, 0), (1, 0, 0)), ((x1, 0, 0), (-1, 0, 0)),
                 ((0, y0, 0), (0, 1, 0)), ((0, y1, 0), (0, -1, 0))):
        out += '[[wall]]\npoint = [%r, %r, %r]\nnormal = [%r, %r, %r]\n' % tuple(float(v) for v in p + n)
    return out


def settle(out):
    (x0, x1), (y0, y1), _ = BOX
    with open(os.path.join(out, 'settle.toml'), 'w') as f:
        f.write('# make_scoop_bench.py settle: %d spheres fall and settle (5 layers)\n' % N)
        f.write('[simulation]\ndt = %r\nsteps = 8000\ngravity = [0.0, 0.0, -9.81]\nenergy_balance = false\n\n' % DT)
        f.write(COMMON)
        f.write('\n[particles]\ngenerator = "random"\nbox_min = [%r, %r, 0.0]\nbox_max = [%r, %r, 0.045]\n'
                'count = %d\nradius = %r\nseed = 38\n\n' % (x0, y0, x1, y1, N, R))
        f.write(walls())
        f.write('\n[output]\ndir = "settle_out"\nevery = 0\nprogress = false\n')


def read_csv(path):
    rows = []
    with open(path) as f:
        header = None
        for line in f:
            if line.startswith('#') or not line.strip():
                continue
            if header is None:
                header = line.strip().split(',')
                continue
            rows.append(dict(zip(header, (float(v) for v in line.strip().split(',')))))
    return rows


def bench(final, out, steps_t, steps_r, untracked):
    rows = read_csv(final)
    shutil.copy(final, os.path.join(out, 'particles.csv'))
    (x0, x1), (y0, y1), (z0, z1) = BOX
    with open(os.path.join(out, 'particles.data'), 'w') as f:
        f.write('make_scoop_bench.py: the settled bed, %d spheres of d = %g m\n\n%d atoms\n1 atom types\n\n'
                % (len(rows), 2 * R, len(rows)))
        f.write('%r %r xlo xhi\n%r %r ylo yhi\n%r %r zlo zhi\n\nAtoms\n\n' % (x0, x1, y0, y1, z0, z1))
        for r in rows:
            f.write('%d 1 %r %r %r %r %r\n' % (r['id'], 2 * r['radius'], RHO, r['x'], r['y'], r['z']))
        f.write('\nVelocities\n\n')
        for r in rows:
            f.write('%d %r %r %r %r %r %r\n' % (r['id'], r['vx'], r['vy'], r['vz'], r['wx'], r['wy'], r['wz']))
    t_switch = steps_t * DT
    pivot = tuple(c + v * t_switch for c, v in zip(CENTROID, VELOCITY))  # where the translation leaves it
    with open(os.path.join(out, 'scene.toml'), 'w') as f:
        f.write('# make_scoop_bench.py bench: the scoop through the settled bed, %d + %d steps\n' % (steps_t, steps_r))
        f.write('[simulation]\ndt = %r\nsteps = %d\ngravity = [0.0, 0.0, -9.81]\n' % (DT, steps_t + steps_r))
        if untracked:
            f.write('energy_balance = false\n')
        f.write('\n' + COMMON + '\n[particles]\nfile = "particles.csv"\n\n' + walls())
        f.write('\n[[object]]\nname = "scoop"\nmesh = "%s"\ncells = [30, 20, 24]\ncentroid = [%r, %r, %r]\n' % ((STL,) + CENTROID))
        f.write('[[object.motion]]\nstart = 0.0\ntype = "translate"\nvelocity = [%r, %r, %r]\n' % VELOCITY)
        f.write('[[object.motion]]\nstart = %r\ntype = "rotate"\naxis = [0.0, 1.0, 0.0]\nomega = %r\n' % (t_switch, OMEGA))
        f.write('\n[output]\ndir = "ours_out"\nevery = 0\nprogress = false\n')
        # Digging pinches columns of particles against the floor (fixtures/scenes/scoop: 10.7 % of R).
        f.write('\n[checks]\nmax_overlap = 0.3\n')
    with open(os.path.join(out, 'liggghts.vars'), 'w') as f:
        f.write('-var data %s -var stl %s -var steps_t %d -var steps_r %d -var vx %r -var vy %r -var vz %r '
                '-var ox %r -var oy %r -var oz %r -var period %r -var ylo %r -var yhi %r -var xhi %r\n'
                % ((os.path.join(out, 'particles.data'), STL, steps_t, steps_r) + VELOCITY + pivot
                   + (2 * math.pi / OMEGA, y0, y1, x1)))


def main():
    if len(sys.argv) == 3 and sys.argv[1] == 'settle':
        os.makedirs(sys.argv[2], exist_ok=True)
        settle(sys.argv[2])
    elif len(sys.argv) in (6, 7) and sys.argv[1] == 'bench':
        os.makedirs(sys.argv[3], exist_ok=True)
        bench(sys.argv[2], os.path.abspath(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5]), sys.argv[6:] == ['--untracked'])
    else:
        sys.exit(__doc__)


if __name__ == '__main__':
    main()
