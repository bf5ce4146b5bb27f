"""Views are zero-copy: a View's numpy array lies on the engine's own memory (the pointer
quarry_view_particles gives), writes through a custom property's view are what get_property then
reads, read-only views cannot be written or made writeable, and the epoch rule holds — after an
insertion the view refuses its stale array until refreshed."""

import ctypes
import unittest

import numpy as np

import quarry
import support
from quarry import _abi
from quarry.simulation import _lib


def engine_pointer(sim, field):
    """The data pointer of quarry_view_particles, asked of the C ABI directly."""
    raw = _abi.quarry_view()
    status = _lib.quarry_view_particles(_abi.quarry_sim(sim._sim.id), int(field), ctypes.byref(raw))
    assert status == quarry.Status.OK
    return raw.data, raw.epoch


class Views(unittest.TestCase):
    def setUp(self):
        self.sim, self.ids = support.drag_simulation(threads=1)
        self.sim.step(30)  # the two types alternate in engine order: type order is another

    def tearDown(self):
        self.sim.close()

    def test_a_position_view_is_the_engines_memory(self):
        view = self.sim.view("position")
        array = view.array
        address, epoch = engine_pointer(self.sim, quarry.Field.POSITION)
        print(
            "\nposition view: numpy data %#x, engine's %#x, epoch %d"
            % (array.ctypes.data, address, epoch)
        )
        self.assertEqual(array.ctypes.data, address)
        self.assertEqual(view.address, address)
        self.assertEqual(view.epoch, epoch)
        self.assertEqual(array.shape, (support.PARTICLES, 3))
        self.assertFalse(array.flags.owndata)
        # In type order through the type_order view, it is what the copies say.
        order = self.sim.view("type_order").array
        copies = self.sim.particles(["id", "position"])
        np.testing.assert_array_equal(array[order], copies.position)
        np.testing.assert_array_equal(self.sim.view("id").array[order], copies.id)
        # A step moves the particles in place: the view's array is on the same memory, new values.
        before = array.copy()
        self.sim.step(1)
        after = view.array
        self.assertEqual(after.ctypes.data, address)
        self.assertTrue(
            np.all(after[:, 2] < before[:, 2]), "the particles fall: the view must show it"
        )
        np.testing.assert_array_equal(
            after[self.sim.view("type_order").array], self.sim.particles("position").position
        )

    def test_read_only_views_cannot_be_written(self):
        array = self.sim.view("velocity").array
        with self.assertRaises(ValueError):
            array[0, 0] = 1.0
        with self.assertRaises(ValueError):
            array.flags.writeable = True
        self.assertFalse(self.sim.view("force").writable)

    def test_writes_through_a_property_view_reach_the_engine(self):
        index = self.sim.register_property("temperature", components=2, unit="K", initial=293.15)
        self.assertEqual(self.sim.register_property("temperature", components=2), index)
        view = self.sim.view_property("temperature")
        self.assertTrue(view.writable)
        array = view.array
        np.testing.assert_array_equal(array, np.full((support.PARTICLES, 2), 293.15))
        engine_ids = self.sim.view("id").array
        array[:, 0] = engine_ids * 10.0  # by id, so that the order cannot matter
        view[:, 1] = -1.5  # through the View itself
        values = self.sim.get_property("temperature")
        ids = self.sim.particles("id").id
        print(
            "\nproperty view: wrote %d x 2 values through numpy at %#x; "
            "get_property reads them back" % (len(ids), array.ctypes.data)
        )
        np.testing.assert_array_equal(values[:, 0], ids * 10.0)
        np.testing.assert_array_equal(values[:, 1], np.full(len(ids), -1.5))
        # And set_property's values show in the view (engine order).
        self.sim.set_property("temperature", np.column_stack([ids * 1.0, ids * 2.0]))
        order = self.sim.view("type_order").array
        np.testing.assert_array_equal(view.array[order], np.column_stack([ids * 1.0, ids * 2.0]))
        # The property follows its particles through re-sorts.
        self.sim.step(60)
        values = self.sim.get_property("temperature")
        ids = self.sim.particles("id").id
        np.testing.assert_array_equal(values, np.column_stack([ids * 1.0, ids * 2.0]))

    def test_a_view_goes_stale_when_particles_are_added(self):
        view = self.sim.view("position")
        epoch = view.epoch
        new_ids = support.add_line(self.sim, 8, 0.5)
        self.assertEqual(len(new_ids), 8)
        self.assertNotEqual(self.sim.epoch, epoch)
        self.assertFalse(view.valid)
        with self.assertRaises(quarry.StaleViewError) as caught:
            view.array
        print(
            "\nafter add_particles: epoch %d -> %d; %s"
            % (epoch, self.sim.epoch, caught.exception.message)
        )
        view.refresh()
        self.assertEqual(view.epoch, self.sim.epoch)
        self.assertEqual(view.array.shape, (support.PARTICLES + 8, 3))
        address, _ = engine_pointer(self.sim, quarry.Field.POSITION)
        self.assertEqual(view.array.ctypes.data, address)
        # Removal too; and the removed ids are gone.
        self.sim.remove_particles(new_ids[:3])
        with self.assertRaises(quarry.StaleViewError):
            view.array
        self.assertEqual(len(view.refresh()), support.PARTICLES + 5)
        self.assertNotIn(new_ids[0], self.sim.particles("id").id)

    def test_a_view_survives_steps_without_a_re_sort(self):
        sim, _ = support.drag_simulation(threads=1, sort_interval=0)
        with sim:
            view = sim.view("velocity")
            epoch = view.epoch
            sim.step(100)
            self.assertTrue(view.valid)
            self.assertEqual(view.epoch, epoch)
            np.testing.assert_allclose(
                np.asarray(view)[:, 2], -support.GRAVITY * 100 * support.TIME_STEP, rtol=1e-12
            )

    def test_loads_written_through_the_next_step_view_act_as_set_ones(self):
        # A linear drag F = -c v (c = m / tau) through set_external_loads (type order) in one
        # simulation and written in place through view_next_step_loads (engine order, placed
        # through type_order) in the other: the same bits after every step (both add the same
        # values to the same stored forces before the opening half kick), also across re-sorts.
        copied, ids = support.drag_simulation(threads=1, sort_interval=7)
        written, _ = support.drag_simulation(threads=1, sort_interval=7)
        with copied, written:
            loads = written.view_next_step_loads("force")
            self.assertTrue(loads.writable)
            for step in range(60):
                state = copied.particles(["id", "velocity", "mass"])
                drag = -(state.mass / support.relaxation_time(state.id))[:, None] * state.velocity
                copied.set_external_loads(force=drag, mode="replace", hold="next_step")
                loads.refresh()  # a re-sort moves the epoch: the new order is accepted here
                self.assertFalse(np.any(loads.array), "the next step's loads start at zero")
                loads.array[written.view("type_order").array] = drag
                copied.step(1)
                written.step(1)
                for field in ("position", "velocity"):
                    np.testing.assert_array_equal(
                        getattr(written.particles(field), field), getattr(copied.particles(field), field)
                    )
            with self.assertRaises(ValueError):
                written.view_next_step_loads("position")

    def test_views_of_a_closed_simulation_are_refused(self):
        view = self.sim.view("radius")
        self.sim.close()
        self.assertFalse(view.valid)
        with self.assertRaises(quarry.InvalidHandleError):
            view.array


if __name__ == "__main__":
    unittest.main()
