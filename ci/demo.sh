#!/usr/bin/env bash
# The README's demo command: install dependencies, build, and run the main job on a built-in
# example — the seed's DEM-Util distance_calculate sample (List 2.1 of the user's guide: the
# Stanford dragon placed in a 44^3 data space on 76^3 nodes), the original program reproduced byte
# for byte, the same mesh on a 64^3 grid checked against the independent CGAL oracle, a DEM
# impact, and the seed's sample_main01 (particles on a moving object) end to end. ~3 minutes.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
bash ci/install-deps.sh
bash ci/build.sh
BIN="$ROOT/${BUILD_DIR:-build}/apps/ppohdem"
VAL="$ROOT/${BUILD_DIR:-build}/validation/tools"
OUT="${DEMO_OUT:-$ROOT/demo-output}"
mkdir -p "$OUT"

echo "== 1. mesh statistics"
"$BIN" mesh-info fixtures/meshes/dragon_100k.stl

echo "== 2. the seed's sample: ppohdem voxelize input_constants_voxelizer.dat (in $OUT)"
cat > "$OUT/input_constants_voxelizer.dat" <<DAT
$ROOT/fixtures/meshes/dragon_100k.stl
./
76 76 76
Lx_Ly_Lz: 44 44 44
sizeX_sizeY_sizeZ: 10 10 10
posX_posY_posZ: 22 22 11
DAT
(cd "$OUT" && "$BIN" voxelize input_constants_voxelizer.dat --vtk distance.vtk)
head -c 200 "$OUT/distance_0000.dat" | head -3

echo "== 3. the original program, number for number: --compat ppohdem-1.0 on its own test cube"
mkdir -p "$OUT/compat/data"
cp fixtures/ppohdem-1.0/test-cube.stl "$OUT/compat/data/"
cp fixtures/ppohdem-1.0/util-cube/input_constants_voxelizer.dat "$OUT/compat/"
(cd "$OUT/compat" && "$BIN" voxelize --compat ppohdem-1.0 input_constants_voxelizer.dat)
if xz -dc fixtures/ppohdem-1.0/util-cube/np1/distance_0000.dat.xz | cmp -s - "$OUT/compat/distance_0000.dat"; then
  echo "compat: distance_0000.dat is byte-identical to the original Fortran program's output"
else
  echo "compat: distance_0000.dat DIFFERS from the original's output" >&2; exit 1
fi

echo "== 4. the dragon on a 64^3 grid: fast (2 MPI ranks), exact and seed, against the CGAL oracle"
BOX="-8 -1 -4 8 11 4"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
mpirun -np 2 --oversubscribe "$BIN" voxelize --mesh fixtures/meshes/dragon_100k.stl --cells 64 64 64 --box $BOX --threads 1 --out "$OUT/dragon_fast.vtk"
"$BIN" voxelize --mesh fixtures/meshes/dragon_100k.stl --cells 64 64 64 --box $BOX --method exact --out "$OUT/dragon_exact.vtk"
"$BIN" voxelize --mesh fixtures/meshes/dragon_100k.stl --cells 64 64 64 --box $BOX --method seed --out "$OUT/dragon_seed.vtk"
if [ -x "$VAL/ppohdem-oracle" ]; then
  "$VAL/ppohdem-oracle" --mesh fixtures/meshes/dragon_100k.stl --cells 64 64 64 --box $BOX --threads 2 --out "$OUT/dragon_cgal.vtk"
  for m in fast exact seed; do
    echo "-- $m vs CGAL"
    "$VAL/ppohdem-compare" "$OUT/dragon_$m.vtk" "$OUT/dragon_cgal.vtk" | grep -E "max \||RMS|sign mismatches|Lipschitz"
  done
fi

echo "== 5. DEM: two 1 mm spheres, Hertz-Mindlin, e = 0.5 (fixtures/scenes/two_spheres.toml)"
mkdir -p "$OUT/two_spheres"
cp fixtures/scenes/two_spheres.toml fixtures/scenes/two_spheres.csv "$OUT/two_spheres/"
"$BIN" simulate "$OUT/two_spheres/two_spheres.toml" --quiet
echo "== 6. the seed's sample_main01 end to end: voxelize, then 600 particles falling on the moving,"
echo "==    rotating object for 150,000 steps (the original's own run used its test cube, as here)"
mkdir -p "$OUT/seed-sample"
cat > "$OUT/seed-sample/input_constants_voxelizer.dat" <<DAT
$ROOT/fixtures/ppohdem-1.0/test-cube.stl
./
76 76 76
Lx_Ly_Lz: 44 44 44
sizeX_sizeY_sizeZ: 6 6 6
posX_posY_posZ: 22 22 16
DAT
cp fixtures/seed-sample/input_params_update.dat "$OUT/seed-sample/"
(cd "$OUT/seed-sample" && "$BIN" voxelize input_constants_voxelizer.dat && "$BIN" simulate input_params_update.dat --quiet)
echo "== 6b. the same sample as a modern TOML scene (fixtures/seed-sample/sample_main01.toml, the"
echo "==     dragon of step 2): 2000 steps of it and of the legacy input must agree bit for bit"
MOD="$OUT/seed-sample-modern"
mkdir -p "$MOD/legacy" "$MOD/toml"
cp "$OUT/distance_0000.dat" "$OUT/input_constants_voxelizer.dat" fixtures/seed-sample/input_params_update.dat "$MOD/legacy/"
cp fixtures/seed-sample/sample_main01.toml fixtures/seed-sample/sample_particles.csv "$MOD/toml/"
VOX_ARGS=$(sed -n 's|^#   ppohdem voxelize ||p' fixtures/seed-sample/sample_main01.toml)
(cd "$MOD/toml" && "$BIN" voxelize --quiet ${VOX_ARGS/..\/meshes/$ROOT/fixtures/meshes} >/dev/null &&
  "$BIN" simulate sample_main01.toml --steps 2000 --quiet 2>/dev/null | grep "energy balance")
(cd "$MOD/legacy" && "$BIN" simulate input_params_update.dat --steps 2000 --quiet >/dev/null 2>&1)
if cmp -s <(grep -v '^#' "$MOD/legacy/out/final.csv") <(grep -v '^#' "$MOD/toml/out/final.csv") &&
   cmp -s <(grep -v '^#' "$MOD/legacy/out/objects.csv") <(grep -v '^#' "$MOD/toml/out/objects.csv"); then
  echo "modern: final.csv and objects.csv are identical to the legacy input's"
else
  echo "modern: the TOML scene DIFFERS from the legacy input" >&2; exit 1
fi
echo "== 7. picture of the last frame (POV-Ray; the particles and the cube at step 150,000)"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
# colors.inc is in povray-includes (only recommended by povray).
command -v povray >/dev/null && [ -f /usr/share/povray-3.7/include/colors.inc ] ||
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends povray povray-includes >/dev/null || true
if command -v povray >/dev/null; then
  FRAME="$OUT/seed-sample/out/frame_150000"
  if povray +I"$FRAME.pov" +O"$FRAME.png" +W800 +H600 -D +A +L/usr/share/povray-3.7/include 2>"$FRAME.povray.log"; then
    echo "picture: $FRAME.png"
  else
    echo "picture: povray failed, see $FRAME.povray.log" >&2
  fi
else
  echo "picture: povray is not available; skipped (render $OUT/seed-sample/out/frame_150000.pov yourself)"
fi
echo "== demo outputs are in $OUT (open the .vtk files in ParaView)"
