"""epaphe.exact: the bar on a rigid wall (V1) from inputs/bar-on-wall.xml against its closed form
(bar L = 0.2 m, S = 4e-4 m^2, rho = 8000 kg/m^3, E = 2e11 Pa: c = 5000 m/s, v0 = 100 m/s, gap
U0 = 2 mm): t0 = U0/v0 = 2e-5 s, t1 = t0 + 2L/c = 1e-4 s, F = rho c S v0 = 1.6 MN; a section at
distance s from the contact face moves at v0 until t0 + s/c, rests until t0 + (2L - s)/c, then
moves back at -v0. Also: where the solutions do not apply, and the two-bar case's force."""
import os
import unittest

import numpy as np

import support
from epaphe.deck import read_deck
from epaphe.errors import EpapheError
from epaphe.exact import EXACT, exact_solution
from epaphe.schema import Schema

L, S, RHO, E, V0, U0 = 0.2, 0.02 * 0.02, 8000.0, 2e11, 100.0, 2e-3
C = (E / RHO) ** 0.5
T0, T1, F = U0 / V0, U0 / V0 + 2 * L / C, RHO * C * S * V0


def closed_form_u(s, t):
    """Displacement (m) of the section at distance s from the contact face at times t."""
    a, b = T0 + s / C, T0 + (2 * L - s) / C
    return V0 * np.minimum(t, a) - V0 * np.clip(t - b, 0.0, None)


class BarOnWall(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.schema = Schema.of(support.RUN)
        cls.ex = exact_solution("bar-on-wall", support.BAR, cls.schema)

    def test_constants(self):
        ex = self.ex
        self.assertEqual(ex.body, "Bar")
        for got, want in ((ex.t0, T0), (ex.t1, T1), (ex.F, F), (ex.c, C), (ex.m, RHO * L * S), (ex.U0, U0)):
            self.assertAlmostEqual(got, want, delta=1e-12 * abs(want))
        self.assertAlmostEqual(T0, 2e-5, delta=1e-18)  # the numbers docs/verification.md V1 states
        self.assertAlmostEqual(T1, 1e-4, delta=1e-18)
        self.assertAlmostEqual(F, 1.6e6, delta=1e-6)

    def test_curves(self):
        t = (np.arange(2000) + 0.5) * 1e-7  # off the breaks (U0 = 0.202 - 0.2 is 2e-3 + 2e-18)
        np.testing.assert_allclose(self.ex.force(t), np.where((t >= T0) & (t < T1), F, 0.0))
        for s in (0.0, 0.05, L / 2, L):
            np.testing.assert_allclose(self.ex.displacement([s], t)[:, 0], closed_form_u(s, t), rtol=0, atol=1e-15)
        face = closed_form_u(0.0, t)
        np.testing.assert_allclose(self.ex.face(t), face, atol=1e-15)
        np.testing.assert_allclose(self.ex.gap(t), np.where((t >= T0) & (t < T1), 0.0, U0 - face), atol=1e-15)
        # momentum m v0 until t0, falling at F to -m v0 at t1: the rebound at -v0
        np.testing.assert_allclose(
            self.ex.momentum(np.array([0.0, T0, (T0 + T1) / 2, T1, 2e-4])),
            RHO * L * S * V0 * np.array([1, 1, 0, -1, -1]),
            atol=1e-12,
        )

    def test_measures(self):
        m = self.ex.measures(2e-4, np.array([0]), 0, -1)
        self.assertAlmostEqual(m["contact start"], T0)
        self.assertAlmostEqual(m["contact end"], T1)
        self.assertAlmostEqual(m["impulse"], F * (T1 - T0), delta=1e-9)  # 128 N s
        self.assertAlmostEqual(m["rebound velocity"], -V0)
        # the Box mesh's node ids: x of node i is i L / nx; the contact face is x+ (s = L - x)
        ids = np.array([0, 100, 50])
        np.testing.assert_allclose(self.ex.node_s(ids), [L, 0.0, L / 2], atol=1e-15)

    def test_does_not_apply(self):
        with self.assertRaisesRegex(EpapheError, "'two-bars' does not apply .*two bodies"):
            exact_solution("two-bars", support.BAR, self.schema)
        tilted = read_deck(support.BAR).override({"Bodies->Bar->Initial velocity": "{100, 5, 0}"}, self.schema)
        with self.assertRaisesRegex(EpapheError, "'bar-on-wall' does not apply.*not along \\+x"):
            exact_solution("bar-on-wall", tilted, self.schema)
        with self.assertRaisesRegex(EpapheError, "unknown exact solution 'bar-on-floor'.*bar-on-wall"):
            exact_solution("bar-on-floor", support.BAR, self.schema)
        self.assertEqual(sorted(EXACT), ["bar-on-wall", "two-bars"])

    def test_two_bars_force(self):
        """V2: the force is rho c S v / 2 for 4L/c (the struck bar is identical, clamped far)."""
        ex = exact_solution("two-bars", os.path.join(support.SOURCE, "inputs", "two-bars.xml"), self.schema)
        self.assertAlmostEqual(ex.F, ex.bar.rho * ex.c * ex.S * ex.v0 / 2, delta=1e-9 * ex.F)
        self.assertAlmostEqual(ex.t1 - ex.t0, 4 * ex.L / ex.c, delta=1e-15)


if __name__ == "__main__":
    unittest.main()
