#!/usr/bin/env bash
# Whole-process SDF benchmark (issue 37): the wall time of the whole `ppohdem voxelize` process
# (start-up, STL read, checks, tree, signs, queries, VTK write, exit) against the whole process of
# the CGAL oracle (`ppohdem-bench-sdf run --method cgal --threads 2`: STL read, CGAL's AABB tree
# and side-of-mesh test, raw write), on the benchmark grid (validation/benchmarks/bench_grid.hpp).
# Rounds are interleaved (ours 1 thread, ours 2 threads, CGAL, then again); the table gives the
# best of the rounds of each and the ratios CGAL / ours. The voxelize field is also compared with
# the oracle's (max |error| in h, sign mismatches), so a faster run is seen to stay exact.
# The load average before and after is printed: the machine may be shared.
# Usage: ci/bench-sdf-process.sh [build-dir]
#   env: SIZES="128" MESHES="dragon_100k" ROUNDS=3 THREADS="1 2"
#        BASELINE=/path/to/an/older/ppohdem: also timed in every round (2 threads), for a
#        before/after comparison under the same load.
#   (a 256^3 round costs about 90 s of CGAL on 2 threads.)
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=${1:-$ROOT/build-bench}
SIZES=${SIZES:-128}
MESHES=${MESHES:-dragon_100k}
ROUNDS=${ROUNDS:-3}
THREADS=${THREADS:-"1 2"}
BASELINE=${BASELINE:-}
OUT=$BUILD/bench-sdf-process
mkdir -p "$OUT"
load() { cut -d' ' -f1-3 /proc/loadavg; }
echo "bench-sdf-process: start $(date -u '+%Y-%m-%d %H:%M:%S UTC'), $(nproc) cores, load average $(load)"

if [ ! -f "$BUILD/CMakeCache.txt" ]; then
  cmake -S "$ROOT" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
cmake --build "$BUILD" --target ppohdem ppohdem-bench-sdf -j2 >/dev/null
PPOHDEM=$BUILD/apps/ppohdem
BENCH=$BUILD/validation/benchmarks/ppohdem-bench-sdf

# Wall seconds of one command (its output discarded; a failure stops the script).
wall() {
  local t0 t1
  t0=$(date +%s%N)
  "$@" >/dev/null 2>"$OUT/last.err" || { cat "$OUT/last.err" >&2; exit 1; }
  t1=$(date +%s%N)
  awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.3f", (b - a) / 1e9 }'
}
best() { tr ' ' '\n' | sed '/^$/d' | sort -g | head -1; }

printf '%-12s %4s %s | %9s | %s\n' mesh n "$(for t in $THREADS; do printf '%9s ' "ours-${t}t"; done)" cgal-2t \
  "$(for t in $THREADS; do printf '%9s ' "ratio-${t}t"; done)max_err_h sign_mismatches"
for mesh in $MESHES; do
  M=$ROOT/fixtures/meshes/$mesh.stl
  for n in $SIZES; do
    read -r -a BOX <<<"$("$BENCH" box --mesh "$M")"
    declare -A times=()
    for round in $(seq "$ROUNDS"); do
      for t in $THREADS; do
        s=$(wall "$PPOHDEM" voxelize --mesh "$M" --cells "$n" "$n" "$n" --box "${BOX[@]}" --threads "$t" --quiet \
          --out "$OUT/ours_${t}t.vtk")
        times[ours$t]="${times[ours$t]:-} $s"
      done
      if [ -n "$BASELINE" ]; then
        s=$(wall "$BASELINE" voxelize --mesh "$M" --cells "$n" "$n" "$n" --box "${BOX[@]}" --threads 2 --quiet \
          --out "$OUT/baseline.vtk")
        times[baseline]="${times[baseline]:-} $s"
      fi
      s=$(wall "$BENCH" run --method cgal --threads 2 --mesh "$M" --n "$n" --out "$OUT/cgal.f64")
      times[cgal]="${times[cgal]:-} $s"
      echo "  round $round: ours ${THREADS// /,} threads:$(for t in $THREADS; do printf ' %s' "$(best <<<"${times[ours$t]}" )"; done)" \
        "(best so far), cgal $s s, load $(load)" >&2
    done
    cgal=$(best <<<"${times[cgal]}")
    last_t=${THREADS##* }
    cmp=$("$BENCH" compare --mesh "$M" --n "$n" --candidate "$OUT/ours_${last_t}t.vtk" --oracle "$OUT/cgal.f64")
    max_err=$(tr ' ' '\n' <<<"$cmp" | sed -n 's/^max_all_h=//p')
    flips=$(tr ' ' '\n' <<<"$cmp" | sed -n 's/^sign_mismatches=//p')
    printf '%-12s %4s %s | %9s | %s%-9s %s\n' "$mesh" "$n" \
      "$(for t in $THREADS; do printf '%9s ' "$(best <<<"${times[ours$t]}")"; done)" "$cgal" \
      "$(for t in $THREADS; do printf '%9s ' "$(awk -v c="$cgal" -v o="$(best <<<"${times[ours$t]}")" 'BEGIN { printf "%.1fx", c / o }')"; done)" \
      "$max_err" "$flips"
    if [ -n "$BASELINE" ]; then
      base=$(best <<<"${times[baseline]}")
      echo "  baseline $BASELINE, 2 threads: $base s ($(awk -v c="$cgal" -v o="$base" 'BEGIN { printf "%.1fx", c / o }'))"
    fi
    rm -f "$OUT"/ours_*t.vtk "$OUT/cgal.f64" "$OUT/baseline.vtk"
    unset times
  done
done
echo "bench-sdf-process: end $(date -u '+%Y-%m-%d %H:%M:%S UTC'), load average $(load)" \
  "(best of $ROUNDS interleaved rounds; seconds of wall time of the whole process)"
