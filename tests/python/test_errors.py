"""Errors become exceptions: every non-OK status raises the QuarryError subclass of its code,
carrying the code, its C name and the engine's own message (what and where) — for a bad length,
an unknown id, a call in the wrong state, a broken deck, a dead handle — and the module's own
checks (before the engine is called) raise the same classes."""

import os
import unittest

import numpy as np

import quarry
import support
from quarry import _abi

SOURCE = os.environ.get("QUARRY_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))


class EngineErrors(unittest.TestCase):
    def setUp(self):
        self.sim, self.ids = support.drag_simulation(threads=1)

    def tearDown(self):
        self.sim.close()

    def check(self, error, cls, status, *fragments):
        self.assertIsInstance(error, cls)
        self.assertIsInstance(error, quarry.QuarryError)
        self.assertEqual(error.status, status)
        self.assertEqual(error.status_name, quarry.status_name(status))
        self.assertEqual(str(error), "%s: %s" % (error.status_name, error.message))
        for fragment in fragments:
            self.assertIn(fragment, error.message)
        print("\n  %s" % error)

    def test_a_bad_length(self):
        with self.assertRaises(quarry.BadLengthError) as caught:
            self.sim.set_external_loads(np.zeros((support.PARTICLES + 1, 3)))
        self.check(
            caught.exception,
            quarry.BadLengthError,
            quarry.Status.ERROR_BAD_LENGTH,
            "quarry_set_external_loads: 41 entries for 40 particles",
        )
        self.assertIsInstance(caught.exception, ValueError)
        with self.assertRaises(quarry.BadLengthError) as caught:
            self.sim.set_property(
                self.sim.register_property("heat", 2), np.zeros(support.PARTICLES)
            )
        self.check(
            caught.exception,
            quarry.BadLengthError,
            quarry.Status.ERROR_BAD_LENGTH,
            "quarry_set_property 'heat': 40 values for 40 particles × 2 components",
        )

    def test_an_unknown_id(self):
        with self.assertRaises(quarry.NotFoundError) as caught:
            self.sim.remove_particles([self.ids[0], 987654])
        self.check(
            caught.exception,
            quarry.NotFoundError,
            quarry.Status.ERROR_NOT_FOUND,
            "particle id 987654 does not exist",
            "nothing was removed",
        )
        self.assertEqual(len(self.sim), support.PARTICLES)
        with self.assertRaises(quarry.NotFoundError) as caught:
            self.sim.set_external_loads(np.ones((1, 3)), ids=[987654])
        self.check(
            caught.exception,
            quarry.NotFoundError,
            quarry.Status.ERROR_NOT_FOUND,
            "particle id 987654 (entry 0)",
        )
        with self.assertRaises(LookupError):
            self.sim.particle_index(987654)

    def test_the_wrong_state(self):
        with self.assertRaises(quarry.WrongStateError) as caught:
            self.sim.add_material("steel", 7800, 2e11, 0.3)
        self.check(
            caught.exception,
            quarry.WrongStateError,
            quarry.Status.ERROR_WRONG_STATE,
            "quarry_add_material: the simulation is started",
        )
        with quarry.Simulation.empty() as empty:
            with self.assertRaises(quarry.WrongStateError) as caught:
                empty.advance(0.1)
            self.check(
                caught.exception,
                quarry.WrongStateError,
                quarry.Status.ERROR_WRONG_STATE,
                "quarry_advance: the simulation is not started yet",
            )

    def test_an_incomplete_definition_is_an_input_error(self):
        with quarry.Simulation.empty() as empty:
            empty.set_settings(domain=((-1, -1, -1), (1, 1, 1)))
            empty.add_material("ore", 2500, 1e6, 0.3)
            empty.add_particle_type("fine", "ore", 1e-3)
            with self.assertRaises(quarry.InputError) as caught:
                empty.start()
            self.check(
                caught.exception, quarry.InputError, quarry.Status.ERROR_INPUT, "interaction"
            )

    def test_a_broken_deck_names_its_line(self):
        deck = os.path.join(SOURCE, "tests", "bad_decks", "02_unknown_key.yaml")
        with self.assertRaises(quarry.InputError) as caught:
            quarry.Simulation.open(deck=deck)
        self.check(
            caught.exception,
            quarry.InputError,
            quarry.Status.ERROR_INPUT,
            '02_unknown_key.yaml:7:5: error: unknown key "densty" in material',
        )

    def test_a_bad_value_and_a_bad_enum(self):
        with self.assertRaises(quarry.BadValueError) as caught:
            self.sim.advance(float("nan"))
        self.check(
            caught.exception,
            quarry.BadValueError,
            quarry.Status.ERROR_BAD_VALUE,
            "not a finite number",
        )
        with self.assertRaises(quarry.BadValueError) as caught:
            self.sim.set_external_loads(np.zeros((support.PARTICLES, 3)), hold="forever")
        self.check(
            caught.exception,
            quarry.BadValueError,
            quarry.Status.ERROR_BAD_VALUE,
            '"forever"',
            "until_changed",
        )

    def test_a_dead_handle(self):
        forged = quarry.Simulation(_abi.quarry_sim(0xDEAD), False)
        with self.assertRaises(quarry.InvalidHandleError) as caught:
            forged.step(1)
        self.check(
            caught.exception,
            quarry.InvalidHandleError,
            quarry.Status.ERROR_INVALID_HANDLE,
            "quarry_step: handle 0xdead is not an open simulation",
        )
        forged._finalizer.detach()
        self.sim.close()
        with self.assertRaises(quarry.InvalidHandleError) as caught:
            self.sim.particles()
        self.check(
            caught.exception,
            quarry.InvalidHandleError,
            quarry.Status.ERROR_INVALID_HANDLE,
            "closed",
        )
        self.sim.close()  # twice: nothing

    def test_the_modules_own_checks(self):
        with self.assertRaises(quarry.BadLengthError) as caught:
            self.sim.set_external_loads(np.zeros(7))
        self.check(
            caught.exception,
            quarry.BadLengthError,
            quarry.Status.ERROR_BAD_LENGTH,
            "7 values are not 3 per entry",
        )
        with self.assertRaises(TypeError) as caught:
            self.sim.set_settings(time_stp=1e-5)
        self.assertIn('did you mean "time_step"', str(caught.exception))
        with self.assertRaises(quarry.BadValueError) as caught:
            self.sim.particles(["postion"])
        self.assertIn('did you mean "position"', caught.exception.message)
        with self.assertRaises(quarry.NotFoundError) as caught:
            self.sim.num_particles("coarse_")
        self.assertIn('did you mean "coarse"', caught.exception.message)


class AbiVersion(unittest.TestCase):
    def test_the_library_has_the_modules_major(self):
        major, minor = quarry.abi_version()
        print(
            "\nlibrary %s (ABI %d.%d) from %s; module ABI %d.%d"
            % (
                quarry.version(),
                major,
                minor,
                quarry.library_path,
                quarry.ABI_MAJOR,
                quarry.ABI_MINOR,
            )
        )
        self.assertEqual(major, quarry.ABI_MAJOR)

    def test_another_major_is_refused_clearly(self):
        with self.assertRaises(ImportError) as caught:
            _abi.check_abi_version((quarry.ABI_MAJOR + 1) << 16 | 3)
        self.assertIn(
            "libquarry.so has ABI %d.3, this Python module was written for ABI %d.%d"
            % (quarry.ABI_MAJOR + 1, quarry.ABI_MAJOR, quarry.ABI_MINOR),
            str(caught.exception),
        )
        _abi.check_abi_version(
            quarry.ABI_MAJOR << 16 | (quarry.ABI_MINOR + 1)
        )  # a newer minor is fine

    def test_open_sends_the_modules_version(self):
        # The engine refuses a caller of another major at quarry_open with VERSION.
        import ctypes

        from quarry.simulation import _lib

        info = _abi.sized(_abi.quarry_open_info, abi_version=(quarry.ABI_MAJOR + 1) << 16)
        handle = _abi.quarry_sim(0)
        status = _lib.quarry_open(ctypes.byref(info), ctypes.byref(handle))
        self.assertEqual(status, quarry.Status.ERROR_VERSION)


if __name__ == "__main__":
    unittest.main()
