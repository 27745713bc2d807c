#!/bin/sh
# A realisation ensemble of the settling bed (docs/port-validation.md, "Other codes"): the
# exported settling_bed with its lattice jittered by other seeds (the scene's generator:
# lattice, jitter 0.1 R, seed 42 for the exported scene; here seeds 1..N), run by ppohdem. The
# one-ulp ensemble of the port check samples one realisation's chaos; this one samples the
# spread of outcomes over realisations of the same macroscopic start, the yardstick for
# "the same physics" that the peers' runs are compared with (realisation_table.py).
#   validation/peers/port/realisations.sh PPOHDEM SCRATCH N
# Writes SCRATCH/realisations/seedJ (frames) and SCRATCH/realisations.csv (observables, one
# row per seed, via `ppohdem validate --port --external` on groups of three).
set -eu
ppohdem=$(readlink -f "$1")
scratch=$2
n=$3
mkdir -p "$scratch/realisations"
scratch=$(readlink -f "$scratch")
"$ppohdem" validate --export-scenes "$scratch/scenes" > /dev/null
scene="$scratch/scenes/settling_bed/scene.toml"
for j in $(seq 1 "$n"); do
  out="$scratch/realisations/seed$j"
  [ -f "$out/frame_014000.csv" ] && continue
  gen="$scratch/realisations/generator$j.toml"
  sed "s|^file = \"particles.csv\"|generator = \"lattice\"\nbox_min = [0, 0, 0]\nbox_max = [0.02, 0.02, 0.03]\ncount = 1000\nradius = 0.001\nseed = $j\njitter = 0.1|" \
    "$scene" > "$gen"
  "$ppohdem" simulate "$gen" --quiet --output-dir "$out" > "$out.log" 2>&1
done
rm -f "$scratch/realisations.csv"
j=1
while [ $((j + 2)) -le "$n" ]; do
  d="$scratch/realisations"
  "$ppohdem" validate --port --external "$d/seed$j" "$d/seed$((j + 1))" "$d/seed$((j + 2))" \
    --out "$d/judge$j/report.md" > "$d/judge$j.log" 2>&1 || true
  csv="$d/judge$j/img/port_observables_settling_bed.csv"
  if [ -f "$scratch/realisations.csv" ]; then tail -n +2 "$csv" >> "$scratch/realisations.csv"; else cp "$csv" "$scratch/realisations.csv"; fi
  j=$((j + 3))
done
echo "wrote $scratch/realisations.csv"
