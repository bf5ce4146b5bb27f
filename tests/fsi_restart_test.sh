#!/bin/bash
# A run with structures (two-way shell coupling) restarted through the CLI: `quarry run` of
# the deck to a time past a checkpoint taken between two synchronisations, then `quarry restart`
# of that checkpoint (on another thread count), writes every file of the run that went straight
# through, to the byte: particle and structure frames and series, monitors.csv,
# structure_plate.csv, the last checkpoint. Restarted into another folder, it writes the same
# structure frames, series and monitors (the checkpoint carries them), particle frames and last
# checkpoint. Then a checkpoint whose structures section is damaged (the checksum made right
# again, so that the section's own checks must find it) is refused with exit 2 and a message
# saying what is wrong.
# Usage: fsi_restart_test.sh QUARRY DECK WORK_DIR PYTHON
set -euo pipefail
quarry=$1 deck=$2 work=$3 python=$4
rm -rf "$work"
mkdir -p "$work"
cd "$work"
"$quarry" run "$deck" --output-dir straight --quiet --threads 1
"$quarry" run "$deck" --end-time 0.0055 --output-dir split --quiet --threads 1  # its last checkpoint: step 117
cp split/checkpoint.qck step117.qck
"$quarry" restart split/checkpoint.qck --quiet --threads 2
diff -r straight split
test "$(grep -c 'structure_plate_000[0-9].vtu' split/structure_plate.pvd)" -eq 6
test "$(wc -l < split/structure_plate.csv)" -ge 13
echo "restarted at step 117 (between two synchronisations): every file as the run that went through"

"$quarry" restart step117.qck --quiet --threads 2 --output-dir elsewhere
for file in straight/structure_plate* straight/particles_*.vtu straight/checkpoint.qck; do
  name=$(basename "$file")
  case "$name" in particles_00000[0-2].vtu | structure_plate_000[0-1].vtu) continue ;; esac  # before the checkpoint
  cmp "$file" "elsewhere/$name"
done
echo "restarted into another folder: the structure's series, frames and monitors, the particle frames after the checkpoint and the last checkpoint as the run that went through"

# The structures section's version, or its first nodal position made NaN (after the version, the
# count, the name "plate", the surface index and the positions' length).
source "$(dirname "$0")/restart_checks.sh"
damage step117.qck bad_version.qck structures 0 "<I" 9
expect_refused bad_version.qck "bad_version.qck: error: cannot restore checkpoint: its 'structures' section: version 9"
damage step117.qck bad_position.qck structures "4 + 8 + 8 + 5 + 8 + 8" "<d" nan
expect_refused bad_position.qck "cannot restore checkpoint: its 'structures' section: .*nodal positions entry 0 is not finite"
echo "damaged checkpoints refused: ok"
