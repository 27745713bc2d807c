#!/usr/bin/env bash
# The issue-7 DEM benchmark against the peers: the standard settling-bed scene
# (validation/peers/make_bench.py: d = 1 mm, 2500 kg/m^3, E = 1e7 Pa, nu = 0.3, measured e = 0.5,
# mu = 0.5, Hertz-Mindlin with history, gravity, lattice at 1.05 d in a walled box,
# dt = 20% of the Rayleigh time) run by ppohdem (every engine `ppohdem simulate --engine`
# offers) and by LIGGGHTS, LAMMPS (GRANULAR) and YADE, each on 1 and 2 cores, in this one script.
#
#   bash ci/bench-dem.sh [--quick] [--build-dir DIR] [--out DIR] [--codes "ours liggghts lammps yade"]
#                        [--sizes "N:STEPS ..."] [--engines "reference fast"] [--repeat K] [--untracked]
#
#   --quick   10,000 particles x 10,000 steps only (< 20 min on the 2-core VM)
#   default   10,000 particles x 10,000 steps and 100,000 particles x 300 steps (< 30 min)
# The 10,000-step run is the settling bed the issue's peer figures describe (LIGGGHTS 6.8e6
# particle-steps/s here against the issue's 6.9e6): the bed falls onto the floor and settles
# (about 4.3 contacts per particle at the end). The first ~1,500 steps are a free fall with
# almost no contacts, so shorter runs (e.g. --sizes "10000:1000") measure the neighbour list
# and integration, not the contact law; docs/performance.md reports both. The 100,000 x 300
# run (free fall) gives the memory per particle and the scaling with N.
#   --engines  the ppohdem engines to run (default: every one `ppohdem simulate --help` lists)
#   --untracked also run every ppohdem engine with `[simulation] energy_balance = false` (no
#              contact energy book-keeping, which none of the peers does), as "<engine>-untracked"
#   (the fast engine also runs once per round with `--alternate-threads 1,2`: 1 and 2 threads
#   taking turns every 500 steps in one process, a 2-thread speed-up free of the drift between
#   separate runs; its own table in results.md)
#   --phases LIST  step numbers ending the timed phases of the 10,000-step run (default
#              "500,2500,6000": free fall, impact, dense settling, settled bed; "none" to skip).
#              ppohdem runs with `simulate --phases`, LIGGGHTS and LAMMPS run their deck's `run` in
#              pieces (`run N upto pre no post no`); results.md gets a table per phase (best
#              over the rounds, against LIGGGHTS on 1 core) and phases.tsv every phase of every run
#   --cores "1"  run every code on 1 core only (default "1 2"; also "2")
#   --repeat K run every code K times, interleaved (all codes once, then all again, ...), and
#              add a table of the best and median loop times and their ratios: on a shared or
#              virtual machine single runs of one binary vary more than the differences
#              looked for (docs/performance.md, the machine)
# Peers missing from PATH are skipped (install: apt-get install liggghts lammps yade).
#
# Per run it prints: particle-steps per second (time loop only: LAMMPS/LIGGGHTS "Loop time",
# YADE's O.run, ppohdem's "wall"), the same from CPU time (user + sys of all processes: less
# sensitive to other jobs on a shared machine), peak memory per particle (sum over ranks of
# /usr/bin/time -v "Maximum resident set size" / N; includes each code's fixed overhead:
# Python for YADE, MPI for all), and the physics cross-check of the final state
# (validation/peers/crosscheck.py, one code for all: kinetic energy, mean height,
# max overlap / d, particle contacts per particle) so we know the codes solved the same problem.
# A markdown table is written to OUT/results.md (default build-bench-dem/results.md) with the
# date, the machine load (uptime) and the command. 2 cores: 2 MPI ranks for LIGGGHTS and LAMMPS,
# 2 OpenMP threads for YADE (it has no MPI in Debian), and for ppohdem 2 threads
# (OMP_NUM_THREADS) and, when the engine runs under MPI, 2 ranks.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
QUICK=0
BUILD_DIR=${BUILD_DIR:-build}
OUT=""
CODES="ours liggghts lammps yade"
SIZES_ARG=""
ENGINES_ARG=""
REPEAT=1
UNTRACKED=0
PHASES_ARG="500,2500,6000"
CORES="1 2"
while [ $# -gt 0 ]; do
  case "$1" in
    --quick) QUICK=1 ;;
    --build-dir) BUILD_DIR=$2; shift ;;
    --out) OUT=$2; shift ;;
    --codes) CODES=$2; shift ;;
    --sizes) SIZES_ARG=$2; shift ;;
    --engines) ENGINES_ARG=$2; shift ;;
    --repeat) REPEAT=$2; shift ;;
    --untracked) UNTRACKED=1 ;;
    --phases) PHASES_ARG=$2; shift ;;
    --cores) CORES=$2; shift ;;
    *) echo "bench-dem: unknown argument $1" >&2; exit 2 ;;
  esac
  shift
done
OUT=${OUT:-$ROOT/build-bench-dem}
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
PY=/usr/bin/python3
# The peers (Debian liggghts, lammps, yade; ~1 min to install here) only for this script.
bash ci/install-deps.sh --peers >&2
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
MPIRUN=(mpirun --oversubscribe --bind-to none -np 2)

case "$BUILD_DIR" in /*) PPOHDEM="$BUILD_DIR/apps/ppohdem" ;; *) PPOHDEM="$ROOT/$BUILD_DIR/apps/ppohdem" ;; esac  # --build-dir absolute or relative
if [[ " $CODES " == *" ours "* ]] && [ ! -x "$PPOHDEM" ]; then
  echo "bench-dem: building ppohdem in $BUILD_DIR" >&2
  BUILD_DIR=$BUILD_DIR bash ci/build.sh >/dev/null
fi
# ppohdem engines: every name `ppohdem simulate --help` lists after "engine:".
ENGINES=()
if [[ " $CODES " == *" ours "* ]]; then
  help=$("$PPOHDEM" simulate --help 2>&1 || true)
  for e in ${ENGINES_ARG:-reference fast}; do
    if grep -qE "engine:.*\b$e\b" <<<"$help"; then ENGINES+=("$e"); else echo "bench-dem: no engine '$e' in $PPOHDEM, skipped" >&2; fi
  done
fi
if ! [[ "$REPEAT" =~ ^[1-9][0-9]*$ ]]; then echo "bench-dem: --repeat needs a positive integer, got '$REPEAT'" >&2; exit 2; fi

if [ "$QUICK" -eq 1 ]; then SIZES=("10000:10000"); else SIZES=("10000:10000" "100000:300"); fi
if [ -n "$SIZES_ARG" ]; then read -r -a SIZES <<<"$SIZES_ARG"; fi
RESULTS="$OUT/results.tsv"
PHASES_TSV="$OUT/phases.tsv"
printf 'code\tN\tcores\tround\tphase\tfirst_step\tlast_step\tseconds\n' >"$PHASES_TSV"
# The phase ends for a run of STEPS steps: the marks below STEPS, or nothing.
phase_marks() {  # steps
  [ "$PHASES_ARG" = none ] && return
  local last=${PHASES_ARG##*,}
  if [ "$1" -gt "$last" ]; then echo "$PHASES_ARG"; fi
}
printf 'code\tN\tcores\tsteps\tloop_s\tpsteps_per_s\tcpu_psteps_per_s\tpeak_rss_MB\tbytes_per_particle\tcrosscheck\n' >"$RESULTS"

# peak RSS [kB] summed over the mem.* files of a run (one per process)
sum_rss() { cat "$1"/mem.* 2>/dev/null | awk -F': ' '/Maximum resident set size/ {s += $2} END {print s + 0}'; }
# user + sys seconds summed over the mem.* files
sum_cpu() { cat "$1"/mem.* 2>/dev/null | awk -F': ' '/User time|System time/ {s += $2} END {print s + 0}'; }

record() {  # code N cores steps loop_seconds rundir finalfile
  local code=$1 n=$2 cores=$3 steps=$4 loop=$5 dir=$6 final=$7
  local rss cpu cross pps cpps
  rss=$(sum_rss "$dir"); cpu=$(sum_cpu "$dir")
  cross=$($PY "$ROOT/validation/peers/crosscheck.py" "$final" 2>/dev/null | tail -1 || true)
  [ -n "$cross" ] || cross="crosscheck failed ($final)"
  pps=$(awk -v n="$n" -v s="$steps" -v t="$loop" 'BEGIN {printf "%.3g", (t > 0 ? n * s / t : 0)}')
  cpps=$(awk -v n="$n" -v s="$steps" -v t="$cpu" 'BEGIN {printf "%.3g", (t > 0 ? n * s / t : 0)}')
  printf '%s\t%s\t%s\t%s\t%.3f\t%s\t%s\t%.1f\t%.0f\t%s\n' "$code" "$n" "$cores" "$steps" "$loop" "$pps" "$cpps" \
    "$(awk -v r="$rss" 'BEGIN {print r / 1024}')" "$(awk -v r="$rss" -v n="$n" 'BEGIN {print r * 1024 / n}')" \
    "$cross" | tee -a "$RESULTS"
}

TIMEV='/usr/bin/time -v -o mem.$$'   # one file per process (pid), expanded inside sh -c

run_peer() {  # code N steps cores case_dir
  local code=$1 n=$2 steps=$3 cores=$4 case_dir=$5
  local dir="$case_dir/$code-$cores" L loop
  rm -rf "$dir"; mkdir -p "$dir"; cd "$dir"
  L=$(cut -d' ' -f1 "$case_dir/box.txt")
  case "$code" in
    lammps|liggghts)
      local exe=lmp deck="$ROOT/validation/peers/lammps/in.bench" extra=(-nocite)
      if [ "$code" = liggghts ]; then exe=liggghts; deck="$ROOT/validation/peers/liggghts/in.bench"; extra=(); fi
      local marks; marks=$(phase_marks "$steps")
      if [ -n "$marks" ]; then  # the deck's one run in pieces: one "Loop time" per phase
        sed "s|^run  *\${steps}.*|variable phase_end index ${marks//,/ } ${steps}\nlabel phase_loop\nrun \${phase_end} upto pre no post no\nnext phase_end\njump SELF phase_loop|" \
          "$deck" >in.phases
        deck=$dir/in.phases
      fi
      local cmd="$TIMEV $exe -in $deck -var data $case_dir/particles.data -var steps $steps -var L $L -var out final.dump -log log.txt ${extra[*]}"
      if [ "$cores" -eq 1 ]; then sh -c "$cmd" >out.txt 2>&1; else "${MPIRUN[@]}" sh -c "$cmd" >out.txt 2>&1; fi
      loop=$(grep -oE 'Loop time of [0-9.eE+-]+' out.txt | awk '{s += $4} END {if (NR) printf "%.6g", s}')
      if [ -n "$marks" ]; then
        grep -oE 'Loop time of [0-9.eE+-]+' out.txt | awk -v c="$code" -v n="$n" -v k="$cores" -v r="$rep" \
          -v m="0,$marks,$steps" 'BEGIN {split(m, e, ",")} {printf "%s\t%s\t%s\t%s\t%d\t%s\t%s\t%s\n", c, n, k, r, NR, e[NR], e[NR + 1], $4}' \
          >>"$PHASES_TSV"
      fi
      record "$code" "$n" "$cores" "$steps" "${loop:-0}" "$dir" final.dump ;;
    yade)
      sh -c "$TIMEV yade -n -j $cores -x $ROOT/validation/peers/yade/bench.py $case_dir/particles.csv $steps $L final.csv" >out.txt 2>&1
      loop=$(grep -oE 'loop_seconds [0-9.]+' out.txt | awk '{print $2}')
      record "yade" "$n" "$cores" "$steps" "${loop:-0}" "$dir" final.csv ;;
  esac
  cd "$ROOT"
}

# scene.toml in the current directory: the case's scene reading its particles and writing
# into DIR/out; "untracked" adds energy_balance = false (no contact energy book-keeping, which
# the peers do not do either).
write_our_scene() {  # case_dir dir [untracked]
  local case_dir=$1 dir=$2 untracked=${3:-}
  sed "s|^file = \"particles.csv\"|file = \"$case_dir/particles.csv\"|; s|^dir = \"ours_out\"|dir = \"$dir/out\"|" \
    "$case_dir/scene.toml" >scene.toml
  if [ -n "$untracked" ]; then sed -i 's|^\[simulation\]$|[simulation]\nenergy_balance = false|' scene.toml; fi
}

run_ours() {  # engine N steps case_dir [untracked]
  local engine=$1 n=$2 steps=$3 case_dir=$4 untracked=${5:-} cores mode dir loop speeds one_loop="" line label=$1
  [ -n "$untracked" ] && label="$engine-untracked"
  for cores in $CORES; do
    for mode in threads ranks; do
      [ "$cores" -eq 1 ] && [ "$mode" = ranks ] && continue
      if [ "$mode" = ranks ] && [ "$engine" = reference ]; then  # serial by design: refuses P > 1
        printf 'ppohdem-%s (ranks)\t%s\t2\t%s\tnot run: the reference engine runs on one rank only\n' \
          "$engine" "$n" "$steps" | tee -a "$RESULTS"
        continue
      fi
      dir="$case_dir/ppohdem-$label-$cores-$mode"
      rm -rf "$dir"; mkdir -p "$dir"; cd "$dir"
      write_our_scene "$case_dir" "$dir" "$untracked"
      local marks; marks=$(phase_marks "$steps")
      local cmd="$TIMEV $PPOHDEM simulate scene.toml --engine $engine --quiet${marks:+ --phases $marks}"
      local ok=0
      if [ "$mode" = threads ]; then
        OMP_NUM_THREADS=$cores sh -c "$cmd" >out.txt 2>&1 && ok=1
      else
        OMP_NUM_THREADS=1 "${MPIRUN[@]}" sh -c "$cmd" >out.txt 2>&1 && ok=1
      fi
      loop=$(grep -oE 'wall [0-9.]+ s' out.txt | head -1 | awk '{print $2}' || true)
      # Under mpirun, an engine without MPI runs two independent copies: its run header then
      # says "ranks 1" and the run is not a 2-rank result.
      if [ "$mode" = ranks ] && ! grep -q 'ranks 2' out.txt; then
        printf 'ppohdem-%s (ranks)\t%s\t2\t%s\tnot run: the engine does not use MPI (header says ranks 1)\n' \
          "$engine" "$n" "$steps" | tee -a "$RESULTS"
        cd "$ROOT"; continue
      fi
      if [ "$ok" -eq 1 ] && [ -n "$loop" ]; then
        record "ppohdem-$label ($mode)" "$n" "$cores" "$steps" "$loop" "$dir" "$dir/out/final.csv"
        # "phase K: steps A-B, wall S s, ..." (simulate --phases)
        sed -nE 's/^phase ([0-9]+): steps ([0-9]+)-([0-9]+), wall ([0-9.]+) s.*/\1 \2 \3 \4/p' out.txt |
          awk -v c="ppohdem-$label ($mode)" -v n="$n" -v k="$cores" -v r="$rep" \
            '{printf "%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n", c, n, k, r, $1, $2, $3, $4}' >>"$PHASES_TSV"
        [ "$cores" -eq 1 ] && one_loop=$loop
        speeds=$(grep -m1 '^threads' out.txt || true)
        if [ -n "$speeds" ]; then
          # With this round's 1-thread time and the probe's line round trip, so that each line
          # says in which state of the machine its ratio was measured.
          line=$(tail -n 1 "$PROBES" 2>/dev/null | grep -oE 'line [0-9]+ ns' || true)
          echo "round $rep, ppohdem-$label, $cores $mode: $loop s$( [ -n "$one_loop" ] && awk -v a="$one_loop" -v b="$loop" \
            'BEGIN {printf " against %.3f s on 1 thread (%.2fx)", a, a / b}')${line:+, probe $line}; $speeds" >>"$SPEEDS"
        fi
      else
        printf 'ppohdem-%s (%s)\t%s\t%s\t%s\tfailed: see %s/out.txt\n' "$label" "$mode" "$n" "$cores" "$steps" "$dir" | tee -a "$RESULTS"
      fi
      cd "$ROOT"
    done
  done
}

# One run of the fast engine that switches between 1 and 2 OpenMP threads every 500 steps
# (`ppohdem simulate --alternate-threads 1,2`): the two counts share the same minutes of the
# machine and the same phases of the run, so their ratio does not carry the drift between
# separate runs. One line per round into alternating.tsv.
ALTERNATING="$OUT/alternating.tsv"
printf 'engine\tN\tsteps\t1_thread_psteps_per_s\t2_threads_psteps_per_s\tratio\n' >"$ALTERNATING"
run_alternating() {  # engine N steps case_dir [untracked]
  local engine=$1 n=$2 steps=$3 case_dir=$4 untracked=${5:-} label=$1 dir one two speeds
  [ -n "$untracked" ] && label="$engine-untracked"
  dir="$case_dir/ppohdem-$label-alternating"
  rm -rf "$dir"; mkdir -p "$dir"; cd "$dir"
  write_our_scene "$case_dir" "$dir" "$untracked"
  if OMP_NUM_THREADS=2 "$PPOHDEM" simulate scene.toml --engine "$engine" --quiet --alternate-threads 1,2 \
      --alternate-every 500 >out.txt 2>&1; then
    one=$(awk '/^alternate threads: 1 thread.*particle-steps/ {print $(NF-4)}' out.txt | tr -d ,)
    two=$(awk '/^alternate threads: 2 thread.*particle-steps/ {print $(NF-4)}' out.txt | tr -d ,)
    if [ -z "$one" ] || [ -z "$two" ]; then
      echo "bench-dem: the alternating run has no ratio ($steps steps: shorter than two blocks of 500)" >&2
      cd "$ROOT"; return
    fi
    printf '%s\t%s\t%s\t%s\t%s\t%s\n' "ppohdem-$label" "$n" "$steps" "$one" "$two" \
      "$(awk -v a="$one" -v b="$two" 'BEGIN {printf "%.3f", (a > 0 ? b / a : 0)}')" | tee -a "$ALTERNATING"
    speeds=$(grep -m1 '^threads' out.txt || true)
    [ -n "$speeds" ] && echo "round $rep, ppohdem-$label, alternating 1 and 2 threads: $speeds" >>"$SPEEDS"
  else
    echo "bench-dem: the alternating run failed: see $dir/out.txt" >&2
  fi
  cd "$ROOT"
}

# The machine's own 2-thread ratio at the moment (validation/peers/scaling_probe.cpp: loops with
# nothing shared between the threads) and what sharing costs (a cache line's round trip between
# the threads, a barrier), once per round, next to the engines' figures.
PROBE="$OUT/scaling_probe"
PROBES="$OUT/probe.txt"
: >"$PROBES"
# The fast engine's own measure of its threads' speeds against each other (the "threads:" line
# of `ppohdem simulate`, fast_engine.hpp ThreadSpeeds): below 1 when the two virtual CPUs are not
# equally fast during the run, which the probe's loops above do not always show.
SPEEDS="$OUT/thread_speeds.txt"
: >"$SPEEDS"
g++ -O2 -fopenmp "$ROOT/validation/peers/scaling_probe.cpp" -o "$PROBE" 2>/dev/null || PROBE=""

LOAD_START=$(uptime)
for spec in "${SIZES[@]}"; do
  n=${spec%%:*}; steps=${spec##*:}
  case_dir="$OUT/n$n"
  mkdir -p "$case_dir"
  $PY validation/peers/make_bench.py "$n" "$steps" "$case_dir"
  for rep in $(seq "$REPEAT"); do
    echo "bench-dem: N = $n, $steps steps (dt = 8.65e-6 s), round $rep of $REPEAT, load: $(uptime)" >&2
    [ -n "$PROBE" ] && echo "round $rep ($(date -u +%H:%M) UTC): $("$PROBE")" | tee -a "$PROBES" >&2
    for code in $CODES; do
      case "$code" in
        ours) for e in "${ENGINES[@]}"; do
                run_ours "$e" "$n" "$steps" "$case_dir"
                [ "$e" = fast ] && [ "$CORES" != 1 ] && run_alternating "$e" "$n" "$steps" "$case_dir"
                [ "$UNTRACKED" -eq 1 ] && run_ours "$e" "$n" "$steps" "$case_dir" untracked
                [ "$UNTRACKED" -eq 1 ] && [ "$e" = fast ] && [ "$CORES" != 1 ] && run_alternating "$e" "$n" "$steps" "$case_dir" untracked
              done ;;
        liggghts|lammps|yade)
          exe=$code; [ "$code" = lammps ] && exe=lmp
          if ! command -v "$exe" >/dev/null 2>&1; then echo "bench-dem: $exe not installed, skipped" >&2; continue; fi
          for cores in $CORES; do run_peer "$code" "$n" "$steps" "$cores" "$case_dir"; done ;;
      esac
    done
  done
done

{
  echo "Measured $(date -u '+%Y-%m-%d %H:%M UTC') on $(nproc) cores ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')),"
  echo "command: \`bash ci/bench-dem.sh$([ "$QUICK" -eq 1 ] && echo ' --quick')$([ "$REPEAT" -gt 1 ] && echo " --repeat $REPEAT")$([ "$UNTRACKED" -eq 1 ] && echo " --untracked")\`; load at start: ${LOAD_START##*load average: }, at end: $(uptime | sed 's/.*load average: //')."
  echo
  echo "| code | N | cores | steps | loop [s] | particle-steps/s (wall) | particle-steps/s (CPU) | peak RSS [MB] | bytes/particle | final state: KE [J], mean z [m], max overlap/d, contacts/particle |"
  echo "|---|---|---|---|---|---|---|---|---|---|"
  tail -n +2 "$RESULTS" | awk -F'\t' 'NF >= 10 {printf "| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", $1, $2, $3, $4, $5, $6, $7, $8, $9, $10} NF < 10 {gsub("\t", " | "); print "| " $0 " |"}'
  if [ "$REPEAT" -gt 1 ]; then
    # Best and median loop time of each (code, N, cores) over the rounds, and the ratios of
    # particle-steps per second against LIGGGHTS on 1 core and against the same code on 1 core
    # (bests against bests, medians against medians).
    echo
    echo "Over the $REPEAT interleaved rounds (loop seconds; ratios of particle-steps per second):"
    echo
    echo "| code | N | cores | runs | best [s] | median [s] | best vs LIGGGHTS 1 core | median vs LIGGGHTS 1 core | median vs own 1 core |"
    echo "|---|---|---|---|---|---|---|---|---|"
    tail -n +2 "$RESULTS" | awk -F'\t' 'NF >= 10 && $5 > 0 {print $1 "\t" $2 "\t" $3 "\t" $5}' |
      sort -t"$(printf '\t')" -k1,1 -k2,2n -k3,3n -k4,4g |
      awk -F'\t' '
        { key = $1 "\t" $2 "\t" $3; if (!(key in count)) order[++keys] = key; t[key, ++count[key]] = $4 }
        END {
          for (k = 1; k <= keys; k++) {
            key = order[k]; c = count[key]
            best[key] = t[key, 1]
            med[key] = (c % 2) ? t[key, (c + 1) / 2] : 0.5 * (t[key, c / 2] + t[key, c / 2 + 1])
          }
          for (k = 1; k <= keys; k++) {
            key = order[k]; split(key, f, "\t")
            o = f[1]; sub(/ \(ranks\)$/, " (threads)", o)  # ppohdem on 1 core runs as 1 thread
            lig = "liggghts\t" f[2] "\t1"; own = o "\t" f[2] "\t1"
            rb = (lig in best) ? sprintf("%.2f", best[lig] / best[key]) : "-"
            rm = (lig in med) ? sprintf("%.2f", med[lig] / med[key]) : "-"
            ro = (own in med) ? sprintf("%.2f", med[own] / med[key]) : "-"
            printf "| %s | %s | %s | %d | %.3f | %.3f | %s | %s | %s |\n", f[1], f[2], f[3], count[key], best[key], med[key], rb, rm, ro
          }
        }'
    # The same rounds paired: a code's r-th run against LIGGGHTS' r-th 1-core run (the rounds
    # run every code once, in order, minutes apart), so a slow minute cancels in part.
    if cut -f1 "$RESULTS" | grep -qx liggghts; then
      echo
      echo "Per round against LIGGGHTS on 1 core (each run's particle-steps per second over those of the same round's LIGGGHTS run):"
      echo
      echo "| code | N | cores | ratio by round | median |"
      echo "|---|---|---|---|---|"
      tail -n +2 "$RESULTS" | awk -F'\t' '
          NF >= 10 && $5 > 0 {
            key = $1 "\t" $2 "\t" $3
            if (!(key in seen)) order[++keys] = key
            t[key, ++seen[key]] = $5
          }
          END {
            for (k = 1; k <= keys; k++) {
              key = order[k]; split(key, f, "\t")
              lig = "liggghts\t" f[2] "\t1"
              if (!(lig in seen) || key == lig) continue
              n = 0; list = ""
              for (r = 1; r <= seen[key] && r <= seen[lig]; r++) {
                q[++n] = t[lig, r] / t[key, r]
                list = list (n > 1 ? ", " : "") sprintf("%.2f", q[n])
              }
              for (a = 1; a <= n; a++) for (b = a + 1; b <= n; b++) if (q[b] < q[a]) { x = q[a]; q[a] = q[b]; q[b] = x }
              m = (n % 2) ? q[(n + 1) / 2] : 0.5 * (q[n / 2] + q[n / 2 + 1])
              printf "| %s | %s | %s | %s | %.2f |\n", f[1], f[2], f[3], list, m
            }
          }'
    fi
  fi
  if [ "$(wc -l <"$PHASES_TSV")" -gt 1 ]; then
    echo
    $PY "$ROOT/validation/peers/phase_table.py" "$PHASES_TSV"
  fi
  if [ "$(wc -l <"$ALTERNATING")" -gt 1 ]; then
    echo
    echo "2 threads against 1 in one run (\`--alternate-threads 1,2 --alternate-every 500\`: blocks of 500 steps"
    echo "in the order 1 2 2 1 1 2 ..., so both see the same minutes of the machine and the same phases of the run):"
    echo
    echo "| engine | N | steps | 1 thread [particle-steps/s] | 2 threads [particle-steps/s] | ratio |"
    echo "|---|---|---|---|---|---|"
    tail -n +2 "$ALTERNATING" | awk -F'\t' '{printf "| %s | %s | %s | %s | %s | %s |\n", $1, $2, $3, $4, $5, $6}'
    tail -n +2 "$ALTERNATING" | sort -t"$(printf '\t')" -k1,1 -k2,2n -k6,6g |
      awk -F'\t' '{key = $1 " N = " $2; r[key, ++c[key]] = $6; if (c[key] == 1) o[++k] = key}
        END {for (i = 1; i <= k; i++) {key = o[i]; n = c[key]
          m = (n % 2) ? r[key, (n + 1) / 2] : 0.5 * (r[key, n / 2] + r[key, n / 2 + 1])
          printf "\nMedian ratio, %s: %.3f over %d run(s).\n", key, m, n}}'
  fi
  if [ -s "$PROBES" ]; then
    echo
    echo "The machine's own 2-thread ratio (time on 1 thread / on 2) at the start of each round"
    echo "(validation/peers/scaling_probe.cpp: independent multiply chains, and a sum over 32 MB),"
    echo "and what sharing costs between the two threads (a cache line's round trip, a barrier):"
    echo
    sed 's/^/- /' "$PROBES"
  fi
  if [ -s "$SPEEDS" ]; then
    echo
    echo "The fast engine's threads against each other, as its force kernel measured them in each run"
    echo "(the slowest thread's speed over the fastest's; with 2 threads at a ratio q the run can be at"
    echo "most 1 + q times as fast as on the faster core alone), with the same round's 1-thread run and"
    echo "the probe's line round trip (docs/machine.md \"Two states of the VM\": 90-170 ns and"
    echo "380-450 ns are two placements of the two vCPUs, and the 2-thread ratio follows them):"
    echo
    sed 's/^/- /' "$SPEEDS"
  fi
} >"$OUT/results.md"
echo "bench-dem: wrote $OUT/results.md" >&2
cat "$OUT/results.md"
