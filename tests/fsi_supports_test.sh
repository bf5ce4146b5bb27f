#!/usr/bin/env bash
# A structure's monitor table has each support's reaction (issue 17 §5, "reactions per
# support"): tests/fsi/plate_bed.yaml's plate is clamped on its whole edge, one support, so its
# support_1 reaction is the total reaction to the bit (the same sums: other nodes add zeros).
# usage: fsi_supports_test.sh QUARRY DECK WORKDIR
set -euo pipefail
quarry=$1 deck=$2 work=$3
rm -rf "$work"
"$quarry" run "$deck" --end-time 0.05 --quiet --output-dir "$work" > /dev/null
table=$work/structure_plate.csv
head -1 "$table" | grep -q ',support_1_reaction_x_N,support_1_reaction_y_N,support_1_reaction_z_N$' ||
  { echo "no support columns in $(head -1 "$table")"; exit 1; }
head -1 "$table" | grep -q 'support_2' && { echo "two supports on a plate clamped all round"; exit 1; }
awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) c[$i] = i; next }
  { rows++; if ($(c["support_1_reaction_z_N"]) != $(c["reaction_z_N"])) { print "row " NR ": support " $(c["support_1_reaction_z_N"]) " != total " $(c["reaction_z_N"]); bad = 1 }
    if ($(c["reaction_z_N"]) != 0) loaded = 1 }
  END { if (bad || rows < 3 || !loaded) { print "rows " rows ", loaded " loaded; exit 1 } }' "$table"
echo "supports: ok"
