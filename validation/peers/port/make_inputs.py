#!/usr/bin/python3
"""A ppohdem particle CSV (an exported port scene's start, perturbed) as the peers' inputs.

    /usr/bin/python3 validation/peers/port/make_inputs.py START.csv OUT_DIR

START.csv is a ppohdem particle file, e.g. frame_000000.csv of
`ppohdem simulate scenes/settling_bed/scene.toml --steps 0 --perturb-seed K --output-dir D`
(docs/port-validation.md, "Other codes"). Writes into OUT_DIR:
  particles.data  LAMMPS / LIGGGHTS data file (atom_style sphere / granular:
                  id type diameter density x y z), coordinates with 17 significant digits so
                  that the one-ulp perturbation survives (%.17g round-trips a double)
  particles.csv   the same particles as a ppohdem CSV (YADE's deck reads it)
"""
import os
import sys

DENSITY = 2500.0      # kg/m^3, the settling_bed scene's [material] density
BOX_SIDE = 0.02       # m, the side walls at x, y = 0 and 0.02 (the scene's [[wall]] entries)


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    start, out = sys.argv[1], sys.argv[2]
    rows = []
    with open(start) as f:
        header = None
        for number, line in enumerate(f, 1):
            if line.startswith('#') or not line.strip():
                continue
            if header is None:
                header = line.strip().split(',')
                if header[:4] != ['id', 'x', 'y', 'z'] or header[-1] != 'radius':
                    sys.exit('%s:%d: expected the header id,x,y,z,...,radius, found %s' % (start, number, line.strip()))
                continue
            v = line.strip().split(',')
            if len(v) != len(header):
                sys.exit('%s:%d: expected %d values, found %d' % (start, number, len(header), len(v)))
            rows.append((int(v[0]), float(v[1]), float(v[2]), float(v[3]), float(v[-1])))
    if not rows:
        sys.exit('%s: no particles' % start)
    os.makedirs(out, exist_ok=True)
    top = max(z + r for _, _, _, z, r in rows)
    with open(os.path.join(out, 'particles.data'), 'w') as f:
        # The LAMMPS box (boundary f f f) only has to hold the particles: 2x the top, nothing
        # rises that far in a bed released from rest.
        f.write('ppohdem port scene start %s\n\n%d atoms\n1 atom types\n\n' % (os.path.basename(start), len(rows)))
        f.write('0 %.17g xlo xhi\n0 %.17g ylo yhi\n0 %.17g zlo zhi\n\nAtoms\n\n' % (BOX_SIDE, BOX_SIDE, 2 * top))
        for pid, x, y, z, r in rows:
            f.write('%d 1 %.17g %.17g %.17g %.17g %.17g\n' % (pid, 2 * r, DENSITY, x, y, z))
    with open(os.path.join(out, 'particles.csv'), 'w') as f:
        f.write('id,x,y,z,vx,vy,vz,wx,wy,wz,radius\n')
        for pid, x, y, z, r in rows:
            f.write('%d,%.17g,%.17g,%.17g,0,0,0,0,0,0,%.17g\n' % (pid, x, y, z, r))


if __name__ == '__main__':
    main()
