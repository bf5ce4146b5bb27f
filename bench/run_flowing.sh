#!/usr/bin/env bash
# Quarry vs. LIGGGHTS 3.8.0 and LAMMPS on flowing material (issue 21 (a)): a pour. A jittered
# lattice of 4 mm spheres, lifted 5 cm above the floor of a closed box, falls and piles up; the
# settled bed's material (bench/peers: Hertz-Mindlin with history, E = 5 MPa, e = 0.5,
# mu = 0.5) and the same skin in every code. Quarry writes the lattice once as a LAMMPS data
# file (quarry_pour --write-data) and every code starts from it (LIGGGHTS and LAMMPS by
# read_data). The timed run is the whole pour from rest, codes interleaved run by run, at 1 and
# 2 threads/ranks. Writes
#   bench/results/<date>-<machine>-flowing.csv   one row per timed run
#   bench/results/<date>-<machine>-flowing.md    medians, Quarry/peer ratios, rebuilds, the
#                                                neighbour stage's share, the physics check
#   bench/results/<date>-<machine>-flowing.png   particle-steps per second against N
# Usage:  bash bench/run_flowing.sh                   # 30k, 3 repeats, quarry liggghts lmp_granular
#         SIZES="30k 200k" REPEATS=3 bash bench/run_flowing.sh
#         SKINS="0.0004 0.0008" bash bench/run_flowing.sh   # several skins (m), each timed
# Options (environment): SIZES (30k 200k), REPEATS, CODES (quarry liggghts lmp_granular),
#   THREADS ("1 2"), SKINS (m, default 0.0004 = 0.1 d), STEPS (default 20000), QUIET_WAIT,
#   MACHINE, BUILD_DIR, SKIP_BUILD=1, SKIP_INSTALL=1, APPEND=1 (as bench/run.sh). Lattices and
#   logs go to bench/_work/flowing/ (not committed).
set -euo pipefail
BENCH=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$BENCH/.." && pwd)
cd "$ROOT"
source "$BENCH/lib.sh"

SIZES=${SIZES:-"30k"}
REPEATS=${REPEATS:-3}
CODES=${CODES:-"quarry liggghts lmp_granular"}
THREADS=${THREADS:-"1 2"}
SKINS=${SKINS:-"0.0004"}
STEPS=${STEPS:-20000}
DT=1.0e-5   # s, quarry_pour's time step (pour_defaults)
QUIET_WAIT=${QUIET_WAIT:-60}
BUILD_DIR=${BUILD_DIR:-build/release}
WORK="$BENCH/_work/flowing"
RUNS="$WORK/runs"
LOGS="$WORK/logs"
DATE=$(date +%F)
MACHINE=${MACHINE:-"$(nproc)cpu-$(cpu_slug)"}
RESULTS=$(results_name "$BENCH/results/$DATE-$MACHINE-flowing")

build_bench quarry_pour quarry_bench_report
QBIN="$ROOT/$BUILD_DIR/bench/quarry_pour"
QREPORT="$ROOT/$BUILD_DIR/bench/quarry_bench_report"
[ "${SKIP_INSTALL:-0}" != 1 ] && install_peers
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMP_NUM_THREADS=1          # the peers' binaries; Quarry sets its own thread count
MPIRUN="mpirun -np 2 --bind-to core"

mkdir -p "$RUNS" "$LOGS" "$BENCH/results"
for f in "$BENCH"/peers/model_* "$BENCH"/peers/in.*.pour "$BENCH"/peers/pour_metrics.in; do
  ln -sf "../../../peers/$(basename "$f")" "$RUNS/$(basename "$f")"
done

# size -> "nx ny nz": 30k = 30 × 40 × 25 on a 5 mm lattice (0.15 × 0.20 m floor), 200k =
# 80 × 100 × 25 (0.40 × 0.50 m): the same height of fall and of pile.
geom() {
  case $1 in
    30k)  echo "30 40 25" ;;
    200k) echo "80 100 25" ;;
    *) echo "unknown size $1" >&2; exit 1 ;;
  esac
}

# The shared starting lattice of a size (positions to 17 digits; not timed).
lattice() {
  local s=$1 nx ny nz
  read -r nx ny nz <<<"$(geom "$s")"
  [ -f "$RUNS/pour_$s.data" ] || "$QBIN" --nx "$nx" --ny "$ny" --nz "$nz" --write-data "$RUNS/pour_$s.data" \
      > "$LOGS/lattice_$s.log" 2>&1
}

# One timed run: appends one CSV row.
bench_one() {   # size code threads skin rep
  local s=$1 code=$2 np=$3 skin=$4 rep=$5 nx ny nz
  read -r nx ny nz <<<"$(geom "$s")"
  local tag="${s}_${code}_np${np}_skin${skin}_r${rep}"
  local log="$LOGS/$tag.log" cmd launch=""
  [ "$np" = 2 ] && launch="$MPIRUN"
  local peer_vars="-var dfile pour_$s.data -var skin $skin -var dt $DT -var nsteps $STEPS -log none"
  case $code in
    quarry)       cmd="env OMP_PROC_BIND=false $QBIN --nx $nx --ny $ny --nz $nz --from-data pour_$s.data --skin $skin --threads $np --steps $STEPS"; launch="" ;;
    liggghts)     cmd="liggghts -in in.lig.pour $peer_vars -var zwall wz0" ;;
    lmp_granular) cmd="lmp -in in.lmp.pour $peer_vars -var zwall wz" ;;
  esac
  wait_quiet
  # shellcheck disable=SC2086 # $launch and $cmd are word lists
  timed_run "$tag" "$log" "$RUNS" $launch $cmd
  parse_run_log "$code" "$log" "$STEPS"
  echo "$DATE,$MACHINE,$s,$R_N,$code,$np,$rep,$STEPS,$R_LOOP,$R_PSS,$R_COORD,$R_NEIGH,$R_NB,$RSS_KIB,$R_ZMAX,$R_ZMEAN,$R_FLOOR,$R_WEIGHT,$OTHER_LOAD,$skin,$R_KE,$R_SHARE" >> "$RESULTS.csv"
  echo "  $tag: $(awk -v p="$R_PSS" 'BEGIN{printf "%.2f", p/1e6}') M particle-steps/s (loop $R_LOOP s, $R_NB list builds, other load $OTHER_LOAD cores)"
}

for s in $SIZES; do lattice "$s"; done
[ -f "$RESULTS.csv" ] || "$QREPORT" --pour --header > "$RESULTS.csv"
for s in $SIZES; do
  echo "== pour $s"
  for rep in $(seq 1 "$REPEATS"); do          # repeats outermost, codes interleaved run by run
    for skin in $SKINS; do
      for code in $CODES; do
        for np in $THREADS; do bench_one "$s" "$code" "$np" "$skin" "$rep"; done
      done
    done
  done
done

"$QREPORT" --pour "$RESULTS.csv" "$RESULTS.md" "$RESULTS.png" \
  "# Quarry vs. LIGGGHTS and LAMMPS, flowing material: a pour — $DATE, $MACHINE"
{
  echo
  echo "## Machine and run"
  echo
  machine_line
  echo "- Invocation: \`SIZES=\"$SIZES\" REPEATS=$REPEATS CODES=\"$CODES\" THREADS=\"$THREADS\" SKINS=\"$SKINS\" STEPS=$STEPS bash bench/run_flowing.sh\`; Quarry commit $(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo unknown) (plus uncommitted changes, if any)"
  echo "- The pour: 4 mm spheres on a 5 mm lattice (jitter ±0.1 mm) lifted 5 cm above the floor of a closed box, at rest; $STEPS steps of $DT s from rest (the bottom layer lands after 0.10 s, the top one after about 0.15 s). Every code reads the same lattice (quarry_pour --write-data)."
  stage_tables "$SIZES" "$SKINS"
} >> "$RESULTS.md"
echo "wrote $RESULTS.csv, $RESULTS.md, $RESULTS.png"
