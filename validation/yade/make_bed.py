#!/usr/bin/python3
"""Initial conditions of the YADE-comparison settling bed (plain Python, no YADE needed).

    /usr/bin/python3 validation/yade/make_bed.py [OUT_DIR]     (default: fixtures/yade)

1,000 spheres of radius R = 1 mm on a 10 x 10 x 10 simple-cubic lattice of pitch 1.05 d
(d = 2R) in a 21 mm x 21 mm open-top box (walls at x, y = 0 and 21 mm, floor z = 0), each
centre displaced by a uniform random jitter of +/-0.04 R per axis (so no two spheres touch:
the closest pair along an axis is 0.1 R - 2 * 0.04 R = 0.02 R apart), at rest. Three seeds
(1, 2, 3) give the three runs whose spread sets the tolerance of the comparison.
Python's random.Random (Mersenne Twister) is reproducible across versions for random().
Writes bed_seed{1,2,3}.csv in ppohdem's particle CSV format (docs/dem.md):
id,x,y,z,vx,vy,vz,wx,wy,wz,radius.
"""
import os
import random
import sys

R = 1.0e-3           # m
PITCH = 1.05 * 2 * R  # m
N_AXIS = 10
JITTER = 0.04 * R    # m


def write(path, seed):
    rng = random.Random(seed)
    tmp = path + '.tmp'
    with open(tmp, 'w') as f:
        f.write('# settling bed for the YADE comparison: make_bed.py seed %d (R = 1 mm, pitch 1.05 d, '
                'jitter 0.04 R)\n' % seed)
        f.write('id,x,y,z,vx,vy,vz,wx,wy,wz,radius\n')
        n = 0
        for k in range(N_AXIS):
            for j in range(N_AXIS):
                for i in range(N_AXIS):
                    n += 1
                    c = [PITCH / 2 + PITCH * q + rng.uniform(-JITTER, JITTER) for q in (i, j, k)]
                    f.write('%d,%.12g,%.12g,%.12g,0,0,0,0,0,0,%.12g\n' % (n, c[0], c[1], c[2], R))
    os.replace(tmp, path)


if __name__ == '__main__':
    here = os.path.dirname(os.path.abspath(__file__))
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, '..', '..', 'fixtures', 'yade')
    os.makedirs(out, exist_ok=True)
    for seed in (1, 2, 3):
        write(os.path.join(out, 'bed_seed%d.csv' % seed), seed)
