#!/usr/bin/env bash
# The two-way flagship against the rigid one (issue 17, "Performance"): examples/truck_bed (the
# bed a rigid STL) and examples/truck_bed_two_way (the same pour onto the bed as steel shells,
# real stiffness, no mass scaling), both to END_TIME (default: the decks' 3 s), on 1 and 2
# threads, interleaved, REPEATS times (default 1). Per run: wall time, the structure's share of
# it (the stage table's "hook structure" rows), the shell steps per DEM step; per pair: the
# two-way / rigid wall-time ratio. The structure's time is its work on either thread: on two
# threads its steps between synchronisations run alongside the DEM's on a thread of their own
# (structure_own_thread_s; waited_s: how long the DEM's steps waited for them). At the end of each two-way run it checks the bed's
# equilibrium: the rails' reaction against the coupled load and the ore in the bed (the
# deck's in_bed monitor) times g. Lines go to bench/results/DATE-CPU-two-way.txt with the
# machine line; copy the figures into docs/performance.md.
# usage: bench/run_two_way.sh   (BUILD_DIR=build/release, END_TIME=3.0, REPEATS=1, SKIP_BUILD=1,
#                                QUIET_WAIT=30)
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
BUILD_DIR=${BUILD_DIR:-build/release}
END_TIME=${END_TIME:-3.0}
REPEATS=${REPEATS:-1}
QUIET_WAIT=${QUIET_WAIT:-30}
source bench/lib.sh
build_bench quarry
bin=$ROOT/$BUILD_DIR/src/cli/quarry
out=bench/results/$(date -u +%F)-$(cpu_slug)-two-way.txt
for n in 2 3 4 5 6 7 8 9; do  # a second run on the same day keeps the first one's file
  [[ -e $out ]] || break
  out=bench/results/$(date -u +%F)-$(cpu_slug)-two-way-$n.txt
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
{
  echo "# Two-way flagship against the rigid flagship (bench/run_two_way.sh), $(date -u '+%F %H:%M') UTC, to t = $END_TIME s"
  machine_line
} > "$out"

# run NAME DECK THREADS: one timed run; prints its line and appends it to $out.
run() {
  local name=$1 deck=$2 threads=$3 dir=$work/$1-$3 b0 t0 b1 t1 hz log
  hz=$(getconf CLK_TCK)
  rm -rf "$dir"
  log=$work/$name-$threads.log
  wait_quiet
  b0=$(busy); t0=$(date +%s.%N)
  "$bin" run "$deck" --output-dir "$dir" --end-time "$END_TIME" --threads "$threads" > "$log" 2>&1 ||
    { echo "$name on $threads threads FAILED:"; tail -20 "$log"; exit 1; }
  b1=$(busy); t1=$(date +%s.%N)
  awk -v name="$name" -v threads="$threads" -v t0="$t0" -v t1="$t1" -v b="$((b1 - b0))" -v hz="$hz" '
    /^quarry: [0-9]+ steps in/ { dem = $2 }
    /^structure ".*": t .* steps of/ { for (i = 1; i <= NF; ++i) if ($(i + 1) == "steps" && $(i + 2) == "of") fem = $i }
    /^hook structure.*%$/ { hook += $(NF - 1) }                   # in the table (this thread)
    /^hook structure.*on its own thread/ { own += $(NF - 7) }       # alongside, its own thread
    /^alongside \(waited\)/ { waited = $(NF - 1) }
    /^total \(wall\)/ { wall = $(NF - 1) }
    END {
      elapsed = t1 - t0; other = b / hz / elapsed - threads; if (other < 0) other = 0
      line = sprintf("RUN %s threads=%d wall_s=%.2f loop_s=%.2f dem_steps=%d", name, threads, elapsed, wall, dem)
      if (fem > 0) line = line sprintf(" shell_steps=%d shell_per_dem=%.2f structure_s=%.2f structure_share=%.3f"\
                                       " structure_own_thread_s=%.2f waited_s=%.2f",
                                       fem, fem / dem, hook + own, (hook + own) / wall, own, waited)
      print line
    }' "$log" | tee -a "$out"
  if [ "$name" = two_way ]; then
    # The settled bed's equilibrium: time means over the last 0.1 s (the rows sample the
    # period loads and the ringing) of the rails' reaction, the coupled load the shells
    # received (they carry no weight of their own), the particles' force on the bed (the DEM's
    # side) and the weight of the ore in the bed (the deck's in_bed monitor).
    awk -F, -v end="$END_TIME" 'NR == 1 { for (i = 1; i <= NF; ++i) c[$i] = i; next }
      $1 > end - 0.1 { n++; r += $(c["reaction_z_N"]); l -= $(c["load_z_N"]); if ($(c["max_displacement_m"]) > d) d = $(c["max_displacement_m"]) }
      END { printf "%.6g %.6g %.6g\n", r / n, l / n, d }' "$dir/structure_truck_bed.csv" > "$work/structure_means"
    awk -F, -v end="$END_TIME" 'NR == 1 { for (i = 1; i <= NF; ++i) c[$i] = i; next }
      $1 > end - 0.1 { n++; f -= $(c["truck_bed_Fz_N"]); m += $(c["in_bed_mass_kg"]) }
      END { printf "%.6g %.6g\n", f / n, 9.81 * m / n }' "$dir/monitors.csv" > "$work/dem_means"
    read -r reaction load displacement < "$work/structure_means"
    read -r dem_force weight < "$work/dem_means"
    awk -v r="$reaction" -v l="$load" -v f="$dem_force" -v w="$weight" -v d="$displacement" 'BEGIN {
      printf "EQUILIBRIUM last_0.1s_means reaction_z_N=%.2f coupled_load_z_N=%.2f particles_on_bed_z_N=%.2f ore_in_bed_weight_N=%.2f reaction/weight=%.4f max_displacement_mm=%.3f\n",
             r, l, f, w, r / w, 1000 * d }' | tee -a "$out"
  fi
}

for repeat in $(seq 1 "$REPEATS"); do
  for threads in 1 2; do
    run rigid examples/truck_bed/truck_bed.yaml "$threads"
    run two_way examples/truck_bed_two_way/truck_bed_two_way.yaml "$threads"
  done
done
# Medians per code and thread count, and the ratio.
awk '/^RUN/ { split($2, a, " "); name = $2; for (i = 3; i <= NF; ++i) { split($i, kv, "="); v[kv[1]] = kv[2] }
              key = name " " v["threads"]; walls[key] = walls[key] " " v["wall_s"] }
     END { for (t = 1; t <= 2; ++t) {
             r = median(walls["rigid " t]); w = median(walls["two_way " t])
             printf "SUMMARY threads=%d rigid_wall_s=%.2f two_way_wall_s=%.2f two_way/rigid=%.2f\n", t, r, w, w / r } }
     function median(s,   x, n, i, j, tmp) { n = split(s, x, " ")
       for (i = 1; i <= n; ++i) for (j = i + 1; j <= n; ++j) if (x[j] + 0 < x[i] + 0) { tmp = x[i]; x[i] = x[j]; x[j] = tmp }
       return n % 2 ? x[(n + 1) / 2] : (x[n / 2] + x[n / 2 + 1]) / 2 }' "$out" | tee -a "$out"
echo "results: $out"
