#!/usr/bin/env python3
"""Reads a MED file that `quarry run` exported back with meshio (Debian's python3-meshio, which
reads MED through h5py), independently of libmedC, and checks: the mesh (nodes, TRIA3 cells),
the field names, their code_aster component names (PRES; FX FY FZ), the record times (the run's
end 0.33 s is not a multiple of the 0.1 s interval: its remainder joins the last record), that
the nodal forces of every record sum to the total load written per element in the CSV, and that
the code_aster .comm template names the MED file's real mesh and fields.

Usage: med_meshio_test.py QUARRY_BINARY WORK_FOLDER. Exit 77 (ctest: skipped) without meshio/h5py.
"""
import csv
import os
import re
import shutil
import subprocess
import sys

try:
    import meshio
    import h5py  # meshio's MED reader needs it; read here for the exact step times
    import numpy as np
except ImportError as missing:
    print(f"SKIP: {missing} (install python3-meshio python3-h5py; scripts/install_deps.sh does)")
    sys.exit(77)

quarry, work = sys.argv[1], sys.argv[2]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)

# A 0.2 m square plate in the deck itself, 4 × 4 squares of two triangles, 20 beads poured on it.
n, side = 4, 0.2
vertices = [[side * i / n - 0.1, side * j / n - 0.1, 0.0] for i in range(n + 1) for j in range(n + 1)]
triangles = []
for i in range(n):
    for j in range(n):
        a, b, c, d = i * (n + 1) + j, (i + 1) * (n + 1) + j, (i + 1) * (n + 1) + j + 1, i * (n + 1) + j + 1
        triangles += [[a, b, c], [a, c, d]]
deck = f"""simulation:
  end_time: 0.33
  domain: {{min: [-0.12, -0.12, -0.05], max: [0.12, 0.12, 0.3]}}
materials:
  - {{name: glass, density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25}}
interactions:
  - {{materials: [glass, glass], restitution: 0.3, static_friction: 0.5}}
particle_types:
  - {{name: bead, material: glass, size: {{distribution: fixed, radius: 0.008}}}}
surfaces:
  - {{name: plate, type: mesh, material: glass, export: true,
     vertices: {vertices}, triangles: {triangles}}}
factories:
  - {{name: pour, particle_type: bead, region: {{type: box, min: [-0.06, -0.06, 0.03], max: [0.06, 0.06, 0.12]}}, count: 20}}
output:
  directory: out
  interval: 0
  plots: false
export:
  interval: 0.1
  formats: [med, csv]
"""
deck_path = os.path.join(work, "plate.yaml")
with open(deck_path, "w") as f:
    f.write(deck)
run = subprocess.run([quarry, "run", deck_path, "--output-dir", os.path.join(work, "out"), "--quiet",
                      "--overwrite"], capture_output=True, text=True)
if run.returncode != 0:
    sys.exit(f"quarry run failed ({run.returncode}):\n{run.stdout}\n{run.stderr}")

folder = os.path.join(work, "out", "fem_export")
mesh = meshio.read(os.path.join(folder, "plate.med"))
failures = []


def check(condition, what):
    if not condition:
        failures.append(what)


check(np.allclose(mesh.points, np.array(vertices)), "node coordinates differ from the deck's vertices")
check([block.type for block in mesh.cells] == ["triangle"], f"cells {[b.type for b in mesh.cells]}")
check(np.array_equal(mesh.cells[0].data, np.array(triangles)), "connectivity differs from the deck's triangles")

# Several records: meshio names each step "NAME[k] - TIME".
expected_times = [0.1, 0.2, 0.33]
step_name = re.compile(r"^(\w+)\[(\d+)\] - ([0-9.eE+-]+)$")
records = {}  # field → {k: (time, values)}
for name, values in list(mesh.point_data.items()) + [(k, v[0]) for k, v in mesh.cell_data.items()]:
    match = step_name.match(name)
    if match:
        records.setdefault(match.group(1), {})[int(match.group(2))] = (float(match.group(3)), values)
check(sorted(records) == ["force", "nodal_force", "pressure", "shear_stress"], f"fields {sorted(records)}")
for field, steps in records.items():
    times = [steps[k][0] for k in sorted(steps)]
    check(np.allclose(times, expected_times, atol=1e-3), f"{field}: record times {times}")

# Component names (meshio keeps them per field, in the file's order of fields: alphabetical).
components = [names for names in mesh.field_data.get("med:nom", [])]
check(components == [["FX", "FY", "FZ"], ["FX", "FY", "FZ"], ["PRES"], ["FX", "FY", "FZ"]],
      f"component names {components}")

# Σ nodal forces of each record = Σ element forces of the same record in the CSV (N): the
# barycentric distribution conserves each contact force (issue 4's consistent nodal loads).
element_totals = {}
with open(os.path.join(folder, "plate_loads.csv")) as f:
    for row in csv.DictReader(f):
        total = element_totals.setdefault(round(float(row["time_s"]), 6), np.zeros(3))
        total += [float(row["force_x_N"]), float(row["force_y_N"]), float(row["force_z_N"])]
for k in sorted(records.get("nodal_force", {})):
    time, values = records["nodal_force"][k]
    nodal_total = np.asarray(values).sum(axis=0)
    csv_total = element_totals.get(round(time, 6))
    check(csv_total is not None and np.allclose(nodal_total, csv_total, rtol=1e-7, atol=1e-9),
          f"record {k}: nodal sum {nodal_total} N, CSV element sum {csv_total} N")
last = np.asarray(records["nodal_force"][max(records["nodal_force"])][1]).sum(axis=0)
weight = 20 * 2500 * 4 / 3 * np.pi * 0.008 ** 3 * 9.81  # N, the beads' weight
check(-last[2] > 0.2 * weight, f"last record carries {-last[2]} N of the beads' {weight} N")

# The .comm template: LIRE_MAILLAGE names the MED mesh, LIRE_CHAMP names fields of the file.
with open(os.path.join(folder, "plate.comm")) as f:
    comm = f.read()
med_names = re.findall(r"NOM_MED='([^']*)'", comm)
check(med_names[:1] == ["plate"], f"LIRE_MAILLAGE NOM_MED {med_names[:1]}")
check(all(name in records for name in med_names[1:]) and len(med_names) == 3, f"LIRE_CHAMP NOM_MED {med_names[1:]}")
check("F mmed plate.med D 20" in comm, ".comm does not name plate.med")
instants = [float(x) for x in re.search(r"instants = \[([^\]]*)\]", comm).group(1).split(",")]
# meshio prints the times with 6 digits in the names; the exact ones are the steps' PDT attribute.
with h5py.File(os.path.join(folder, "plate.med"), "r") as med:
    steps = med["CHA"]["pressure"]
    exact = [float(steps[key].attrs["PDT"]) for key in sorted(steps.keys())]
check(instants == exact, f".comm instants {instants}, MED step times {exact}")

if failures:
    sys.exit("FAILED:\n  " + "\n  ".join(failures))
print(f"ok: {len(mesh.points)} nodes, {len(triangles)} triangles, fields {sorted(records)} with components "
      f"{components}, record times {expected_times}, nodal sums = CSV element sums")
