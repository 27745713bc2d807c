#!/usr/bin/env bash
# Fuzz every file reader with libFuzzer + AddressSanitizer + UndefinedBehaviorSanitizer.
#
#   ci/fuzz.sh [SECONDS] [TARGET...]     SECONDS per target (default 60); TARGETs default to all
#   RUNS=N ci/fuzz.sh [SECONDS] ...        stop each target after N executions (SECONDS stays a cap);
#                                          the campaign of docs/reliability.md used RUNS=10000000
#
# Installs clang and its runtime libraries if missing, configures a separate clang build
# (${BUILD_DIR:-build-fuzz}: fuzzing on, CGAL/MPI/OpenMP/tests off), builds the targets of
# tests/fuzz/, then runs each target for SECONDS on one core. Each run starts from the
# committed seeds (tests/fuzz/corpus/<target>/) and replays every known crash reproducer
# (tests/fuzz/regressions/<target>/); new interesting inputs go to a working corpus in the build
# directory, which later runs continue from. Prints one summary line per target and exits
# non-zero if any target found a crash, leak, UB report, out-of-memory or timeout; the
# reproducers are then in ${BUILD_DIR}/fuzz-artifacts/<target>/ and the logs in fuzz-logs/.
# docs/reliability.md describes the targets and the measured campaign.
set -euo pipefail
cd "$(dirname "$0")/.."
SRC=$(pwd)
SECONDS_PER_TARGET=${1:-60}
shift || true
BUILD_DIR=${BUILD_DIR:-build-fuzz}
JOBS=${JOBS:-$(nproc)}
RUNS=${RUNS:-}
if [ -n "$RUNS" ] && ! [[ "$RUNS" =~ ^[1-9][0-9]*$ ]]; then
  echo "fuzz: RUNS must be a positive whole number of executions, got '$RUNS'" >&2; exit 2
fi
ALL_TARGETS=(stl_ascii stl_binary voxelizer_input update_params_input vtk distance_dat scene_toml particle_csv
             checkpoint checkpoint_part)
TARGETS=("$@")
if [ "${#TARGETS[@]}" -eq 0 ]; then TARGETS=("${ALL_TARGETS[@]}"); fi

# Longest input per target: a few times the largest seed, small enough for fast mutation.
declare -A MAX_LEN=([stl_ascii]=8192 [stl_binary]=4096 [voxelizer_input]=1024 [update_params_input]=1024
                    [vtk]=4096 [distance_dat]=4096 [scene_toml]=4096 [particle_csv]=4096 [checkpoint]=4096
                    [checkpoint_part]=4096)
declare -A DICT=([stl_ascii]=stl_ascii [vtk]=vtk [voxelizer_input]=legacy_inputs
                 [update_params_input]=legacy_inputs [distance_dat]=distance_dat
                 [scene_toml]=scene_toml [particle_csv]=particle_csv)

# ---- tools: the project's dependencies, then clang with libFuzzer and the sanitizer runtimes ---
bash ci/install-deps.sh
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
fuzz_packages=(clang libclang-rt-14-dev)
missing=()
for p in "${fuzz_packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -gt 0 ]; then
  echo "fuzz: installing ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# ---- build: -O1 -g with assertions on (no NDEBUG; libstdc++ bounds checks) --------------------
if [ ! -f "$BUILD_DIR/CMakeCache.txt" ]; then
  CC=clang CXX=clang++ cmake -S . -B "$BUILD_DIR" -G Ninja \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" \
    -DCMAKE_CXX_FLAGS="-D_GLIBCXX_ASSERTIONS" \
    -DPPOHDEM_ENABLE_FUZZING=ON -DPPOHDEM_ENABLE_TESTING=OFF \
    -DPPOHDEM_ENABLE_CGAL=OFF -DPPOHDEM_ENABLE_MPI=OFF -DPPOHDEM_ENABLE_OPENMP=OFF
fi
cmake --build "$BUILD_DIR" --target ppohdem_fuzzers --parallel "$JOBS"

# ---- run ---------------------------------------------------------------------------------------
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
failed=0
for t in "${TARGETS[@]}"; do
  if [ -z "${MAX_LEN[$t]:-}" ]; then echo "fuzz: unknown target '$t' (known: ${ALL_TARGETS[*]})" >&2; exit 2; fi
  work="$BUILD_DIR/fuzz-corpus/$t"
  artifacts="$BUILD_DIR/fuzz-artifacts/$t"
  log="$BUILD_DIR/fuzz-logs/$t.log"
  mkdir -p "$work" "$artifacts" "$(dirname "$log")"
  seeds=("$SRC/tests/fuzz/corpus/$t")
  if [ -d "$SRC/tests/fuzz/regressions/$t" ]; then seeds+=("$SRC/tests/fuzz/regressions/$t"); fi
  runs=()
  if [ -n "$RUNS" ]; then runs=(-runs="$RUNS"); fi
  dict=()
  if [ -n "${DICT[$t]:-}" ]; then dict=(-dict="$SRC/tests/fuzz/dict/${DICT[$t]}.dict"); fi
  before=$(find "$artifacts" -type f | wc -l)
  status=0
  "$BUILD_DIR/tests/fuzz/fuzz_$t" "$work" "${seeds[@]}" "${dict[@]}" "${runs[@]}" \
    -max_total_time="$SECONDS_PER_TARGET" -max_len="${MAX_LEN[$t]}" \
    -rss_limit_mb=2048 -malloc_limit_mb=2048 -timeout=10 \
    -print_final_stats=1 -artifact_prefix="$artifacts/" >"$log" 2>&1 || status=$?
  after=$(find "$artifacts" -type f | wc -l)
  findings=$((after - before))
  if [ "$status" -ne 0 ] && [ "$findings" -eq 0 ]; then findings=1; fi  # failed without an artifact
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  last=$(grep -E '^#[0-9]+.*cov: ' "$log" | tail -1 || true)
  cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$last")
  ft=$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<<"$last")
  corpus=$(sed -n 's/.* corp: \([0-9]*\)\/.*/\1/p' <<<"$last")
  printf 'fuzz %-20s %12s execs %8s exec/s  cov %5s  ft %6s  corpus %5s  findings %d  (exit %d)\n' \
    "$t" "${execs:-?}" "${rate:-?}" "${cov:-?}" "${ft:-?}" "${corpus:-?}" "$findings" "$status"
  if [ "$findings" -ne 0 ]; then
    failed=1
    echo "fuzz: $t: FINDING, see $log and $artifacts/" >&2
    grep -E 'ERROR: |runtime error|SUMMARY|terminate called|invariant violated' "$log" | head -5 >&2 || true
  fi
done
exit "$failed"
