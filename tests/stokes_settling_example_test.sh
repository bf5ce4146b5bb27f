#!/bin/bash
# The stokes_settling example as its README runs it, in a copy of the example's folder under the
# build tree (the source tree stays clean): `quarry udf build usrStokesDrag.c`, then `quarry run`
# to the seed's end time; the particle's settling velocity in monitors.csv must be within 1 % of
# the analytic 0.002725 m/s (seed 001), and the velocity plot must exist. Then a short run that
# writes a checkpoint: restarting it is refused (exit 2), as the fluid is not checkpointed yet.
# Usage: stokes_settling_example_test.sh QUARRY EXAMPLE_DIR WORK_DIR
set -euo pipefail
quarry=$1 example=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
cp "$example/stokes_settling.yaml" "$example/usrStokesDrag.c" "$work/"
cd "$work"
"$quarry" udf build usrStokesDrag.c
"$quarry" run stokes_settling.yaml --quiet --overwrite
test -s out/mean_speed.png
# The fluid's fields: a frame at t = 0 and every 0.0015 s to 0.015 s, listed in fluid.pvd.
test "$(ls out/fluid_*.vti | wc -l)" -eq 11
test "$(grep -c 'fluid_0000[0-9][0-9].vti' out/fluid.pvd)" -eq 11
# The last row's mean_vz_m_s (the column is found by its name).
velocity=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "mean_vz_m_s") column = i; next }
                    { last = $column } END { print last }' out/monitors.csv)
echo "terminal velocity ${velocity} m/s (analytic -0.002725)"
awk -v v="$velocity" 'BEGIN { r = -v / 0.002725; exit !(r > 0.99 && r < 1.01) }'

sed 's/^  plots: true/  plots: true\n  checkpoint_interval: 0.002/' stokes_settling.yaml > checkpointed.yaml
"$quarry" run checkpointed.yaml --end-time 0.003 --output-dir out_checkpoint --quiet --overwrite
set +e
message=$("$quarry" restart out_checkpoint/checkpoint.qck --quiet 2>&1)
code=$?
set -e
echo "$message"
test "$code" -eq 2
grep -q "a run with a fluid: section cannot be restarted yet" <<< "$message"
