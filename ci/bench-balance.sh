#!/usr/bin/env bash
# Particles per rank (max/mean) before and after the load balance (docs/performance.md "Load
# balance"; docs/dem.md "Load balance"), and the exchanges' messages per rank per step, on
#   bed     the standard settling bed of ci/bench-dem.sh (validation/peers/make_bench.py,
#           10,000 particles, 10,000 steps: fallen and settled on the floor);
#   sample  the seed's sample_main01 (fixtures/seed-sample/sample_main01.toml, ci/demo.sh step
#           6b: 600 particles falling onto the dragon), its first 30,000 steps (60 s: the sheet
#           has fallen onto the dragon and the floor), with [checks] max_overlap = 1 as the
#           legacy input of the same sample sets (core/src/dem/legacy_scene.cpp; 0.25 stops it
#           at step 15,684, where the soft spring of the original lets a wall overlap 43 %).
# Each scene runs once on 1 rank to its end with a checkpoint there; then, for each P, a
# restart at P ranks runs `--window` more steps twice, with `[parallel] balance = "off"`
# (before: the equal bricks of the scene's initial box, never re-cut, as before issue 37) and
# "rcb" (after: bisection by particle count, re-cut at list builds when max/mean > 1.05).
# Both report the load at their last list build and must end with the same final.csv (checked).
# With --full, the P-rank runs start at step 0 instead (slower: every step at P ranks).
#
#   bash ci/bench-balance.sh [--build-dir DIR] [--out DIR] [--ranks "2 4 8"] [--window N] [--full]
#                            [--scenes "bed sample"]
# Ranks beyond the cores are oversubscribed (mpirun --oversubscribe; the 2-core VM runs 8
# ranks on 2 cores): the loads and message counts do not depend on it, the times do.
# Prints a markdown table and writes it to OUT/balance.md (default build-bench-balance/).
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
BUILD_DIR=build
OUT=""
RANKS="2 4 8"
WINDOW=200
FULL=0
SCENES="bed sample"
while [ $# -gt 0 ]; do
  case "$1" in
    --build-dir) BUILD_DIR=$2; shift 2 ;;
    --out) OUT=$2; shift 2 ;;
    --ranks) RANKS=$2; shift 2 ;;
    --window) WINDOW=$2; shift 2 ;;
    --full) FULL=1; shift ;;
    --scenes) SCENES=$2; shift 2 ;;
    *) echo "bench-balance: unknown argument $1" >&2; exit 2 ;;
  esac
done
OUT=${OUT:-$ROOT/build-bench-balance}
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
BIN="$ROOT/$BUILD_DIR/apps/ppohdem"
[ -x "$BIN" ] || { echo "bench-balance: $BIN not found (build first)" >&2; exit 2; }
PY=/usr/bin/python3
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
# Waiting ranks yield the core and are not pinned (docs/dem.md "Domain decomposition").
export OMPI_MCA_mpi_yield_when_idle=1 OMP_WAIT_POLICY=passive OMP_NUM_THREADS=1

# make_scene NAME DIR: writes the scene into DIR; its file's path on stdout.
make_scene() {
  case "$1" in
    bed)
      $PY validation/peers/make_bench.py 10000 10000 "$2" >/dev/null
      echo "$2/scene.toml" ;;
    sample)
      cp fixtures/seed-sample/sample_main01.toml fixtures/seed-sample/sample_particles.csv "$2/"
      sed -i 's/^max_overlap = 0.25 /max_overlap = 1.0 /' "$2/sample_main01.toml"
      grep -q '^max_overlap = 1.0 ' "$2/sample_main01.toml" || { echo "bench-balance: max_overlap not set" >&2; exit 2; }
      local vox
      vox=$(sed -n 's|^#   ppohdem voxelize ||p' fixtures/seed-sample/sample_main01.toml)
      (cd "$2" && "$BIN" voxelize --quiet ${vox/..\/meshes/$ROOT/fixtures/meshes} >/dev/null)
      echo "$2/sample_main01.toml" ;;
    *) echo "bench-balance: unknown scene $1" >&2; exit 2 ;;
  esac
}

# with_balance SCENE MODE: a copy of SCENE with [parallel] balance = MODE, its path on stdout.
with_balance() {
  local copy="${1%.toml}_$2.toml"
  { cat "$1"; printf '\n[parallel]\nbalance = "%s"\n' "$2"; } > "$copy"
  echo "$copy"
}

TABLE="$OUT/balance.md"
{
  echo "| scene | ranks | steps | before: max/mean (equal bricks) | after: max/mean (rcb) | re-cuts | messages per rank per step, equal bricks | messages, rcb | as all-to-all | peers of rank 0 (equal / rcb) |"
  echo "|---|---|---|---|---|---|---|---|---|---|"
} > "$TABLE"
for name in $SCENES; do
  dir="$OUT/$name"
  rm -rf "$dir"; mkdir -p "$dir"
  scene=$(make_scene "$name" "$dir")
  STEPS=$([ "$name" = bed ] && echo 10000 || echo 30000)
  start=0
  restart=()
  if [ "$FULL" -eq 0 ]; then
    echo "bench-balance: $name on 1 rank to step $STEPS (checkpoint)" >&2
    "$BIN" simulate "$scene" --engine fast --quiet --output-dir "$dir/settle" --steps "$STEPS" --checkpoint-every "$STEPS" >/dev/null 2>"$dir/settle.log"
    start=$STEPS
    restart=(--restart "$dir/settle/checkpoint.bin")
  fi
  end=$((start + (FULL == 1 ? STEPS : WINDOW)))
  for p in $RANKS; do
    declare -A line=()
    for mode in off rcb; do
      echo "bench-balance: $name, $p ranks, balance $mode, steps $start to $end" >&2
      out="$dir/np${p}_$mode"
      mpirun -n "$p" --oversubscribe --bind-to none "$BIN" simulate "$(with_balance "$scene" "$mode")" --engine fast --quiet \
        --output-dir "$out" --steps "$end" "${restart[@]}" >"$out.log" 2>&1
      line[$mode]=$(grep '^load balance:' "$out.log")
    done
    cmp -s <(grep -v '^#' "$dir/np${p}_off/final.csv") <(grep -v '^#' "$dir/np${p}_rcb/final.csv") ||
      { echo "bench-balance: $name at $p ranks: final.csv differs between balance off and rcb" >&2; exit 1; }
    $PY - "$name" "$p" "$start-$end" "${line[off]}" "${line[rcb]}" >> "$TABLE" <<'PY'
import re, sys
name, p, steps, off, rcb = sys.argv[1:]
pat = re.compile(r"(\d+) re-cuts; particles per rank max/mean ([\d.]+) \(equal bricks of the initial box: ([\d.]+)\); "
                 r"exchanges: ([\d.]+) messages per rank per step \(max ([\d.]+); as all-to-all exchanges: ([\d.]+)\), (\d+) peers")
o, r = pat.search(off), pat.search(rcb)
print(f"| {name} | {p} | {steps} | {o.group(2)} | {r.group(2)} | {r.group(1)} | {o.group(4)} | {r.group(4)} | "
      f"{r.group(6)} | {o.group(7)} / {r.group(7)} |")
PY
    unset line
  done
done
{
  echo
  echo "Command: bash ci/bench-balance.sh $([ "$FULL" -eq 1 ] && echo --full) --ranks \"$RANKS\" --window $WINDOW; $(date -u +%Y-%m-%d) on $(hostname), $(getconf _NPROCESSORS_ONLN) cores (ranks oversubscribed beyond them); load: $(uptime | sed 's/.*load/load/')"
} >> "$TABLE"
cat "$TABLE"
