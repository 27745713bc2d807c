#!/usr/bin/env bash
# The original DEM sample's whole run (150,000 steps, one core) under
# `--compat ppohdem-1.0`, against the original's final full-precision dump and all 300
# data/outNNN.dat frames (fixtures/ppohdem-1.0/dem-sample/). The default ctest run stops at
# step 50,000; this is the rest. Usage: BUILD_DIR=build bash ci/compat_dem_full.sh
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${BUILD_DIR:-build}
cmake --build "$BUILD_DIR" --target test_compat_ppohdem10_dem
"$BUILD_DIR/tests/compat/test_compat_ppohdem10_dem" --gtest_also_run_disabled_tests \
  --gtest_filter='Ppohdem10DemFull.*'
