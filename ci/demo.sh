#!/usr/bin/env bash
# The README's demo command: install dependencies, build, and run the main job on a built-in
# example — the seed's DEM-Util distance_calculate sample (List 2.1 of the user's guide: the
# Stanford dragon placed in a 44^3 data space on 76^3 nodes), then the same mesh on a 64^3 grid
# checked against the independent CGAL oracle.
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

echo "== 3. exact and seed methods on a 64^3 grid, against the CGAL oracle"
BOX="-8 -1 -4 8 11 4"
"$BIN" voxelize --mesh fixtures/meshes/dragon_100k.stl --cells 64 64 64 --box $BOX --method exact --out "$OUT/dragon_exact.vtk"
"$BIN" voxelize --mesh fixtures/meshes/dragon_100k.stl --cells 64 64 64 --box $BOX --method seed --out "$OUT/dragon_seed.vtk"
if [ -x "$VAL/ppohdem-oracle" ]; then
  "$VAL/ppohdem-oracle" --mesh fixtures/meshes/dragon_100k.stl --cells 64 64 64 --box $BOX --threads 2 --out "$OUT/dragon_cgal.vtk"
  echo "-- exact vs CGAL"
  "$VAL/ppohdem-compare" "$OUT/dragon_exact.vtk" "$OUT/dragon_cgal.vtk"
  echo "-- seed vs CGAL"
  "$VAL/ppohdem-compare" "$OUT/dragon_seed.vtk" "$OUT/dragon_cgal.vtk"
fi
echo "== demo outputs are in $OUT (open the .vtk files in ParaView)"
