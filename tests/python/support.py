"""Shared set-up of the Python module's tests: the drag simulation of tests/capi/coupling_partner.c
(the same particles, types, sizes and drag coefficients) built through quarry.Simulation."""

import os
import tempfile

import numpy as np

import quarry

PARTICLES = 40
RADIUS = 1e-3  # m
DENSITY = 2500.0  # kg/m³
GRAVITY = 9.81  # m/s²
TIME_STEP = 1e-4  # s


def output_directory(name):
    """A fresh directory for a test's files, under the build tree when ctest runs the tests."""
    root = os.environ.get("QUARRY_TEST_OUTPUT")
    if root:
        os.makedirs(root, exist_ok=True)
    return tempfile.mkdtemp(prefix=name + "-", dir=root)


def drag_simulation(threads=2, sort_interval=25):
    """An empty simulation built by calls: one material, two particle types of radius 1 mm, dt =
    1e-4 s, gravity −9.81 m/s² in z, re-sorted every `sort_interval` steps; and 40 particles on
    a line in x, 1 cm apart (no contacts), types alternating 0, 1, 0, ... Returns it and the ids."""
    sim = quarry.Simulation.empty(threads=threads)
    sim.set_settings(
        time_step=TIME_STEP,
        gravity=(0.0, 0.0, -GRAVITY),
        domain=((-2.0, -2.0, -2.0), (2.0, 2.0, 2.0)),
        impact_speed=0.05,
        sort_interval=sort_interval,
    )
    sim.add_material("ore", DENSITY, 1e6, 0.3)
    sim.add_interaction("ore", "ore", restitution=0.5, static_friction=0.5, rolling_model="none")
    sim.add_particle_type("fine", "ore", RADIUS)
    sim.add_particle_type("coarse", "ore", RADIUS)
    sim.start()
    ids = add_line(sim, PARTICLES, 0.0)
    return sim, ids


def add_line(sim, count, y):
    """count particles at x = −0.5 + 0.01 k, y, z = 1.5 m, of types 0, 1, 0, ...; their ids."""
    k = np.arange(count)
    position = np.column_stack([-0.5 + 0.01 * k, np.full(count, y), np.full(count, 1.5)])
    return sim.add_particles(position, particle_type=k % 2)


def relaxation_time(ids):
    """τ = m / c (s) of the particles with these ids: 0.02 to 0.06 s as in coupling_partner.c's
    drag_of, so that they fall at different speeds and the spatial sort reorders them."""
    return 0.02 + 0.001 * (np.asarray(ids, dtype=np.int64) % 41)
