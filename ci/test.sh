#!/usr/bin/env bash
# The README's test command: install dependencies, build, run every test suite.
# MPI tests run at 1 and 2 ranks (--oversubscribe); as root Open MPI needs the two variables.
# Then the same with Clang 14 in build-clang (docs/portability.md): the whole project built
# warning-free, and the test suite (every test; CLANG_TESTS="-L unit" runs a labelled subset).
set -euo pipefail
cd "$(dirname "$0")/.."
bash ci/install-deps.sh
bash ci/build.sh
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-2}
(cd "${BUILD_DIR:-build}" && ctest --output-on-failure --timeout 900 -j "$(nproc)")
CC=clang CXX=clang++ BUILD_DIR=${CLANG_BUILD_DIR:-build-clang} bash ci/build.sh
read -r -a clang_tests <<<"${CLANG_TESTS:-}"
(cd "${CLANG_BUILD_DIR:-build-clang}" && ctest --output-on-failure --timeout 900 -j "$(nproc)" "${clang_tests[@]}")
