#!/usr/bin/env bash
# Known-good builds and run configurations that must pass the port check (issue 36;
# docs/port-validation.md, "Known-good runs"), from a clone, in one script:
#
#   bash ci/port-known-good.sh [--only "O0 fma clang ranks4 ..."] [--scratch DIR] [--jobs N]
#
# Builds the reference build `build/` (Release, ppohdem + ppohdem-validate, with CGAL) and one
# build directory per compiler variant, build-kg-<label>/, with the `ppohdem` executable only
# (ccache, nice -n 10). Each variant's ppohdem runs the check's simulations (the deterministic
# tier's dense scenes and the chaotic tier's 3 runs per scene); the Chung & Ooi rows run inside
# ppohdem-validate, copied from `build/` beside it (the reference build's code, not the
# variant's). Then `ppohdem validate --port` runs once per configuration, and
# validation/port/known_good_table.py prints the table of SCRATCH/table.md.
#
# Compiler variants (CMAKE_BUILD_TYPE=None, so CMAKE_CXX_FLAGS are the only optimisation flags;
# each build's log shows one compile command to check it):
#   O0      GCC -O0                    O2      GCC -O2
#   fma     GCC -O3 -mfma -ffp-contract=fast (x86-64's baseline ISA has no FMA instruction:
#           -ffp-contract=fast alone, GCC's C++ default anyway, changes nothing)
#   native  GCC -O3 -march=native      clang   clang++-14 Release (-O3; the project adds
#                                              -ffp-contract=off for Clang, CMakeLists.txt)
# Run configurations, with the reference build:
#   threads1, threads2 (OMP_NUM_THREADS), ranks1, ranks2, ranks4 (--launcher "mpirun -n N
#   --oversubscribe", 1 thread each), sse2 (PPOHDEM_SIMD=sse2: the scalar contact path)
set -euo pipefail
cd "$(dirname "$0")/.."
src=$(pwd)
only="O0 fma clang ranks4 O2 native threads1 threads2 ranks1 ranks2 sse2"
scratch=/tmp/ppohdem-known-good
jobs=2
while [ $# -gt 0 ]; do
  case $1 in
    --only) only=$2; shift 2 ;;
    --scratch) scratch=$2; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    *) echo "port-known-good.sh: unknown argument '$1' (expected --only, --scratch or --jobs)" >&2; exit 2 ;;
  esac
done
mkdir -p "$scratch"
scratch=$(readlink -f "$scratch")
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
lean=(-DPPOHDEM_ENABLE_TESTING=OFF -DPPOHDEM_ENABLE_PYTHON=OFF -DPPOHDEM_ENABLE_FORTRAN=OFF -DPPOHDEM_ENABLE_CGAL=OFF)

if [ ! -f build/CMakeCache.txt ]; then
  cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" > "$scratch/configure-build.log"
fi
nice -n 10 cmake --build build -j2 --target ppohdem ppohdem-validate > "$scratch/build-build.log"

variant_flags() {  # label -> the compiler and CMake arguments of the variant
  case $1 in
    O0) echo "gcc|-DCMAKE_BUILD_TYPE=None|-DCMAKE_CXX_FLAGS=-O0 -DNDEBUG" ;;
    O2) echo "gcc|-DCMAKE_BUILD_TYPE=None|-DCMAKE_CXX_FLAGS=-O2 -DNDEBUG" ;;
    fma) echo "gcc|-DCMAKE_BUILD_TYPE=None|-DCMAKE_CXX_FLAGS=-O3 -DNDEBUG -mfma -ffp-contract=fast" ;;
    native) echo "gcc|-DCMAKE_BUILD_TYPE=None|-DCMAKE_CXX_FLAGS=-O3 -DNDEBUG -march=native" ;;
    clang) echo "clang|-DCMAKE_BUILD_TYPE=Release|-DCMAKE_CXX_FLAGS=" ;;
    *) echo "" ;;
  esac
}

check() {  # label, ppohdem binary, environment (VAR=VALUE ...), then more validate arguments
  local label=$1 bin=$2 environment=$3 j=${check_jobs:-$jobs}
  shift 3
  mkdir -p "$scratch/$label"
  echo "[known-good] $label: $environment ppohdem validate --port $* ($(date -u +%H:%M) UTC)" >&2
  # shellcheck disable=SC2086
  (cd "$scratch/$label" && nice -n 10 env $environment "$bin" validate --port --jobs "$j" --out report.md "$@" \
     > stdout.log 2> stderr.log) || true
}

rows=()
for label in $only; do
  spec=$(variant_flags "$label")
  if [ -n "$spec" ]; then
    IFS='|' read -r compiler build_type flags <<< "$spec"
    dir=build-kg-$label
    cc=(); [ "$compiler" = clang ] && cc=(-DCMAKE_C_COMPILER=clang-14 -DCMAKE_CXX_COMPILER=clang++-14)
    echo "[known-good] $label: building $dir ($(date -u +%H:%M) UTC)" >&2
    cmake -S . -B "$dir" -G Ninja "${cc[@]}" "$build_type" "$flags" "${launcher[@]}" "${lean[@]}" \
      > "$scratch/configure-$label.log"
    nice -n 10 cmake --build "$dir" -j2 --target ppohdem > "$scratch/build-$label.log"
    # the proof that the variant is what it says: the fast engine's force kernel's compile command
    { ninja -C "$dir" -t commands ppohdem | grep 'force_kernel.cpp.o -c' | head -n 1; } >> "$scratch/build-$label.log" || true
    cp build/apps/ppohdem-validate "$dir/apps/"
    check "$label" "$src/$dir/apps/ppohdem" ""
  else
    case $label in
      threads1) check "$label" "$src/build/apps/ppohdem" OMP_NUM_THREADS=1 ;;
      threads2) check "$label" "$src/build/apps/ppohdem" OMP_NUM_THREADS=2 ;;
      ranks1|ranks2|ranks4)
        # one run at a time: a run's ranks are the 2 cores' load already
        check_jobs=1 check "$label" "$src/build/apps/ppohdem" OMP_NUM_THREADS=1 \
          --launcher "mpirun -n ${label#ranks} --oversubscribe" ;;
      sse2) check "$label" "$src/build/apps/ppohdem" PPOHDEM_SIMD=sse2 ;;
      *) echo "port-known-good.sh: unknown configuration '$label'" >&2; exit 2 ;;
    esac
  fi
  rows+=("$label=$scratch/$label")
done
/usr/bin/python3 validation/port/known_good_table.py "${rows[@]}" | tee "$scratch/table.md"
