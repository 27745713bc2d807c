#!/usr/bin/python3
"""The cost model of the fast engine on many nodes (docs/performance.md "Projection to many
nodes"): per-rank counts from `ppohdem project --csv` (the engine's own bricks and halo rule),
measured compute costs, and a stated network.

    /usr/bin/python3 validation/projection/scaling_model.py CSV [CSV ...] [--weak] [options]

One time step of rank r (the step ends in a collective, so the slowest rank sets the pace):

  T(P) = max_r [ c (n_r (1 + beta) + alpha g_r)                          compute
                + max(0, L m_r + b_r / B - c i_r) ]                      the halo refresh, exposed
       + ceil(log2 P) (L + S / B)                                         the step's one allreduce
       + [ 4 L p_r + g_r e / B + 4 ceil(log2 P) L + (P - 1) 4 / B ] / k   a list build every k steps

  n_r, g_r   owned particles and ghosts of rank r (the CSV); m_r = max(messages in, out) and
             b_r = max(bytes in, out) of the per-step refresh (one message per peer holding
             ghosts; 48 B per ghost: its owner's half kick); p_r peers (a build's ghost creation and migration each
             send a count and a block to every peer); e = 266 B per created ghost
  i_r        interior particles of rank r (no ghost partner; the CSV's `interior`): the engine
             posts the refresh before the drift and waits for it after the interior particles'
             pairs (docs/dem.md "Domain decomposition (MPI)"), so their compute hides it; c i_r
             counts their whole particle-step (the sum pass and closing kick come after the
             wait) but not the halo layer's drift (before it). --no-overlap (or a CSV without
             the column) charges the whole refresh, as the code did before.
  c          compute per particle-step on one rank here [s] (measured; --c)
  beta       extra compute per owned particle when the rank has ghosts (callgrind; --beta)
  alpha      extra compute per ghost (callgrind; --alpha)
  L, B       network latency per message [s] and bandwidth [B/s] (--latency, --bandwidth);
             messages are charged one after the other
  S          bytes of the step's allreduce (core/src/dem/fast/step_record.hpp, StepRecord):
             1,776 B with the energies tracked (counts, screen, the rates' 3 exact sums of 70
             words, the next drift's maximum, the deepest contact), 96 B untracked (--no-sums)
  k          steps per list build (--steps-per-build); a build adds 5 collectives to its
             step's one (counted by DemFastMpi.OneCollectiveAStepOn*Ranks): the migration's
             vote on a fallback to all ranks, the balance check's max and mean, the lost
             histories' allgather (a count and a block: 4 bytes a rank when none is lost); a
             re-cut's own bisection (18-37 more at 2-4 ranks, rare) is left out

Strong scaling: E(P) = c N / (P T(P)). Weak scaling (--weak: the CSV's beds hold the same
particles per rank): E(P) = c n / T(P), n the particles per rank.
Prints a markdown table per CSV.

--here CORES --steps S [--measured P:SECONDS,...]: the check on this machine instead: P ranks
share CORES cores (mpirun --oversubscribe), so the loop of S steps takes
  S max_r w_r (P <= CORES), or S sum_r w_r / CORES (P > CORES),  w_r = c (n_r (1 + beta) + alpha g_r);
the halo is copied through shared memory (at most 0.5 MB per rank per step on the check's bed,
neglected) and there are no list builds in the check's window.
"""
import argparse
import csv
import math
import sys
from collections import defaultdict

REFRESH_BYTES = 48       # per ghost per step (a half kick: 2 vectors of 3 doubles; ppohdem project prints it)
CREATION_BYTES = 266     # per ghost at its creation (ppohdem project prints it)
RECORD_BYTES = 8 * (1 + 4 + 3 * 70 + 1 + 6)   # StepRecord, energies tracked (dem_step_record_test)
RECORD_BYTES_UNTRACKED = 8 * (1 + 4 + 1 + 6)  # StepRecord, energies untracked
BUILD_COLLECTIVES = 5    # a list build's own, besides its step's allreduce (see k above)


def read_ranks(path):
    """{P: [row, ...]} from a `ppohdem project --csv` file."""
    by_p = defaultdict(list)
    with open(path) as f:
        for row in csv.DictReader(f):
            by_p[int(row['ranks'])].append({k: float(v) for k, v in row.items()})
    if not by_p:
        sys.exit('scaling_model.py: %s: no rows' % path)
    return by_p


def step_time(rows, p, a):
    """The model's time of one step on P ranks and its parts [s]."""
    lg = math.ceil(math.log2(p)) if p > 1 else 0
    ghosts = p > 1
    compute = halo = build = 0.0
    for r in rows:
        n, g = r['owned'], r['ghosts_in']
        work = a.c * (n * (1.0 + (a.beta if ghosts else 0.0)) + a.alpha * g)
        m = max(r['messages_in'], r['messages_out'])
        b = max(r['refresh_bytes_in'], r['refresh_bytes_out'])
        h = m * a.latency + b / a.bandwidth
        if a.overlap and 'interior' in r:
            h = max(0.0, h - a.c * r['interior'])
        bl = (4 * r['peers'] * a.latency + max(r['creation_bytes_in'], r['creation_bytes_out']) / a.bandwidth
              + BUILD_COLLECTIVES * lg * a.latency + (p - 1) * 4 / a.bandwidth) / a.steps_per_build
        if work + h + bl > compute + halo + build:
            compute, halo, build = work, h, bl
    record = RECORD_BYTES if a.sums else RECORD_BYTES_UNTRACKED
    collectives = lg * (a.latency + record / a.bandwidth)
    return compute + halo + build + collectives, compute, halo, build, collectives


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('csv', nargs='+')
    ap.add_argument('--weak', action='store_true', help='the beds hold the same particles per rank')
    ap.add_argument('--c', type=float, required=True, help='compute per particle-step on one rank [s]')
    ap.add_argument('--beta', type=float, default=0.04)
    ap.add_argument('--alpha', type=float, default=0.04)
    ap.add_argument('--latency', type=float, default=2.0e-6, help='per message [s]')
    ap.add_argument('--bandwidth', type=float, default=10.0e9, help='[B/s]')
    ap.add_argument('--steps-per-build', type=float, default=60.0)
    ap.add_argument('--no-sums', dest='sums', action='store_false', help='energies untracked')
    ap.add_argument('--no-overlap', dest='overlap', action='store_false',
                    help='charge the whole halo refresh (the code before the overlap)')
    ap.add_argument('--here', type=int, default=0, help='the check: ranks share this many cores')
    ap.add_argument('--steps', type=int, default=0, help='the check: steps of the measured loop')
    ap.add_argument('--measured', default='', help='the check: P:SECONDS,... measured loop times')
    a = ap.parse_args()
    if a.here:
        return check_here(a)
    for path in a.csv:
        by_p = read_ranks(path)
        print('\n%s: c = %.3g s, beta = %.3g, alpha = %.3g, L = %.3g s, B = %.3g B/s, a build every %g steps%s%s'
              % (path, a.c, a.beta, a.alpha, a.latency, a.bandwidth, a.steps_per_build,
                 '' if a.sums else ', energies untracked', '' if a.overlap else ', no overlap'))
        print('| ranks | particles | per rank | compute [ms] | halo exposed [ms] | builds [ms] | collectives [ms] | step [ms] | '
              '%s efficiency |' % ('weak' if a.weak else 'strong'))
        print('|---|---|---|---|---|---|---|---|---|')
        for p in sorted(by_p):
            rows = by_p[p]
            total = sum(r['owned'] for r in rows)
            t, comp, halo, build, coll = step_time(rows, p, a)
            ideal = a.c * total / p
            print('| %d | %d | %.0f | %.3f | %.3f | %.3f | %.3f | %.3f | %.1f %% |'
                  % (p, total, total / p, comp * 1e3, halo * 1e3, build * 1e3, coll * 1e3, t * 1e3,
                     100.0 * ideal / t))


def check_here(a):
    """The model's loop times on this machine against the measured ones."""
    measured = {}
    for item in filter(None, a.measured.split(',')):
        p, t = item.split(':')
        measured[int(p)] = float(t)
    by_p = defaultdict(list)
    for path in a.csv:
        for p, rows in read_ranks(path).items():
            by_p[p] = rows
    if 1 in measured and 1 not in by_p:
        by_p[1] = [{'owned': sum(r['owned'] for r in by_p[min(by_p)]), 'ghosts_in': 0.0}]
    print('| ranks | cores | max owned | max ghosts | model [s] | measured [s] | measured / model |')
    print('|---|---|---|---|---|---|---|')
    for p in sorted(by_p):
        rows = by_p[p]
        extra = a.beta if p > 1 else 0.0
        work = [a.c * (r['owned'] * (1.0 + extra) + a.alpha * r['ghosts_in']) for r in rows]
        per_step = max(work) if p <= a.here else sum(work) / a.here
        model = a.steps * per_step
        t = measured.get(p)
        print('| %d | %d | %.0f | %.0f | %.3f | %s | %s |'
              % (p, min(p, a.here), max(r['owned'] for r in rows), max(r['ghosts_in'] for r in rows), model,
                 '%.3f' % t if t else '-', '%.2f' % (t / model) if t else '-'))


if __name__ == '__main__':
    main()
