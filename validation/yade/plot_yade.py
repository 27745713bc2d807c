#!/usr/bin/python3
"""Plots of the YADE comparison (called by yade_checks.cpp after the rows are computed).

    /usr/bin/python3 validation/yade/plot_yade.py WORK_DIR YADE_DIR IMG_DIR [ENGINE]

WORK_DIR holds ours_*_<ENGINE>.csv written by yade_checks.cpp, YADE_DIR the YADE outputs
(fixtures/yade or a live rerun). Writes yade_two_spheres.png, yade_oblique_wall.png,
yade_belt.png and yade_settling_bed.png into IMG_DIR.
"""
import os
import sys

import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def load(path):
    # '#' provenance lines first (np.genfromtxt would take a leading comment as the header)
    with open(path) as f:
        lines = [l for l in f if l.strip() and not l.startswith('#')]
    return np.genfromtxt(lines, delimiter=',', names=True)


def main():
    work, yade, img = sys.argv[1:4]
    eng = sys.argv[4] if len(sys.argv) > 4 else 'reference'

    o = load(os.path.join(work, 'ours_two_spheres_%s.csv' % eng))
    y = load(os.path.join(yade, 'yade_two_spheres_series.csv'))
    fig, ax = plt.subplots(figsize=(5.5, 4))
    m = o['overlap'] > 0
    ax.plot(o['overlap'][m] * 1e6, o['force'][m] * 1e3, '-', label='ppohdem (%s)' % eng)
    m = y['overlap'] > 0
    ax.plot(y['overlap'][m] * 1e6, y['force'][m] * 1e3, '--', label='YADE 2023.02a')
    ax.set_xlabel('overlap [um]')
    ax.set_ylabel('normal force [mN]')
    ax.set_title('Two spheres, e = 0.5, 0.1 m/s: force-overlap loop')
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(img, 'yade_two_spheres.png'), dpi=110)

    o = load(os.path.join(work, 'ours_oblique_%s.csv' % eng))
    fig, axs = plt.subplots(1, 2, figsize=(9, 3.8))
    axs[0].plot(o['angle_deg'], o['vt_ours'], 'o-', label='ppohdem v_t')
    axs[0].plot(o['angle_deg'], o['vt_yade'], 'x--', label='YADE v_t')
    axs[0].plot(o['angle_deg'], o['vn_ours'], 's-', label='ppohdem v_n')
    axs[0].plot(o['angle_deg'], o['vn_yade'], '+--', label='YADE v_n')
    axs[0].set_xlabel('incidence angle [deg]')
    axs[0].set_ylabel('rebound velocity [m/s]')
    axs[0].legend(fontsize=8)
    axs[1].plot(o['angle_deg'], o['omega_ours'], 'o-', label='ppohdem')
    axs[1].plot(o['angle_deg'], o['omega_yade'], 'x--', label='YADE')
    axs[1].set_xlabel('incidence angle [deg]')
    axs[1].set_ylabel('rebound spin [rad/s]')
    axs[1].legend(fontsize=8)
    fig.suptitle('Alumina sphere on a wall, 3.9 m/s, mu = 0.092 (Chung & Ooi test 4 material)')
    fig.tight_layout()
    fig.savefig(os.path.join(img, 'yade_oblique_wall.png'), dpi=110)

    o = load(os.path.join(work, 'ours_belt_%s.csv' % eng))
    fig, ax = plt.subplots(figsize=(5.5, 4))
    ax.plot(o['time'] * 1e3, o['vx_ours'], '-', label='ppohdem (%s)' % eng)
    ax.plot(o['time'] * 1e3, o['vx_yade'], '--', label='YADE 2023.02a')
    ax.axhline(0.2 / 7, color='k', lw=0.8, label='rigid body 2V/7')
    ax.set_xlabel('time [ms]')
    ax.set_ylabel('sphere velocity v_x [m/s]')
    ax.set_title('Sphere on a floor moving at V = 0.1 m/s')
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(img, 'yade_belt.png'), dpi=110)

    o = load(os.path.join(work, 'ours_bed_%s.csv' % eng))
    names = ['packing fraction', 'coordination number', 'potential energy [J]']
    fig, axs = plt.subplots(1, 3, figsize=(10, 3.4))
    for q in range(3):
        m = o['quantity'] == q
        axs[q].plot(o['seed'][m], o['ours'][m], 'o', label='ppohdem (%s)' % eng)
        axs[q].plot(o['seed'][m], o['yade'][m], 'x', ms=9, label='YADE')
        axs[q].set_xlabel('lattice jitter seed')
        axs[q].set_title(names[q], fontsize=10)
        axs[q].set_xticks([1, 2, 3])
    axs[0].legend(fontsize=8)
    fig.suptitle('Settling bed, 1,000 spheres: per-seed statistics')
    fig.tight_layout()
    fig.savefig(os.path.join(img, 'yade_settling_bed.png'), dpi=110)


if __name__ == '__main__':
    main()
