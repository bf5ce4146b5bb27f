#!/usr/bin/env bash
# A structure's coupling surface in the FEM load export (issue 17 §5): `export: true` in the
# deck's structures: entry writes the deformed surface's loads and displacement as any exported
# surface's (the values are checked in src/fsi/coupled_export_test.cpp): the MED file, the
# code_aster template reading the displacement (NOEU_DEPL_R), the VTU records with it. The same
# run with output.plots on writes the structure's three plots (issue 17 §5: displacement,
# reactions, energies) as PNG files.
# usage: fsi_export_test.sh QUARRY DECK WORKDIR
set -euo pipefail
quarry=$1 deck=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
# The deck with plots on, its model named by its absolute path (the copy is not beside it).
sed -e "s|model: plate_8x8.bdf|model: $(cd "$(dirname "$deck")" && pwd)/plate_8x8.bdf|" \
    -e "s|plots: false|plots: true|" "$deck" > "$work/deck.yaml"
grep -q "plots: true" "$work/deck.yaml" || { echo "the deck copy has no plots: true"; exit 1; }
"$quarry" run "$work/deck.yaml" --end-time 0.05 --quiet --output-dir "$work/out" > /dev/null
work=$work/out
folder=$work/fem_export
test -s "$folder/plate.med" || { echo "no $folder/plate.med"; exit 1; }
grep -q "NOM_MED='displacement'" "$folder/plate.comm" || { echo "the .comm reads no displacement"; exit 1; }
grep -q "TYPE_CHAM='NOEU_DEPL_R'" "$folder/plate.comm" || { echo "the .comm reads no DEPL_R field"; exit 1; }
test "$(grep -c 'plate_loads_0000[0-9][0-9].vtu' "$folder/plate_loads.pvd")" -eq 5 ||
  { echo "not 5 records in $(cat "$folder/plate_loads.pvd")"; exit 1; }
grep -q 'Name="displacement"' "$folder/plate_loads_000004.vtu" || { echo "no displacement in the VTU record"; exit 1; }
for plot in displacement reactions energies; do
  png=$work/structure_plate_$plot.png
  test "$(head -c 8 "$png" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a || { echo "$png is not a PNG"; exit 1; }
done
echo "structure export and plots: ok"
