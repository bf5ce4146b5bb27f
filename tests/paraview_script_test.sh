#!/usr/bin/env bash
# open_in_paraview.py (issue 20): every run writes it into its output folder and lists it in the
# manifest; ParaView's pvpython runs it from anywhere after the folder has moved (relative
# paths), showing the particles as Point Gaussian spheres of the radius array and the surface
# coloured by pressure, and saves a screenshot. Exit 77 (CTest: skipped) without pvpython or
# xvfb-run, after the checks that need neither.
set -euo pipefail
quarry=$1 deck=$2 out=$3
rm -rf "$out" "$out.moved"
"$quarry" run "$deck" --end-time 0.01 --output-dir "$out" --quiet > /dev/null
[ -s "$out/open_in_paraview.py" ] || { echo "no open_in_paraview.py in the output folder"; exit 1; }
grep -qx "open_in_paraview.py" "$out/.quarry_outputs" || { echo "open_in_paraview.py is not in the manifest"; exit 1; }
if ! command -v pvpython > /dev/null || ! command -v xvfb-run > /dev/null; then
  echo "pvpython or xvfb-run is not installed: the script was written, not run (skipped)"
  exit 77
fi
mv "$out" "$out.moved"
cd /
xvfb-run -a pvpython "$out.moved/open_in_paraview.py" --screenshot "$out.moved/view.png" > "$out.moved.log" 2>&1 || {
  cat "$out.moved.log"; echo "pvpython failed"; exit 1; }
cat "$out.moved.log"
grep -q "particles: 'Point Gaussian' representation, coloured by POINTS velocity, radius from array radius" \
  "$out.moved.log" || { echo "the particles are not Point Gaussian spheres scaled by radius"; exit 1; }
grep -Eq "truck_bed: 'Surface' representation, coloured by (POINTS pressure_smoothed|CELLS pressure)" \
  "$out.moved.log" || { echo "the surface is not coloured by pressure"; exit 1; }
[ -s "$out.moved/view.png" ] || { echo "no screenshot"; exit 1; }
echo "open_in_paraview.py: particles and surface shown, screenshot written: ok"
