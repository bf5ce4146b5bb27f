#!/usr/bin/env bash
# Threads on a busy machine (issue 21 §3): the hopper example (examples/hopper, to END_TIME;
# DECK= another deck, e.g. examples/truck_bed_two_way/truck_bed_two_way.yaml)
# on 1 thread, on 2 threads as `quarry run` chooses them (the thread governor), and on 2
# threads held fixed (--fixed-threads), each on a quiet machine and beside one competing
# CPU-bound process per core minus one (a busy loop started before the run and stopped after
# it: the controlled load). Interleaved run by run, REPEATS times. Writes
#   bench/results/<date>-<machine>-busy.csv   one row per run (wall, user, sys seconds)
#   bench/results/<date>-<machine>-busy.md    medians and the 2-thread / 1-thread ratios
# Target (issue 21): with one competing process, 2 threads / 1 thread ≤ 1.1 in wall time.
# Usage:  bash bench/run_busy.sh
#         END_TIME=0.8 REPEATS=5 bash bench/run_busy.sh
# Options (environment): END_TIME (s, default 0.5), REPEATS (3), LOADS ("quiet busy"),
#   QUIET_WAIT, MACHINE, BUILD_DIR, SKIP_BUILD=1, APPEND=1 (as bench/run.sh). Logs and run
#   folders go to bench/_work/busy/.
set -euo pipefail
BENCH=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$BENCH/.." && pwd)
cd "$ROOT"
source "$BENCH/lib.sh"

END_TIME=${END_TIME:-0.5}
REPEATS=${REPEATS:-3}
LOADS=${LOADS:-"quiet busy"}
QUIET_WAIT=${QUIET_WAIT:-60}
BUILD_DIR=${BUILD_DIR:-build/release}
WORK="$BENCH/_work/busy"
LOGS="$WORK/logs"
DATE=$(date +%F)
MACHINE=${MACHINE:-"$(nproc)cpu-$(cpu_slug)"}
RESULTS=$(results_name "$BENCH/results/$DATE-$MACHINE-busy")
build_bench quarry
QUARRY="$ROOT/$BUILD_DIR/src/cli/quarry"
DECK_NAME=${DECK:-examples/hopper/hopper.yaml}
DECK="$ROOT/$DECK_NAME"
mkdir -p "$LOGS" "$BENCH/results"

# config -> quarry's thread options
threads_of() {
  case $1 in
    one) echo "--threads 1" ;;
    two) echo "--threads 2" ;;
    two_fixed) echo "--threads 2 --fixed-threads" ;;
  esac
}

# The competing load: one busy loop per core but one (pure user time, no memory traffic).
LOAD_PIDS=()
start_load() {
  local k
  for ((k = 1; k < $(nproc); ++k)); do
    awk 'BEGIN { for (;;) x++ }' & LOAD_PIDS+=($!)
  done
  sleep 1   # let the scheduler spread them
}
stop_load() {
  [ ${#LOAD_PIDS[@]} -gt 0 ] && kill "${LOAD_PIDS[@]}" 2>/dev/null && wait "${LOAD_PIDS[@]}" 2>/dev/null || true
  LOAD_PIDS=()
}
trap stop_load EXIT

[ -f "$RESULTS.csv" ] || echo "date,machine,load,config,rep,end_time,wall_s,user_s,sys_s,steps_one_thread" > "$RESULTS.csv"
for rep in $(seq 1 "$REPEATS"); do
  for load in $LOADS; do
    for config in one two two_fixed; do
      tag="${load}_${config}_r$rep"
      [ "$load" = quiet ] && wait_quiet
      [ "$load" = busy ] && start_load
      t0=$(date +%s.%N)
      # shellcheck disable=SC2046 # the thread options are a word list
      timed_run "$tag" "$LOGS/$tag.log" "$WORK" "$QUARRY" run "$DECK" --end-time "$END_TIME" \
          --output-dir "$WORK/out_$tag" --overwrite $(threads_of "$config")
      t1=$(date +%s.%N)
      stop_load
      wall=$(awk -v a="$t0" -v b="$t1" 'BEGIN{printf "%.3f", b-a}')
      # The run's summary says how many steps the governor ran on one thread.
      one=$(sed -n 's/^quarry: \([0-9][0-9]*\) of the [0-9]* steps ran on 1 thread.*/\1/p' "$LOGS/$tag.log" | tail -1)
      [ -n "$one" ] || one=0
      echo "$DATE,$MACHINE,$load,$config,$rep,$END_TIME,$wall,$USER_S,$SYS_S,$one" >> "$RESULTS.csv"
      echo "  $tag: $wall s wall (user $USER_S s)"
      rm -rf "$WORK/out_$tag"
    done
  done
done

# Medians per (load, config) and the ratios to one thread under the same load.
{
  echo "# Threads on a busy machine: $DECK_NAME to $END_TIME s — $DATE, $MACHINE"
  echo
  echo "Wall seconds of \`quarry run $DECK_NAME --end-time $END_TIME\`, median over the repeats (min .. max). Busy: one CPU-bound process per core but one runs beside it (a busy loop). \"2 threads\" is what \`quarry run --threads 2\` does (the thread governor may run steps on one thread); \"2 fixed\" adds \`--fixed-threads\`. Issue 21 asks 2 threads / 1 thread ≤ 1.1 when busy."
  echo
  echo "| load | threads | runs | wall s median | min .. max | / 1 thread (medians) | steps on 1 thread (median) |"
  echo "|---|---|---|---|---|---|---|"
  awk -F, 'NR > 1 { key = $3 "," $4; v[key] = v[key] " " $7; s[key] = s[key] " " $10; n[key]++ }
    function median(list,   a, m, i, j, t) {
      m = split(list, a, " ")
      for (i = 1; i <= m; i++) for (j = i + 1; j <= m; j++) if (a[j] + 0 < a[i] + 0) { t = a[i]; a[i] = a[j]; a[j] = t }
      lo = a[1]; hi = a[m]
      return m % 2 ? a[(m + 1) / 2] : (a[m / 2] + a[m / 2 + 1]) / 2
    }
    END {
      split("quiet busy", loads, " "); split("one two two_fixed", configs, " ")
      label["one"] = "1"; label["two"] = "2"; label["two_fixed"] = "2 fixed"
      for (l = 1; l <= 2; l++) {
        base = (loads[l] ",one") in n ? median(v[loads[l] ",one"]) : 0
        for (c = 1; c <= 3; c++) {
          key = loads[l] "," configs[c]
          if (!(key in n)) continue
          med = median(v[key]); low = lo; high = hi
          printf "| %s | %s | %d | %.2f | %.2f .. %.2f | %s | %.0f |\n", loads[l], label[configs[c]], n[key], med,
                 low, high, (base > 0 ? sprintf("**%.2f**", med / base) : "-"), median(s[key])
        }
      }
    }' "$RESULTS.csv"
  echo
  echo "## Machine and run"
  echo
  machine_line
  echo "- Invocation: \`END_TIME=$END_TIME REPEATS=$REPEATS LOADS=\"$LOADS\" bash bench/run_busy.sh\`; Quarry commit $(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo unknown) (plus uncommitted changes, if any)"
} > "$RESULTS.md.tmp" && mv "$RESULTS.md.tmp" "$RESULTS.md"
echo "wrote $RESULTS.csv, $RESULTS.md"
