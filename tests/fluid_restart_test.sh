#!/bin/bash
# CFD-DEM restart through the CLI (issue #18): `quarry run` of a fluid deck to a time past a
# checkpoint taken inside a coupling interval, then `quarry restart` of that checkpoint (on
# another thread count), writes every file of the run that went straight through, to the byte:
# particle and fluid frames and series, monitors.csv, fluid_monitors.csv, the last checkpoint.
# Then a checkpoint whose fluid section is damaged (the checksum made right again, so that the
# section's own checks must find it) is refused with exit 2 and a message saying what is wrong,
# as is one with a flipped bit (the checksum).
# Usage: fluid_restart_test.sh QUARRY DECK WORK_DIR PYTHON
set -euo pipefail
quarry=$1 deck=$2 work=$3 python=$4
rm -rf "$work"
mkdir -p "$work"
cd "$work"
"$quarry" run "$deck" --output-dir straight --quiet --threads 1
"$quarry" run "$deck" --end-time 0.002 --output-dir split --quiet --threads 1  # its last checkpoint: step 228
cp split/checkpoint.qck step228.qck
"$quarry" restart split/checkpoint.qck --quiet --threads 2
diff -r straight split
test -s split/fluid_monitors.csv
test "$(grep -c 'fluid_0000[0-9][0-9].vti' split/fluid.pvd)" -eq 9
echo "restarted at step 228 (inside a coupling interval): every file as the run that went through"

# The fluid section's version, or its first pressure value made NaN (after the version and three
# padded velocity arrays, each its length and values, and the pressure's length).
source "$(dirname "$0")/restart_checks.sh"
damage step228.qck bad_version.qck fluid 0 "<I" 7
expect_refused bad_version.qck "bad_version.qck: error: cannot restore checkpoint: its 'fluid' section: version 7"
damage step228.qck bad_pressure.qck fluid "4 + 3 * (8 + 8 * u64(4)) + 8" "<d" nan
expect_refused bad_pressure.qck "cannot restore checkpoint: its 'fluid' section: the fluid's pressure value 0 is not a finite number"
cp step228.qck flipped.qck
printf '\x55' | dd of=flipped.qck bs=1 seek=5000 conv=notrunc status=none
expect_refused flipped.qck "cannot restore checkpoint: the checksum does not match"
echo "damaged checkpoints refused: ok"
