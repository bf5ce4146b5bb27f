"""Surfaces from Python: a floor's window-mean loads are the momentum the particles received
(exactly), a coupled floor's nodes set and read back while it lifts the pile, a deck's surface
found by name, and the sample points of a particle type."""

import os
import unittest

import numpy as np

import quarry
from test_checkpoint import settled_pile

SOURCE = os.environ.get("QUARRY_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))


class Surfaces(unittest.TestCase):
    def test_the_floors_window_loads_are_the_momentum_the_particles_received(self):
        # Over a window of N steps the particles' momentum changes by what gravity and the floor
        # give them. Velocity Verlet kicks with (F_{n−1} + F_n)/2 in step n, F = −W + R_n (W the
        # weight, R_n the floor's push up on the pile at the end of step n, = Σ force_z + W),
        # while the window sums R_n dt over n = 1..N. So
        #   ΔP_z = −W T + dt Σ R_n − dt (R_N − R_0)/2 = −W T − F_z T − dt (R_N − R_0)/2,
        # F_z the z sum of the window-mean nodal forces on the floor (the particles push it
        # down), T = N dt the window — exactly, up to round-off.
        with settled_pile() as sim:
            floor = sim.find_surface("floor")
            info = sim.surface_info("floor")
            self.assertEqual(info, quarry.SurfaceInfo(9, 4, 8, quarry.Driver.FIXED))
            self.assertEqual(
                sim.surface_loads(floor).window, 0.0
            )  # the first read starts the window
            start = sim.particles(["mass", "velocity", "force"])
            weight = float(np.sum(start.mass)) * 9.81  # N
            steps = sim.advance(0.02)
            loads = sim.surface_loads(floor)
            end = sim.particles(["mass", "velocity", "force"])
            window, dt = loads.window, sim.time_step  # s
            push = [float(np.sum(p.force[:, 2])) + weight for p in (start, end)]  # N, R_0 and R_N
            momentum_change = float(
                np.sum(end.mass * end.velocity[:, 2]) - np.sum(start.mass * start.velocity[:, 2])
            )
            nodal = loads.nodal_force.sum(axis=0)  # N
            impulse = -weight * window - nodal[2] * window - dt * (push[1] - push[0]) / 2  # N s
            print(
                "\nfloor: window %.6g s (%d steps) ending at t = %.6g s; mean nodal force sum %s N "
                "against the weight %.6g N; momentum change %.6g N s, from the window loads "
                "%.6g N s, difference %.3g (weight x window %.3g)"
                % (
                    window,
                    steps,
                    loads.time,
                    np.array2string(nodal, precision=6),
                    weight,
                    momentum_change,
                    impulse,
                    momentum_change - impulse,
                    weight * window,
                )
            )
            self.assertAlmostEqual(window, steps * dt, delta=1e-12)
            self.assertEqual(loads.time, sim.time)
            self.assertLess(abs(momentum_change - impulse), 1e-12 * weight * window)
            self.assertAlmostEqual(-nodal[2] / weight, 1.0, delta=0.05)  # nearly at rest
            np.testing.assert_allclose(
                loads.element_force.sum(axis=0), nodal, rtol=1e-9, atol=1e-12
            )
            self.assertTrue(np.all(loads.pressure >= 0.0))
            self.assertEqual(loads.shear_stress.shape, (4, 3))

    def test_a_coupled_floor_moves_as_set(self):
        with settled_pile() as sim:
            sim.set_surface_driver("floor", "coupled")
            self.assertEqual(sim.surface_info("floor").driver, quarry.Driver.COUPLED)
            nodes, velocities = sim.surface_nodes("floor")
            np.testing.assert_array_equal(velocities, 0.0)
            speed = np.array([0.0, 0.0, 0.01])  # m/s, up
            sim.set_surface_nodes("floor", nodes, np.tile(speed, (len(nodes), 1)))
            before = sim.particles(["id", "position"])
            steps = sim.advance(0.01)
            moved, moving = sim.surface_nodes("floor")
            rise = moved[:, 2] - nodes[:, 2]
            after = sim.particles(["id", "position"])
            print(
                "\ncoupled floor at 0.01 m/s for %d steps: nodes rose %.6g m (expected %.6g m); "
                "the lowest bead rose %.3g m"
                % (
                    steps,
                    rise.mean(),
                    0.01 * steps * sim.time_step,
                    np.min(after.position[:, 2]) - np.min(before.position[:, 2]),
                )
            )
            np.testing.assert_allclose(rise, 0.01 * steps * sim.time_step, rtol=1e-9)
            np.testing.assert_array_equal(moving, np.tile(speed, (9, 1)))
            self.assertGreater(np.min(after.position[:, 2]), np.min(before.position[:, 2]))
            with self.assertRaises(quarry.BadLengthError):
                sim.set_surface_nodes("floor", nodes[:5])

    def test_a_decks_surface(self):
        deck = os.path.join(SOURCE, "examples", "bouncing_sphere", "bouncing_sphere.yaml")
        with quarry.Simulation.open(deck=deck) as sim:
            self.assertEqual(len(sim), 1)
            plate = sim.find_surface("plate")
            self.assertEqual(sim.surface_info(plate).driver, quarry.Driver.FIXED)
            with self.assertRaises(quarry.NotFoundError):
                sim.find_surface("plat")
            sim.advance(0.05)
            self.assertGreater(sim.steps, 0)

    def test_sample_points(self):
        with settled_pile() as sim:
            unit = sim.sample_points("bead", 1000, seed=7)
            self.assertEqual(unit.shape, (1000, 3))
            self.assertTrue(np.all(np.linalg.norm(unit, axis=1) <= 1.0))
            np.testing.assert_array_equal(unit, sim.sample_points(0, 1000, seed=7))
            placed = sim.sample_point_positions("bead", 50, seed=7)
            p = sim.particles(["position", "radius"])
            self.assertEqual(placed.shape, (27, 50, 3))
            np.testing.assert_allclose(
                placed,
                p.position[:, None, :] + p.radius[:, None, None] * unit[None, :50, :],
                rtol=0,
                atol=1e-15,
            )


if __name__ == "__main__":
    unittest.main()
