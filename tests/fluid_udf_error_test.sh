#!/bin/bash
# A drag UDF that reports an error during a run: `quarry run` exits 3 and prints the function,
# the particle, every input and the UDF's message (issue #18 §4). The UDF is built with
# `quarry udf build` into a copy of the deck's folder under the build tree.
# Usage: fluid_udf_error_test.sh QUARRY DECKS_DIR WORK_DIR
set -euo pipefail
quarry=$1 decks=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
cp "$decks/fluid_udf_fails.yaml" "$decks/fluid_failing_drag.c" "$work/"
cd "$work"
"$quarry" udf build fluid_failing_drag.c
set +e
output=$("$quarry" run fluid_udf_fails.yaml --quiet --overwrite 2>&1)
code=$?
set -e
echo "$output"
test "$code" -eq 3
grep -q 'drag UDF "usrFailingDrag"' <<< "$output"
grep -q "particle id 1" <<< "$output"
grep -q "its message: refusing after 1 ms, as the test wants" <<< "$output"
grep -q "its input: particle_volume" <<< "$output"
