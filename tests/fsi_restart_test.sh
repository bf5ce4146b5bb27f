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

# damage.py IN OUT WHAT: the structures section's version, or its first nodal position made NaN;
# the header's CRC-32 of the payload written again.
cat > damage.py <<'PY'
import math, struct, sys, zlib
data = bytearray(open(sys.argv[1], "rb").read())
header = 32
name = struct.pack("<Q", 10) + b"structures"
at = data.index(name, header) + len(name) + 8  # the section's bytes follow its length
if sys.argv[3] == "version":
    struct.pack_into("<I", data, at, 9)
else:  # version, count, name "plate", surface index, then the positions' length and values
    struct.pack_into("<d", data, at + 4 + 8 + 8 + 5 + 8 + 8, math.nan)
struct.pack_into("<I", data, 24, zlib.crc32(bytes(data[header:])) & 0xffffffff)
open(sys.argv[2], "wb").write(data)
PY
expect_refused() {  # FILE PATTERN
  set +e
  message=$("$quarry" restart "$1" --quiet --output-dir refused 2>&1)
  code=$?
  set -e
  echo "$message"
  test "$code" -eq 2 || { echo "expected exit code 2, got $code"; exit 1; }
  grep -q "$2" <<< "$message" || { echo "expected: $2"; exit 1; }
}
"$python" damage.py step117.qck bad_version.qck version
expect_refused bad_version.qck "bad_version.qck: error: cannot restore checkpoint: its 'structures' section: version 9"
"$python" damage.py step117.qck bad_position.qck position
expect_refused bad_position.qck "cannot restore checkpoint: its 'structures' section: .*nodal positions entry 0 is not finite"
echo "damaged checkpoints refused: ok"
