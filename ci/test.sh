#!/usr/bin/env bash
# The README's test command: install dependencies, build, run every test suite.
# MPI tests run at 1 and 2 ranks (--oversubscribe); as root Open MPI needs the two variables.
# Then the same with Clang 14 in build-clang (docs/portability.md): the whole project built
# warning-free, and the test suite (every test; CLANG_TESTS="-L unit" runs a labelled subset).
set -euo pipefail
cd "$(dirname "$0")/.."
# Disk: a build takes about 0.6 GB and its test run writes about 1.3 GB of scratch files, removed
# once the suite has passed (the two suites together peak near 2.5 GB).
free_kb=$(df -Pk . | awk 'NR == 2 {print $4}')
echo "ci/test.sh: $((free_kb / 1024)) MB free on $(df -P . | awk 'NR == 2 {print $6}')"
if [ "$free_kb" -lt 3000000 ]; then echo "ci/test.sh: warning: less than 3 GB free; the builds and test scratch need about 2.5 GB" >&2; fi
bash ci/install-deps.sh
bash ci/build.sh
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-2}
(cd "${BUILD_DIR:-build}" && ctest --output-on-failure --timeout 900 -j "$(nproc)")
rm -rf "${BUILD_DIR:-build}/test-scratch" "${BUILD_DIR:-build}/tests_scratch"  # passed: the scratch is not needed
CC=clang CXX=clang++ BUILD_DIR=${CLANG_BUILD_DIR:-build-clang} bash ci/build.sh
read -r -a clang_tests <<<"${CLANG_TESTS:-}"
(cd "${CLANG_BUILD_DIR:-build-clang}" && ctest --output-on-failure --timeout 900 -j "$(nproc)" "${clang_tests[@]}")
rm -rf "${CLANG_BUILD_DIR:-build-clang}/test-scratch" "${CLANG_BUILD_DIR:-build-clang}/tests_scratch"
