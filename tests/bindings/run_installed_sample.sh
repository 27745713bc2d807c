#!/usr/bin/env bash
# Builds one of the ORIGINAL, unmodified ppohDEM sample programs (or a C program) against an installed ppohdem
# exactly as docs/fortran.md tells users to (mpif90 + pkg-config), runs it, and compares its
# files byte for byte with the original program's stored outputs (fixtures/ppohdem-1.0).
#
#   run_installed_sample.sh PREFIX FIXTURES WORK CASE
#     PREFIX    an install prefix (cmake --install build --prefix PREFIX)
#     FIXTURES  the repository's fixtures/ folder
#     WORK      a scratch folder (emptied)
#     CASE      util-cube-np1 | util-cube-np2 | util-sphere-{centered,offset}-np{1,2}
#               | dem-10 (Time_finish 10: frames 1-10, the dumps up to step 5000)
#               | dem-full (the shipped input: 300 frames, the dumps up to step 150000; ~1-2 min)
#               | dem-pattern (another valid call pattern: tests/bindings/fortran/dem_pattern.f90)
#               | dem-corrected (PPOHDEM_PHYSICS=corrected, 500 steps: free fall, closed form)
#               | c-pkgconfig (a C program built with cc + pkg-config ppohdem-c)
set -euo pipefail
prefix=$(realpath "$1"); fixtures=$(realpath "$2"); work=$3; case_name=$4
export PKG_CONFIG_PATH="$prefix/lib/pkgconfig${PKG_CONFIG_PATH:+:$PKG_CONFIG_PATH}"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
here=$(dirname "$(realpath "$0")")
orig="$fixtures/ppohdem-1.0"
rm -rf "$work" && mkdir -p "$work" && cd "$work"
work=$(pwd)
fail=0

same() {  # same FILE EXPECTED_STREAM_COMMAND...
  local file=$1; shift
  if cmp -s "$file" <("$@"); then echo "identical: $file"; else echo "DIFFERS:   $file"; fail=1; fi
}

build() {  # build SOURCE PKG OUT — the contract line of docs/fortran.md
  # shellcheck disable=SC2046
  mpif90 $(pkg-config --cflags "$2") "$1" $(pkg-config --libs "$2") -o "$3"
}

case $case_name in
  util-*)
    build "$orig/source/utils/src/sample_DEMutil.f90" ppohdem-util-fortran sample_DEMutil
    mkdir -p input data
    ranks=${case_name##*-np}
    shape=${case_name%-np*}
    if [[ $shape == util-cube ]]; then
      cp "$orig/util-cube/input_constants_voxelizer.dat" input/
      cp "$orig/test-cube.stl" data/
      expected_dir="$orig/util-cube/np$ranks"; names=(distance_0000.dat distance_0001.dat)
      expect_stl=(cat "$orig/object_mesh_cube.stl")
    else
      variant=${shape#util-sphere-}
      cp "$orig/util-sphere/$variant/input_constants_voxelizer.dat" input/
      xz -dc "$orig/util-sphere/sphere_uv64x32.stl.xz" > data/sphere_uv64x32.stl
      expected_dir="$orig/util-sphere/$variant"; names=("np${ranks}_distance_0000.dat" "np${ranks}_distance_0001.dat")
      expect_stl=(xz -dc "$orig/util-sphere/$variant/object_mesh.stl.xz")
    fi
    mpirun --oversubscribe -np "$ranks" ./sample_DEMutil > stdout.txt 2>&1 || { cat stdout.txt; exit 1; }
    for ((r = 0; r < ranks; r++)); do
      same "distance_000$r.dat" xz -dc "$expected_dir/${names[$r]}.xz"
    done
    same object_mesh.stl "${expect_stl[@]}"
    # The timing logs keep the original's format: (1I3,F16.6) lines, then 'Total ' (1A,F16.6).
    for log in log-timings1 log-timings2 log-timings3 log-timings_0000.log; do
      if ! grep -Eq '^Total +[0-9]+\.[0-9]{6}$' "$log" || ! grep -Eq '^  1 +[0-9]+\.[0-9]{6}$' "$log"; then
        echo "BAD FORMAT: $log"; fail=1
      fi
    done
    ;;
  dem-10|dem-full|dem-pattern)
    if [[ $case_name == dem-pattern ]]; then
      build "$here/fortran/dem_pattern.f90" ppohdem-dem-fortran sample_program
    else
      build "$orig/source/examples/sample_main01.f90" ppohdem-dem-fortran sample_program
    fi
    mkdir -p data obj distance fullprec
    xz -dc "$orig/util-cube/np1/distance_0000.dat.xz" > distance_0000.dat
    cp "$orig/object_mesh_cube.stl" object_mesh.stl
    d="$orig/dem-sample"
    if [[ $case_name == dem-full ]]; then
      cp "$d/input_params_update.dat" .
      frames=300; dumps=0,1,2,10,100,500,1000,5000,50000,150000; objects=(001 002 010 100 150 300)
    else
      sed 's/^Time_finish: 300/Time_finish: 10/' "$d/input_params_update.dat" > input_params_update.dat
      frames=10; dumps=0,1,2,10,100,500,1000,5000; objects=(001 002 010)
      [[ $case_name == dem-pattern ]] && { frames=2; dumps=0,500,1000; objects=(001 002); }
    fi
    PPOHDEM_RANDOM_SEED=12345 PPOHDEM_STATE_DUMPS=$dumps ./sample_program > stdout.txt 2>&1 || { cat stdout.txt; exit 1; }
    for s in ${dumps//,/ }; do
      name=$(printf 'state_step%06d.dat' "$s")
      expected="$d/fullprec/$name.xz"; [[ $s == 150000 ]] && expected="$d/fullprec/state_final.dat.xz"
      same "fullprec/$name" xz -dc "$expected"
    done
    cat $(for ((f = 1; f <= frames; f++)); do printf 'data/out%03d.dat ' "$f"; done) > frames.dat
    same frames.dat sh -c "xz -dc '$d/data/out001_to_out300.dat.xz' | head -c $((frames * 39000))"
    [[ -e $(printf 'data/out%03d.dat' $((frames + 1))) ]] && { echo "EXTRA FRAME written"; fail=1; }
    same objects_distance.csv xz -dc "$d/objects_distance/objects_distance_init.csv.xz"
    for n in "${objects[@]}"; do
      same "distance/objects_distance$n.csv" xz -dc "$d/objects_distance/objects_distance$n.csv.xz"
      same "obj/obj$n.pov" cat "$d/obj/obj$n.pov"
    done
    ;;
  dem-corrected)
    build "$orig/source/examples/sample_main01.f90" ppohdem-dem-fortran sample_program
    mkdir -p data obj distance
    xz -dc "$orig/util-cube/np1/distance_0000.dat.xz" > distance_0000.dat
    cp "$orig/object_mesh_cube.stl" object_mesh.stl
    sed 's/^Time_finish: 300/Time_finish: 1/' "$orig/dem-sample/input_params_update.dat" > input_params_update.dat
    PPOHDEM_PHYSICS=corrected PPOHDEM_RANDOM_SEED=12345 ./sample_program > stdout.txt 2>&1 || { cat stdout.txt; exit 1; }
    [[ -e data/out001.dat && ! -e data/out002.dat ]] || { echo "expected exactly one frame"; fail=1; }
    # No contact during the first 500 steps (1 s): the sheet falls freely, and velocity Verlet is
    # exact for a constant acceleration: z = z0 - g t^2 / 2 = z0 - 0.005 (g = 0.01, t = 1 s),
    # x and y unchanged. The frame lists the particles in id order with 6 significant digits
    # (E16.6): the tolerance is 0.6 units of the last printed digit (the print's half unit plus
    # margin; 6e-6 at z ~ 5). The original's symplectic Euler falls 0.00501.
    xz -dc "$orig/dem-sample/fullprec/state_step000000.dat.xz" | grep -v '^#' > initial.txt
    if ! paste -d' ' initial.txt data/out001.dat | awk '
        { x0 = $2; y0 = $3; z0 = $4; n = NF; x = $(n-3); y = $(n-2); z = $(n-1); r0 = $11; r = $n
          if (abs(x - x0) > tol(x0) || abs(y - y0) > tol(y0) || abs(z - (z0 - 0.005)) > tol(z0) ||
              abs(r - r0) > tol(r0)) {
            print "particle " $1 ": got " x, y, z, r " expected " x0, y0, z0 - 0.005, r0; bad = 1 } }
        function abs(v) { return v < 0 ? -v : v }
        function tol(v,  e) { e = log(abs(v)) / log(10); e = (e == int(e) || e >= 0) ? int(e) : int(e) - 1
                             return 0.6 * 10 ^ (e - 5) }
        END { if (NR != 600) { print "expected 600 particles, got " NR; bad = 1 }; exit bad }'; then
      fail=1
    else
      echo "free fall of 600 particles as z0 - g t^2 / 2: ok"
    fi
    ;;
  c-pkgconfig)
    # shellcheck disable=SC2046
    cc -std=c99 $(pkg-config --cflags ppohdem-c) "$here/cmake_consumer/version.c" $(pkg-config --libs ppohdem-c) -o version
    ./version | tee version.txt
    grep -Eq '^ppohdem [0-9]+\.[0-9]+\.[0-9]+$' version.txt || fail=1
    ;;
  *) echo "unknown case $case_name" >&2; exit 2 ;;
esac
if [[ $fail == 0 ]]; then echo "$case_name: all files identical to the original's"; fi
exit $fail
