#!/usr/bin/python3
"""Physics cross-check of a benchmark run's final state, the same code for every DEM code.

    /usr/bin/python3 validation/peers/crosscheck.py FILE

FILE: a ppohdem/YADE particle CSV (id,x,y,z,vx,vy,vz,...,radius) or a LAMMPS/LIGGGHTS custom
dump (id x y z vx vy vz radius; the last snapshot is used). Prints one line
    n=N ke=J mean_z=m max_overlap_d=- contacts_pp=-
kinetic energy of translation sum m v^2/2 (m from rho = 2500 kg/m^3 and the radius), mean
centre height, largest particle-particle overlap over the diameter, and touching particle
pairs x 2 / N (walls excluded), all from positions and velocities.
"""
import sys

import numpy as np
from scipy.spatial import cKDTree


def load(path):
    with open(path) as f:
        text = f.read()
    if text.startswith('ITEM:'):
        snap = text.split('ITEM: TIMESTEP')[-1].splitlines()
        i = next(k for k, l in enumerate(snap) if l.startswith('ITEM: ATOMS'))
        cols = snap[i].split()[2:]
        a = np.array([[float(x) for x in l.split()] for l in snap[i + 1:] if l.strip()])
        return {c: a[:, k] for k, c in enumerate(cols)}
    lines = [l for l in text.splitlines() if l.strip() and not l.startswith('#')]
    cols = lines[0].split(',')
    a = np.array([[float(x) for x in l.split(',')] for l in lines[1:]])
    return {c: a[:, k] for k, c in enumerate(cols)}


def main():
    d = load(sys.argv[1])
    x = np.column_stack([d['x'], d['y'], d['z']])
    r = d['radius']
    m = 2500.0 * 4.0 / 3.0 * np.pi * r ** 3
    ke = float(np.sum(0.5 * m * (d['vx'] ** 2 + d['vy'] ** 2 + d['vz'] ** 2)))
    dia = 2.0 * float(np.max(r))
    pairs = cKDTree(x).query_pairs(dia, output_type='ndarray')
    if len(pairs):
        dist = np.linalg.norm(x[pairs[:, 0]] - x[pairs[:, 1]], axis=1)
        over = r[pairs[:, 0]] + r[pairs[:, 1]] - dist
        touching = over > 0
        max_over = float(np.max(over[touching])) / dia if touching.any() else 0.0
        ncont = int(np.sum(touching))
    else:
        max_over, ncont = 0.0, 0
    print('n=%d ke=%.5e mean_z=%.6e max_overlap_d=%.4e contacts_pp=%.4f' % (
        len(r), ke, float(np.mean(x[:, 2])), max_over, 2.0 * ncont / len(r)))


if __name__ == '__main__':
    main()
