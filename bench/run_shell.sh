#!/usr/bin/env bash
# Shell solver throughput beside CalculiX (issue 17, "Performance"): Quarry's explicit shells on
# a clamped steel plate at 10k and 100k quads, 1 and 2 threads interleaved, then ccx's explicit
# dynamics on the same 10k plate (S4R, which ccx expands to a layer of solids). ccx's cost per
# increment is the difference of two runs (20 and 120 increments of its own stable step), so its
# set-up is not counted. Prints one line per figure; copy them into docs/performance.md with the
# machine and the date.
# usage: bench/run_shell.sh [BUILD_DIR]   (default build/release; needs ccx for the comparison)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build/release}
bin=$build/bench/quarry_shell_plate
[ -x "$bin" ] || { echo "build $bin first: cmake --preset release && cmake --build --preset release"; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "host: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) CPUs, $(date -u +%F)"
"$bin" --n 100 --steps 200 --repeats 5 --threads 1 2 --ccx-input "$work/plate.inp"
"$bin" --n 316 --steps 40 --repeats 3 --threads 1 2
if ! command -v ccx >/dev/null; then echo "ccx not installed: no CalculiX comparison"; exit 0; fi
# ccx chooses its own stable increment (the expanded solids' thickness limits it); find it first.
sed -e 's/^\*DYNAMIC, EXPLICIT, DIRECT/*DYNAMIC, EXPLICIT/' "$work/plate.inp" > "$work/probe.inp"
(cd "$work" && ccx probe > probe.log 2>&1) || true
increment=$(sed -n 's/.*COURANT initial stable time increment: *\([0-9.eE+-]*\).*/\1/p' "$work/probe.log" | head -1)
[ -n "$increment" ] || { echo "ccx did not report its stable increment"; cat "$work/probe.log"; exit 1; }
seconds() {  # ccx wall time for `steps` increments of its stable step
  local steps=$1 period
  period=$(awk -v d="$increment" -v n="$steps" 'BEGIN { printf "%.9g", d * n }')
  awk -v p="$period" '/^\*DYNAMIC, EXPLICIT, DIRECT/ { print "*DYNAMIC, EXPLICIT"; getline; print "1e-9, " p; next }
                      { sub(/^\*STEP, INC=[0-9]+/, "*STEP, INC=1000000"); print }' "$work/plate.inp" > "$work/run$steps.inp"
  local start end
  start=$(date +%s.%N)
  (cd "$work" && ccx "run$steps" > "run$steps.log" 2>&1)
  end=$(date +%s.%N)
  awk -v a="$start" -v b="$end" 'BEGIN { printf "%.3f", b - a }'
}
t20=$(seconds 20)
t120=$(seconds 120)
awk -v a="$t20" -v b="$t120" -v d="$increment" 'BEGIN {
  per = (b - a) / 100
  printf "CCX_SHELL elements=10000 increment=%.4g s_per_increment=%.4g element_steps_per_s=%.4g (runs of 20 and 120 increments: %.2f s, %.2f s)\n", d, per, 10000 / per, a, b }'
