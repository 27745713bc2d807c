#!/usr/bin/env bash
# SDF speed-versus-error benchmark (issue 4). One script, one machine:
#   ours: "fast" exact everywhere (2 threads; 1 thread up to 128^3; float storage at 128^3) and its band
#   mode (--band 3: exact within 3 h, closest-triangle transfer beyond; 2 threads); the reference
#   builders (only at 64^3, where they finish quickly); the CGAL oracle (2 threads); OpenVDB
#   meshToVolume with a 3-voxel band and with a whole-grid band (time-boxed: "did not finish in
#   N s"), on bunny_closed and dragon at 64^3, 128^3, 256^3, plus the open bunny at 64^3
#   (compared with the reference's winding number: CGAL has no sign for an open mesh, and
#   OpenVDB needs closed meshes); then ci/bench-sdf-process.sh: the whole `ppohdem voxelize`
#   process against the CGAL oracle's at 128^3.
# Writes  $BUILD/bench-sdf/results.tsv, docs/img/sdf_time_vs_error.png and prints the table,
# the load average before and after (the machine may be shared) and the disk write bandwidth.
# Oracle fields are cached in $BUILD/bench-sdf/cache between runs (the first run spends about
# 5 of its minutes in CGAL at 256^3).
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
echo "bench-sdf: start $(date -u '+%Y-%m-%d %H:%M:%S UTC'), load: $(uptime | sed 's/.*load average: //')" | tee "$OUT/load.txt"

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
rm -f "$OUT/runs.txt"
printf 'mesh\tn\tmethod\tthreads\tprecision\tstatus\tseconds\tnodes_per_second\tpeak_rss_bytes\tfield_bytes\tmax_all_h\trms_all_h\tmax_band_h\trms_band_h\tsign_mismatches\toracle\tload1\n' >"$RESULTS"

kv() { tr ' ' '\n' <<<"$1" | sed -n "s/^$2=//p"; }

# record MESH N LABEL THREADS ORACLE_FILE ORACLE_NAME LIMIT -- command...
# Runs the command under `timeout LIMIT`, compares its field with the oracle, appends a row.
record() {
  local mesh=$1 n=$2 label=$3 threads=$4 oracle=$5 oname=$6 limit=$7; shift 8
  local field=$OUT/${mesh}_${n}_${label}.f64 line status=ok load
  load=$(cut -d' ' -f1 /proc/loadavg)
  if line=$(timeout "$limit" "$@" --out "$field" 2>"$OUT/last.err"); then :; else
    local rc=$?
    status=$([ $rc = 124 ] && echo "did not finish in ${limit} s" || echo "failed ($rc)")
    printf '%s\t%s\t%s\t%s\t-\t%s\t-\t-\t-\t-\t-\t-\t-\t-\t-\t%s\t%s\n' "$mesh" "$n" "$label" "$threads" "$status" "$oname" "$load" >>"$RESULTS"
    echo "$mesh $n $label: $status"; rm -f "$field"; return 0
  fi
  local cmp
  cmp=$("$BENCH" compare --mesh "$MESHES/$mesh.stl" --n "$n" --candidate "$field" --oracle "$oracle" --band 3)
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$mesh" "$n" "$label" "$threads" \
    "$(kv "$line" precision)" "$status" "$(kv "$line" seconds)" "$(kv "$line" nodes_per_second)" \
    "$(kv "$line" peak_rss_bytes)" "$(kv "$line" field_bytes)" "$(kv "$cmp" max_all_h)" "$(kv "$cmp" rms_all_h)" \
    "$(kv "$cmp" max_band_h)" "$(kv "$cmp" rms_band_h)" "$(kv "$cmp" sign_mismatches)" "$oname" "$load" >>"$RESULTS"
  echo "$mesh $n $label: $(kv "$line" seconds) s, max $(kv "$cmp" max_all_h) h (band $(kv "$cmp" max_band_h) h)," \
       "sign mismatches $(kv "$cmp" sign_mismatches), load $load"
  echo "$line" >>"$OUT/runs.txt"
  rm -f "$field"
}

for mesh in bunny_closed dragon_100k; do
  for n in $SIZES; do
    M=$MESHES/$mesh.stl
    ORACLE=$CACHE/${mesh}_${n}_cgal.f64
    if [ ! -f "$ORACLE" ] || [ ! -f "$ORACLE.txt" ]; then
      line=$("$BENCH" run --method cgal --threads 2 --mesh "$M" --n "$n" --out "$ORACLE")
      echo "$line load1=$(cut -d' ' -f1 /proc/loadavg)" >"$ORACLE.txt"
    fi
    line=$(cat "$ORACLE.txt")
    printf '%s\t%s\tcgal-oracle\t2\tdouble\tok (cached %s)\t%s\t%s\t%s\t%s\t0\t0\t0\t0\t0\tcgal\t%s\n' "$mesh" "$n" \
      "$(date -u -r "$ORACLE.txt" '+%m-%d %H:%M')" "$(kv "$line" seconds)" "$(kv "$line" nodes_per_second)" \
      "$(kv "$line" peak_rss_bytes)" "$(kv "$line" field_bytes)" "$(kv "$line" load1)" >>"$RESULTS"
    F=(run --method fast --mesh "$M" --n "$n")
    record "$mesh" "$n" fast-2t 2 "$ORACLE" cgal 600 -- "$BENCH" "${F[@]}" --threads 2
    # One thread at 64^3 and 128^3 (the 2-thread speed-up is fast-1t / fast-2t); not at 256^3,
    # to keep the whole script within 15 minutes on an idle machine.
    [ "$n" = 256 ] || record "$mesh" "$n" fast-1t 1 "$ORACLE" cgal 600 -- "$BENCH" "${F[@]}" --threads 1
    record "$mesh" "$n" fast-band3-2t 2 "$ORACLE" cgal 600 -- "$BENCH" "${F[@]}" --threads 2 --band 3
    if [ "$n" = 128 ]; then
      record "$mesh" "$n" fast-band3-1t 1 "$ORACLE" cgal 600 -- "$BENCH" "${F[@]}" --threads 1 --band 3
      record "$mesh" "$n" fast-float-2t 2 "$ORACLE" cgal 600 -- "$BENCH" "${F[@]}" --threads 2 --precision float
    fi
    if [ "$n" = 64 ]; then
      record "$mesh" "$n" exact 1 "$ORACLE" cgal "$REF_LIMIT" -- "$BENCH" run --method exact --threads 1 --mesh "$M" --n "$n"
      record "$mesh" "$n" seed 1 "$ORACLE" cgal "$REF_LIMIT" -- "$BENCH" run --method seed --threads 1 --mesh "$M" --n "$n"
    fi
    record "$mesh" "$n" openvdb-band3 2 "$ORACLE" cgal 300 -- "$VDB" --band 3 --threads 2 --mesh "$M" --n "$n"
    record "$mesh" "$n" openvdb-whole 2 "$ORACLE" cgal "$VDB_WHOLE_LIMIT" -- "$VDB" --band whole --threads 2 --mesh "$M" --n "$n"
  done
done

# The open bunny: the oracle is the reference's winding-number sign with its exact distance.
M=$MESHES/bunny.stl
REFO=$CACHE/bunny_64_exact.f64
[ -f "$REFO" ] || "$BENCH" run --method exact --threads 1 --mesh "$M" --n 64 --out "$REFO" >"$REFO.txt"
record bunny 64 fast-2t 2 "$REFO" reference-exact 600 -- "$BENCH" run --method fast --threads 2 --mesh "$M" --n 64
record bunny 64 fast-band3-2t 2 "$REFO" reference-exact 600 -- "$BENCH" run --method fast --threads 2 --band 3 --mesh "$M" --n 64
record bunny 64 openvdb-band3 2 "$REFO" reference-exact 300 -- "$VDB" --band 3 --threads 2 --mesh "$M" --n 64

# The whole `ppohdem voxelize` process against the CGAL oracle's, at 128^3 on the dragon
# (issue 37; interleaved rounds, its own table).
SIZES=128 bash "$ROOT/ci/bench-sdf-process.sh" "$BUILD"

# Write bandwidth of this machine (the "physical view" in docs/performance.md).
dd if=/dev/zero of="$OUT/dd.bin" bs=16M count=8 conv=fdatasync 2>"$OUT/dd.txt" || true
rm -f "$OUT/dd.bin"
tail -1 "$OUT/dd.txt"

echo "bench-sdf: end $(date -u '+%Y-%m-%d %H:%M:%S UTC'), load: $(uptime | sed 's/.*load average: //')" | tee -a "$OUT/load.txt"
/usr/bin/python3 "$ROOT/validation/benchmarks/plot_sdf.py" "$RESULTS" "$ROOT/docs/img/sdf_time_vs_error.png"
echo "bench-sdf: total $(( $(date +%s) - START )) s; results in $RESULTS"
