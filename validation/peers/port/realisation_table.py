#!/usr/bin/python3
"""The peers' observables against two yardsticks (docs/port-validation.md, "Other codes").

    /usr/bin/python3 validation/peers/port/realisation_table.py REALISATIONS.csv MEMBERS.csv \
        LABEL=OBSERVABLES.csv ...

REALISATIONS.csv: ppohdem's runs of the settling bed from other lattice jitters
(realisations.sh); MEMBERS.csv: the shipped one-ulp ensemble
(fixtures/port-baseline/settling_bed.members.csv); each OBSERVABLES.csv: a code's three runs
(img/port_observables_settling_bed.csv beside its --external report). For each observable at
the last observable time: the one-ulp ensemble's mean and sd, the realisations' mean and sd,
and each code's mean over its runs standardised both ways: z1 by the one-ulp ensemble (what
the port check sees), zR by the realisations (is it a possible outcome of the same physics
from another start?). The last row counts the observables with |zR| > 3.
"""
import csv
import math
import sys


def read(path):
    with open(path) as f:
        rows = [r for r in csv.reader(line for line in f if not line.startswith('#'))]
    header, body = rows[0], rows[1:]
    return header, body


def columns(path, skip=()):
    header, body = read(path)
    out = {}
    for k, name in enumerate(header):
        if name in skip:
            continue
        out[name] = [float(r[k]) for r in body]
    return out


def stats(values):
    n = len(values)
    mean = sum(values) / n
    sd = math.sqrt(sum((v - mean) ** 2 for v in values) / (n - 1)) if n > 1 else float('nan')
    return mean, sd


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    real = columns(sys.argv[1])
    members = columns(sys.argv[2], skip=('seed', 'role'))
    codes = []
    for arg in sys.argv[3:]:
        label, _, path = arg.partition('=')
        codes.append((label, columns(path)))
    last = max(int(n.split('@')[1]) for n in real)
    names = [n for n in real if n.endswith('@%d' % last) and n in members]
    nreal = len(next(iter(real.values())))
    print('Observables at step %d; one-ulp ensemble: %d members; realisations: %d lattice jitters; '
          'each code: the mean of its runs as z1 (by the one-ulp sd) / zR (by the realisations\' mean and sd).\n'
          % (last, len(next(iter(members.values()))), nreal))
    head = '| observable | one-ulp mean (sd) | realisations mean (sd) | one-ulp mean as zR |'
    head += ''.join(' %s z1 / zR |' % label for label, _ in codes)
    print(head)
    print('|---' * (4 + len(codes)) + '|')
    beyond = [0] * len(codes)
    for name in names:
        m_mean, m_sd = stats(members[name])
        r_mean, r_sd = stats(real[name])
        cells = [name.split('@')[0], '%.6g (%.2g)' % (m_mean, m_sd), '%.6g (%.2g)' % (r_mean, r_sd),
                 '%+.2f' % ((m_mean - r_mean) / r_sd)]
        for k, (label, obs) in enumerate(codes):
            c_mean = sum(obs[name]) / len(obs[name])
            z1, zr = (c_mean - m_mean) / m_sd, (c_mean - r_mean) / r_sd
            beyond[k] += abs(zr) > 3
            cells.append('%+.1f / %+.2f' % (z1, zr))
        print('| ' + ' | '.join(cells) + ' |')
    print('| observables with \\|zR\\| > 3 | | | |' + ''.join(' %d of %d |' % (b, len(names)) for b in beyond))


if __name__ == '__main__':
    main()
