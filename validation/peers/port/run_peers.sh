#!/bin/sh
# The peers' verdicts (docs/port-validation.md, "Other codes"): LIGGGHTS, LAMMPS and YADE run
# the port check's settling_bed from three one-ulp-perturbed starts (ppohdem's own members
# 1001-1003, written by `ppohdem simulate --steps 0 --perturb-seed K`), their outputs become
# ppohdem frames, and `ppohdem validate --port --external` judges each code's three runs.
#   validation/peers/port/run_peers.sh PPOHDEM SCRATCH ["ppohdem liggghts lammps lammps-walls yade"]
# PPOHDEM is a ppohdem built with CGAL (its validate mode). Prints one table row per code;
# the reports are SCRATCH/<code>/report.md (the runs' observables in SCRATCH/<code>/img). ppohdem itself runs as the control.
set -eu
ppohdem=$(readlink -f "$1")
scratch=$2
codes=${3:-"ppohdem liggghts lammps lammps-walls yade"}
here=$(cd "$(dirname "$0")" && pwd)
py=/usr/bin/python3
mkdir -p "$scratch"
scratch=$(readlink -f "$scratch")
"$ppohdem" validate --export-scenes "$scratch/scenes" > /dev/null
scene="$scratch/scenes/settling_bed/scene.toml"
for k in 1001 1002 1003; do
  "$ppohdem" simulate "$scene" --steps 0 --perturb-seed $k --quiet --output-dir "$scratch/start$k" > "$scratch/start$k.log" 2>&1
  "$py" "$here/make_inputs.py" "$scratch/start$k/frame_000000.csv" "$scratch/input$k"
done
for code in $codes; do
  dirs=""
  for k in 1001 1002 1003; do
    run="$scratch/$code/run$k"
    log="$scratch/$code/run$k.log"
    rm -rf "$run"
    mkdir -p "$run"
    t0=$(date +%s)
    case $code in
      ppohdem)
        "$ppohdem" simulate "$scene" --perturb-seed $k --quiet --output-dir "$run" > "$log" 2>&1 ;;
      lammps|lammps-walls)
        # lammps-walls: the walls given ppohdem's wall law (in.settling_bed.lammps says why)
        walls=""
        [ "$code" = lammps-walls ] && walls="-var wallE 7692307.692307692 -var wallkt 9049773.755656108"
        # shellcheck disable=SC2086
        (cd "$run" && lmp -log none -in "$here/in.settling_bed.lammps" -var data "$scratch/input$k/particles.data" \
           -var out bed.dump $walls > "$log" 2>&1)
        "$py" "$here/dump_to_frames.py" "$run/bed.dump" "$run" "LAMMPS $(lmp -h | sed -n 's/^Large-scale.*- \(.*\)$/\1/p' | head -1), settling_bed start perturb-seed $k" >> "$log"
        rm "$run/bed.dump" ;;
      liggghts)
        (cd "$run" && liggghts -log none -in "$here/in.settling_bed.liggghts" -var data "$scratch/input$k/particles.data" \
           -var out bed.dump > "$log" 2>&1)
        "$py" "$here/dump_to_frames.py" "$run/bed.dump" "$run" "LIGGGHTS-PUBLIC, settling_bed start perturb-seed $k" >> "$log"
        rm "$run/bed.dump" ;;
      yade)
        yade -n -j 1 -x "$here/settling_bed_yade.py" "$scratch/input$k/particles.csv" "$run" \
          "YADE, settling_bed start perturb-seed $k" > "$log" 2>&1 ;;
      *) echo "run_peers.sh: unknown code '$code' (expected ppohdem, liggghts, lammps, lammps-walls or yade)" >&2; exit 2 ;;
    esac
    echo "$code seed $k: $(( $(date +%s) - t0 )) s wall" >&2
    dirs="$dirs $run"
  done
  # shellcheck disable=SC2086
  verdict=$("$ppohdem" validate --port --external $dirs --out "$scratch/$code/report.md" 2>&1 | grep -E "^settling_bed " || true)
  echo "| $code | $verdict |"
done
