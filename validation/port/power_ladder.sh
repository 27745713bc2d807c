#!/bin/sh
# The power of the port check (docs/port-validation.md "Power"): known-bad changes, each
# physical parameter scaled by (1 + 10^-k) and (1 - 10^-k), checked against a baseline;
# prints one Markdown row per parameter: the verdict at each k.
#   validation/port/power_ladder.sh PPOHDEM BASELINE_DIR SCRATCH [k ...]
# Default k: 1 2 3 4 6 8. Each check runs 3 members of each scene (~10 s of CPU).
set -u
ppohdem=$1
baseline=$2
scratch=$3
shift 3
ks=${*:-1 2 3 4 6 8}
mkdir -p "$scratch"
printf '| parameter |'
for k in $ks; do printf ' 1+1e-%s | 1-1e-%s |' "$k" "$k"; done
printf '\n|---|'
for k in $ks; do printf -- '---|---|'; done
printf '\n'
for p in friction restitution young dt gravity; do
  printf '| %s |' "$p"
  for k in $ks; do
    for sign in + -; do
      f=$(/usr/bin/python3 -c "print(repr(1 $sign 10**-$k))")
      "$ppohdem" validate --against "$baseline" --scale-parameter "$p=$f" --jobs 2 \
        --out "$scratch/$p-$k$sign/report.md" --work-dir "$scratch/work" > "$scratch/$p-$k$sign.log" 2>&1
      case $? in
        0) printf ' pass |' ;;
        1) printf ' **FAIL** |' ;;
        *) printf ' error |' ;;
      esac
    done
  done
  printf '\n'
done
