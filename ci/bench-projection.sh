#!/usr/bin/env bash
# The projection of the fast engine to many nodes (docs/performance.md "Projection to many nodes
# (issue 37)"): the dry run of the engine's bricks and halo (`ppohdem project`) on the
# 1,000,000- and 10,000,000-particle lattice beds of validation/peers/make_bench.py (made in
# memory) for P = 2 ... 4,096, and on weak-scaling beds of 25,000 particles per rank; the cost
# model (validation/projection/scaling_model.py) fed by the compute cost measured here; and its
# check against runs at 1, 2, 4 and 8 ranks of the 100,000-particle bed (4 and 8 oversubscribed
# on this machine's cores), with the exchanged bytes counted by validation/benchmarks/
# mpi_byte_count.c.
#
#   bash ci/bench-projection.sh [--build-dir DIR] [--out DIR] [--quick] [--repeat N] [--c SECONDS]
#
# --c: the compute per particle-step the projection uses (default: the 1-rank check run's,
# which on a loaded machine is too large; docs/performance.md uses quiet-machine figures).
# --quick: the 1,000,000 bed and weak scaling to 512 ranks only (a minute); the default also
# runs the 10,000,000 bed (3 minutes, 0.4 GB) and weak scaling to 4,096 ranks (102,400,000
# particles: 4.5 GB, about 15 minutes on this VM).
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
BUILD_DIR=build
OUT=""
QUICK=0
REPEAT=3
C_GIVEN=""
while [ $# -gt 0 ]; do
  case "$1" in
    --build-dir) BUILD_DIR=$2; shift 2 ;;
    --out) OUT=$2; shift 2 ;;
    --quick) QUICK=1; shift ;;
    --repeat) REPEAT=$2; shift 2 ;;
    --c) C_GIVEN=$2; shift 2 ;;
    *) echo "bench-projection: unknown argument $1" >&2; exit 2 ;;
  esac
done
OUT=${OUT:-$ROOT/build-bench-projection}
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
BIN="$ROOT/$BUILD_DIR/apps/ppohdem"
[ -x "$BIN" ] || { echo "bench-projection: $BIN not found (build first)" >&2; exit 2; }
PY=/usr/bin/python3
MODEL="$PY $ROOT/validation/projection/scaling_model.py"
CORES=$(getconf _NPROCESSORS_ONLN)  # (nproc would obey OMP_NUM_THREADS)
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_mpi_yield_when_idle=1 OMP_WAIT_POLICY=passive OMP_NUM_THREADS=1

echo "== dry runs (ppohdem project)"
"$BIN" project --lattice 100,100,100 --csv "$OUT/bed1e6.csv" | tee "$OUT/bed1e6.md"
WEAK_RANKS=1,2,4,8,16,32,64,128,256,512
if [ "$QUICK" = 0 ]; then
  "$BIN" project --lattice 200,200,250 --csv "$OUT/bed1e7.csv" | tee "$OUT/bed1e7.md"
  WEAK_RANKS=$WEAK_RANKS,1024,2048,4096
fi
"$BIN" project --weak 25,25,40 --ranks $WEAK_RANKS --csv "$OUT/weak.csv" | tee "$OUT/weak.md"

echo "== the check's bed: 100,000 particles, 200 steps of free fall (no list build)"
$PY validation/peers/make_bench.py 100000 200 "$OUT/bed100k" >/dev/null
"$BIN" project "$OUT/bed100k/scene.toml" --ranks 2,4,8 --csv "$OUT/bed100k.csv" >/dev/null
# loop_seconds P: the best of REPEAT runs' steps time (the `timing:` line).
loop_seconds() {
  local best=""
  for _ in $(seq "$REPEAT"); do
    local t
    t=$(mpirun -n "$1" --oversubscribe --bind-to none "$BIN" simulate "$OUT/bed100k/scene.toml" --engine fast --quiet 2>&1 |
        sed -n 's/^timing:.*, steps \([0-9.]*\) s,.*/\1/p')
    [ -n "$t" ] || { echo "bench-projection: no timing line at $1 ranks" >&2; exit 1; }
    best=$($PY -c "print(min(float(x) for x in '$best $t'.split()))")
  done
  echo "$best"
}
MEASURED=""
for p in 1 2 4 8; do
  t=$(loop_seconds $p)
  echo "$p ranks: best loop $t s"
  MEASURED="$MEASURED${MEASURED:+,}$p:$t"
done
C=$($PY -c "m='$MEASURED'.split(',')[0].split(':'); print(float(m[1]) / (200 * 100000))")
echo "c = $C s per particle-step (1 rank)"
$MODEL "$OUT/bed100k.csv" --c "$C" --here "$CORES" --steps 200 --measured "$MEASURED" | tee "$OUT/check.md"

echo "== exchanged bytes per step (PMPI counts, 30 - 10 steps) against the dry run"
mpicc -shared -fPIC -O2 -o "$OUT/libmpicount.so" validation/benchmarks/mpi_byte_count.c
for p in 2 4 8; do
  for s in 10 30; do
    mpirun -n $p --oversubscribe --bind-to none -x LD_PRELOAD="$OUT/libmpicount.so" "$BIN" simulate \
      "$OUT/bed100k/scene.toml" --engine fast --steps $s --quiet > "$OUT/count.$p.$s.log" 2>&1
  done
done
# The collectives too: the step's one allreduce (the "record" line: a derived datatype) of the
# model's S bytes, and no allgather between list builds.
$PY - "$OUT" "$ROOT/validation/projection" <<'PYEOF'
import csv, re, sys
out = sys.argv[1]
sys.path.insert(0, sys.argv[2])
from scaling_model import RECORD_BYTES
rows = list(csv.DictReader(open(out + '/bed100k.csv')))
print('| ranks | rank | sent B/step (counted) | dry run | messages/step (counted) | dry run | '
      'allreduces of S B/step (counted) | model | allgathers/step |')
print('|---|---|---|---|---|---|---|---|---|')
bad = 0
for p in (2, 4, 8):
    d = {}
    for s in (10, 30):
        for line in open('%s/count.%d.%d.log' % (out, p, s)):
            m = re.match(r'mpicount rank (\d+) (\S+) calls (\d+) bytes (\d+)', line)
            if m:
                d[(s, int(m[1]), m[2])] = (int(m[3]), float(m[4]))
    for r in range(p):
        row = [x for x in rows if int(x['ranks']) == p and int(x['rank']) == r][0]
        per_step = lambda kind, k: (d[(30, r, kind)][k] - d[(10, r, kind)][k]) / 20
        sent, calls = per_step('send', 1), per_step('send', 0)
        records, record_bytes, gathers = per_step('record', 0), per_step('record', 1), per_step('allgather', 0)
        bad += sent != float(row['refresh_bytes_out']) or calls != float(row['messages_out'])
        bad += records != 1 or record_bytes != RECORD_BYTES or gathers != 0
        print('| %d | %d | %.0f | %s | %.2f | %s | %.2f x %.0f | 1 x %d | %.2f |'
              % (p, r, sent, row['refresh_bytes_out'], calls, row['messages_out'], records,
                 record_bytes / records if records else 0, RECORD_BYTES, gathers))
sys.exit(1 if bad else 0)
PYEOF

[ -n "$C_GIVEN" ] && C=$C_GIVEN
echo "== the model (c = $C s; beta, alpha from callgrind; EDR-class network)"
$MODEL "$OUT/bed1e6.csv" --c "$C" | tee "$OUT/model.md"
[ "$QUICK" = 0 ] && $MODEL "$OUT/bed1e7.csv" --c "$C" | tee -a "$OUT/model.md"
$MODEL "$OUT/weak.csv" --c "$C" --weak | tee -a "$OUT/model.md"
