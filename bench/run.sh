#!/usr/bin/env bash
# Quarry vs. LIGGGHTS 3.8.0 and LAMMPS on the settled-bed reference problem (issue 3), side by
# side on this machine: builds Quarry (Release), installs the peers (Debian packages) if missing,
# settles each bed once with LAMMPS and starts every code from those same particles (LIGGGHTS and
# Quarry read LAMMPS' data file and re-settle it 2,000 steps with their own contact model, since
# a data file carries no tangential contact history), times 2,000 steps of each code at 1 and 2
# threads/ranks, interleaving the codes run by run, and writes
#   bench/results/<date>-<machine>.csv   one row per timed run
#   bench/results/<date>-<machine>.md    medians, Quarry/peer ratios, memory, settled-bed check
#   bench/results/<date>-<machine>.png   particle-steps per second against N
# Usage:  bash bench/run.sh                              # 10k 50k 200k, 3 repeats
#         SIZES="10k" REPEATS=3 bash bench/run.sh
#         SIZES="1m" CODES="quarry liggghts" bash bench/run.sh
# Options (environment): SIZES, REPEATS, CODES (quarry liggghts lmp_granular lmp_ghh),
#   THREADS ("1 2"), QUIET_WAIT (s to wait for an idle machine before each run), MACHINE (name
#   in the result files), BUILD_DIR (default build/release = `cmake --preset release`),
#   SKIP_BUILD=1, SKIP_INSTALL=1, BEDS_ONLY=1 (prepare the settled beds, time nothing), APPEND=1
#   (add the runs to the day's latest results file rather than start the next one). Beds and
#   logs go to bench/_work/ (large; not committed); beds are reused by later invocations (delete
#   bench/_work/runs/<code>_<size>.* to rebuild one; a Quarry bed is built from the LAMMPS one,
#   bed_<size>.rst.data, whichever codes are timed).
set -euo pipefail
BENCH=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$BENCH/.." && pwd)
cd "$ROOT"

SIZES=${SIZES:-"10k 50k 200k"}
REPEATS=${REPEATS:-3}
CODES=${CODES:-"quarry liggghts lmp_granular lmp_ghh"}
THREADS=${THREADS:-"1 2"}
QUIET_WAIT=${QUIET_WAIT:-60}
NWARM=200
NRESETTLE=2000   # steps LIGGGHTS and Quarry re-settle the LAMMPS bed (bench/peers/in.lig.settle)
SEED=4711
BUILD_DIR=${BUILD_DIR:-build/release}
WORK="$BENCH/_work"
RUNS="$WORK/runs"
LOGS="$WORK/logs"
DATE=$(date +%F)
cpu_slug() { lscpu | sed -n 's/^Model name: *//p' | head -1 | tr 'A-Z' 'a-z' | sed 's/[^a-z0-9]\+/-/g; s/^-//; s/-$//' | cut -c1-32; }
MACHINE=${MACHINE:-"$(nproc)cpu-$(cpu_slug)"}
RESULTS="$BENCH/results/$DATE-$MACHINE"
# An earlier invocation of the same day and machine keeps its files: this one takes the next free
# suffix (-b, -c, ...). APPEND=1 adds this invocation's runs to the day's latest file instead
# (e.g. SIZES="1m" after a run of the smaller sizes, one report for both).
if [ "${BEDS_ONLY:-0}" != 1 ]; then
  latest=$RESULTS
  for suffix in b c d e f g h i j k l m n o p q r s t u v w x y z; do
    [ -e "$RESULTS.csv" ] || break
    latest=$RESULTS; RESULTS="$BENCH/results/$DATE-$MACHINE-$suffix"
  done
  [ "${APPEND:-0}" = 1 ] && RESULTS=$latest
  [ -e "$RESULTS.csv" ] && [ "${APPEND:-0}" != 1 ] && { echo "bench/run.sh: no free name for the results of $DATE-$MACHINE; set MACHINE" >&2; exit 2; }
fi

# ---- build Quarry (Release) ------------------------------------------------------------------
if [ "${SKIP_BUILD:-0}" != 1 ]; then
  if [ "$BUILD_DIR" = build/release ]; then
    cmake --preset release -DQUARRY_BUILD_BENCH=ON > /dev/null
  else
    cmake --preset release -B "$BUILD_DIR" -DQUARRY_BUILD_BENCH=ON > /dev/null
  fi
  cmake --build "$BUILD_DIR" --target quarry_settled_bed quarry_bench_report
fi
QBIN="$ROOT/$BUILD_DIR/bench/quarry_settled_bed"
QREPORT="$ROOT/$BUILD_DIR/bench/quarry_bench_report"

# ---- install the peers (Debian 12 packages) ----------------------------------------------------
if [ "${SKIP_INSTALL:-0}" != 1 ]; then
  if ! command -v lmp >/dev/null || ! command -v liggghts >/dev/null || ! command -v mpirun >/dev/null \
     || ! env time --version >/dev/null 2>&1; then
    apt-get update
    DEBIAN_FRONTEND=noninteractive apt-get install -y liggghts lammps openmpi-bin time
  fi
fi
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMP_NUM_THREADS=1          # the peers' binaries; Quarry sets its own thread count
MPIRUN="mpirun -np 2 --bind-to core"

mkdir -p "$RUNS" "$LOGS" "$BENCH/results"
for f in "$BENCH"/peers/common.in "$BENCH"/peers/model_* "$BENCH"/peers/in.*; do
  ln -sf "../../peers/$(basename "$f")" "$RUNS/$(basename "$f")"
done

# size -> "nx ny nz steps lammps_recipe"; the LAMMPS bed's recipe as in bench/peers
# (lattice:<settle steps> | tile:<from>:<rx>:<ry>:<resettle>). Every code starts from that bed.
geom() {
  case $1 in
    10k)  echo "20 20 25 2000 lattice:25000" ;;
    50k)  echo "40 50 25 2000 lattice:20000" ;;
    200k) echo "80 100 25 2000 tile:50k:2:2:5000" ;;
    1m)   echo "200 200 25 500 tile:50k:5:4:3000" ;;
    *) echo "unknown size $1" >&2; exit 1 ;;
  esac
}

# ---- settled beds (not timed) ------------------------------------------------------------------
# LAMMPS bed bed_<size>.rst (restart, for the LAMMPS runs) and bed_<size>.rst.data (write_data,
# what LIGGGHTS and Quarry read); then, if LIGGGHTS is timed, its re-settled restart.
build_peer_bed() {   # size
  local s=$1 nx ny nz steps how from rx ry nre
  read -r nx ny nz steps how <<<"$(geom "$s")"
  if [ ! -f "$RUNS/bed_$s.rst" ] || [ ! -f "$RUNS/bed_$s.rst.data" ]; then
    case $how in
      lattice:*)
        ( cd "$RUNS" && $MPIRUN lmp -in in.lmp.settle -var nx $nx -var ny $ny -var nz $nz \
            -var seed $SEED -var model granular -var nsettle ${how#lattice:} \
            -var rfile bed_$s.rst -log none ) > "$LOGS/settle_${s}_lammps.log" 2>&1 ;;
      tile:*)
        IFS=: read -r _ from rx ry nre <<<"$how"
        build_peer_bed "$from"
        ( cd "$RUNS" && $MPIRUN lmp -in in.lmp.replicate -var nx $nx -var ny $ny -var nz $nz \
            -var dfile bed_$from.rst.data -var rx $rx -var ry $ry -var model granular \
            -var nsettle $nre -var rfile bed_$s.rst -log none ) > "$LOGS/settle_${s}_lammps.log" 2>&1 ;;
    esac
  fi
  if [[ " $CODES " == *" liggghts "* ]] && [ ! -f "$RUNS/lig_$s.rst" ]; then
    ( cd "$RUNS" && $MPIRUN liggghts -in in.lig.settle -var nx $nx -var ny $ny -var nz $nz \
        -var dfile bed_$s.rst.data -var nsettle $NRESETTLE -var rfile lig_$s.rst -log none ) \
        > "$LOGS/settle_${s}_liggghts.log" 2>&1
  fi
}

# Quarry starts from the LAMMPS bed, as LIGGGHTS does: same particles (ids, positions, sizes,
# velocities), re-settled NRESETTLE steps with Quarry's model, saved as quarry_<size>.qck.
build_quarry_bed() {   # size
  local s=$1 nx ny nz steps how
  read -r nx ny nz steps how <<<"$(geom "$s")"
  [ -f "$RUNS/quarry_$s.qck" ] && return 0
  build_peer_bed "$s"
  "$QBIN" --nx $nx --ny $ny --nz $nz --from-data "$RUNS/bed_$s.rst.data" --settle-steps $NRESETTLE \
      --threads 2 --steps 0 --bed "$RUNS/quarry_$s.qck" > "$LOGS/settle_${s}_quarry.log" 2>&1
}

busy() { awk '/^cpu /{print $2+$3+$4+$7+$8+$9}' /proc/stat; }   # jiffies, all cores

# The machine may be shared: before each timed run wait (at most QUIET_WAIT s) until the other
# processes use < 0.15 cores over 2 s. Measured either way; the CPU used by others during each
# run is recorded (column other_load).
wait_quiet() {
  local t=0 b0 b1 hz; hz=$(getconf CLK_TCK)
  while [ "$t" -lt "$QUIET_WAIT" ]; do
    b0=$(busy); sleep 2; b1=$(busy); t=$((t+2))
    [ $(( (b1-b0)*100 / (2*hz) )) -lt 15 ] && return 0
  done
  return 0
}

# "key value" of GNU time -v output
time_field() { sed -n "s/^[[:space:]]*$2: //p" "$1" | head -1; }

# ---- one timed run: appends one CSV row ---------------------------------------------------------
bench_one() {   # size code threads rep
  local s=$1 code=$2 np=$3 rep=$4 nx ny nz steps how
  read -r nx ny nz steps how <<<"$(geom "$s")"
  local tag="${s}_${code}_np${np}_r${rep}" log="$LOGS/${s}_${code}_np${np}_r${rep}.log"
  local cmd launch=""
  [ "$np" = 2 ] && launch="$MPIRUN"
  case $code in
    quarry)       cmd="env OMP_PROC_BIND=true OMP_PLACES=cores $QBIN --nx $nx --ny $ny --nz $nz --bed quarry_$s.qck --threads $np --warmup $NWARM --steps $steps"; launch="" ;;
    liggghts)     cmd="liggghts -in in.lig.bench -var rfile lig_$s.rst" ;;
    lmp_granular) cmd="lmp -in in.lmp.bench -var model granular -var rfile bed_$s.rst" ;;
    lmp_ghh)      cmd="lmp -in in.lmp.bench -var model ghh -var rfile bed_$s.rst" ;;
  esac
  [ "$code" != quarry ] && cmd="$cmd -var nx $nx -var ny $ny -var nz $nz -var nwarm $NWARM -var nsteps $steps -log none"
  wait_quiet
  local b0 t0 b1 t1 hz; hz=$(getconf CLK_TCK)
  b0=$(busy); t0=$(date +%s.%N)
  ( cd "$RUNS" && env time -v -o "$LOGS/$tag.time" $launch $cmd ) > "$log" 2>&1 || echo "  $tag FAILED (see $log)"
  b1=$(busy); t1=$(date +%s.%N)
  local user sys rss other
  user=$(time_field "$LOGS/$tag.time" "User time (seconds)")
  sys=$(time_field "$LOGS/$tag.time" "System time (seconds)")
  rss=$(time_field "$LOGS/$tag.time" "Maximum resident set size (kbytes)")
  other=$(awk -v b=$((b1-b0)) -v hz="$hz" -v u="$user" -v s="$sys" -v t0="$t0" -v t1="$t1" \
          'BEGIN{o=(b/hz-u-s)/(t1-t0); if(o<0)o=0; printf "%.3f", o}')
  local n loop pss coord neigh nb zmax zmean floor weight
  if [ "$code" = quarry ]; then
    local line; line=$(grep -m1 '^QUARRY_BENCH' "$log" || true)
    kv() { sed -n "s/.* $1=\([^ ]*\).*/\1/p" <<<"$line"; }
    n=$(kv n); loop=$(kv loop_s); pss=$(kv pss); coord=$(kv coordination); neigh=$(kv neigh_pp)
    nb=$(kv rebuilds); zmax=$(kv zmax); zmean=$(kv zmean); floor=$(kv floor_force); weight=$(kv weight)
  else
    local timed after lt metrics
    after=$(sed -n '/BENCH_BEGIN/,$p' "$log")
    timed=$(sed -n '/BENCH_BEGIN/,/BENCH_END/p' "$log")
    lt=$(grep -m1 -o 'Loop time of [0-9.e+-]* on [0-9]* procs for [0-9]* steps with [0-9]* atoms' <<<"$after" || true)
    loop=$(awk '{print $4}' <<<"$lt"); n=$(awk '{print $12}' <<<"$lt")
    pss=$(awk -v n="$n" -v s="$steps" -v l="$loop" 'BEGIN{if(l>0) printf "%.6g", n*s/l}')
    nb=$(sed -n 's/.*Neighbor list builds = \([0-9]*\).*/\1/p' <<<"$timed" | head -1)
    neigh=$(sed -n 's/.*Ave neighs\/atom = \([0-9.]*\).*/\1/p' <<<"$timed" | head -1)
    coord=$(sed -n 's/^CONTACTS_PER_PARTICLE \([0-9.e+-]*\).*/\1/p' "$log" | head -1)
    metrics=$(grep -m1 '^BED_METRICS' "$log" || true)
    zmax=$(awk '{print $2}' <<<"$metrics"); zmean=$(awk '{print $3}' <<<"$metrics"); weight=$(awk '{print $5}' <<<"$metrics")
    floor=$(awk -v a="$(awk '{print $4}' <<<"$metrics")" -v b="$(sed -n 's/^FZ_NO_FLOOR //p' "$log" | head -1)" \
            'BEGIN{if(a!="" && b!="") printf "%.7g", a-b}')
  fi
  echo "$DATE,$MACHINE,$s,$n,$code,$np,$rep,$steps,$loop,$pss,$coord,$neigh,$nb,$rss,$zmax,$zmean,$floor,$weight,$other" >> "$RESULTS.csv"
  echo "  $tag: $(awk -v p="$pss" 'BEGIN{printf "%.2f", p/1e6}') M particle-steps/s (loop $loop s, other load $other cores)"
}

for s in $SIZES; do
  echo "== settled beds $s"
  [[ " $CODES " =~ " liggghts "|" lmp_" ]] && build_peer_bed "$s"
  [[ " $CODES " == *" quarry "* ]] && build_quarry_bed "$s"   # builds the LAMMPS bed if missing
done
[ "${BEDS_ONLY:-0}" = 1 ] && { echo "beds ready in $RUNS"; exit 0; }
[ -f "$RESULTS.csv" ] || "$QREPORT" --header > "$RESULTS.csv"
for s in $SIZES; do
  echo "== timing $s"
  for rep in $(seq 1 "$REPEATS"); do          # repeats outermost, codes interleaved run by run
    for code in $CODES; do
      for np in $THREADS; do bench_one "$s" "$code" "$np" "$rep"; done
    done
  done
done

"$QREPORT" "$RESULTS.csv" "$RESULTS.md" "$RESULTS.png" \
  "# Quarry vs. LIGGGHTS and LAMMPS, settled bed — $DATE, $MACHINE"
{
  echo
  echo "## Machine and run"
  echo
  # Hosts of one model name differ (a "AMD EPYC" guest may be Zen 3 or Zen 4): family, model,
  # widest vector unit and caches say which one the figures are from.
  cpu_field() { lscpu | sed -n "s/^$1: *//p" | head -1; }
  vector=AVX2; grep -qw avx512f /proc/cpuinfo && vector=AVX-512
  grep -qw avx2 /proc/cpuinfo || vector=SSE
  echo "- CPU: $(cpu_field 'Model name'), family $(cpu_field 'CPU family') model $(cpu_field 'Model'), $vector, L2 $(cpu_field 'L2 cache'), L3 $(cpu_field 'L3 cache'), hypervisor $(cpu_field 'Hypervisor vendor'); $(nproc --all) logical CPUs; memory $(free -g | awk '/^Mem:/{print $2}') GiB"
  echo "- Invocation: \`SIZES=\"$SIZES\" REPEATS=$REPEATS CODES=\"$CODES\" THREADS=\"$THREADS\" bash bench/run.sh\`; Quarry commit $(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo unknown) (plus uncommitted changes, if any)"
  echo "- Beds: every code starts from the same LAMMPS-settled bed (bench/peers); LIGGGHTS and Quarry read its data file and re-settle it $NRESETTLE steps with their own model (a data file has no tangential contact history), LAMMPS continues from its restart."
  for s in $SIZES; do
    # This invocation's last repeat (logs of an earlier one with more repeats may lie beside it).
    last="$LOGS/${s}_quarry_np1_r$REPEATS.log"
    [ -f "$last" ] || continue
    echo
    echo "### Quarry per-stage time, $s, 1 thread ($(basename "$last"))"
    echo
    echo '```'
    sed -n '/^stage/,/^total/p' "$last"
    echo '```'
  done
} >> "$RESULTS.md"
echo "wrote $RESULTS.csv, $RESULTS.md, $RESULTS.png"
