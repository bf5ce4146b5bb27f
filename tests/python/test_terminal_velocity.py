"""The terminal-velocity check of tests/capi/coupling_partner.c (check 1), from Python.

Particles fall under gravity with a linear drag F = −c v that this partner computes from the
velocities it reads and sets before every step through set_external_loads (replace, next step
only): v(t) = v_t (1 − e^{−t/τ}), v_t = m g / c, τ = m / c. The engine applies F_n = −c v_n in
both half kicks of step n, with gravity, so v_{n+1} = v_n + dt (g − v_n / τ): forward Euler for
the ODE. Its exact discrete solution is v_n = v_t (1 − (1 − a)^n), a = dt/τ, which the engine
must reproduce to round-off; its distance to the continuous solution is
v_t [e^{−an} − (1 − a)^n] ≈ v_t (a/2)(t/τ) e^{−t/τ} ≤ v_t a / (2e) (largest at t = τ), the
tolerance (× 1.05 for the O(a²) remainder). The derivation is coupling_partner.c's.
"""

import math
import unittest

import numpy as np

import support

STEPS = 5000  # 0.5 s: t/τ from 8 to 25, the particles reach v_t


class TerminalVelocity(unittest.TestCase):
    def test_drag_set_every_step_follows_forward_euler_and_the_ode(self):
        sim, _ = support.drag_simulation()
        with sim:
            dt, g = support.TIME_STEP, support.GRAVITY
            worst_discrete = 0.0  # |v − discrete| / v_t
            worst_ratio = 0.0  # |v − continuous| / bound
            first_epoch = sim.epoch
            epochs = set()
            for n in range(STEPS):
                p = sim.particles(["id", "mass", "velocity"])
                epochs.add(p.epoch)
                tau = support.relaxation_time(p.id)  # s
                drag_coefficient = p.mass / tau  # kg/s
                v_terminal = g * tau  # m/s
                a = dt / tau
                t = sim.time
                self.assertEqual(sim.steps, n)
                discrete = -v_terminal * (1.0 - (1.0 - a) ** n)
                continuous = -v_terminal * (1.0 - np.exp(-t / tau))
                bound = 1.05 * v_terminal * a / (2.0 * math.e)
                vz = p.velocity[:, 2]
                worst_discrete = max(
                    worst_discrete, float(np.max(np.abs(vz - discrete) / v_terminal))
                )
                worst_ratio = max(worst_ratio, float(np.max(np.abs(vz - continuous) / bound)))
                sim.set_external_loads(
                    -drag_coefficient[:, None] * p.velocity, mode="replace", hold="next_step"
                )
                sim.step(1)
            p = sim.particles(["id", "velocity"])
            v_terminal = g * support.relaxation_time(p.id)
            reached = float(np.min(-p.velocity[:, 2] / v_terminal))
            print(
                "\ndrag from Python, %d particles, %d steps: worst |v - discrete| / v_t = %.3g; "
                "worst |v - continuous| / bound = %.4f; slowest particle at %.6f v_t; "
                "%d epochs seen"
                % (len(p.id), STEPS, worst_discrete, worst_ratio, reached, len(epochs))
            )
            self.assertLess(
                worst_discrete, 1e-11, "the engine departs from forward Euler's discrete solution"
            )
            self.assertLessEqual(
                worst_ratio, 1.0, "the error against v_t (1 - e^(-t/tau)) passes its bound"
            )
            self.assertGreater(
                reached, 1.0 - 1e-3, "a particle did not reach its terminal velocity"
            )
            self.assertTrue(
                np.all(p.velocity[:, :2] == 0.0), "drag made a horizontal velocity out of nothing"
            )
            self.assertGreater(
                len(epochs), 1, "no re-sort happened: the type-order bookkeeping went untested"
            )
            self.assertNotEqual(sim.epoch, first_epoch)


if __name__ == "__main__":
    unittest.main()
