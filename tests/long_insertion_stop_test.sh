#!/usr/bin/env bash
# SIGTERM during a long insertion (two million particles placed at t = 0) is taken promptly: exit
# 130 with a checkpoint, the particles not yet placed still waiting in it (issue 19: the stop was
# ignored until the insertion had finished).
set -euo pipefail
quarry=$1 deck=$2 out=$3
rm -rf "$out" && mkdir -p "$(dirname "$out")"
"$quarry" run "$deck" --output-dir "$out" --quiet > "$out.log" 2>&1 &
pid=$!
sleep 0.5
start=$(date +%s.%N)
kill -TERM "$pid"
set +e; wait "$pid"; code=$?; set -e
took=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.2f", b - a }')
cat "$out.log"
echo "exit $code, $took s after SIGTERM"
[ "$code" -eq 130 ] || { echo "expected exit code 130, got $code"; exit 1; }
[ -f "$out/checkpoint.qck" ] || { echo "no checkpoint"; exit 1; }
grep -q "quarry restart" "$out.log" || { echo "no restart hint"; exit 1; }
# The stop came before the factory had placed all its particles: the rest wait in the checkpoint.
placed=$(sed -n 's/.* \([0-9]*\) particles, .*/\1/p' "$out.log" | tail -1)
[ -n "$placed" ] && [ "$placed" -lt 2000000 ] || { echo "the insertion was not interrupted ($placed placed)"; exit 1; }
echo "stopped with $placed of 2000000 particles placed: ok"
