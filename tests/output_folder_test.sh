#!/usr/bin/env bash
# A run into a folder that holds an earlier run's output is refused (exit 2, naming the folder)
# unless --overwrite, which removes the files that run wrote and nothing else; temporary files a
# killed run left are cleaned up (issue 19).
set -euo pipefail
quarry=$1 deck=$2 out=$3
rm -rf "$out"
"$quarry" run "$deck" --end-time 0.02 --output-dir "$out" --quiet > /dev/null
[ -f "$out/.quarry_outputs" ] || { echo "no manifest of the run's files"; exit 1; }
echo "the user's own notes" > "$out/notes.txt"
touch "$out/particles_000009.vtu.tmp.4242.7"      # what a killed run leaves
set +e
"$quarry" run "$deck" --end-time 0.02 --output-dir "$out" --quiet > "$out.log" 2>&1
code=$?
set -e
cat "$out.log"
[ "$code" -eq 2 ] || { echo "expected exit 2 for a folder with an earlier run's output, got $code"; exit 1; }
grep -q "holds an earlier run's output" "$out.log" || { echo "no message naming the earlier output"; exit 1; }
grep -q -- "--overwrite" "$out.log" || { echo "no hint"; exit 1; }
[ ! -e "$out/particles_000009.vtu.tmp.4242.7" ] || { echo "the stale temporary file is still there"; exit 1; }
frames_before=$(ls "$out"/particles_*.vtu | wc -l)
"$quarry" run "$deck" --end-time 0.005 --output-dir "$out" --quiet --overwrite > /dev/null
[ -f "$out/notes.txt" ] || { echo "--overwrite removed a file the run had not written"; exit 1; }
frames_after=$(ls "$out"/particles_*.vtu | wc -l)
[ "$frames_after" -lt "$frames_before" ] || { echo "the earlier run's frames were not removed ($frames_before -> $frames_after)"; exit 1; }
echo "refused without --overwrite; with it, $frames_before frames -> $frames_after, the user's file kept: ok"
