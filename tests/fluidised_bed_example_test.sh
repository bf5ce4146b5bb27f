#!/bin/bash
# The fluidised_bed example, briefly: `check` accepts it, and a short run writes its fluid
# monitors (fluid_monitors.csv with the columns docs/deck.md names, listed in the run's manifest
# so that --overwrite removes them) and their plots. The physics (the pressure-drop plateau) is
# verified by cfdem_tests' FluidisedBed case on a smaller bed.
# Usage: fluidised_bed_example_test.sh QUARRY EXAMPLE_DIR WORK_DIR
set -euo pipefail
quarry=$1 example=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
cp "$example/fluidised_bed.yaml" "$work/"
cd "$work"
"$quarry" check fluidised_bed.yaml
"$quarry" run fluidised_bed.yaml --end-time 0.004 --quiet --overwrite
header=$(head -n 1 out/fluid_monitors.csv)
echo "$header"
test "$header" = "time_s,bed_dp_Pa,bed_dp_dynamic_Pa,feed_Q_m3_s,feed_U_m_s,slip_slip_x_m_s,slip_slip_y_m_s,slip_slip_z_m_s"
# A row after the first step and every 0.005 s (none more before 0.004 s), and one at the end.
test "$(wc -l < out/fluid_monitors.csv)" -eq 3
# After the first step the flow-rate monitor reads the inlet's superficial 0.024 m/s: the beads
# rest on a plate above the plenum, so the inlet's cells hold none (later the falling beads push
# fluid up through the plane as well).
awk -F, 'NR == 2 { exit !($5 > 0.023999 && $5 < 0.024001) }' out/fluid_monitors.csv
for f in fluid_monitors.csv fluid_pressure_drop.png fluid_flow_rate.png fluid_slip_velocity.png fluid.pvd; do
  test -s "out/$f"
  grep -qx "$f" out/.quarry_outputs || { echo "$f missing from the manifest"; exit 1; }
done
