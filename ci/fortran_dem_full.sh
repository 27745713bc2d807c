#!/usr/bin/env bash
# The ORIGINAL, unmodified sample_main01.f90 for its whole run (150,000 steps, 300 frames)
# against an installed ppohdem, compared byte for byte with the original's stored outputs:
# all 300 data/outNNN.dat, the dumps up to step 150000, objects_distance*.csv and obj*.pov of
# the stored frames. About 1-2 minutes; not in the default ctest (ctest runs 5000 steps).
#   ci/fortran_dem_full.sh [BUILD_DIR]   (default build; installs into BUILD_DIR/fortran-full)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(realpath "${1:-$root/build}")
prefix=$build/fortran-full/install
cmake --install "$build" --prefix "$prefix" > /dev/null
exec "$root/tests/bindings/run_installed_sample.sh" "$prefix" "$root/fixtures" "$build/fortran-full/work" dem-full
