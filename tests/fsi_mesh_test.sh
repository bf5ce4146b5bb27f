#!/bin/bash
# A structure from a Gmsh mesh (tests/fsi/plate_mesh.yaml: tests/models/plate.msh with its
# entry's unit, section, material, supports and coupling group) runs as the same plate from
# bulk data does: the deck with tests/models/plate_fixed.bdf in the mesh's place (its lone
# `SPC 1 3 3` taken out, which no support box can say; its EDEM card's PERIOD and FILTER
# overridden as the mesh deck sets them) writes the same structure monitors and particle
# monitors, to the byte. Then the mesh run restarted from a checkpoint (on another thread
# count) writes the same files as the run that went straight through.
# Usage: fsi_mesh_test.sh QUARRY SOURCE_DIR WORK_DIR
set -euo pipefail
quarry=$1 source=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
cd "$work"
deck=$source/tests/fsi/plate_mesh.yaml
"$quarry" run "$deck" --output-dir mesh --quiet --threads 1

# The bulk-data deck: the same lines up to `structures:`, then the bulk data's entry.
grep -v '^SPC     1       3       3       0\.$' "$source/tests/models/plate_fixed.bdf" > plate.bdf
test "$(grep -c '^SPC ' plate.bdf)" -eq 0
{
  sed '/^structures:/q' "$deck"
  printf '  - {name: plate, model: plate.bdf, material: steel, period: 1.0e-4, filter: 2.5e-4,\n'
  printf '     mass_scaling_time_step: 1.0e-5, damping: 2000}\n'
} > bulk.yaml
"$quarry" run bulk.yaml --output-dir bulk --quiet --threads 1
cmp mesh/structure_plate.csv bulk/structure_plate.csv
cmp mesh/monitors.csv bulk/monitors.csv
test "$(wc -l < mesh/structure_plate.csv)" -ge 10
echo "the Gmsh mesh and the bulk data run the same plate: structure and particle monitors identical"

"$quarry" run "$deck" --end-time 0.006 --output-dir split --quiet --threads 1  # checkpoint at 0.005 s
"$quarry" restart split/checkpoint.qck --quiet --threads 2
for file in structure_plate.csv monitors.csv structure_plate.pvd particles.pvd checkpoint.qck; do
  cmp "mesh/$file" "split/$file"
done
echo "restarted from its checkpoint: the mesh run's monitors, series and last checkpoint as the run that went through"
