#!/usr/bin/python3
"""Per-phase table of ci/bench-dem.sh: the best (and median) wall time of each phase of each
code over the interleaved rounds, and LIGGGHTS' 1-core time of the same phase over it
(> 1: faster than LIGGGHTS on 1 core).

    /usr/bin/python3 validation/peers/phase_table.py phases.tsv

phases.tsv: code, N, cores, round, phase, first_step, last_step, seconds (one row per phase
of every run)."""
import collections
import csv
import statistics
import sys

# The standard settling bed's phases (ci/bench-dem.sh default --phases 500,2500,6000).
NAMES = {(0, 500): 'free fall', (500, 2500): 'impact', (2500, 6000): 'dense settling',
         (6000, 10000): 'settled bed'}


def main():
    rows = collections.defaultdict(list)
    order = []
    with open(sys.argv[1], newline='') as f:
        for r in csv.DictReader(f, delimiter='\t'):
            key = (r['code'], int(r['N']), int(r['cores']), int(r['first_step']), int(r['last_step']))
            if key not in rows:
                order.append(key)
            rows[key].append(float(r['seconds']))
    print('Per phase, over the rounds (wall seconds of the phase; ratio = LIGGGHTS on 1 core / this '
          'code, best against best and median against median):')
    print()
    print('| phase | steps | code | N | cores | runs | best [s] | median [s] | best vs LIGGGHTS 1 core '
          '| median vs LIGGGHTS 1 core |')
    print('|---|---|---|---|---|---|---|---|---|---|')
    for key in sorted(order, key=lambda k: (k[1], k[3], order.index(k))):
        code, n, cores, first, last = key
        t = rows[key]
        lig = rows.get(('liggghts', n, 1, first, last))
        best_ratio = '%.2f' % (min(lig) / min(t)) if lig else '-'
        median_ratio = '%.2f' % (statistics.median(lig) / statistics.median(t)) if lig else '-'
        print('| %s | %d-%d | %s | %d | %d | %d | %.4f | %.4f | %s | %s |' % (
            NAMES.get((first, last), 'phase'), first, last, code, n, cores, len(t), min(t),
            statistics.median(t), best_ratio, median_ratio))


if __name__ == '__main__':
    main()
