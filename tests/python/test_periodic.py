"""Periodic axes through the Python module (set_settings(periodic=...), ABI 1.1): in a box periodic
in x and y a sphere leaving through the x face re-enters at the other with its velocity, two
spheres touch through the faces (equal and opposite forces); the axes are given as names or as
three flags and read back as names; bad axes and periods too short for the particles raise
BadValueError with the engine's text and leave the settings as they were."""

import unittest

import numpy as np

import quarry

RADIUS = 0.005  # m
BOX = 0.1  # m, the period along x and y


def periodic_box(periodic, start=True):
    """Glass spheres of radius 5 mm in [0, 0.1]² × [−0.05, 0.05] m, dt = 1e-5 s, no gravity,
    with these periodic axes; started with three spheres: 1 at x = 0.098 m moving +1 m/s (it crosses
    the x face after 2 ms), 2 and 3 at rest 9.9 mm apart through the x faces."""
    sim = quarry.Simulation.empty(threads=1)
    sim.add_material("glass", 2500.0, 1e7, 0.3)
    sim.add_interaction("glass", "glass", restitution=0.5, static_friction=0.5)
    sim.add_particle_type("bead", "glass", RADIUS)
    sim.set_settings(
        time_step=1e-5,
        gravity=(0.0, 0.0, 0.0),
        domain=((0.0, 0.0, -0.05), (BOX, BOX, 0.05)),
        impact_speed=1.0,
        periodic=periodic,
    )
    if start:
        sim.start()
        sim.add_particles(
            [[0.098, 0.05, 0.0], [0.004, 0.02, 0.0], [BOX - 0.0059, 0.02, 0.0]],
            velocity=[[1.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]],
        )
    return sim


def by_id(sim):
    p = sim.particles(["id", "position", "velocity", "force"])
    return {int(i): (p.position[k], p.velocity[k], p.force[k]) for k, i in enumerate(p.id)}


class PeriodicAxes(unittest.TestCase):
    def test_a_sphere_reenters_and_a_pair_touches_through_the_faces(self):
        with periodic_box(("x", "y")) as sim:
            self.assertEqual(sim.settings["periodic"], ("x", "y"))
            sim.step(1)
            p = by_id(sim)
            self.assertGreater(p[2][2][0], 0.0)  # pushed +x by 3's image at x = −5.9 mm
            self.assertEqual(p[3][2][0], -p[2][2][0])
            force = p[2][2][0]
            sim.step(499)  # 5 mm travelled by sphere 1: from 0.098 m through 0.1 m to 0.003 m
            p = by_id(sim)
            self.assertEqual(len(p), 3)
            self.assertAlmostEqual(p[1][0][0], 0.003, delta=1e-9)
            np.testing.assert_array_equal(p[1][1], [1.0, 0.0, 0.0])
            print(
                "\n  the pair's force through the faces %.4g N; sphere 1 at x = %.6f m after "
                "crossing" % (force, p[1][0][0])
            )

    def test_without_periodic_axes_the_sphere_leaves(self):
        with periodic_box(()) as sim:
            self.assertEqual(sim.settings["periodic"], ())
            sim.step(500)
            p = by_id(sim)
            self.assertEqual(sorted(p), [2, 3])
            np.testing.assert_array_equal(p[2][1], [0.0, 0.0, 0.0])  # 0.09 m apart: no contact

    def test_names_and_flags_are_the_same_axes(self):
        for given in (("x", "y"), ["X", "y"], "xy", (True, True, False), [1, 1, 0]):
            with periodic_box(given, start=False) as sim:
                self.assertEqual(sim.settings["periodic"], ("x", "y"), given)
        self.assertEqual(quarry.default_settings()["periodic"], ())

    def test_bad_axes_and_short_periods_are_refused_and_change_nothing(self):
        with periodic_box(("x", "y"), start=False) as sim:
            cases = [
                (("x", "w"), 'set_settings: periodic: "w" is not an axis'),
                (("y", "y"), 'axis "y" is named twice'),
                ([1, 2, 0], "neither axis names"),
                (1, "neither axis names"),
            ]
            for given, fragment in cases:
                with self.assertRaises(quarry.BadValueError) as caught:
                    sim.set_settings(periodic=given)
                self.assertIn(fragment, caught.exception.message)
                print("\n  %r: %s" % (given, caught.exception))
            with self.assertRaises(quarry.BadValueError) as caught:
                sim.set_settings(domain=((0.0, 0.0, -0.05), (0.03, BOX, 0.05)))
            self.assertIn(
                "the period along x (0.03 m) is shorter than the neighbour search needs",
                caught.exception.message,
            )
            self.assertIn(
                "hint: make the domain at least 0.033 m long along x", caught.exception.message
            )
            print("\n  %s" % caught.exception)
            with self.assertRaises(quarry.BadValueError):
                sim.add_particle_type("boulder", "glass", 0.02)  # needs 3 × (40 + 4) mm > 0.1 m
            self.assertEqual(sim.type_names, ["bead"])
            self.assertEqual(sim.settings["periodic"], ("x", "y"))
            self.assertEqual(sim.settings["domain_max"], (BOX, BOX, 0.05))
            sim.start()  # with the settings that were accepted


if __name__ == "__main__":
    unittest.main()
