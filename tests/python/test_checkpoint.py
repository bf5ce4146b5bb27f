"""Checkpoints from Python: save_state / restore_state in memory and save_checkpoint /
open(checkpoint=) on disk give back a state that continues bit-identically — particles in contact
with each other and with a floor, a partner's loads set by id every step, a custom property — and
restore_state makes every view stale."""

import os
import unittest

import numpy as np

import quarry
import support


def settled_pile(threads=2):
    """27 glass beads (radius 2 mm) dropped in a 3 × 3 × 3 lattice onto a floor of 2 × 2 quads
    and left to settle for 0.1 s: contacts between particles and with the surface, with history."""
    sim = quarry.Simulation.empty(threads=threads)
    sim.set_settings(
        domain=((-0.05, -0.05, -0.01), (0.05, 0.05, 0.1)), sort_interval=50, impact_speed=0.5
    )
    sim.add_material("glass", 2500.0, 5e6, 0.25)
    sim.add_interaction(
        "glass", "glass", restitution=0.5, static_friction=0.4, rolling_friction=0.02
    )
    sim.add_particle_type("bead", "glass", 2e-3)
    grid = np.linspace(-0.02, 0.02, 3)
    nodes = np.array([[x, y, 0.0] for y in grid for x in grid])
    quads = [[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]]
    sim.add_surface("floor", "glass", nodes, quads=quads)
    sim.start()
    offsets = np.linspace(-0.0045, 0.0045, 3)
    position = np.array(
        [[x, y, 0.003 + 0.0045 * (k + 1)] for k in range(3) for y in offsets for x in offsets]
    )
    position[:, 0] += 1e-4 * (np.arange(27) % 3)  # break the symmetry a little
    sim.add_particles(position, particle_type="bead")
    sim.advance(0.1)
    return sim


def run_partner(sim, steps):
    """A partner's loop: a velocity-dependent force by id and a property it keeps, every step."""
    for _ in range(steps):
        p = sim.particles(["id", "velocity", "mass"])
        sim.set_external_loads(-0.05 * p.mass[:, None] * p.velocity / 1e-3, ids=p.id)
        sim.set_property("age", sim.get_property("age") + 1.0)
        sim.step(1)
    p = sim.particles(["id", "position", "velocity", "angular_velocity", "force", "torque"])
    p["age"] = sim.get_property("age")
    return p


def same_bits(a, b):
    return sorted(a) == sorted(b) and all(a[k].tobytes() == b[k].tobytes() for k in a)


class Checkpoints(unittest.TestCase):
    def test_save_state_and_restore_state_continue_bit_identically(self):
        with settled_pile() as sim:
            sim.register_property("age", 1, "steps", 0.0)
            state = sim.save_state()
            time, steps = sim.time, sim.steps
            view = sim.view("position")
            first = run_partner(sim, 200)
            sim.restore_state(state)
            self.assertEqual((sim.time, sim.steps), (time, steps))
            with self.assertRaises(quarry.StaleViewError):
                view.array
            second = run_partner(sim, 200)
            moved = float(np.max(np.abs(first.velocity)))
            print(
                "\nsave_state: %d bytes at t = %.6g s (%d steps); 200 partner steps twice: "
                "same bits %s (max |v| %.3g m/s)"
                % (len(state), time, steps, same_bits(first, second), moved)
            )
            self.assertTrue(
                same_bits(first, second), "the restored state did not continue bit-identically"
            )
            self.assertGreater(moved, 0.0)
            np.testing.assert_array_equal(first.age, np.full(27, 200.0))

    def test_a_checkpoint_file_restores_with_another_thread_count(self):
        path = os.path.join(support.output_directory("checkpoint"), "pile.qck")
        with settled_pile(threads=2) as sim:
            sim.register_property("age", 1, "steps", 0.0)
            sim.save_checkpoint(path)
            with quarry.Simulation.open(checkpoint=path, threads=1) as restored:
                self.assertEqual(restored.properties, sim.properties)
                self.assertEqual((restored.time, restored.steps), (sim.time, sim.steps))
                self.assertEqual(restored.find_surface("floor"), 0)
                a = run_partner(sim, 100)
                b = run_partner(restored, 100)
                print(
                    "\ncheckpoint %s: %d bytes; 2 threads and 1 thread after it: same bits %s"
                    % (os.path.basename(path), os.path.getsize(path), same_bits(a, b))
                )
                self.assertTrue(same_bits(a, b), "the checkpoint did not continue bit-identically")

    def test_bytes_that_are_no_state_are_refused(self):
        with settled_pile() as sim:
            with self.assertRaises(quarry.InputError) as caught:
                sim.restore_state(b"not a checkpoint")
            print("\n%s" % caught.exception)


if __name__ == "__main__":
    unittest.main()
