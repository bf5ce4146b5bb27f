#!/usr/bin/env bash
# README command 1: install what is missing, build Quarry (Release), run the flagship example
# (truck-bed loading). Outputs land in out/truck_bed/ (open truck_bed.pvd/particles.pvd in ParaView).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
cmake --preset release >/dev/null
cmake --build --preset release
# --overwrite: running the quickstart again replaces its own earlier output.
./build/release/src/cli/quarry run examples/truck_bed/truck_bed.yaml --output-dir out/truck_bed --overwrite "$@"
