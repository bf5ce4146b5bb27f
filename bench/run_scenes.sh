#!/usr/bin/env bash
# Quarry vs. LIGGGHTS 3.8.0 on flowing material in equipment (issue 21 (b), (c)): a
# flat-bottomed hopper discharging through its outlet and a rotating drum. Every code reads the
# same walls (an STL) and the same starting particles (a jittered lattice at rest), written once
# by bench/peers/scene_geometry.awk; the settled bed's material (Hertz-Mindlin with history,
# E = 5 MPa, nu = 0.3, e = 0.5, mu = 0.5, no rolling friction) for particles and walls; the same
# step and skin. Quarry runs a deck (`quarry run`, the thread governor on), LIGGGHTS
# bench/peers/in.lig.scene (mesh walls, move/mesh for the drum). LAMMPS is left out: its
# granular walls are primitives and regions, not a mesh, so neither scene's walls can be the same.
# The timed run is the whole flow from rest, codes interleaved run by run, at 1 and 2
# threads/ranks. Every 0.1 s each code records the mass above the hopper's floor, the mass on
# the drum's rising side (x < 0) and the kinetic energy; the physics check compares the
# discharge rate and the rising side's share over the run's second half. Writes
#   bench/results/<date>-<machine>-scenes.csv   one row per timed run
#   bench/results/<date>-<machine>-scenes.md    medians, Quarry/LIGGGHTS, rebuilds, the neighbour
#                                               stage's share, the mean coordination number at the
#                                               end (particle-particle contacts, both codes), the
#                                               physics check
#   bench/results/<date>-<machine>-scenes.png   particle-steps per second against the threads
# Usage:  bash bench/run_scenes.sh                          # hopper and drum, 3 repeats
#         SCENES=drum REPEATS=1 THREADS=1 bash bench/run_scenes.sh
# Options (environment): SCENES (hopper drum), REPEATS, CODES (quarry liggghts), THREADS
#   ("1 2"), SKINS (m, default 0.0006 = 0.1 d), STEPS (default 20000 of 50 µs: 1 s), QUIET_WAIT,
#   MACHINE, BUILD_DIR, SKIP_BUILD=1, SKIP_INSTALL=1, APPEND=1 (as bench/run.sh). Inputs and
#   logs go to bench/_work/scenes/ (not committed).
set -euo pipefail
BENCH=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$BENCH/.." && pwd)
cd "$ROOT"
source "$BENCH/lib.sh"

SCENES=${SCENES:-"hopper drum"}
REPEATS=${REPEATS:-3}
CODES=${CODES:-"quarry liggghts"}
THREADS=${THREADS:-"1 2"}
SKINS=${SKINS:-"0.0006"}
STEPS=${STEPS:-20000}
DT=5.0e-5        # s: 14 % of the Rayleigh step of a 6 mm sphere of this material (0.37 ms)
RECORD=400       # steps between the records of mass and energy (0.02 s)
PERIOD=2.0       # s, one turn of the drum (30 rpm; Froude number w² R / g = 0.10: rolling)
PARTICLE_MASS=2.8274333882308139e-04   # kg, 2500 kg/m³ × π/6 × (6 mm)³
QUIET_WAIT=${QUIET_WAIT:-60}
BUILD_DIR=${BUILD_DIR:-build/release}
WORK="$BENCH/_work/scenes"
RUNS="$WORK/runs"
LOGS="$WORK/logs"
DATE=$(date +%F)
MACHINE=${MACHINE:-"$(nproc)cpu-$(cpu_slug)"}
RESULTS=$(results_name "$BENCH/results/$DATE-$MACHINE-scenes")

if [ "${SKIP_BUILD:-0}" != 1 ]; then
  build_bench quarry_bench_report
  cmake --build "$BUILD_DIR" --target quarry
fi
QBIN="$ROOT/$BUILD_DIR/src/cli/quarry"
QREPORT="$ROOT/$BUILD_DIR/bench/quarry_bench_report"
[ "${SKIP_INSTALL:-0}" != 1 ] && install_peers
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMP_NUM_THREADS=1          # the peers' binaries; Quarry sets its own thread count
MPIRUN="mpirun -np 2 --bind-to core"

mkdir -p "$RUNS" "$LOGS" "$BENCH/results"
ln -sf "../../../peers/in.lig.scene" "$RUNS/in.lig.scene"
END_TIME=$(awk -v s="$STEPS" -v dt="$DT" 'BEGIN{printf "%.10g", s*dt}')

# The scene's walls and particles (one awk, one jitter for every code) and Quarry's deck.
prepare() {   # scene skin
  local s=$1 skin=$2 motion="" monitor domain
  for what in stl data csv; do
    [ -f "$RUNS/$s.$what" ] || awk -v scene="$s" -v what="$what" -f "$BENCH/peers/scene_geometry.awk" > "$RUNS/$s.$what"
  done
  if [ "$s" = hopper ]; then
    domain="{min: [-0.085, -0.085, -0.06], max: [0.085, 0.085, 0.26]}"
    monitor="{name: above_floor, region: {type: box, min: [-0.1, -0.1, 0.0], max: [0.1, 0.1, 0.3]}}"
  else
    domain="{min: [-0.11, -0.11, -0.11], max: [0.11, 0.11, 0.11]}"
    monitor="{name: rising_side, region: {type: box, min: [-0.2, -0.2, -0.2], max: [0.0, 0.2, 0.2]}}"
    # LIGGGHTS' move/mesh rotate turns counter-clockwise about +y: w = +2 pi / period.
    motion=", motion: {type: rotation, axis_point: [0, 0, 0], axis_direction: [0, 1, 0], angular_velocity: $(awk -v p=$PERIOD 'BEGIN{printf "%.17g", 2*atan2(0,-1)/p}')}"
  fi
  cat > "$RUNS/${s}_skin$skin.yaml" <<EOF
# bench/run_scenes.sh: the $s scene (written by the harness; walls and particles from
# bench/peers/scene_geometry.awk, the same files LIGGGHTS reads).
simulation:
  end_time: $END_TIME
  time_step: $DT
  skin: $skin
  impact_speed: 1.5
  max_overlap_fraction: 0.2
  gravity: [0, 0, -9.81]
  domain: $domain
materials:
  - {name: grain, density: 2500, youngs_modulus: 5.0e6, poisson_ratio: 0.3}
interactions:
  - {materials: [grain, grain], restitution: 0.5, static_friction: 0.5, rolling_model: none}
particle_types:
  - {name: grain, material: grain, size: {distribution: fixed, radius: 0.003}}
particles:
  - {file: $s.csv}
surfaces:
  - {name: walls, type: stl, file: $s.stl, material: grain$motion}
monitors:
  - $monitor
output: {directory: out, interval: 0, monitor_interval: $(awk -v r=$RECORD -v dt=$DT 'BEGIN{printf "%.10g", r*dt}'), plots: false, progress_interval: 0}
EOF
}

# The discharge rate (kg/s) or the rising side's share, and the kinetic energy per particle (J),
# each the mean over the records of the run's second half, from "time mass energy particles" rows.
second_half() {   # scene file_of_rows
  awk -v scene="$1" -v t_end="$END_TIME" -v n0="$N0" '
    { t[NR] = $1; m[NR] = $2; e[NR] = $3; n[NR] = $4 }
    END {
      h = 0; for (i = 1; i <= NR; ++i) if (t[i] >= 0.5 * t_end - 1e-9) { if (!h) h = i; ke += e[i] / n[i]; ++k }
      if (scene == "hopper") printf "%.6g nan %.6g\n", (m[h] - m[NR]) / (t[NR] - t[h]), ke / k
      else { for (i = h; i <= NR; ++i) share += m[i]; printf "nan %.6g %.6g\n", share / k / (n0 * '"$PARTICLE_MASS"'), ke / k }
    }' "$2"
}

# One timed run: appends one CSV row.
bench_one() {   # scene code threads skin rep
  local s=$1 code=$2 np=$3 skin=$4 rep=$5
  local tag="${s}_${code}_np${np}_skin${skin}_r${rep}"
  local log="$LOGS/$tag.log" rows="$LOGS/$tag.rows" launch="" period=0
  [ "$s" = drum ] && period=$PERIOD
  N0=$(($(wc -l < "$RUNS/$s.csv") - 1))
  wait_quiet
  if [ "$code" = quarry ]; then
    timed_run "$tag" "$log" "$RUNS" env OMP_PROC_BIND=false "$QBIN" run "${s}_skin$skin.yaml" --threads "$np" --overwrite
    # "quarry: S steps in T s (...), N particles, R removed (left the domain), B list rebuilds (P listed
    # pairs per particle at the end)"
    local line total output neigh
    line=$(grep -m1 '^quarry: [0-9]* steps in' "$log" || true)
    total=$(awk '/^total \(wall\)/{print $3}' "$log"); output=$(awk '/^output /{print $2}' "$log")
    neigh=$(awk '/^neighbor /{print $2}' "$log")
    R_LOOP=$(awk -v t="$total" -v o="${output:-0}" 'BEGIN{printf "%.6g", t-o}')
    R_NB=$(sed -n 's/.* \([0-9]*\) list rebuilds.*/\1/p' <<<"$line")
    R_SHARE=$(awk -v n="$neigh" -v l="$R_LOOP" 'BEGIN{if(l>0 && n!="") printf "%.4f", n/l}')
    # the summary's "(P listed pairs per particle at the end)": the half list with its skin, as
    # the peers' "Ave neighs/atom"
    R_NEIGH=$(sed -n 's/.*(\([0-9.]*\) listed pairs per particle.*/\1/p' <<<"$line")
    # The mean coordination number at the end, 2 × particle-particle contacts / particles, as
    # the peers' contact/atom sum per particle (walls not counted in either).
    R_COORD=$(awk -F, 'NR==1{for(i=1;i<=NF;++i) c[$i]=i; next}
                       {p=$c["particles"]; k=$c["particle_contacts"]} END{if(p>0) printf "%.4f", 2*k/p}' "$RUNS/out/monitors.csv")
    # monitors.csv: time_s, particles, kinetic_energy_J, ..., the scene's mass monitor (last column)
    awk -F, 'NR==1{for(i=1;i<=NF;++i) c[$i]=i; next}
             {print $c["time_s"], $NF, $c["kinetic_energy_J"], $c["particles"]}' "$RUNS/out/monitors.csv" > "$rows"
  else
    [ "$np" = 2 ] && launch="$MPIRUN"
    # shellcheck disable=SC2086 # $launch is a word list
    timed_run "$tag" "$log" "$RUNS" $launch liggghts -in in.lig.scene -var dfile "$s.data" -var mesh "$s.stl" \
      -var period "$period" -var skin "$skin" -var dt "$DT" -var nsteps "$STEPS" -var every "$RECORD" -log none
    parse_run_log liggghts "$log" "$STEPS"
    # thermo rows "step atoms m_above m_rising ke" between the header and the timed run's Loop
    # line (the contacts' run 0 after it has rows of its own)
    awk -v dt="$DT" -v s="$s" '/^ *Step /{on=1; next} /^Loop time/{exit} on && $1 ~ /^[0-9]+$/ {
         print $1*dt, (s == "hopper" ? $3 : $4), $5, $2 }' "$log" > "$rows"
  fi
  local metrics; metrics=$(second_half "$s" "$rows")
  local rate rising ke; read -r rate rising ke <<<"$metrics"
  R_PSS=$(awk -v n="$N0" -v s="$STEPS" -v l="$R_LOOP" 'BEGIN{if(l>0) printf "%.6g", n*s/l}')
  echo "$DATE,$MACHINE,$s,$N0,$code,$np,$rep,$STEPS,$R_LOOP,$R_PSS,${R_COORD:-nan},${R_NEIGH:-nan},$R_NB,$RSS_KIB,nan,nan,nan,nan,$OTHER_LOAD,$skin,$ke,${R_SHARE:-nan},$rate,$rising" >> "$RESULTS.csv"
  echo "  $tag: $(awk -v p="$R_PSS" 'BEGIN{printf "%.2f", p/1e6}') M particle-steps/s (loop $R_LOOP s, $R_NB list builds, discharge $rate kg/s, rising share $rising, other load $OTHER_LOAD cores)"
}

for s in $SCENES; do for skin in $SKINS; do prepare "$s" "$skin"; done; done
[ -f "$RESULTS.csv" ] || "$QREPORT" --scene --header > "$RESULTS.csv"
for rep in $(seq 1 "$REPEATS"); do          # repeats outermost, codes interleaved run by run
  for s in $SCENES; do
    echo "== $s, repeat $rep"
    for skin in $SKINS; do
      for code in $CODES; do
        for np in $THREADS; do bench_one "$s" "$code" "$np" "$skin" "$rep"; done
      done
    done
  done
done

"$QREPORT" --scene "$RESULTS.csv" "$RESULTS.md" "$RESULTS.png" \
  "# Quarry vs. LIGGGHTS, flowing material in equipment: a hopper and a drum — $DATE, $MACHINE"
{
  echo
  echo "## Machine and run"
  echo
  machine_line
  echo "- Invocation: \`SCENES=\"$SCENES\" REPEATS=$REPEATS CODES=\"$CODES\" THREADS=\"$THREADS\" SKINS=\"$SKINS\" STEPS=$STEPS bash bench/run_scenes.sh\`; Quarry commit $(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo unknown) (plus uncommitted changes, if any)"
  echo "- The scenes (bench/peers/scene_geometry.awk): spheres of 6 mm, 2500 kg/m³, from a jittered 6.6 mm lattice at rest; $STEPS steps of $DT s. Hopper: a square bin 0.15 m wide, a round outlet of 40 mm in its flat floor, open from the start, 10,164 spheres. Drum: a closed cylinder of radius 0.1 m and length 0.2 m turning at one turn per $PERIOD s about the horizontal y axis, 11,280 spheres filling about a third of it. Quarry's thread count is the governed one (\`--threads 2\` lets it take one where that is faster)."
  stage_tables "$SCENES" "$SKINS"
} >> "$RESULTS.md"
echo "wrote $RESULTS.csv, $RESULTS.md, $RESULTS.png"
