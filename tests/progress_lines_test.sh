#!/usr/bin/env bash
# Progress lines follow output.progress_interval (wall-clock seconds between them): with 0 a run
# prints none (it once printed one per step: 2000 lines for 2000 steps), with a tiny interval it
# prints some. The summary line and the stage table are printed either way.
set -euo pipefail
quarry=$1 deck=$2 out=$3
rm -rf "$out" && mkdir -p "$out"
for every in 0 1e-9; do
  sed "s/^output:/output:\n  progress_interval: $every/" "$deck" > "$out/deck_$every.yaml"
  "$quarry" run "$out/deck_$every.yaml" --end-time 0.02 --output-dir "$out/run_$every" --threads 1 > "$out/$every.log" 2>&1
  lines=$(grep -c '^t = .* ETA' "$out/$every.log" || true)
  grep -q '^quarry: [0-9]* steps in' "$out/$every.log" || { cat "$out/$every.log"; echo "no summary line"; exit 1; }
  echo "progress_interval $every: $lines progress lines"
  if [ "$every" = 0 ] && [ "$lines" -ne 0 ]; then echo "progress_interval 0 printed progress lines"; exit 1; fi
  if [ "$every" != 0 ] && [ "$lines" -eq 0 ]; then echo "a tiny progress_interval printed none"; exit 1; fi
done
echo ok
