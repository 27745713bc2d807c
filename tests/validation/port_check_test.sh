#!/bin/sh
# The port check reduced (issue 36, docs/port-validation.md "ctest"): a 20-member ensemble of
# the 216-sphere bed; three fresh perturbed runs must pass, the same runs with friction x 0.9
# (a known-bad change) must fail, and three runs made with `ppohdem simulate --perturb-seed`
# of the exported scene must pass through --external.
#   port_check_test.sh PPOHDEM SCRATCH
set -eu
ppohdem=$1
dir=$2
rm -rf "$dir"
mkdir -p "$dir"
"$ppohdem" validate --save-baseline "$dir/baseline" --scenes small_bed --members 20 --held-out 0 --jobs 2 \
  --work-dir "$dir/work"
# Fresh members (seeds 1001-1003, not in the ensemble): must pass.
"$ppohdem" validate --against "$dir/baseline" --jobs 2 --out "$dir/good/report.md" --work-dir "$dir/work"
# A known-bad change: must fail with exit status 1 (2 would be bad input).
set +e
"$ppohdem" validate --against "$dir/baseline" --jobs 2 --scale-parameter friction=0.9 --out "$dir/bad/report.md" \
  --work-dir "$dir/work"
rc=$?
set -e
if [ "$rc" -ne 1 ]; then
  echo "FAILED: friction x 0.9 should fail the port check (exit 1), got exit $rc"
  exit 1
fi
grep -q "Verdict: FAIL" "$dir/bad/report.md"
# Runs of another code's kind: output folders of the exported scene, judged with --external.
"$ppohdem" validate --export-scenes "$dir/scenes" --scenes small_bed
for k in 2001 2002 2003; do
  "$ppohdem" simulate "$dir/scenes/small_bed/scene.toml" --engine fast --quiet --perturb-seed $k \
    --output-dir "$dir/external/run$k" > /dev/null
done
"$ppohdem" validate --port --against "$dir/baseline" --external "$dir/external/run2001" "$dir/external/run2002" \
  "$dir/external/run2003" --out "$dir/external/report.md"
echo "port check reduced: good runs pass, friction x 0.9 fails, external runs pass"
