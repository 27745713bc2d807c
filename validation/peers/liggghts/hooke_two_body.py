#!/usr/bin/python3
"""Two-body collisions with LIGGGHTS' `model hooke` and ppohdem's `model = "hooke"` (issue 38).

    /usr/bin/python3 validation/peers/liggghts/hooke_two_body.py [--ppohdem build/apps/ppohdem]
                                                                 [--liggghts liggghts]

Runs each case below in both codes (LIGGGHTS-PUBLIC 3.8, Debian `liggghts`; ppohdem's
reference engine) and prints the rebound velocities and spins of the two bodies and their
largest difference relative to the impact speed. Cases: two spheres head-on and oblique
(30 degrees), a sphere on a plane wall at 30 and 45 degrees, the tangential dashpot on
(LIGGGHTS' default for hooke) and off, Coulomb mu = 0.3..10. Material: rho = 2500 kg/m^3,
E = 1e7 Pa, nu = 0.3, e = 0.5, R = 0.5 mm, impact speed 0.1 m/s, v_c = 0.1 m/s; dt = 1e-7 s
(about 1,700 steps per contact). Exit status 1 if a difference exceeds --tolerance.

What differs by design (docs/dem.md "Hooke, materials with the linear law"): LIGGGHTS caps the
tangential spring alone and adds the dashpot only while the contact sticks, ppohdem caps the
total; LIGGGHTS' dashpots use v(n+1/2), ppohdem's the predicted v(n+1); LIGGGHTS projects the
spring onto the tangent plane, ppohdem rotates it keeping its length.
"""
import argparse
import math
import os
import subprocess
import sys
import tempfile

R = 0.5e-3      # m
RHO = 2500.0    # kg/m^3
E = 1.0e7       # Pa
NU = 0.3
REST = 0.5
V = 0.1         # m/s, impact speed
VC = 0.1        # m/s, characteristic velocity
DT = 1.0e-7     # s
STEPS = 15000


def cases():
    """(name, bodies, wall, mu, damping); bodies: [(x, v)]; wall: None, or the impact angle on
    the plane z = 0 [deg]."""
    out = []
    for mu, damping in ((0.5, True), (0.5, False), (10.0, True), (10.0, False)):
        # Spheres approaching along x, offset b = R in y: impact angle asin(b / 2R) = 30 deg.
        x_gap = 1.8 * R
        out.append(('pair oblique 30deg mu=%g %s' % (mu, 'damped' if damping else 'undamped'),
                    [((-x_gap / 2, -R / 2, 0.0), (V / 2, 0, 0)), ((x_gap / 2, R / 2, 0.0), (-V / 2, 0, 0))],
                    None, mu, damping))
    out.insert(0, ('pair head-on mu=0.5 damped',
                   [((-1.05 * R, 0, 0), (V / 2, 0, 0)), ((1.05 * R, 0, 0), (-V / 2, 0, 0))], None, 0.5, True))
    for angle, mu in ((30.0, 10.0), (45.0, 0.3)):
        a = math.radians(angle)
        for damping in (True, False):
            out.append(('wall %gdeg mu=%g %s' % (angle, mu, 'damped' if damping else 'undamped'),
                        [((0, 0, 1.02 * R), (V * math.sin(a), 0, -V * math.cos(a)))], angle, mu, damping))
    return out


def liggghts_deck(bodies, wall, mu, damping, dump):
    td = 'on' if damping else 'off'
    lines = [
        'units si', 'atom_style granular', 'atom_modify map array', 'boundary f f f', 'newton off',
        'communicate single vel yes',
        'region box block -0.005 0.005 -0.005 0.005 -0.005 0.005 units box', 'create_box 1 box',
        'neighbor 1.0e-4 bin', 'neigh_modify delay 0',
        'fix m1 all property/global youngsModulus peratomtype %r' % E,
        'fix m2 all property/global poissonsRatio peratomtype %r' % NU,
        'fix m3 all property/global coefficientRestitution peratomtypepair 1 %r' % REST,
        'fix m4 all property/global coefficientFriction peratomtypepair 1 %r' % mu,
        'fix m5 all property/global characteristicVelocity scalar %r' % VC,
        'pair_style gran model hooke tangential history tangential_damping %s' % td,
        'pair_coeff * *',
    ]
    for k, (x, v) in enumerate(bodies, start=1):
        lines += ['create_atoms 1 single %r %r %r units box' % x,
                  'set atom %d diameter %r density %r' % (k, 2 * R, RHO),
                  'group g%d id %d' % (k, k),
                  'velocity g%d set %r %r %r units box' % ((k,) + v)]
    if wall:
        lines.append('fix w all wall/gran model hooke tangential history primitive type 1 zplane 0.0 '
                     'tangential_damping %s' % td)
    lines += ['fix integ all nve/sphere', 'timestep %r' % DT,
              'dump d all custom %d %s id x y z vx vy vz omegax omegay omegaz' % (STEPS, dump),
              'dump_modify d sort id', 'run %d' % STEPS]
    return '\n'.join(lines) + '\n'


def ppohdem_scene(bodies, wall, mu, damping, csv, out):
    rows = ['id,x,y,z,vx,vy,vz,wx,wy,wz,radius']
    for k, (x, v) in enumerate(bodies, start=1):
        rows.append(','.join([str(k)] + [repr(float(c)) for c in tuple(x) + tuple(v) + (0, 0, 0, R)]))
    with open(csv, 'w') as f:
        f.write('\n'.join(rows) + '\n')
    text = ('[simulation]\ndt = %r\nsteps = %d\n' % (DT, STEPS) +
            '[material]\ndensity = %r\nyoung = %r\npoisson = %r\nrestitution = %r\nfriction = %r\n'
            % (RHO, E, NU, REST, mu) +
            '[contact]\nmodel = "hooke"\ncharacteristic_velocity = %r\ntangential_damping = %s\n'
            % (VC, 'true' if damping else 'false') +
            '[particles]\nfile = "%s"\n' % os.path.basename(csv))
    if wall:
        text += '[[wall]]\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\n'
    text += '[output]\ndir = "%s"\nevery = %d\nformats = ["csv"]\n' % (os.path.basename(out), STEPS)
    return text


def wall_model(angle, mu, damping, liggghts_rules, dt=1.0e-8):
    """Reduced model of a sphere on the plane z = 0 (x-z plane, explicit Euler at dt): the hooke
    normal force, a tangential spring k_t = k_n and dashpot gamma_t = gamma_n, with either
    ppohdem's rules (total force capped at mu max(F_n, 0), lever arm R - delta) or LIGGGHTS'
    (spring capped at mu |F_n|, dashpot only while sticking, lever arm R - delta/2).
    Returns the rebound (v_x, R w_y) [m/s]."""
    m = RHO * 4.0 / 3.0 * math.pi * R ** 3
    inertia = 0.4 * m * R * R
    e_star = E / (2.0 * (1.0 - NU * NU))
    k = 16.0 / 15.0 * math.sqrt(R) * e_star * (15.0 * m * VC * VC / (16.0 * math.sqrt(R) * e_star)) ** 0.2
    ln_e = math.log(REST)
    gamma = 2.0 * math.sqrt(m * k) * (-ln_e) / math.sqrt(math.pi ** 2 + ln_e ** 2)
    gamma_t = gamma if damping else 0.0
    a = math.radians(angle)
    vx, vz, z, w, xi = V * math.sin(a), -V * math.cos(a), R, 0.0, 0.0
    while not (z > R and vz > 0.0):
        d = R - z
        fn = ft = 0.0
        lever = z
        if d > 0.0:
            fn = k * d - gamma * vz
            lever = R - 0.5 * d if liggghts_rules else z
            u = vx - w * lever
            xi += u * dt
            spring = -k * xi
            if liggghts_rules:
                cap = mu * abs(fn)
                if abs(spring) > cap:  # slides: the spring at the cap, no dashpot
                    ft = math.copysign(cap, spring)
                    xi = -ft / k
                else:
                    ft = spring - gamma_t * u
            else:
                cap = mu * max(fn, 0.0)
                ft = spring - gamma_t * u
                if abs(ft) > cap:  # slides: the total at the cap, carried by the spring
                    ft = math.copysign(cap, ft)
                    xi = -ft / k
        else:
            xi = 0.0
        vx += ft / m * dt
        vz += fn / m * dt
        w -= lever * ft / inertia * dt
        z += vz * dt
    return vx, w * R


def read_liggghts(dump):
    with open(dump) as f:
        snap = f.read().split('ITEM: TIMESTEP')[-1].splitlines()
    i = next(k for k, l in enumerate(snap) if l.startswith('ITEM: ATOMS'))
    cols = snap[i].split()[2:]
    rows = [dict(zip(cols, map(float, l.split()))) for l in snap[i + 1:] if l.strip()]
    return [(r['vx'], r['vy'], r['vz'], r['omegax'], r['omegay'], r['omegaz']) for r in rows]


def read_ppohdem(final):
    with open(final) as f:
        lines = [l for l in f.read().splitlines() if l.strip() and not l.startswith('#')]
    cols = lines[0].split(',')
    rows = [dict(zip(cols, map(float, l.split(',')))) for l in lines[1:]]
    return [(r['vx'], r['vy'], r['vz'], r['wx'], r['wy'], r['wz']) for r in rows]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--ppohdem', default='build/apps/ppohdem')
    ap.add_argument('--liggghts', default='liggghts')
    ap.add_argument('--tolerance', type=float, default=2e-3,
                    help='head-on difference and model differences, relative to the impact speed')
    args = ap.parse_args()
    worst_head_on = 0.0
    worst_model = 0.0
    table = ['| case | LIGGGHTS v_x, v_y, v_z; R w | ppohdem v_x, v_y, v_z; R w | largest difference / v |'
             ' model, LIGGGHTS rules | model, ppohdem rules |', '|' + '---|' * 6]
    with tempfile.TemporaryDirectory(prefix='hooke_two_body_') as tmp:
        for n, (name, bodies, wall, mu, damping) in enumerate(cases()):
            d = os.path.join(tmp, 'case%d' % n)
            os.makedirs(d)
            dump = os.path.join(d, 'liggghts.dump')
            with open(os.path.join(d, 'in.case'), 'w') as f:
                f.write(liggghts_deck(bodies, wall, mu, damping, dump))
            subprocess.run([args.liggghts, '-in', 'in.case', '-log', 'none', '-screen', 'none'], cwd=d, check=True)
            with open(os.path.join(d, 'scene.toml'), 'w') as f:
                f.write(ppohdem_scene(bodies, wall, mu, damping, os.path.join(d, 'p.csv'), os.path.join(d, 'out')))
            subprocess.run([os.path.abspath(args.ppohdem), 'simulate', 'scene.toml', '--quiet', '--force',
                            '--engine', 'reference'], cwd=d, check=True, stdout=subprocess.DEVNULL,
                           stderr=subprocess.DEVNULL)
            lig = read_liggghts(dump)[0]
            ppo = read_ppohdem(os.path.join(d, 'out', 'final.csv'))[0]
            spin = 4 if wall is not None else 5  # the spin axis: y for the wall (x-z plane), z for the pair
            diff = max(max(abs(p - q) for p, q in zip(lig[:3], ppo[:3])), abs(lig[spin] - ppo[spin]) * R) / V
            cells = ['%+.5f, %+.5f, %+.5f; %+.5f' % (t[0], t[1], t[2], t[spin] * R) for t in (lig, ppo)]
            models = ['', '']
            if wall is not None:
                for k, rules in enumerate((True, False)):
                    vx, wr = wall_model(wall, mu, damping, rules)
                    models[k] = 'v_x %+.5f; R w %+.5f' % (vx, wr)
                    code = lig if rules else ppo
                    worst_model = max(worst_model, abs(vx - code[0]) / V, abs(wr - code[spin] * R) / V)
            if 'head-on' in name:
                worst_head_on = max(worst_head_on, diff)
            table.append('| %s | %s | %s | %.1e | %s | %s |' % (name, cells[0], cells[1], diff, models[0], models[1]))
    print('\n'.join(table))
    print('head-on: largest difference %.2e of v; wall cases: each code against the reduced model with its own'
          ' rules: largest difference %.2e of v (tolerance %.1e)' % (worst_head_on, worst_model, args.tolerance))
    return 0 if max(worst_head_on, worst_model) <= args.tolerance else 1


if __name__ == '__main__':
    sys.exit(main())
