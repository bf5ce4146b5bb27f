"""Step hooks written in Python: a POST_FORCE hook adding linear drag with add_hook_forces reaches
the same terminal velocity as the drag set between steps (test_terminal_velocity), along a
discrete path of its own, derived here; and a Python exception in a hook stops the step and
comes back out of step() chained to the engine's HookError.

The hook-driven scheme. Velocity Verlet with F = m g − c w, where w is the velocity the hook
sees: POST_FORCE runs after the drift and the forces of the new positions, before the closing
half kick, so w_n = v_{n−1} + (dt/2) F_{n−1}/m is the half-step velocity v(t_n − dt/2) of step n
(quarry.h, step hooks). With a = dt/τ, τ = m/c, v_t = g τ (all along −z):
    v_n     = w_n + (dt/2)(g − w_n/τ)                       (closing half kick of step n)
    w_{n+1} = v_n + (dt/2)(g − w_n/τ) = w_n + dt (g − w_n/τ) (opening half kick of step n + 1,
                                                              with step n's force)
so the half-step velocities follow forward Euler: w_{n+1} − v_t = (1 − a)(w_n − v_t). Step 1
starts from rest with F_0 = m g (no hook has run yet: particles are added with their weight), so
w_1 = g dt/2 = v_t a/2, and for n ≥ 1
    w_n = v_t [1 − (1 − a/2)(1 − a)^{n−1}],   v_n = w_n (1 − a/2) + v_t a/2
        = v_t [1 − (1 − a/2)² (1 − a)^{n−1}].
Both tend to v_t — the fixed point of w = w (1 − a) + v_t a is w = v_t, and then v = v_t — so
the hook gives the same terminal velocity m g / c. Against the ODE's v_t (1 − e^{−t/τ}):
ln[(1 − a/2)²(1 − a)^{n−1}] = −an − a²(2n − 1)/4 + O(n a³), so the error is
v_t e^{−an} a²(2n − 1)/4 + O(a³ n) ≤ v_t (a/2) (an) e^{−an} ≤ v_t a/(2e), the bound of forward
Euler in test_terminal_velocity (× 1.05 for the remainder); and w_n is v(t_n − dt/2) within the
same bound.
"""

import gc
import math
import unittest

import numpy as np

import quarry
import support

STEPS = 5000


def compare(recorded, decay, offset):
    """The worst |v_z − expected| / v_t and |v_z − continuous| / bound over the recorded steps:
    expected = −v_t (1 − decay(a, n)), continuous = −v_t (1 − e^{−t/τ}) at t = (n + offset) dt."""
    dt, g = support.TIME_STEP, support.GRAVITY
    worst_discrete, worst_ratio = 0.0, 0.0
    for n, (ids, vz) in recorded.items():
        tau = support.relaxation_time(ids)  # s
        a = dt / tau
        v_terminal = g * tau  # m/s
        expected = -v_terminal * (1.0 - decay(a, n))
        continuous = -v_terminal * (1.0 - np.exp(-(n + offset) * dt / tau))
        bound = 1.05 * v_terminal * a / (2.0 * math.e)
        worst_discrete = max(worst_discrete, float(np.max(np.abs(vz - expected) / v_terminal)))
        worst_ratio = max(worst_ratio, float(np.max(np.abs(vz - continuous) / bound)))
    return worst_discrete, worst_ratio


class DragHook(unittest.TestCase):
    def test_post_force_drag_reaches_the_terminal_velocity(self):
        sim, _ = support.drag_simulation()
        dt, g = support.TIME_STEP, support.GRAVITY
        half_step = {}  # step -> (ids, w_z) seen in the hook, type order
        full_step = {}  # step -> (ids, v_z) at the end of the step

        def drag(s):
            # Zero-copy views in engine order, valid inside this call of the hook.
            velocity = s.view("velocity").array  # m/s, v(t + dt/2)
            ids = s.view("id").array
            inverse_mass = s.view("inverse_mass").array  # 1/kg
            order = s.view("type_order").array
            drag_coefficient = 1.0 / (inverse_mass * support.relaxation_time(ids))  # kg/s
            force = -drag_coefficient[:, None] * velocity  # N, engine order
            s.add_hook_forces(force[order])
            half_step[s.steps] = (ids[order].copy(), velocity[order, 2].copy())

        def record(s):
            p = s.particles(["id", "velocity"])
            full_step[s.steps] = (p.id, p.velocity[:, 2])

        with sim:
            sim.set_hook("post_force", drag)
            sim.set_hook(quarry.HookStage.END_OF_STEP, record)
            taken = sim.advance(STEPS * dt)
            self.assertEqual(taken, STEPS)
            self.assertEqual(sorted(half_step), list(range(1, STEPS + 1)))
            self.assertEqual(sorted(full_step), list(range(1, STEPS + 1)))
            # (discrete error / v_t, error against the ODE / bound) over the steps, for the
            # half-step velocities (the ODE at t_n − dt/2) and the full-step ones (at t_n).
            half = compare(half_step, lambda a, n: (1.0 - a / 2) * (1.0 - a) ** (n - 1), -0.5)
            full = compare(full_step, lambda a, n: (1.0 - a / 2) ** 2 * (1.0 - a) ** (n - 1), 0.0)
            (worst_half, worst_half_ratio), (worst_full, worst_ratio) = half, full
            ids, vz = full_step[STEPS]
            reached = float(np.min(-vz / (g * support.relaxation_time(ids))))
            print(
                "\nPOST_FORCE drag hook, %d steps: half-step w_n against "
                "v_t[1 - (1 - a/2)(1 - a)^(n-1)]: %.3g v_t; full-step v_n against "
                "v_t[1 - (1 - a/2)^2 (1 - a)^(n-1)]: %.3g v_t; |v_n - continuous| / bound = %.4f, "
                "|w_n - v(t - dt/2)| / bound = %.4f; slowest particle at %.6f v_t"
                % (STEPS, worst_half, worst_full, worst_ratio, worst_half_ratio, reached)
            )
            self.assertLess(
                worst_half, 1e-11, "the hook's half-step velocities leave the derived recursion"
            )
            self.assertLess(
                worst_full, 1e-11, "the full-step velocities leave the derived solution"
            )
            self.assertLessEqual(worst_ratio, 1.0)
            self.assertLessEqual(worst_half_ratio, 1.0)
            self.assertGreater(
                reached, 1.0 - 1e-3, "the hook's drag did not bring the particles to m g / c"
            )


class HookErrors(unittest.TestCase):
    def setUp(self):
        self.sim, _ = support.drag_simulation(threads=1)

    def tearDown(self):
        self.sim.close()

    def test_an_exception_in_the_hook_stops_the_step_and_is_chained(self):
        def failing(s):
            if s.steps == 3:
                raise ValueError("the partner's solver diverged")

        self.sim.set_hook("post_force", failing)
        with self.assertRaises(quarry.HookError) as caught:
            self.sim.step(10)
        error = caught.exception
        print("\n%s\n  caused by %r" % (error, error.__cause__))
        self.assertEqual(error.status, quarry.Status.ERROR_HOOK)
        self.assertEqual(error.status_name, "QUARRY_ERROR_HOOK")
        self.assertIn("POST_FORCE hook returned 1 at step 3", error.message)
        self.assertIsInstance(error.__cause__, ValueError)
        self.assertEqual(str(error.__cause__), "the partner's solver diverged")
        self.assertEqual(self.sim.steps, 3, "the step did not stop in step 3")

    def test_a_forbidden_call_inside_a_hook_is_the_cause(self):
        self.sim.set_hook("end_of_step", lambda s: s.set_external_loads(np.zeros((len(s), 3))))
        with self.assertRaises(quarry.HookError) as caught:
            self.sim.step(1)
        cause = caught.exception.__cause__
        self.assertIsInstance(cause, quarry.WrongStateError)
        self.assertIn("not allowed inside a step hook", cause.message)
        self.sim.set_hook("end_of_step", None)
        self.sim.step(2)  # no hook any more

    def test_keyboard_interrupt_passes_through_unchanged(self):
        def interrupted(s):
            raise KeyboardInterrupt

        self.sim.set_hook("end_of_step", interrupted)
        with self.assertRaises(KeyboardInterrupt):
            self.sim.step(5)

    def test_a_true_return_value_stops_the_step(self):
        self.sim.set_hook("end_of_step", lambda s: 7 if s.steps == 2 else None)
        with self.assertRaises(quarry.HookError) as caught:
            self.sim.step(5)
        self.assertIn("returned 7 at step 2", caught.exception.message)
        self.assertIsNone(caught.exception.__cause__)

    def test_the_callback_outlives_the_function_objects_that_made_it(self):
        calls = []
        self.sim.set_hook("end_of_step", lambda s: calls.append(s.steps))
        gc.collect()
        self.sim.step(4)
        self.assertEqual(calls, [1, 2, 3, 4])

    def test_hook_forces_outside_a_hook_are_refused(self):
        with self.assertRaises(quarry.WrongStateError) as caught:
            self.sim.add_hook_forces(np.zeros((len(self.sim), 3)))
        self.assertIn("only inside a POST_FORCE hook", caught.exception.message)


if __name__ == "__main__":
    unittest.main()
