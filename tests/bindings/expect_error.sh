#!/usr/bin/env bash
# expect_error.sh FIXTURES WORK SETUP PROGRAM MESSAGE: runs PROGRAM in WORK (prepared for SETUP:
# none | util | dem) and passes if it exits non-zero, prints MESSAGE, and shows no crash
# (no signal, no Fortran runtime backtrace).
set -uo pipefail
fixtures=$(realpath "$1"); work=$2; setup=$3; program=$(realpath "$4"); message=$5
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 2
case $setup in
  util) mkdir -p input data
        cp "$fixtures/ppohdem-1.0/util-cube/input_constants_voxelizer.dat" input/
        cp "$fixtures/ppohdem-1.0/test-cube.stl" data/ ;;
  dem)  mkdir -p data obj distance
        xz -dc "$fixtures/ppohdem-1.0/util-cube/np1/distance_0000.dat.xz" > distance_0000.dat
        cp "$fixtures/ppohdem-1.0/object_mesh_cube.stl" object_mesh.stl
        cp "$fixtures/ppohdem-1.0/dem-sample/input_params_update.dat" . ;;
esac
output=$("$program" 2>&1); status=$?
echo "$output"
echo "exit status $status"
if [[ $status == 0 ]]; then echo "FAIL: expected a non-zero exit"; exit 1; fi
if [[ $status -gt 128 ]] || grep -q "Backtrace\|Segmentation" <<<"$output"; then echo "FAIL: crashed"; exit 1; fi
if ! grep -qF "$message" <<<"$output"; then echo "FAIL: expected the message: $message"; exit 1; fi
echo "PASS"
