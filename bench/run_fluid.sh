#!/usr/bin/env bash
# The CFD-DEM fluidised bed (issue 18, "Performance"): quarry_fluidised_bed at 10k beads in
# 16 x 16 x 200 cells and 100k beads in 40 x 40 x 40 cells (both >= 50k cells), 1 and 2 threads
# interleaved, REPEATS times (default 3), at each coupling of COUPLING, DEM steps per fluid step
# and the fluid's advection scheme (default "10:central 40:central 160:hybrid": 0.25, 1 and 4 ms;
# the runs print the fluid's least stable step over the timed steps, fluid_stable_dt_ms, which
# counts the drag for central advection and is the CFL limit for hybrid: docs/cfd.md "Time
# step" advises about half of it). Every interval covers the same simulated time: a warm-up of
# 480 DEM steps and 1,280 (10k) or 960 (100k) timed ones, so the DEM figures compare. Each run's
# QUARRY_FLUID_BENCH line goes to bench/results/DATE-CPU-fluid.txt with the machine line; the
# summary (medians per size and thread count: ms per coupled step, the fluid side's parts, the
# DEM, fluid/DEM) is printed and appended. Copy the figures into docs/performance.md.
# usage: bench/run_fluid.sh   (BUILD_DIR=build/release, REPEATS=3, COUPLING="10:central 40:central
#                             160:hybrid", SKIP_BUILD=1,
#                             QUIET_WAIT=30)
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
BUILD_DIR=${BUILD_DIR:-build/release}
REPEATS=${REPEATS:-3}
COUPLING=${COUPLING:-10:central 40:central 160:hybrid}
QUIET_WAIT=${QUIET_WAIT:-30}
source bench/lib.sh
build_bench quarry_fluidised_bed
bin=$BUILD_DIR/bench/quarry_fluidised_bed
out=bench/results/$(date -u +%F)-$(cpu_slug)-fluid.txt
for n in 2 3 4 5 6 7 8 9; do  # a second run on the same day keeps the first one's file
  [[ -e $out ]] || break
  out=bench/results/$(date -u +%F)-$(cpu_slug)-fluid-$n.txt
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
{
  echo "# CFD-DEM fluidised bed (bench/run_fluid.sh), $(date -u '+%F %H:%M') UTC"
  machine_line
} > "$out"
sizes=("10000 16 200 480 1280" "100000 40 40 480 960")  # beads, cells across, cells up, DEM steps warm-up, timed
for coupling in $COUPLING; do
  interval=${coupling%%:*}
  for size in "${sizes[@]}"; do
    read -r beads across up warmup_dem timed_dem <<<"$size"
    if (( warmup_dem % interval || timed_dem % interval )); then
      echo "run_fluid.sh: an interval of $interval DEM steps does not divide $warmup_dem and $timed_dem" >&2; exit 2
    fi
  done
done
for repeat in $(seq 1 "$REPEATS"); do
  for size in "${sizes[@]}"; do
    read -r beads across up warmup_dem timed_dem <<<"$size"
    for coupling in $COUPLING; do
      interval=${coupling%%:*} advection=${coupling#*:}
      warmup=$((warmup_dem / interval)) steps=$((timed_dem / interval))
      for threads in 1 2; do
        wait_quiet
        b0=$(busy); t0=$(date +%s.%N)
        line=$(cd "$work" && "$ROOT/$bin" --particles "$beads" --cells-across "$across" --cells-up "$up" \
                 --warmup "$warmup" --coupled-steps "$steps" --coupling-steps "$interval" --advection "$advection" --threads "$threads" \
                 2>/dev/null | grep '^QUARRY_FLUID_BENCH')
        b1=$(busy); t1=$(date +%s.%N)
        # Cores the others used during the run: all busy jiffies less this run's own CPU time.
        load=$(awk -v b=$((b1-b0)) -v hz="$(getconf CLK_TCK)" -v t0="$t0" -v t1="$t1" -v n="$threads" \
                 'BEGIN { o = b / hz / (t1 - t0) - n; if (o < 0) o = 0; printf "%.2f", o }')
        echo "$line repeat=$repeat busy_cores_beyond_own=$load" | tee -a "$out"
      done
    done
  done
done
# Medians per (beads, interval and scheme, threads).
summary=$(awk '
  /^QUARRY_FLUID_BENCH/ {
    delete kv; for (i = 2; i <= NF; ++i) { split($i, f, "="); kv[f[1]] = f[2] }
    key = kv["particles"] " " kv["coupling_steps"] ":" kv["advection"] " " kv["threads"]; keys[key] = 1; n[key]++
    for (name in kv) v[key, name, n[key]] = kv[name]
  }
  function median(key, name,   m, i, j, t, a) {
    m = n[key]; for (i = 1; i <= m; ++i) a[i] = v[key, name, i]
    for (i = 1; i <= m; ++i) for (j = i + 1; j <= m; ++j) if (a[j] + 0 < a[i] + 0) { t = a[i]; a[i] = a[j]; a[j] = t }
    return m % 2 ? a[(m + 1) / 2] : (a[m / 2] + a[m / 2 + 1]) / 2
  }
  END {
    printf "| beads | cells | DEM steps per fluid step: advection | threads | ms per coupled step | fluid step | void fraction | drag | fluid values | particle forces | DEM | fluid side / DEM | fluid dt / its stable dt |\n"
    printf "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n"
    for (key in keys) {
      split(key, k, " ")
      printf "| %s | %s | %s | %s | %.1f | %.1f | %.2f | %.2f | %.2f | %.2f | %.1f | %.2f | %.2f |\n", k[1], v[key, "cells", 1], k[2], k[3],
        median(key, "step_ms"), median(key, "fluid_step_ms"), median(key, "void_fraction_ms"), median(key, "drag_ms"),
        median(key, "fluid_values_ms"), median(key, "particle_forces_ms"), median(key, "dem_ms"), median(key, "fluid_over_dem"),
        median(key, "fluid_dt_ms") / median(key, "fluid_stable_dt_ms")
    }
  }' "$out" | sort -t'|' -k2,2n -k4,4n -k5,5n)
printf '\nMedians of %s runs:\n%s\n' "$REPEATS" "$summary" | tee -a "$out"
echo "results: $out"
