#!/usr/bin/env bash
# Two ppohdem builds give the same bits? The standard settling bed (10,000 spheres x STEPS,
# validation/peers/make_bench.py), energies tracked and untracked, on the fast engine at 1 and 2
# threads and 2 ranks, and the seed sample (fixtures/seed-sample, SEED_STEPS steps) on both
# engines; compares final.csv and energy.csv without their header lines (docs/dem.md "Checking a
# refactor"). Exit 0 when every pair is identical.
#
#   bash ci/compare-builds.sh BEFORE/ppohdem AFTER/ppohdem [WORKDIR]     (STEPS=10000 SEED_STEPS=15000)
set -euo pipefail
cd "$(dirname "$0")/.."
SRC=$(pwd)
[ $# -ge 2 ] || { echo "usage: ci/compare-builds.sh BIN_A BIN_B [WORKDIR]" >&2; exit 2; }
A=$(readlink -f "$1"); B=$(readlink -f "$2"); W=$(readlink -f -m "${3:-compare-builds}")
for bin in "$A" "$B"; do [ -x "$bin" ] || { echo "compare-builds: $bin is not an executable" >&2; exit 2; }; done
STEPS=${STEPS:-10000}; SEED_STEPS=${SEED_STEPS:-15000}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
rm -rf "$W"; mkdir -p "$W/meshes"
cp "$SRC/fixtures/meshes/dragon_100k.stl" "$W/meshes/"
run_all() {  # $1 binary, $2 tag
  local bin=$1 tag=$2
  for u in 0 1; do
    local d="$W/$tag/bed_u$u"
    /usr/bin/python3 "$SRC/validation/peers/make_bench.py" 10000 "$STEPS" "$d" > /dev/null
    if [ $u = 1 ]; then sed -i 's|^\[simulation\]$|[simulation]\nenergy_balance = false|' "$d/scene.toml"; fi
    for cfg in t1 t2 r2; do
      sed "s|^dir = \"ours_out\"|dir = \"out_$cfg\"|" "$d/scene.toml" > "$d/scene_$cfg.toml"
      case $cfg in
        t1) (cd "$d" && OMP_NUM_THREADS=1 "$bin" simulate "scene_$cfg.toml" --engine fast --quiet > "log_$cfg.txt" 2>&1) ;;
        t2) (cd "$d" && OMP_NUM_THREADS=2 "$bin" simulate "scene_$cfg.toml" --engine fast --quiet > "log_$cfg.txt" 2>&1) ;;
        r2) (cd "$d" && OMP_NUM_THREADS=1 mpirun --oversubscribe --bind-to none -np 2 "$bin" simulate "scene_$cfg.toml" \
               --engine fast --quiet > "log_$cfg.txt" 2>&1) ;;
      esac
      echo "compare-builds: $tag bed (energies $([ $u = 0 ] && echo tracked || echo untracked)) $cfg done"
    done
  done
  local s="$W/$tag/seed"; mkdir -p "$s"; cp "$SRC"/fixtures/seed-sample/* "$s/"; ln -sfn "$W/meshes" "$W/$tag/meshes"
  (cd "$s" && "$bin" voxelize --mesh ../meshes/dragon_100k.stl \
     --placement 10,10,10,6.368421052631579,6.368421052631579,-4.631578947368421 --cells 76 76 76 \
     --box -15.631578947368421 -15.631578947368421 -15.631578947368421 27.789473684210527 27.789473684210527 27.789473684210527 \
     --out dragon.vtk > vox.log 2>&1)
  for e in fast reference; do
    sed "s|^dir = .*|dir = \"out_$e\"|" "$s/sample_main01.toml" > "$s/s_$e.toml"
    (cd "$s" && OMP_NUM_THREADS=1 "$bin" simulate "s_$e.toml" --engine "$e" --steps "$SEED_STEPS" --quiet > "log_$e.txt" 2>&1)
    echo "compare-builds: $tag seed sample $e done"
  done
}
run_all "$A" a
run_all "$B" b
rc=0
for f in $(cd "$W/a" && find . -name final.csv -o -name energy.csv | sort); do
  if cmp -s <(grep -v '^#' "$W/a/$f") <(grep -v '^#' "$W/b/$f"); then echo "same  $f"; else echo "DIFF  $f"; rc=1; fi
done
exit $rc
