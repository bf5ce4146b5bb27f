#!/bin/bash
# The packed_bed example as written: `check` accepts it, the run ends, and the last row of its
# fluid monitors gives Ergun's pressure drop through the lattice's void fraction within 5 %
# (the cfdem_tests case FluidMonitors.PackedBedPressureDropFollowsErgun on a narrower column;
# Ergun 1952: Δp/L = 150 μ (1 − ε)² U/(ε³ d²) + 1.75 ρ (1 − ε) U²/(ε³ d)), and the flow-rate
# monitor the inlet's superficial velocity.
# Usage: packed_bed_example_test.sh QUARRY EXAMPLE_DIR WORK_DIR
set -euo pipefail
quarry=$1 example=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
cp "$example/packed_bed.yaml" "$example/bed.csv" "$work/"
cd "$work"
"$quarry" check packed_bed.yaml
"$quarry" run packed_bed.yaml --quiet --overwrite
header=$(head -n 1 out/fluid_monitors.csv)
test "$header" = "time_s,bed_dp_Pa,bed_dp_dynamic_Pa,feed_Q_m3_s,feed_U_m_s,slip_slip_x_m_s,slip_slip_y_m_s,slip_slip_z_m_s"
awk -F, 'END {
  pi = atan2(0, -1); mu = 1e-3; rho = 1000; d = 1e-3; u = 0.01; span = 0.0231 - 0.0105
  eps = 1 - pi / 6 / 1.05^3
  ergun = 150 * mu * (1 - eps)^2 * u / (eps^3 * d^2) + 1.75 * rho * (1 - eps) * u^2 / (eps^3 * d)
  ratio = $3 / span / ergun
  printf "packed bed: dynamic drop %.5g Pa over %.4g m, Ergun %.5g Pa/m: ratio %.4f; U %.8g m/s\n", $3, span, ergun, ratio, $5
  exit !(ratio > 0.95 && ratio < 1.05 && $5 > 0.01 - 1e-8 && $5 < 0.01 + 1e-8)
}' out/fluid_monitors.csv
for f in fluid_monitors.csv fluid_pressure_drop.png fluid.pvd particles.pvd; do
  test -s "out/$f"
done
