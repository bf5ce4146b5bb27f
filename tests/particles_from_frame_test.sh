#!/usr/bin/env bash
# A run started from the last frame of an earlier run (deck `particles:`, issue #20) begins with
# exactly that run's particles: its first frame's ids, types, radii, masses, positions, velocities
# and angular velocities are byte for byte those of the frame it started from (forces are
# recomputed, without the earlier contact history, so they may differ).
set -euo pipefail
quarry=$1 source_dir=$2 out=$3 python=$4
rm -rf "$out"
mkdir -p "$out/second"
"$quarry" run "$source_dir/tests/decks/settle_beads.yaml" --output-dir "$out/first" --quiet > /dev/null
last=$(ls "$out"/first/particles_*.vtu | tail -1)
cp "$last" "$out/second/frame.vtu"
cp "$source_dir/tests/particles/from_frame.yaml" "$out/second/from_frame.yaml"
"$quarry" run "$out/second/from_frame.yaml" --output-dir "$out/second/out" --quiet > /dev/null
"$python" - "$last" "$out/second/out/particles_000000.vtu" <<'PY'
import re, struct, sys
def arrays(path):
    data = open(path, 'rb').read()
    base = data.index(b'<AppendedData encoding="raw">')
    base = data.index(b'_', base) + 1
    found = {}
    for tag in re.finditer(rb'<DataArray [^>]*Name="([^"]+)"[^>]*offset="(\d+)"', data[:base]):
        start = base + int(tag.group(2))
        size = struct.unpack('<Q', data[start:start + 8])[0]
        found[tag.group(1).decode()] = data[start + 8:start + 8 + size]
    return found
before, after = arrays(sys.argv[1]), arrays(sys.argv[2])
count = len(before['id']) // 8
assert count > 50, f'only {count} particles in the first run\'s last frame'
for name in ['id', 'type', 'radius', 'mass', 'Points', 'velocity', 'angular_velocity', 'type_names']:
    assert before[name] == after[name], f'{name} differs between the frame and the run started from it'
moving = sum(1 for k in range(count) if struct.unpack_from('<d', before['velocity'], 24 * k + 16)[0] != 0.0)
print(f'{count} particles ({moving} moving) restarted bit for bit: ok')
PY
