#!/usr/bin/env bash
# SDF speed-versus-error benchmark (issue 4). One script, one machine:
#   ours ("fast", 2 threads and 1 thread; float storage once), the reference builders (only at
#   64^3, where they finish quickly), the CGAL oracle (2 threads) and OpenVDB meshToVolume with a
#   3-voxel band and with a whole-grid band (time-limited), on bunny_closed and dragon at 64^3,
#   128^3, 256^3, plus the open bunny at 64^3 (compared with the reference's winding number: CGAL
#   has no sign for an open mesh, and OpenVDB needs closed meshes).
# Writes  $BUILD/bench-sdf/results.tsv, docs/img/sdf_time_vs_error.png and prints the table.
# Oracle fields are cached in $BUILD/bench-sdf/cache between runs.
# Usage: ci/bench-sdf.sh [build-dir]      (env: SIZES="64 128 256", VDB_WHOLE_LIMIT=60)
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=${1:-$ROOT/build-bench}
SIZES=${SIZES:-"64 128 256"}
VDB_WHOLE_LIMIT=${VDB_WHOLE_LIMIT:-60}   # seconds before the whole-grid OpenVDB run is stopped
REF_LIMIT=${REF_LIMIT:-120}
OUT=$BUILD/bench-sdf
CACHE=$OUT/cache
mkdir -p "$OUT" "$CACHE"
START=$(date +%s)

if ! dpkg -s libopenvdb-dev libboost-iostreams-dev libcgal-dev >/dev/null 2>&1; then
  if [ "$(id -u)" = 0 ]; then
    apt-get install -y --no-install-recommends libopenvdb-dev libboost-iostreams-dev libcgal-dev
  else
    sudo apt-get install -y --no-install-recommends libopenvdb-dev libboost-iostreams-dev libcgal-dev
  fi
fi
cmake -S "$ROOT" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$BUILD" --target ppohdem-bench-sdf ppohdem-openvdb-sdf -j2
BENCH=$BUILD/validation/benchmarks/ppohdem-bench-sdf
VDB=$BUILD/validation/peers/openvdb/ppohdem-openvdb-sdf
MESHES=$ROOT/fixtures/meshes
RESULTS=$OUT/results.tsv
printf 'mesh\tn\tmethod\tthreads\tprecision\tstatus\tseconds\tnodes_per_second\tpeak_rss_bytes\tfield_bytes\tmax_all_h\trms_all_h\tmax_band_h\trms_band_h\tsign_mismatches\toracle\n' >"$RESULTS"

kv() { tr ' ' '\n' <<<"$1" | sed -n "s/^$2=//p"; }

# record MESH N LABEL THREADS ORACLE_FILE ORACLE_NAME LIMIT -- command...
record() {
  local mesh=$1 n=$2 label=$3 threads=$4 oracle=$5 oname=$6 limit=$7; shift 8
  local field=$OUT/${mesh}_${n}_${label}.f64 line status=ok
  if line=$(timeout "$limit" "$@" --out "$field" 2>"$OUT/last.err"); then :; else
    local rc=$?
    status=$([ $rc = 124 ] && echo "did not finish in ${limit} s" || echo "failed ($rc)")
    printf '%s\t%s\t%s\t%s\t-\t%s\t-\t-\t-\t-\t-\t-\t-\t-\t-\t%s\n' "$mesh" "$n" "$label" "$threads" "$status" "$oname" >>"$RESULTS"
    echo "$mesh $n $label: $status"; return 0
  fi
  local cmp
  cmp=$("$BENCH" compare --mesh "$MESHES/$mesh.stl" --n "$n" --candidate "$field" --oracle "$oracle" --band 3)
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$mesh" "$n" "$label" "$threads" \
    "$(kv "$line" precision)" "$status" "$(kv "$line" seconds)" "$(kv "$line" nodes_per_second)" \
    "$(kv "$line" peak_rss_bytes)" "$(kv "$line" field_bytes)" "$(kv "$cmp" max_all_h)" "$(kv "$cmp" rms_all_h)" \
    "$(kv "$cmp" max_band_h)" "$(kv "$cmp" rms_band_h)" "$(kv "$cmp" sign_mismatches)" "$oname" >>"$RESULTS"
  echo "$mesh $n $label: $(kv "$line" seconds) s, max $(kv "$cmp" max_all_h) h, sign mismatches $(kv "$cmp" sign_mismatches)"
  [ "$label" = fast-2t ] || [ "$label" = exact ] || rm -f "$field"
}

for mesh in bunny_closed dragon_100k; do
  for n in $SIZES; do
    M=$MESHES/$mesh.stl
    ORACLE=$CACHE/${mesh}_${n}_cgal.f64
    if [ ! -f "$ORACLE" ]; then
      line=$("$BENCH" run --method cgal --threads 2 --mesh "$M" --n "$n" --out "$ORACLE")
      echo "$line" >"$ORACLE.txt"
    fi
    line=$(cat "$ORACLE.txt")
    printf '%s\t%s\tcgal-oracle\t2\tdouble\tok\t%s\t%s\t%s\t%s\t0\t0\t0\t0\t0\tcgal\n' "$mesh" "$n" \
      "$(kv "$line" seconds)" "$(kv "$line" nodes_per_second)" "$(kv "$line" peak_rss_bytes)" "$(kv "$line" field_bytes)" >>"$RESULTS"
    record "$mesh" "$n" fast-2t 2 "$ORACLE" cgal 900 -- "$BENCH" run --method fast --threads 2 --mesh "$M" --n "$n"
    if [ "$n" != 64 ] && [ "$n" != 256 ]; then
      record "$mesh" "$n" fast-1t 1 "$ORACLE" cgal 900 -- "$BENCH" run --method fast --threads 1 --mesh "$M" --n "$n"
      record "$mesh" "$n" fast-float-2t 2 "$ORACLE" cgal 900 -- "$BENCH" run --method fast --threads 2 --precision float --mesh "$M" --n "$n"
    fi
    if [ "$n" = 64 ]; then
      record "$mesh" "$n" exact 1 "$ORACLE" cgal "$REF_LIMIT" -- "$BENCH" run --method exact --threads 1 --mesh "$M" --n "$n"
      record "$mesh" "$n" seed 1 "$ORACLE" cgal "$REF_LIMIT" -- "$BENCH" run --method seed --threads 1 --mesh "$M" --n "$n"
    fi
    record "$mesh" "$n" openvdb-band3 2 "$ORACLE" cgal 300 -- "$VDB" --band 3 --threads 2 --mesh "$M" --n "$n"
    if [ "$n" != 256 ]; then
      record "$mesh" "$n" openvdb-whole 2 "$ORACLE" cgal "$VDB_WHOLE_LIMIT" -- "$VDB" --band whole --threads 2 --mesh "$M" --n "$n"
    else
      printf '%s\t%s\topenvdb-whole\t2\t-\tnot run (did not finish in %s s at 128^3)\t-\t-\t-\t-\t-\t-\t-\t-\t-\tcgal\n' "$mesh" "$n" "$VDB_WHOLE_LIMIT" >>"$RESULTS"
    fi
  done
done

# The open bunny: the oracle is the reference's winding-number sign with its exact distance.
M=$MESHES/bunny.stl
REFO=$CACHE/bunny_64_exact.f64
[ -f "$REFO" ] || "$BENCH" run --method exact --threads 1 --mesh "$M" --n 64 --out "$REFO" >"$REFO.txt"
record bunny 64 fast-2t 2 "$REFO" reference-exact 900 -- "$BENCH" run --method fast --threads 2 --mesh "$M" --n 64
record bunny 64 openvdb-band3 2 "$REFO" reference-exact 300 -- "$VDB" --band 3 --threads 2 --mesh "$M" --n 64

# Write bandwidth of this machine (the "physical view" in docs/performance.md).
dd if=/dev/zero of="$OUT/dd.bin" bs=16M count=8 conv=fdatasync 2>"$OUT/dd.txt" || true
rm -f "$OUT/dd.bin"
tail -1 "$OUT/dd.txt"

/usr/bin/python3 "$ROOT/validation/benchmarks/plot_sdf.py" "$RESULTS" "$ROOT/docs/img/sdf_time_vs_error.png"
echo "bench-sdf: total $(( $(date +%s) - START )) s; results in $RESULTS"
