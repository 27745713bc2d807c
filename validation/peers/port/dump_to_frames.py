#!/usr/bin/python3
"""A LAMMPS / LIGGGHTS custom dump as ppohdem frames (docs/port-validation.md, "Other codes").

    /usr/bin/python3 validation/peers/port/dump_to_frames.py DUMP OUT_DIR "COMMENT"

DUMP is written by `dump ... custom N FILE id x y z vx vy vz omegax omegay omegaz radius`
(any column order; the columns are found by name). Each snapshot becomes
OUT_DIR/frame_NNNNNN.csv (NNNNNN = the dump's TIMESTEP, six digits or more) with the header
id,x,y,z,vx,vy,vz,wx,wy,wz,radius, rows sorted by id, values with 17 significant digits.
"""
import os
import sys

COLUMNS = ['id', 'x', 'y', 'z', 'vx', 'vy', 'vz', 'omegax', 'omegay', 'omegaz', 'radius']


def write_frame(out, step, rows, comment):
    path = os.path.join(out, 'frame_%06d.csv' % step)
    tmp = path + '.tmp'
    with open(tmp, 'w') as f:
        f.write('# %s; step %d\n' % (comment, step))
        f.write('id,x,y,z,vx,vy,vz,wx,wy,wz,radius\n')
        for row in sorted(rows, key=lambda r: int(r[0])):
            f.write(row[0] + ',' + ','.join('%.17g' % float(v) for v in row[1:]) + '\n')
    os.replace(tmp, path)


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    dump, out, comment = sys.argv[1:]
    os.makedirs(out, exist_ok=True)
    with open(dump) as f:
        lines = f.read().splitlines()
    i, frames = 0, 0
    while i < len(lines):
        if lines[i].startswith('ITEM: TIMESTEP'):
            step = int(lines[i + 1])
            i += 2
        elif lines[i].startswith('ITEM: NUMBER OF ATOMS'):
            count = int(lines[i + 1])
            i += 2
        elif lines[i].startswith('ITEM: BOX BOUNDS'):
            i += 4
        elif lines[i].startswith('ITEM: ATOMS'):
            names = lines[i].split()[2:]
            missing = [c for c in COLUMNS if c not in names]
            if missing:
                sys.exit('%s:%d: expected the columns %s, missing %s' % (dump, i + 1, ' '.join(COLUMNS), ' '.join(missing)))
            where = [names.index(c) for c in COLUMNS]
            rows = []
            for k in range(count):
                v = lines[i + 1 + k].split()
                if len(v) != len(names):
                    sys.exit('%s:%d: expected %d values, found %d' % (dump, i + 2 + k, len(names), len(v)))
                rows.append([v[w] for w in where])
            write_frame(out, step, rows, comment)
            frames += 1
            i += 1 + count
        else:
            sys.exit('%s:%d: expected an ITEM: line, found %r' % (dump, i + 1, lines[i][:60]))
    print('%s: %d frames into %s' % (dump, frames, out))


if __name__ == '__main__':
    main()
