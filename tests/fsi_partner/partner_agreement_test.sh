#!/usr/bin/env bash
# The external-partner path against the built-in one (issue #17 §4): the same coupled case —
# 40 beads thrown onto the clamped 4 × 4 plate of plate_4x4.bdf, PERIOD 30 µs, FILTER 60 µs,
# 40 ms — run by the built-in path (builtin_reference: beads_on_plate.yaml with a structures:
# entry for the plate, run as `quarry run` runs it, one process), by shell_partner with the DEM
# in its process (libquarry) and by shell_partner against `quarry serve` in another process
# (ipc://, arrays in shared memory); the partners open beads_on_plate.yaml as it is and add the
# plate through quarry_add_surface.
# Each writes its report: the structure's nodal loads at every exchange (their sum and a hash of
# every node's), the plate's final nodal positions and velocities, and every particle's
# position and velocity, all doubles in hexadecimal. The reports must be the same bytes:
# tolerance zero. That is reachable because both paths run the same code on the same numbers:
# the structure's half is fsi::StructureSide in both, fed the window-mean nodal forces and the
# window's length as quarry_get_surface_loads returns them (the built-in coupler takes the same
# means from the same LoadWindow: impulse / length, then × length again), the ABI moves doubles
# unchanged (also over the wire), the DEM is stepped to the same steps (the first step at or
# after each request), and the build has no FP contraction (-ffp-contract=off). (The partner
# adds the plate after the start, the deck before it: one more neighbour-list rebuild, at the
# first step, in the partner's run. Here that changes no bit (measured); where it moved a
# spatial re-sort to another step, contact forces could be summed in another order and the
# runs would differ by round-off: docs/fem.md, "Coupling an external FEM code".) A single
# differing bit in one exchange would grow through the beads' collisions, so any difference
# fails here rather than hiding under a tolerance. builtin_reference also checks that the case
# means something (the beads gave the plate at least their momentum; the plate moved).
# Every server started here is killed on exit, also on failure.
set -euo pipefail
quarry=$1 reference=$2 partner=$3 cases=$4 work=$5
rm -rf "$work"
mkdir -p "$work"
source "$(dirname "$0")/../serve_checks.sh"
trap 'stop_servers_now; rm -f "${ipc_path:-}"' EXIT

deck=$cases/beads_on_plate.yaml model=$cases/plate_4x4.bdf end=0.04

# The built-in path's deck: the same, with the plate as a structures: entry.
{ cat "$deck"; printf 'structures:\n  - {name: plate, model: %s, material: steel}\n' "$model"; } > "$work/with_structures.yaml"
"$reference" "$work/with_structures.yaml" "$work/builtin.txt" > "$work/builtin.out" 2>&1 ||
  { cat "$work/builtin.out"; echo "the built-in path failed"; exit 1; }
cat "$work/builtin.out"

partner() {
  local name=$1; shift
  if ! "$partner" --deck "$deck" --model "$model" --end-time "$end" --report "$work/$name.txt" "$@" \
       > "$work/$name.out" 2>&1; then
    cat "$work/$name.out"; echo "the partner failed ($name)"; exit 1
  fi
  cat "$work/$name.out"
}

# compare NAME: the partner's report against the built-in one, byte for byte.
compare() {
  if cmp -s "$work/builtin.txt" "$work/$1.txt"; then
    echo "$1: the same bits as the built-in path ($(wc -l < "$work/builtin.txt") report lines)"
  else
    echo "$1 differs from the built-in path (first differing lines, built-in < > partner):"
    diff "$work/builtin.txt" "$work/$1.txt" | head -20
    exit 1
  fi
}

partner in_process --threads 2
compare in_process

ipc_path=$(mktemp -u "${TMPDIR:-/tmp}/quarry-shell-partner-XXXXXX.ipc")
serve "$work/serve.log" "ipc://$ipc_path"
partner remote --endpoint "$endpoint"
grep -q "arrays in shared memory" "$work/serve.log" || { cat "$work/serve.log"; echo "ipc without shared memory"; exit 1; }
compare remote
stop_servers "$work/serve.log"
echo "ok: the external partner (in process and against quarry serve) reproduces the built-in path bit for bit"
