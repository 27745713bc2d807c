#!/usr/bin/env bash
# Regenerate the tables of docs/sdf-accuracy.md: every reference SDF method against the CGAL
# oracle on the fixture meshes at three resolutions (about 10 minutes on 2 cores).
# Usage: bash ci/sdf-accuracy.sh [OUTPUT.md]   (default: build/sdf-accuracy-tables.md)
set -euo pipefail
cd "$(dirname "$0")/.."
bash ci/install-deps.sh
bash ci/build.sh
STUDY="${BUILD_DIR:-build}/validation/studies/ppohdem-sdf-study"
OUT="${1:-${BUILD_DIR:-build}/sdf-accuracy-tables.md}"
{
  echo "Command: bash ci/sdf-accuracy.sh; $(date -u +%Y-%m-%dT%H:%MZ); $(nproc) cores; $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
  echo
  echo "### Closed meshes (signed oracle)"
  echo
  "$STUDY" --mesh fixtures/meshes/box.stl fixtures/meshes/icosphere.stl fixtures/meshes/fandisk.stl \
           fixtures/meshes/bunny_closed.stl fixtures/meshes/dragon_100k.stl \
           --nodes 32 64 128 --methods exact seed --oracle-threads 2
  echo
  echo "### Open mesh (the original bunny scan, 5 holes: unsigned oracle, |phi| compared)"
  echo
  "$STUDY" --mesh fixtures/meshes/bunny.stl --nodes 32 64 --methods exact seed --oracle-threads 2
} | tee "$OUT"
