#!/usr/bin/python3
"""The standard DEM benchmark scene of issue 7 as inputs for ppohdem and the three peers.

    /usr/bin/python3 validation/peers/make_bench.py N STEPS OUT_DIR

N = 10000 (25 x 25 x 16 lattice) or 100000 (50 x 50 x 40); any N = nx*ny*nz listed below.
Monodisperse spheres d = 1 mm, 2500 kg/m^3, E = 1e7 Pa, nu = 0.3, e = 0.5 (MEASURED binary
restitution), mu = 0.5, Hertz-Mindlin with tangential history, g = 9.81 m/s^2 along -z, simple
cubic lattice of spacing 1.05 d (each centre jittered by +/-0.02 R per axis, seed 1, so the
lattice is not perfectly symmetric; every code gets the same positions), at rest, in a box of
side n x 1.05 d with plane walls at x, y = 0 and L and a floor at z = 0 (the top is open;
the LAMMPS box is closed 1.05 d above the top layer but nothing rises that far).
dt = 8.65e-6 s = 20 % of the Rayleigh time 4.3269e-5 s (R = 0.5 mm).

Writes into OUT_DIR:
  particles.csv   ppohdem particle file (id,x,y,z,vx,vy,vz,wx,wy,wz,radius); the YADE deck
                  reads it too
  scene.toml      ppohdem scene (`ppohdem simulate scene.toml`), output in OUT_DIR/ours_out
  particles.data  LAMMPS / LIGGGHTS data file (atom_style sphere / granular:
                  id type diameter density x y z)
  box.txt         "L H" [m], for the decks' walls
"""
import math
import os
import random
import sys

D = 1.0e-3            # m, diameter
R = D / 2
RHO = 2500.0          # kg/m^3
PITCH = 1.05 * D      # m
JITTER = 0.02 * R     # m
DT = 8.65e-6          # s, 0.2 * Rayleigh time (4.3269e-5 s)
LATTICES = {1000: (10, 10, 10), 10000: (25, 25, 16), 100000: (50, 50, 40),
            1000000: (100, 100, 100), 10000000: (200, 200, 250)}


def rayleigh_time(radius, rho=RHO, young=1.0e7, nu=0.3):
    g = young / (2 * (1 + nu))
    return math.pi * radius * math.sqrt(rho / g) / (0.1631 * nu + 0.8766)


def main():
    n, steps, out = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
    if n not in LATTICES:
        sys.exit('make_bench.py: N must be one of %s' % sorted(LATTICES))
    assert DT <= 0.2 * rayleigh_time(R)
    nx, ny, nz = LATTICES[n]
    L, H = nx * PITCH, (nz + 1) * PITCH
    os.makedirs(out, exist_ok=True)
    rng = random.Random(1)
    pts = []
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                pts.append([PITCH / 2 + PITCH * q + rng.uniform(-JITTER, JITTER) for q in (i, j, k)])
    with open(os.path.join(out, 'particles.csv'), 'w') as f:
        f.write('# make_bench.py %d: lattice %dx%dx%d, pitch 1.05 d, jitter 0.02 R\n' % (n, nx, ny, nz))
        f.write('id,x,y,z,vx,vy,vz,wx,wy,wz,radius\n')
        for i, p in enumerate(pts):
            f.write('%d,%.10g,%.10g,%.10g,0,0,0,0,0,0,%g\n' % (i + 1, p[0], p[1], p[2], R))
    with open(os.path.join(out, 'particles.data'), 'w') as f:
        f.write('make_bench.py %d: d = 1 mm spheres, 2500 kg/m^3\n\n%d atoms\n1 atom types\n\n' % (n, n))
        f.write('0 %.10g xlo xhi\n0 %.10g ylo yhi\n0 %.10g zlo zhi\n\nAtoms\n\n' % (L, L, H))
        for i, p in enumerate(pts):
            f.write('%d 1 %g %g %.10g %.10g %.10g\n' % (i + 1, D, RHO, p[0], p[1], p[2]))
    with open(os.path.join(out, 'box.txt'), 'w') as f:
        f.write('%.10g %.10g\n' % (L, H))
    walls = [((0, 0, 0), (0, 0, 1)), ((0, 0, 0), (1, 0, 0)), ((L, 0, 0), (-1, 0, 0)),
             ((0, 0, 0), (0, 1, 0)), ((0, L, 0), (0, -1, 0))]
    with open(os.path.join(out, 'scene.toml'), 'w') as f:
        f.write('# The issue-7 benchmark scene, %d particles (make_bench.py). Run:\n'
                '#   ppohdem simulate scene.toml --engine reference\n' % n)
        f.write('[simulation]\ndt = %g\nsteps = %d\ngravity = [0.0, 0.0, -9.81]\n\n' % (DT, steps))
        f.write('[material]\ndensity = 2500.0\nyoung = 1.0e7\npoisson = 0.3\nrestitution = 0.5\n'
                'friction = 0.5\n\n[contact]\nmodel = "hertz-mindlin"\n\n')
        f.write('[particles]\nfile = "particles.csv"\n\n')
        for p, nrm in walls:
            f.write('[[wall]]\npoint = [%.10g, %.10g, %.10g]\nnormal = [%g, %g, %g]\n' % (p + nrm))
        f.write('\n[output]\ndir = "ours_out"\nevery = 0\nprogress = false\n')


if __name__ == '__main__':
    main()
