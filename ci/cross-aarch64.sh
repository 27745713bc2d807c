#!/usr/bin/env bash
# Cross-compile the `ppohdem` command for aarch64 (Debian's g++-aarch64-linux-gnu), run a
# representative subset under qemu-user and compare its output files with the same runs of the
# x86-64 build, byte for byte (docs/portability.md, "aarch64").
#
#   ci/cross-aarch64.sh                  FP_CONTRACT=off (default): a*b+c rounded twice on aarch64
#   FP_CONTRACT=fast ci/cross-aarch64.sh   GCC's default on aarch64: fused multiply-adds
#
# Runs, each on both machines (work files in ${CROSS_DIR:-build-aarch64}/runs/{x86_64,aarch64}):
#   sdf    the fast builder's exact field (no band) of fixtures/meshes/fandisk.stl, 21 x 15 x 21
#          nodes, and the reference builder's exact field of fixtures/meshes/box.stl;
#   hertz  fixtures/scenes/two_spheres.toml: one Hertz-Mindlin pair, head-on, 12,000 steps
#          (approach and the whole contact), reference and fast engines;
#   seed   the seed's sample (fixtures/seed-sample): voxelize the dragon, then its first
#          ${SEED_STEPS:-1000} steps with the reference and the fast engine (SEED_FIELD=host: the
#          aarch64 run takes the x86-64 run's dragon field; SEED_STEPS=N: fewer steps).
# Prints one line per compared file (same / DIFFERS with the count of differing numbers and the
# largest relative difference; header lines and VTK titles aside) and exits non-zero if any
# file differs.
# The x86-64 side is ${HOST_BUILD_DIR:-build} (configured and built here if missing: target
# ppohdem only). MPI and CGAL are off in the cross build; OpenMP is on (libgomp1-arm64-cross).
set -euo pipefail
cd "$(dirname "$0")/.."
SRC=$(pwd)
FP_CONTRACT=${FP_CONTRACT:-off}
case "$FP_CONTRACT" in off|fast) ;; *) echo "cross-aarch64: FP_CONTRACT must be off or fast, got '$FP_CONTRACT'" >&2; exit 2;; esac
CROSS_DIR=${CROSS_DIR:-build-aarch64}
[ "$FP_CONTRACT" = fast ] && CROSS_DIR=${CROSS_DIR}-contract
HOST_BUILD_DIR=${HOST_BUILD_DIR:-build}
SEED_STEPS=${SEED_STEPS:-1000}
HERTZ_STEPS=${HERTZ_STEPS:-12000}  # contact from step ~10,000 to ~11,800
JOBS=${JOBS:-$(nproc)}
# One thread: the results do not depend on the count, and under qemu-user libgomp's waiting
# threads made a 2-thread run a hundred times slower on a busy machine.
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-1}

bash ci/install-deps.sh --cross

# ---- builds ---------------------------------------------------------------------------------
GEN=()
if command -v ninja >/dev/null 2>&1; then GEN=(-G Ninja); fi
LAUNCHER=()
if command -v ccache >/dev/null 2>&1; then LAUNCHER=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
if [ ! -f "$CROSS_DIR/CMakeCache.txt" ]; then
  cmake -S . -B "$CROSS_DIR" "${GEN[@]}" -DCMAKE_TOOLCHAIN_FILE="$SRC/ci/aarch64-toolchain.cmake" \
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS="-ffp-contract=$FP_CONTRACT" "${LAUNCHER[@]}" \
    -DPPOHDEM_ENABLE_TESTING=OFF -DPPOHDEM_ENABLE_MPI=OFF -DPPOHDEM_ENABLE_CGAL=OFF \
    -Dtomlplusplus_DIR="$(dirname "$(dpkg -L libtomlplusplus-dev | grep -m1 'tomlplusplusConfig.cmake$')")"
fi
cmake --build "$CROSS_DIR" --target ppohdem --parallel "$JOBS"
if [ ! -f "$HOST_BUILD_DIR/CMakeCache.txt" ]; then
  cmake -S . -B "$HOST_BUILD_DIR" "${GEN[@]}" -DCMAKE_BUILD_TYPE=Release "${LAUNCHER[@]}"
fi
cmake --build "$HOST_BUILD_DIR" --target ppohdem --parallel "$JOBS"

# ---- runs -------------------------------------------------------------------------------------
X86_EXE=("$SRC/$HOST_BUILD_DIR/apps/ppohdem")
ARM_EXE=(qemu-aarch64 -L /usr/aarch64-linux-gnu "$SRC/$CROSS_DIR/apps/ppohdem")
file "$SRC/$CROSS_DIR/apps/ppohdem" | sed 's/^/cross-aarch64: /'

run_all() {  # run_all <dir> <ppohdem command...>
  local dir=$1; shift
  rm -rf "$dir"; mkdir -p "$dir"/{sdf,hertz_reference,hertz_fast,seed}
  (cd "$dir/sdf" &&
     "$@" voxelize --quiet --mesh "$SRC/fixtures/meshes/fandisk.stl" --cells 21 15 21 \
       --box -0.6 -0.4 -0.6 0.6 0.4 0.6 --method fast --out fandisk_fast.vtk &&
     "$@" voxelize --quiet --mesh "$SRC/fixtures/meshes/box.stl" --cells 21 11 7 \
       --box -1.5 -1 -0.75 1.5 1 0.75 --method exact --out box_exact.vtk)
  for engine in reference fast; do
    cp "$SRC/fixtures/scenes/two_spheres.toml" "$SRC/fixtures/scenes/two_spheres.csv" "$dir/hertz_$engine/"
    (cd "$dir/hertz_$engine" && "$@" simulate --quiet --engine "$engine" --steps "$HERTZ_STEPS" two_spheres.toml)
  done
  cp "$SRC/fixtures/seed-sample/input_params_update.dat" "$dir/seed/"
  { echo "$SRC/fixtures/meshes/dragon_100k.stl"; tail -n +2 "$SRC/fixtures/seed-sample/input_constants_voxelizer.dat"; } \
    >"$dir/seed/input_constants_voxelizer.dat"
  if [ -n "${SEED_FIELD_FROM:-}" ]; then  # the dragon's field made by the other machine's run
    cp "$SEED_FIELD_FROM"/distance_*.dat "$SEED_FIELD_FROM"/object_mesh.stl "$dir/seed/"
  else
    (cd "$dir/seed" && "$@" voxelize --quiet input_constants_voxelizer.dat)
  fi
  for engine in reference fast; do
    mkdir -p "$dir/seed/$engine"
    cp "$dir/seed/input_params_update.dat" "$dir/seed/$engine/"
    (cd "$dir/seed" && "$@" simulate --quiet --engine "$engine" --steps "$SEED_STEPS" input_params_update.dat &&
       mv out "$engine/out")
  done
}
RUNS="$CROSS_DIR/runs"
echo "cross-aarch64: x86-64 runs"
time run_all "$RUNS/x86_64" "${X86_EXE[@]}"
echo "cross-aarch64: aarch64 runs (qemu-user)"
# SEED_FIELD=host: the aarch64 seed run reads the x86-64 run's dragon field instead of making its
# own (76^3 nodes, 100,000 triangles: long under qemu on a busy machine); the seed comparison
# then checks the DEM alone (the SDF comparison is the `sdf` runs').
if [ "${SEED_FIELD:-}" = host ]; then export SEED_FIELD_FROM="$SRC/$RUNS/x86_64/seed"; fi
time run_all "$RUNS/aarch64" "${ARM_EXE[@]}"

# ---- compare ----------------------------------------------------------------------------------
# Header lines ('#' in CSV, '//' in POV-Ray files: dates, thread counts, host, compiler flags) are
# not compared; everything else byte for byte,
# and for differing text files the numbers are compared to say by how much.
/usr/bin/python3 - "$RUNS/x86_64" "$RUNS/aarch64" <<'PY'
import os, re, sys
a_root, b_root = sys.argv[1], sys.argv[2]
num = re.compile(rb'[-+]?(?:\d+\.?\d*|\.\d+)(?:[eEdD][-+]?\d+)?')
def body(path):
    with open(path, 'rb') as f:
        data = f.read()
    if path.endswith('.vtk'):  # line 2, the title: program, host and date
        lines = data.split(b'\n', 2)
        return lines[0] + b'\n' + (lines[2] if len(lines) > 2 else b'')
    if path.endswith('.stl') or b'\0' in data[:4096]:
        return data
    return b''.join(l for l in data.splitlines(True) if not l.startswith((b'#', b'//')))
failed = 0
for dirpath, _, files in sorted(os.walk(a_root)):
    for name in sorted(files):
        a = os.path.join(dirpath, name)
        rel = os.path.relpath(a, a_root)
        b = os.path.join(b_root, rel)
        if not os.path.exists(b):
            print(f'  {rel}: MISSING on aarch64'); failed = 1; continue
        x, y = body(a), body(b)
        if x == y:
            print(f'  {rel}: same ({len(x)} bytes)'); continue
        failed = 1
        nx, ny = num.findall(x), num.findall(y)
        if len(nx) == len(ny) and not rel.endswith('.vtk'):
            diff = [(float(p.replace(b'D', b'e')), float(q.replace(b'D', b'e'))) for p, q in zip(nx, ny) if p != q]
            rel_max = max((abs(p - q) / max(abs(p), abs(q), 1e-300) for p, q in diff), default=0.0)
            print(f'  {rel}: DIFFERS in {len(diff)} of {len(nx)} numbers, largest relative difference {rel_max:.3g}')
        else:
            print(f'  {rel}: DIFFERS ({len(x)} vs {len(y)} bytes)')
sys.exit(failed)
PY
