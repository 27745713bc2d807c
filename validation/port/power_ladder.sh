#!/bin/sh
# The power of the port check (docs/port-validation.md "Power"): known-bad changes, each
# physical parameter scaled by (1 + 10^-k) and (1 - 10^-k), checked against a baseline;
# prints one Markdown row per parameter with the verdict at each k. Once both signs pass at
# some k, the larger k of that parameter are not run ("-").
#   [SCENES=settling_bed] validation/port/power_ladder.sh PPOHDEM BASELINE_DIR SCRATCH [k ...]
# Default k: 2 4 6 8. Each check runs 3 members of each scene (~10 s of CPU; SCENES: only those).
set -u
ppohdem=$1
baseline=$2
scratch=$3
shift 3
ks=${*:-2 4 6 8}
mkdir -p "$scratch"
printf '| parameter |'
for k in $ks; do printf ' x(1+1e-%s) | x(1-1e-%s) |' "$k" "$k"; done
printf '\n|---|'
for k in $ks; do printf -- '---|---|'; done
printf '\n'
for p in friction restitution young dt gravity; do
  printf '| %s |' "$p"
  undetected=no
  for k in $ks; do
    passes=0
    for sign in + -; do
      if [ "$undetected" = yes ]; then
        printf ' - |'
        continue
      fi
      f=$(/usr/bin/python3 -c "print(repr(1 $sign 10**-$k))")
      "$ppohdem" validate --against "$baseline" --scale-parameter "$p=$f" --jobs 2 ${SCENES:+--scenes "$SCENES"} \
        --out "$scratch/$p-$k$sign/report.md" --work-dir "$scratch/work" > "$scratch/$p-$k$sign.log" 2>&1
      case $? in
        0) printf ' pass |'; passes=$((passes + 1)) ;;
        1) printf ' **FAIL** |' ;;
        *) printf ' error |' ;;
      esac
    done
    [ "$passes" -eq 2 ] && undetected=yes
  done
  printf '\n'
done
