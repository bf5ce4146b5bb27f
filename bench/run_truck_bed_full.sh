#!/usr/bin/env bash
# Seed 002 at full scale (issue 21 §4): bench/truck_bed_full/truck_bed_full.yaml (314,522
# cohesive particles poured in three phases onto a bed of 8,630 triangles, per-element loads
# exported to MED and CalculiX) on THREADS threads (default 2), once, under GNU time. While it
# runs, the process's resident memory is sampled every SAMPLE seconds beside the particle count
# of the run's progress, so that the record shows whether memory follows the particles or also
# grows with the export's history (it must stay flat apart from the particles). Writes
# bench/results/DATE-CPU-truck-bed-full.md: wall time, CPU time, peak memory, the memory samples,
# the export's files and sizes, the stage table and the machine.
# usage: bench/run_truck_bed_full.sh   (BUILD_DIR=build/release, THREADS=2, SAMPLE=30,
#                                       END_TIME (s, default the deck's), KEEP=1 keeps the outputs)
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
BUILD_DIR=${BUILD_DIR:-build/release}
THREADS=${THREADS:-2}
SAMPLE=${SAMPLE:-30}
source bench/lib.sh
build_bench quarry
quarry=$ROOT/$BUILD_DIR/src/cli/quarry
work=$(mktemp -d)
[ "${KEEP:-0}" = 1 ] || trap 'rm -rf "$work"' EXIT
cp bench/truck_bed_full/truck_bed_full.yaml bench/truck_bed_full/truck_bed_full.stl "$work/"
out=bench/results/$(date -u +%F)-$(cpu_slug)-truck-bed-full.md
for n in b c d e f g h; do [[ -e $out ]] || break; out=${out%-truck-bed-full*}-truck-bed-full-$n.md; done
args=(run truck_bed_full.yaml --threads "$THREADS" --output-dir out)
[ -n "${END_TIME:-}" ] && args+=(--end-time "$END_TIME")
start=$(date -u '+%F %H:%M')
( cd "$work" && exec env time -v -o time.txt "$quarry" "${args[@]}" > run.log 2>&1 ) &
runner=$!
# Memory samples: seconds since the start, resident MiB of quarry, the last progress line.
: > "$work/memory.txt"
t0=$(date +%s)
while kill -0 "$runner" 2>/dev/null; do
  sleep "$SAMPLE"
  pid=$(pgrep -n -f "$quarry ${args[0]} truck_bed_full.yaml" || true)
  [ -n "$pid" ] || continue
  rss=$(awk '/^VmRSS:/{printf "%.0f", $2/1024}' "/proc/$pid/status" 2>/dev/null || true)
  progress=$(tr '\r' '\n' < "$work/run.log" | grep -a 'particles' | tail -1 | cut -c1-150 || true)
  echo "| $(( $(date +%s) - t0 )) | ${rss:-?} | ${progress:-} |" >> "$work/memory.txt"
done
wait "$runner" || echo "bench: the run failed; see its log below" >&2
field() { sed -n "s/^[[:space:]]*$1: //p" "$work/time.txt" | head -1; }
{
  echo "# Seed 002 at full scale (bench/run_truck_bed_full.sh), started $start UTC"
  echo
  machine_line
  echo "- Quarry $(git rev-parse --short HEAD), ${THREADS} threads, deck bench/truck_bed_full/truck_bed_full.yaml${END_TIME:+, --end-time $END_TIME}"
  echo
  echo "| wall (s) | user (s) | system (s) | peak resident memory (MiB) |"
  echo "|---|---|---|---|"
  echo "| $(field 'Elapsed (wall clock) time (h:mm:ss or m:ss)') | $(field 'User time (seconds)') | $(field 'System time (seconds)') | $(( $(field 'Maximum resident set size (kbytes)') / 1024 )) |"
  echo
  echo "Resident memory while it ran (every ${SAMPLE} s):"
  echo
  echo "| s | MiB | progress |"
  echo "|---|---|---|"
  cat "$work/memory.txt"
  echo
  echo "Export (out/fem_export):"
  echo
  echo '```'
  (cd "$work/out/fem_export" && ls -l | awk 'NR>1 {printf "%12d  %s\n", $5, $9}' && du -sb . | awk '{printf "%12d  total\n", $1}')
  echo '```'
  echo
  echo "The run's summary:"
  echo
  echo '```'
  tr '\r' '\n' < "$work/run.log" | grep -a -v '^ *$' | tail -30
  echo '```'
} > "$out"
cat "$out"
echo "results: $out"
