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
#   THREADS ("1 2"), PIN=1 (bind Quarry's threads to cores, OMP_PROC_BIND=true: only on a
#   machine known to be idle; a run pinned to a busy core took 88 s of wall time for 49 s of
#   CPU, issue 21), QUIET_WAIT (s to wait for an idle machine before each run), MACHINE (name
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
source "$BENCH/lib.sh"

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
MACHINE=${MACHINE:-"$(nproc)cpu-$(cpu_slug)"}
RESULTS="$BENCH/results/$DATE-$MACHINE"
# An earlier invocation of the same day and machine keeps its files: this one takes the next free
# suffix (-b, -c, ...). APPEND=1 adds this invocation's runs to the day's latest file instead
# (e.g. SIZES="1m" after a run of the smaller sizes, one report for both).
[ "${BEDS_ONLY:-0}" != 1 ] && RESULTS=$(results_name "$RESULTS")

# ---- build Quarry (Release) ------------------------------------------------------------------
build_bench quarry_settled_bed quarry_bench_report
QBIN="$ROOT/$BUILD_DIR/bench/quarry_settled_bed"
QREPORT="$ROOT/$BUILD_DIR/bench/quarry_bench_report"

# ---- install the peers (Debian 12 packages) ----------------------------------------------------
[ "${SKIP_INSTALL:-0}" != 1 ] && install_peers
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMP_NUM_THREADS=1          # the peers' binaries; Quarry sets its own thread count
MPIRUN="mpirun -np 2 --bind-to core"
BIND="OMP_PROC_BIND=false"
[ "${PIN:-0}" = 1 ] && BIND="OMP_PROC_BIND=true OMP_PLACES=cores"

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

# ---- one timed run: appends one CSV row ---------------------------------------------------------
bench_one() {   # size code threads rep
  local s=$1 code=$2 np=$3 rep=$4 nx ny nz steps how
  read -r nx ny nz steps how <<<"$(geom "$s")"
  local tag="${s}_${code}_np${np}_r${rep}" log="$LOGS/${s}_${code}_np${np}_r${rep}.log"
  local cmd launch=""
  [ "$np" = 2 ] && launch="$MPIRUN"
  case $code in
    quarry)       cmd="env $BIND $QBIN --nx $nx --ny $ny --nz $nz --bed quarry_$s.qck --threads $np --warmup $NWARM --steps $steps"; launch="" ;;
    liggghts)     cmd="liggghts -in in.lig.bench -var rfile lig_$s.rst" ;;
    lmp_granular) cmd="lmp -in in.lmp.bench -var model granular -var rfile bed_$s.rst" ;;
    lmp_ghh)      cmd="lmp -in in.lmp.bench -var model ghh -var rfile bed_$s.rst" ;;
  esac
  [ "$code" != quarry ] && cmd="$cmd -var nx $nx -var ny $ny -var nz $nz -var nwarm $NWARM -var nsteps $steps -log none"
  wait_quiet
  # shellcheck disable=SC2086 # $launch and $cmd are word lists
  timed_run "$tag" "$log" "$RUNS" $launch $cmd
  parse_run_log "$code" "$log" "$steps"
  echo "$DATE,$MACHINE,$s,$R_N,$code,$np,$rep,$steps,$R_LOOP,$R_PSS,$R_COORD,$R_NEIGH,$R_NB,$RSS_KIB,$R_ZMAX,$R_ZMEAN,$R_FLOOR,$R_WEIGHT,$OTHER_LOAD" >> "$RESULTS.csv"
  echo "  $tag: $(awk -v p="$R_PSS" 'BEGIN{printf "%.2f", p/1e6}') M particle-steps/s (loop $R_LOOP s, other load $OTHER_LOAD cores)"
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
  machine_line
  echo "- Invocation: \`SIZES=\"$SIZES\" REPEATS=$REPEATS CODES=\"$CODES\" THREADS=\"$THREADS\" PIN=${PIN:-0} bash bench/run.sh\`; Quarry commit $(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo unknown) (plus uncommitted changes, if any)"
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
