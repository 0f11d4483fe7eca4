"""epaphe.stage: nodal diameters and travelling waves of a stage, the nodal diameter of a ring's mode,
and the modal-interaction speeds of Legrand et al. (2009), on fields whose answer is known."""
import unittest

import numpy as np

import support  # noqa: F401  (puts python/ on the path)
from epaphe.stage import interaction_speeds, nodal_diameter_content, nodal_diameter_of, travelling_waves


class NodalDiameters(unittest.TestCase):
    def test_travelling_waves(self):
        # 6 blades, a forward 2-ND wave at 50 Hz (amplitude 1) and a backward 1-ND wave at 100 Hz (0.5)
        N, T, dt = 6, 400, 1e-3
        t, th = np.arange(T) * dt, 2 * np.pi * np.arange(N) / N
        x = np.array(
            [np.cos(2 * th[k] - 2 * np.pi * 50 * t) + 0.5 * np.cos(th[k] + 2 * np.pi * 100 * t) for k in range(N)]
        )
        w = travelling_waves(x, dt)
        i50, i100 = np.argmin(abs(w["frequency"] - 50)), np.argmin(abs(w["frequency"] - 100))
        self.assertAlmostEqual(w["forward"][2, i50], 1.0, places=6)
        self.assertLess(w["backward"][2, i50], 1e-4)
        self.assertAlmostEqual(w["backward"][1, i100], 0.5, places=6)
        self.assertLess(w["forward"][1, i100], 1e-4)
        # the spatial content: NDs 1 and 5 (0.25 each: 0.5 split over +-1), 2 and 4 (0.5 each), none at 0 and 3
        nd = nodal_diameter_content(x)
        np.testing.assert_allclose(nd, [0, 0.25, 0.5, 0, 0.5, 0.25], atol=1e-12)

    def test_ring_mode(self):
        # a ring of 48 nodes about the axis {0, 0, 1} through {0.1, 0, 0}: radial cos(3 theta) plus a
        # little tangential motion; its nodal diameter is 3, all of its radial energy
        th = 2 * np.pi * np.arange(48) / 48 + 0.3
        coords = np.c_[0.1 + 0.3 * np.cos(th), 0.3 * np.sin(th), np.zeros(48)]
        er, et = np.c_[np.cos(th), np.sin(th), 0 * th], np.c_[-np.sin(th), np.cos(th), 0 * th]
        u = np.cos(3 * th)[:, None] * er + 0.2 * np.sin(3 * th)[:, None] * et
        n, share = nodal_diameter_of(u, coords, center=(0.1, 0, 0))
        self.assertEqual(n, 3)
        self.assertGreater(share, 1 - 1e-12)
        n, _ = nodal_diameter_of(np.ones(48)[:, None] * er, coords, center=(0.1, 0, 0))
        self.assertEqual(n, 0)  # breathing

    def test_interaction_speeds(self):
        # Omega_n = (omega_b + omega_c,n) / n: blade 100 Hz, casing 2-ND at 300 Hz -> 2 pi 400 / 2
        rows = interaction_speeds([100.0], [(300.0, 2), (500.0, 0), (700.0, 3)])
        self.assertEqual([r[1] for r in rows], [2, 3])  # the breathing mode (0 ND) has no travelling wave
        self.assertAlmostEqual(rows[0][0], 2 * np.pi * 400 / 2, places=9)
        self.assertAlmostEqual(rows[1][0], 2 * np.pi * 800 / 3, places=9)


if __name__ == "__main__":
    unittest.main()
