#!/usr/bin/env bash
# The end-of-run stage table accounts for the run's wall time (issue 20: the flagship's table
# summed 63 s of a 71 s run; the output at the end was not timed): its timed stages add up to
# within 5 % of the wall time the summary line reports, and its total is that wall time. No
# absolute timing is asserted.
set -euo pipefail
quarry=$1 deck=$2 out=$3
rm -rf "$out" && mkdir -p "$(dirname "$out")"  # its log sits beside it
"$quarry" run "$deck" --end-time 0.1 --output-dir "$out" --threads 1 > "$out.log" 2>&1
cat "$out.log"
wall=$(sed -n 's/^quarry: [0-9]* steps* in \([0-9.]*\) s .*/\1/p' "$out.log")
[ -n "$wall" ] || { echo "no summary line with the wall time"; exit 1; }
awk -v wall="$wall" '
  /^stage +time/ { table = 1; next }
  table && /^total \(wall\)/ { total = $3; done = 1; next }
  table && /^untimed/ { next }
  table && !done && NF >= 3 { timed += $(NF - 1) }
  END {
    if (!done) { print "no stage table with a total (wall) line"; exit 1 }
    if (total + 0.006 < wall || total - 0.006 > wall) { printf "table total %s s, summary %s s\n", total, wall; exit 1 }
    if (timed < 0.95 * wall) { printf "the stages time %.3f s of %.3f s\n", timed, wall; exit 1 }
    printf "stages %.3f s of %.3f s wall: ok\n", timed, wall
  }' "$out.log"
