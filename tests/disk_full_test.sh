#!/usr/bin/env bash
# A disk that fills during a run (issue 19): exit 2 with the path and the reason, no temporary
# files left, and every output written before intact (complete XML frames and series, a monitor
# table whose rows all have the header's columns). Two ways to fill it: as root, a 300 KB tmpfs
# (a real ENOSPC); always, a file-size limit (EFBIG; SIGXFSZ ignored so that write() fails
# instead of killing the process).
set -euo pipefail
quarry=$1 deck=$2 work=$3

check_case() {  # mode: tmpfs | limit
  local mode=$1 dir="$work/$1" out="$work/$1/out" reason code
  rm -rf "$dir" && mkdir -p "$dir"
  if [ "$mode" = tmpfs ]; then
    mount -t tmpfs -o size=300k tmpfs "$dir" 2>/dev/null || { echo "tmpfs: cannot mount, skipped"; return 0; }
    reason="No space left on device"
    set +e; "$quarry" run "$deck" --output-dir "$out" --end-time 0.5 --quiet > "$dir.log" 2>&1; code=$?; set -e
  else
    reason="File too large"
    set +e
    bash -c "trap '' XFSZ; ulimit -f 30; exec \"\$0\" run \"\$1\" --output-dir \"\$2\" --end-time 0.5 --quiet" \
      "$quarry" "$deck" "$out" > "$dir.log" 2>&1
    code=$?; set -e
  fi
  cat "$dir.log"
  [ "$code" -eq 2 ] || { echo "$mode: expected exit 2, got $code"; return 1; }
  grep -q "error: cannot write '$out/.*': $reason" "$dir.log" || { echo "$mode: no path and reason"; return 1; }
  grep -q "hint:" "$dir.log" || { echo "$mode: no hint"; return 1; }
  local leftovers frames=0 columns
  leftovers=$(find "$out" -name '*.tmp.*' | wc -l)
  [ "$leftovers" -eq 0 ] || { echo "$mode: $leftovers temporary files left"; return 1; }
  for f in "$out"/*.vtu "$out"/*.pvd; do
    [ -e "$f" ] || continue
    tail -c 200 "$f" | grep -q "</VTKFile>" || { echo "$mode: incomplete file $f"; return 1; }
    frames=$((frames + 1))
  done
  [ "$frames" -ge 2 ] || { echo "$mode: expected earlier outputs to be kept, found $frames"; return 1; }
  columns=$(head -1 "$out/monitors.csv" | awk -F, '{print NF}')
  awk -F, -v n="$columns" 'NF != n { print "monitors.csv line " NR " has " NF " columns, not " n; bad = 1 } END { exit bad }' \
    "$out/monitors.csv"
  [ "$mode" = tmpfs ] && umount "$dir"
  echo "$mode: exit 2, $frames earlier outputs intact, no temporary files: ok"
}

rm -rf "$work" && mkdir -p "$work"
trap 'umount "$work/tmpfs" 2>/dev/null || true' EXIT
if [ "$(id -u)" = 0 ]; then check_case tmpfs; else echo "tmpfs: not root, skipped"; fi
check_case limit
