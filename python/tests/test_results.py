"""epaphe.results on a short run of the bar on a rigid wall (inputs/bar-on-wall.xml, End time 4e-5 s):
the arrays, their units and the known values of the case (docs/verification.md V1: bar 0.2 m x 2 cm
x 2 cm, rho 8000 kg/m^3, E 2e11 Pa (c = 5000 m/s), 100 m/s towards a wall 2 mm away: contact from
t0 = 2e-5 s, plateau F = rho c S v = 1.6 MN), and the errors on wrong files and names."""
import os
import unittest

import h5py
import numpy as np

import support
import epaphe
from epaphe.errors import EpapheError, UnknownName

V, GAP, H = 100.0, 2e-3, 1e-7  # m/s, m, s: the deck's speed, gap, time step
T0, F = GAP / V, 8000 * 5000 * 0.02 * 0.02 * V  # contact start (s), plateau force (N)
MASS = 8000 * 0.2 * 0.02 * 0.02  # kg


class ShortBarRun(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = support.workdir("results")
        cls.path = support.short_bar_run(cls.dir)
        cls.out = epaphe.open(cls.path)

    @classmethod
    def tearDownClass(cls):
        cls.out.close()

    def test_run(self):
        r = self.out
        self.assertEqual(r.status, "complete")
        self.assertTrue(r.complete)
        # one record a step (Output->Every 1) from 0 to the last step before End time
        self.assertEqual(r.records, 400)
        np.testing.assert_allclose(r.time, H * np.arange(400), rtol=0, atol=1e-18)
        self.assertEqual(float(r.attrs["time_step"]), H)
        self.assertEqual(r.name, "bar on a rigid wall (V1)")
        # the deck the run was made from, with the override
        self.assertEqual(r.deck.get("Time->End time"), "4e-5")
        self.assertEqual(r.deck.get("Contact->Method"), "Lagrange")

    def test_bodies_and_node_sets(self):
        bar = self.out.bodies["Bar"]
        self.assertEqual(list(self.out.bodies), ["Bar"])
        self.assertEqual(sorted(bar.nodesets), ["x+", "x-"])
        d = bar.nodesets["x-"].displacement
        self.assertEqual(d.shape, (400, bar.nodesets["x-"].nodes.size, 3))
        # before contact the bar moves freely at 100 m/s: u = v t at every node (central difference
        # is exact for a constant speed; round-off on 2e-3 m over 200 steps stays far below 1e-12 m).
        # (After t0 the far face moves too, by up to 5e-6 m: the discrete model's fast high
        # wavenumbers arrive before the 1-D wave, at t0 + L/c = 6e-5 s.)
        free = self.out.time < T0 - 1.5 * H
        np.testing.assert_allclose(
            d[free, :, 0], V * self.out.time[free, None] * np.ones(d.shape[1]), rtol=0, atol=1e-12
        )
        np.testing.assert_allclose(d[free, :, 1:], 0.0, atol=1e-12)
        np.testing.assert_allclose(
            bar.nodesets["x-"].velocity[free, :, 0], V, rtol=1e-9
        )  # round-off of the modal recovery: 2e-12 seen
        # the contact face stops at the wall (Lagrange: no penetration, up to round-off)
        u = bar.nodesets["x+"].displacement.mean(axis=1)[:, 0]
        np.testing.assert_allclose(u, np.minimum(V * self.out.time, GAP), rtol=0, atol=1e-12)
        # momentum and mass: m v = 64 kg m/s, m = 0.64 kg
        self.assertAlmostEqual(bar.rigid_mass, MASS, delta=1e-9 * MASS)
        np.testing.assert_allclose(bar.momentum[0], [MASS * V, 0, 0], rtol=1e-9, atol=1e-6)

    def test_contact(self):
        c = self.out.bodies["Bar"].contact
        t = self.out.time
        self.assertEqual(c.gap.shape, (400, c.nodes.size))
        np.testing.assert_allclose(c.gap[0], GAP, rtol=1e-12)  # 2 mm at t = 0
        np.testing.assert_allclose(c.force.sum(axis=1), c.total_force, rtol=1e-12, atol=1e-6)
        # no force before the step that closes the gap (the Lagrange force of step n acts over
        # [t_n, t_n+1]: the first is on the record before t0)
        self.assertTrue(np.all(c.total_force[t < T0 - 1.5 * H] == 0.0))
        self.assertGreater(c.total_force.max(), 0.0)
        # impulse over the run = F (t_end - t0): 32 N s; V1 asserts 2 % on the impulse
        impulse = c.total_force.sum() * H
        self.assertAlmostEqual(impulse, F * (t[-1] + H - T0), delta=0.02 * F * (t[-1] + H - T0))

    def test_energy(self):
        e = self.out.energy
        self.assertAlmostEqual(e.kinetic[0], 0.5 * MASS * V**2, delta=1e-9 * 0.5 * MASS * V**2)  # 3200 J
        self.assertEqual(e.strain[0], 0.0)
        for name in ("kinetic", "strain", "total", "contact_work", "external_work", "damping", "balance_error"):
            self.assertEqual(getattr(e, name).shape, (400,), name)
        # the sweep's bound for a complete bar run (tests/unit_sweep: energy balance < 1e-8)
        self.assertLess(np.abs(e.balance_error).max(), 1e-8)
        # no thermal model: no heat term (verification.heat-balance reads a run with one)
        self.assertFalse(e.has_heat)
        self.assertEqual(e.heat, {})

    def test_flat_view(self):
        h = epaphe.history(self.path)
        self.assertIn("time", h)
        np.testing.assert_array_equal(
            h["bodies/Bar/contact/total_force"].reshape(-1), self.out.bodies["Bar"].contact.total_force
        )
        self.assertEqual(int(h["attrs"]["steps"]), 400)
        self.assertIn("rigid_mass", h["bodies/Bar/attrs"])
        self.assertNotIn("run/deck", h)  # numbers only

    def test_unknown_names(self):
        with self.assertRaises(UnknownName) as cm:
            self.out.bodies["Wheel"]
        self.assertIn("'Wheel'", str(cm.exception))
        self.assertIn("available: Bar", str(cm.exception))
        with self.assertRaises(UnknownName) as cm:
            self.out.bodies["Bar"].nodesets["y+"]
        self.assertIn("'y+'", str(cm.exception))
        self.assertIn("x+, x-", str(cm.exception))
        self.assertIsInstance(cm.exception, KeyError)  # `in`, .get() work as on a dict
        self.assertIsNone(self.out.bodies.get("Wheel"))

    def test_wrong_files(self):
        with self.assertRaisesRegex(EpapheError, "no such file: .*absent.h5"):
            epaphe.open(os.path.join(self.dir, "absent.h5"))
        with self.assertRaisesRegex(EpapheError, "bar-on-wall.xml: not an HDF5 file"):
            epaphe.open(os.path.join(self.dir, "bar-on-wall.xml"))
        notime = os.path.join(self.dir, "notime.h5")
        with h5py.File(notime, "w") as f:
            f["energy/kinetic"] = np.zeros(3)
        with self.assertRaisesRegex(EpapheError, "notime.h5: not an Epaphe history file"):
            epaphe.open(notime)
        stopped = os.path.join(self.dir, "stopped.h5")
        with h5py.File(stopped, "w") as f:
            f["time"] = np.zeros(1)
            f.attrs["status"] = "stopped: test"
        with self.assertRaisesRegex(EpapheError, "stopped: test"):
            epaphe.history(stopped)
        self.assertEqual(epaphe.open(stopped).status, "stopped: test")


if __name__ == "__main__":
    unittest.main()
