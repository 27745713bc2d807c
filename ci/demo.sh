#!/usr/bin/env bash
# The README's demo command: install dependencies, build, run the main job on a built-in
# example (the seed's distance_calculate sample on a fixture mesh).
set -euo pipefail
cd "$(dirname "$0")/.."
bash ci/install-deps.sh
bash ci/build.sh
BIN="$PWD/${BUILD_DIR:-build}/apps/ppohdem"
OUT="${DEMO_OUT:-$PWD/demo-output}"
mkdir -p "$OUT"
echo "== ppohdem mesh-info fixtures/meshes/dragon_100k.stl"
"$BIN" mesh-info fixtures/meshes/dragon_100k.stl
