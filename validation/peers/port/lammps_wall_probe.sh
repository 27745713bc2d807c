#!/bin/sh
# LAMMPS's fix wall/gran law, measured with one sphere (docs/port-validation.md, "Other codes"):
# a sphere (R = 1 mm, 2500 kg/m^3) settles on the floor for 20,000 steps (the resting overlap
# gives the wall's E*), then gets vx = 1e-5 m/s: it rolls and oscillates on the tangential
# spring at omega^2 = k_t (7/2) / m (the spring at the contact point of a free sphere), far
# below sliding (the spring force ~3e-7 N against mu F_n ~5e-5 N); the period gives k_t / a.
#   validation/peers/port/lammps_wall_probe.sh SCRATCH ["WALL_E WALL_KT"]
# Without the 2nd argument the deck's walls are LAMMPS's own (E 1e7, k_t NULL).
set -eu
scratch=$1
wall=${2:-"1.0e7 NULL"}
set -- $wall
mkdir -p "$scratch"
cd "$scratch"
cat > one.data <<'DATA'
one sphere

1 atoms
1 atom types

0 0.02 xlo xhi
0 0.02 ylo yhi
0 0.01 zlo zhi

Atoms

1 1 0.002 2500 0.01 0.01 0.00099
DATA
cat > in.probe <<DECK
units si
atom_style sphere
atom_modify map array
boundary f f f
newton off
comm_modify vel yes
read_data one.data
neighbor 2.0e-4 bin
pair_style granular
pair_coeff * * hertz/material 1.0e7 0.29641845 0.3 tangential mindlin NULL 0.0 0.5 damping tsuji limit_damping
fix zw all wall/gran granular hertz/material $1 0.29641845 0.3 tangential mindlin $2 0.0 0.5 damping tsuji limit_damping zplane 0.0 NULL
fix grav all gravity 9.81 vector 0.0 0.0 -1.0
fix integ all nve/sphere
timestep 1.0e-5
variable zz equal z[1]
thermo_style custom step v_zz
thermo_modify format float %.15g
thermo 20000
run 20000
velocity all set 1.0e-5 0.0 0.0
variable vx equal vx[1]
thermo_style custom step v_vx
thermo_modify format float %.15g
thermo 1
run 400
DECK
lmp -log none -in in.probe > probe.out 2>&1
/usr/bin/python3 - <<'PY'
import math
lines = open('probe.out').read().splitlines()
blocks, cur = [], None
for line in lines:
    if line.split()[:2] in (['Step', 'v_zz'], ['Step', 'v_vx']):
        cur = []
        blocks.append(cur)
    elif line.startswith('Loop'):
        cur = None
    elif cur is not None:
        cur.append([float(x) for x in line.split()])
E, nu, R, rho, g = 1.0e7, 0.3, 1.0e-3, 2500.0, 9.81
m = rho * 4.0 / 3.0 * math.pi * R ** 3
delta = R - blocks[0][-1][1]
estar = m * g / (4.0 / 3.0 * math.sqrt(R) * delta ** 1.5)
v = [row[1] for row in blocks[1]]
mean = sum(v) / len(v)
v = [x - mean for x in v]
crossings = [k + v[k] / (v[k] - v[k + 1]) for k in range(len(v) - 1) if v[k] * v[k + 1] < 0]
period = 2.0 * (crossings[-1] - crossings[0]) / (len(crossings) - 1) * 1.0e-5
kt = (2.0 * math.pi / period) ** 2 * m * 2.0 / 7.0
print('resting overlap %.6g m: wall E* = %.6g Pa (E/(2(1-nu^2)) = %.6g, E/(2(1-nu)) = %.6g)'
      % (delta, estar, E / (2 * (1 - nu * nu)), E / (2 * (1 - nu))))
print('tangential period %.6g s: k_t / a = %.6g Pa (8 G* = %.6g, E (2-nu)(1+nu)/4 = %.6g)'
      % (period, kt / math.sqrt(R * delta), 2 * E / ((1 + nu) * (2 - nu)), E * (2 - nu) * (1 + nu) / 4))
PY
