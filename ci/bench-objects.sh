#!/usr/bin/env bash
# The object benchmark of issue 38 item 4 (docs/performance.md "Objects"): the scoop of
# fixtures/scenes/scoop driven through a settled bed of 1,355 spheres, translated for 15,000
# steps and then rotated for 25,000 (validation/peers/make_scoop_bench.py has the scene), run by
# ppohdem (fast engine) and LIGGGHTS (validation/peers/liggghts/in.scoop), interleaved, best of
# K rounds:
#   1 core:  ppohdem 1 thread, and 1 thread without the far-object skip (--no-object-skip),
#            against LIGGGHTS on 1 rank;
#   2 cores: ppohdem 2 threads and 2 ranks against LIGGGHTS on 2 ranks.
#
#   bash ci/bench-objects.sh [--build-dir DIR] [--out DIR] [--repeat K] [--steps "T R"] [--tracked]
#                            [--cores "1 2"]
#
#   --repeat K   rounds (default 3); each round runs every configuration once (~1-2 min)
#   --steps      translation and rotation steps (default "15000 25000", the issue's)
#   --cores      "1", "2" or "1 2" (default): which of the two groups above to run
#   --tracked    ppohdem books the contact energies ([simulation] energy_balance, its default);
#                default untracked, as LIGGGHTS does not book them
# On a machine shared with other work, run it with OMP_WAIT_POLICY=passive
# OMPI_MCA_mpi_yield_when_idle=1 (both codes): spinning threads and ranks otherwise take the
# cores from each other (docs/performance.md "Objects").
# Times are the codes' own loop times (ppohdem "wall", LIGGGHTS "Loop time" summed over its two
# runs); the CPU seconds (user + sys of all processes) are printed beside them, as the machine may
# be shared. Writes OUT/results.tsv and OUT/results.md (default build-bench-objects/).
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
BUILD_DIR=${BUILD_DIR:-build}
OUT=""
REPEAT=3
STEPS="15000 25000"
TRACKED=0
CORES="1 2"
while [ $# -gt 0 ]; do
  case "$1" in
    --build-dir) BUILD_DIR=$2; shift ;;
    --out) OUT=$2; shift ;;
    --repeat) REPEAT=$2; shift ;;
    --steps) STEPS=$2; shift ;;
    --tracked) TRACKED=1 ;;
    --cores) CORES=$2; shift ;;
    *) echo "bench-objects: unknown argument $1" >&2; exit 2 ;;
  esac
  shift
done
if ! [[ "$REPEAT" =~ ^[1-9][0-9]*$ ]]; then echo "bench-objects: --repeat needs a positive integer" >&2; exit 2; fi
read -r STEPS_T STEPS_R <<<"$STEPS"
OUT=${OUT:-$ROOT/build-bench-objects}
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
PY=/usr/bin/python3
case "$BUILD_DIR" in /*) PPOHDEM="$BUILD_DIR/apps/ppohdem" ;; *) PPOHDEM="$ROOT/$BUILD_DIR/apps/ppohdem" ;; esac
if [ ! -x "$PPOHDEM" ]; then BUILD_DIR=$BUILD_DIR bash ci/build.sh >/dev/null; fi
command -v liggghts >/dev/null || bash ci/install-deps.sh --peers >&2
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
MPIRUN=(mpirun --oversubscribe --bind-to none -np 2)

# The settled bed (once per OUT), then the case.
if [ ! -f "$OUT/settle/settle_out/final.csv" ]; then
  mkdir -p "$OUT/settle"
  $PY validation/peers/make_scoop_bench.py settle "$OUT/settle"
  (cd "$OUT/settle" && "$PPOHDEM" simulate settle.toml --quiet >settle.txt 2>&1)
fi
CASE="$OUT/case"
$PY validation/peers/make_scoop_bench.py bench "$OUT/settle/settle_out/final.csv" "$CASE" "$STEPS_T" "$STEPS_R" \
  $([ "$TRACKED" -eq 1 ] || echo --untracked)
N=$(grep -cv '^#' "$CASE/particles.csv"); N=$((N - 1))
RESULTS="$OUT/results.tsv"
printf 'config\tround\tloop_s\tcpu_s\tmean_z_mm\tmax_z_mm\n' >"$RESULTS"
LOAD_BEFORE=$(uptime)

# mean and largest height of the final particles [mm] (ppohdem final.csv or a LIGGGHTS dump)
heights() {
  $PY - "$1" <<'PYEOF'
import sys
p = sys.argv[1]
if p.endswith('.csv'):
    lines = [l for l in open(p) if not l.startswith('#')]
    k = lines[0].strip().split(',').index('z')
    z = [float(l.split(',')[k]) for l in lines[1:]]
else:
    block = open(p).read().split('ITEM: ATOMS')[-1].strip().split('\n')
    k = block[0].split().index('z')
    z = [float(l.split()[k]) for l in block[1:]]
print('%.4f\t%.4f' % (1e3 * sum(z) / len(z), 1e3 * max(z)))
PYEOF
}

run_config() {  # name round
  local name=$1 rep=$2 dir="$OUT/runs/$1" loop cpu
  rm -rf "$dir"; mkdir -p "$dir"; cd "$dir"
  local timed=(/usr/bin/time -f '%U %S' -o cpu.txt)
  case "$name" in
    liggghts-1|liggghts-2)
      local cmd=(liggghts -in "$ROOT/validation/peers/liggghts/in.scoop" $(cat "$CASE/liggghts.vars") -var out final.dump -log log.txt)
      if [ "$name" = liggghts-1 ]; then
        "${timed[@]}" "${cmd[@]}" >out.txt 2>&1
      else
        "${timed[@]}" "${MPIRUN[@]}" "${cmd[@]}" >out.txt 2>&1
      fi
      loop=$(grep -oE 'Loop time of [0-9.eE+-]+' out.txt | awk '{s += $4} END {printf "%.3f", s}')
      final=final.dump ;;
    *)
      sed "s|^file = \"particles.csv\"|file = \"$CASE/particles.csv\"|" "$CASE/scene.toml" >scene.toml
      local cmd=("$PPOHDEM" simulate scene.toml --quiet)
      case "$name" in
        ppohdem-1-noskip) OMP_NUM_THREADS=1 "${timed[@]}" "${cmd[@]}" --no-object-skip >out.txt 2>&1 ;;
        ppohdem-1) OMP_NUM_THREADS=1 "${timed[@]}" "${cmd[@]}" >out.txt 2>&1 ;;
        ppohdem-2-threads) OMP_NUM_THREADS=2 "${timed[@]}" "${cmd[@]}" >out.txt 2>&1 ;;
        ppohdem-2-ranks) OMP_NUM_THREADS=1 "${timed[@]}" "${MPIRUN[@]}" "${cmd[@]}" >out.txt 2>&1 ;;
      esac
      loop=$(grep -oE 'wall [0-9.]+ s' out.txt | head -1 | awk '{print $2}')
      final=ours_out/final.csv ;;
  esac
  cpu=$(awk '{printf "%.3f", $1 + $2}' cpu.txt)
  printf '%s\t%s\t%s\t%s\t%s\n' "$name" "$rep" "$loop" "$cpu" "$(heights "$final")" | tee -a "$RESULTS"
  cd "$ROOT"
}

CONFIGS=()
[[ " $CORES " == *" 1 "* ]] && CONFIGS+=(liggghts-1 ppohdem-1 ppohdem-1-noskip)
[[ " $CORES " == *" 2 "* ]] && CONFIGS+=(liggghts-2 ppohdem-2-threads ppohdem-2-ranks)
for rep in $(seq 1 "$REPEAT"); do
  for c in "${CONFIGS[@]}"; do run_config "$c" "$rep"; done
done
LOAD_AFTER=$(uptime)

# The table: best loop time per configuration, speed against LIGGGHTS on the same cores.
$PY - "$RESULTS" "$OUT/results.md" "$N" "$STEPS_T" "$STEPS_R" "$TRACKED" "$LOAD_BEFORE" "$LOAD_AFTER" <<'PYEOF'
import sys, collections, datetime
tsv, md, n, st, sr, tracked, load0, load1 = sys.argv[1:]
rows = [l.rstrip('\n').split('\t') for l in open(tsv)][1:]
best, cpu, heights, median = {}, {}, {}, collections.defaultdict(list)
for name, rep, loop, c, mz, xz in rows:
    loop = float(loop)
    median[name].append(loop)
    if name not in best or loop < best[name]:
        best[name], cpu[name], heights[name] = loop, float(c), (mz, xz)
steps = int(st) + int(sr)
peer = {'1': 'liggghts-1', '2': 'liggghts-2'}
out = ['# Object benchmark (ci/bench-objects.sh)', '',
       '%s UTC; %s particles, %s + %s steps (translate, rotate); ppohdem energies %s; best of %d rounds.'
       % (datetime.datetime.utcnow().strftime('%Y-%m-%d %H:%M'), n, st, sr, 'tracked' if tracked == '1' else 'untracked',
          max(len(v) for v in median.values())),
       'Load before: %s' % load0.strip(), 'Load after: %s' % load1.strip(), '',
       'CPU: user + sys of the whole process of the best round (setup included: the scoop\'s field, ~0.2 s).', '',
       '| configuration | cores | best loop [s] | median [s] | CPU [s] | particle-steps/s | speed vs LIGGGHTS same cores (loop / CPU) | mean z / max z [mm] |',
       '|---|---|---|---|---|---|---|---|']
for name in ['liggghts-1', 'ppohdem-1', 'ppohdem-1-noskip', 'liggghts-2', 'ppohdem-2-threads', 'ppohdem-2-ranks']:
    if name not in best:
        continue
    cores = '1' if name.endswith('-1') or 'noskip' in name else '2'
    m = sorted(median[name])[len(median[name]) // 2]
    ratio = best[peer[cores]] / best[name] if peer[cores] in best else float('nan')
    cpu_ratio = cpu[peer[cores]] / cpu[name] if peer[cores] in best else float('nan')
    out.append('| %s | %s | %.2f | %.2f | %.2f | %.3g | %.2fx / %.2fx | %s / %s |'
               % (name, cores, best[name], m, cpu[name], int(n) * steps / best[name], ratio, cpu_ratio, *heights[name]))
open(md, 'w').write('\n'.join(out) + '\n')
print('\n'.join(out))
PYEOF
