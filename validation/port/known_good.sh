#!/bin/sh
# Known-good builds and run configurations that must pass the port check
# (docs/port-validation.md "Power"): runs 3 perturbed members of each exported scene with the
# given command, and judges them against the baseline with --external.
#   validation/port/known_good.sh LABEL BASELINE_DIR SCRATCH PPOHDEM_VALIDATE_BIN -- COMMAND...
# COMMAND is the simulate command without the scene, e.g.
#   known_good.sh "2 ranks" fixtures/port-baseline /tmp/kg build/apps/ppohdem -- \
#       mpirun -n 2 build/apps/ppohdem simulate
set -u
label=$1
baseline=$2
scratch=$3
judge=$4
shift 5
mkdir -p "$scratch"
"$judge" validate --export-scenes "$scratch/scenes" > /dev/null
for scene in settling_bed seed_sample; do
  dirs=""
  for k in 3001 3002 3003; do
    out="$scratch/$scene/run$k"
    rm -rf "$out"
    "$@" "$scratch/scenes/$scene/scene.toml" --engine fast --quiet --perturb-seed $k --output-dir "$out" \
      > "$scratch/$scene-$k.log" 2>&1 || echo "$label: $scene seed $k failed (see $scratch/$scene-$k.log)"
    dirs="$dirs $out"
  done
  # shellcheck disable=SC2086
  verdict=$("$judge" validate --port --against "$baseline" --external $dirs --out "$scratch/$scene-report.md" 2>&1 |
            grep -E "^$scene ")
  echo "| $label | $verdict |"
done
