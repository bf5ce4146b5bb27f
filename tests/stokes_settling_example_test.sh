#!/bin/bash
# The stokes_settling example as its README runs it, in a copy of the example's folder under the
# build tree (the source tree stays clean): `quarry udf build usrStokesDrag.c`, then `quarry run`
# to the seed's end time; the particle's settling velocity in monitors.csv must be within 1 % of
# the analytic 0.002725 m/s (seed 001), and the velocity plot must exist. Then a short run that
# writes a checkpoint inside a coupling interval, restarted from another folder (the UDF is found
# again) to the end: its monitors and fluid series are those of the run that went through.
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

# 0.00212 s: step 2120, 20 steps into a coupling interval of 50.
sed 's/^  plots: true/  plots: true\n  checkpoint_interval: 0.00212/' stokes_settling.yaml > checkpointed.yaml
"$quarry" run checkpointed.yaml --end-time 0.003 --output-dir out_checkpoint --quiet --overwrite
(mkdir -p elsewhere && cd elsewhere && "$quarry" restart ../out_checkpoint/checkpoint.qck --quiet)
for f in monitors.csv particles.pvd fluid.pvd fluid_000010.vti; do
  cmp "out/$f" "out_checkpoint/$f" || { echo "$f differs after the restart"; exit 1; }
done
