"""epaphe.measures on synthetic signals with known answers: the spectrum of a sine (its engine order
and amplitude), engine-order lines, contact events per revolution of a synthetic rotor file, the
study measures of a rectangular force pulse, the RMS difference of two known curves."""
import math
import os
import unittest

import h5py
import numpy as np

import support
from epaphe.errors import EpapheError
from epaphe.measures import (
    contact_events,
    engine_order_lines,
    errors,
    raw_measures,
    rms_difference,
    sine_spectrum,
    spectrum,
)
from epaphe.study import Watch

OMEGA = 1000.0  # rad/s
PERIOD = 2 * math.pi / OMEGA  # s, one revolution
N = 400  # samples a revolution


def rotor_file(path, force, u):
    """An Epaphe-shaped file: a blade whose deck turns the casing at OMEGA, one record per sample,
    contact nodes 7 and 9 (tip-le holds 7, tip-te holds 9), the tip-le displacement along x."""
    t = np.arange(force.shape[0]) * PERIOD / N
    deck = (
        '<ParameterList name="Epaphe"><ParameterList name="Surfaces"><ParameterList name="Casing">'
        f'<Parameter name="Rotation speed" type="double" value="{-OMEGA}"/></ParameterList></ParameterList>'
        "</ParameterList>"
    )
    with h5py.File(path, "w") as f:
        f.attrs["status"] = "complete"
        f["time"] = t
        f["run/deck"] = deck
        f["bodies/Blade/contact/nodes"] = np.array([7, 9])
        f["bodies/Blade/contact/force"] = force
        f["bodies/Blade/contact/total_force"] = force.sum(axis=1)
        f["bodies/Blade/nodesets/tip-le/nodes"] = np.array([7])
        f["bodies/Blade/nodesets/tip-le/displacement"] = np.stack([u, 0 * u, 0 * u], axis=1)[:, None, :]
        f["bodies/Blade/nodesets/tip-te/nodes"] = np.array([9])
        f["bodies/Blade/nodesets/tip-te/displacement"] = np.zeros((t.size, 1, 3))
        f["bodies/Blade/nodesets/hub/nodes"] = np.array([3])
        f["bodies/Blade/nodesets/hub/displacement"] = np.zeros((t.size, 1, 3))
    return t


class Spectra(unittest.TestCase):
    def test_sine(self):
        """A sine of engine order 6 (6 periods a revolution) and amplitude 2e-4 m, plus an offset,
        over 5 whole revolutions after 1 skipped: the largest bin is at order 6 with amplitude 2e-4 m.
        The Hann window's amplitude correction (2 / sum(w)) is exact for a sine on a bin of a
        periodic window; numpy's window is symmetric (N points, not N+1), so the sum is off by
        1/N: 1/2000 here, inside the 1e-3 asked."""
        t = np.arange(6 * N) * PERIOD / N
        u = 3e-3 + 2e-4 * np.sin(6 * OMEGA * t + 0.3)
        eo, freq, amp = sine_spectrum(t, u, PERIOD, skip=1)
        k = int(np.argmax(amp))
        self.assertAlmostEqual(eo[k], 6.0, places=9)
        self.assertAlmostEqual(freq[k], 6 * OMEGA / (2 * math.pi), delta=1e-9 * freq[k])
        self.assertAlmostEqual(amp[k], 2e-4, delta=1e-3 * 2e-4)
        self.assertLess(amp[0], 1e-6 * 2e-4)  # the offset is removed
        lines = engine_order_lines(eo, amp, 5)
        self.assertEqual(lines["order"], 6)
        self.assertAlmostEqual(lines["off"], 0.0, places=9)
        self.assertAlmostEqual(lines["lines"][6], amp[k])
        self.assertGreater(lines["even_fraction"], 0.99)  # all of it on an even order

    def test_too_short(self):
        t = np.arange(N) * PERIOD / N
        with self.assertRaisesRegex(EpapheError, "fewer than --skip 3"):
            sine_spectrum(t, np.sin(OMEGA * t), PERIOD, skip=3)


class ContactEvents(unittest.TestCase):
    def test_two_touches_a_revolution(self):
        """tip-le touches twice a revolution, at 45 and 225 degrees, each time for 1/10 of a
        revolution with one bounce inside (merged: less than 0.15 revolution after the start).
        6 revolutions sampled (the last record 1/400 short of the 6th's end: 5 whole), 2 skipped:
        revolutions 2, 3, 4 counted, 2 events each, in contact 20 % of the time less the bounces."""
        path = os.path.join(support.workdir("measures"), "rotor.h5")
        n = 6 * N
        phase = (np.arange(n) % N) / N  # fraction of the revolution
        on = ((phase >= 0.125) & (phase < 0.225)) | ((phase >= 0.625) & (phase < 0.725))
        bounce = ((phase >= 0.15) & (phase < 0.16)) | ((phase >= 0.65) & (phase < 0.66))
        force = np.zeros((n, 2))
        force[:, 0] = np.where(on & ~bounce, 50.0, 0.0)
        t = rotor_file(path, force, 1e-4 * np.sin(2 * OMEGA * np.arange(n) * PERIOD / N))
        ev = contact_events(path, "Blade", ["tip-le"], skip=2)["tip-le"]
        self.assertEqual(ev["per_rev"], [2, 2, 2])
        self.assertEqual(ev["mean"], 2.0)
        np.testing.assert_allclose(ev["fraction"], 0.2 - 0.02, atol=1e-12)  # the bounces are off
        np.testing.assert_allclose(ev["angles"], [45, 225] * 4, atol=1e-9)  # the events of the 6th revolution too
        with self.assertRaisesRegex(EpapheError, "'hub' has no contact node"):
            contact_events(path, "Blade", ["hub"], skip=2)
        with self.assertRaisesRegex(EpapheError, "unknown node set 'tip-mid' \\(available: hub, tip-le, tip-te\\)"):
            contact_events(path, "Blade", ["tip-mid"])
        eo, _, amp = spectrum(path, "Blade", "tip-le", "x", skip=2)  # engine order 2 of the displacement
        self.assertAlmostEqual(eo[int(np.argmax(amp))], 2.0)
        self.assertAlmostEqual(t[1] - t[0], PERIOD / N)


class StudyMeasures(unittest.TestCase):
    def test_rectangular_pulse(self):
        """A force F = 1.6 MN from t0 = 2e-5 s to t1 = 1e-4 s on a 1e-7 s grid (the bar on the wall's
        exact force): contact start t0, end t1, impulse F (t1 - t0) = 128 N s, plateau F."""
        h = 1e-7
        t = np.arange(2000) * h
        f = np.where((t >= 2e-5 - h / 2) & (t < 1e-4 - h / 2), 1.6e6, 0.0)
        run = dict(
            t=t,
            force=f,
            gap=np.where(f > 0, -1e-9, 1e-3)[:, None],
            momentum=np.tile([-64.0, 0, 0], (t.size, 1)),
            mass=0.64,
            balance=np.full(t.size, 1e-13),
            u=None,
        )
        m = raw_measures(run, Watch("Bar", "x-", -1, 0, 1e-6), None)
        self.assertAlmostEqual(m["contact start"], 2e-5, delta=1e-12)
        self.assertAlmostEqual(m["contact end"], 1e-4, delta=1e-12)
        self.assertAlmostEqual(m["impulse"], 128.0, delta=1e-9 * 128)
        self.assertAlmostEqual(m["plateau force"], 1.6e6, delta=1e-9 * 1.6e6)
        self.assertAlmostEqual(m["max penetration"], 1e-9)
        self.assertAlmostEqual(m["rebound velocity"], -100.0)
        ref = dict(m, **{"impulse": 128.0 * 1.01, "duration": 8e-5, "contact start": 2e-5 + 4e-7})
        e = errors(m, ref, scale=1e-3)
        self.assertAlmostEqual(e["impulse"], 0.01 / 1.01)  # relative
        self.assertAlmostEqual(e["contact start"], 4e-7 / 8e-5)  # over the contact duration
        self.assertAlmostEqual(e["max penetration"], 0.0)
        self.assertEqual(e["energy balance"], 1e-13)

    def test_rms_difference(self):
        """u = sin, ur = sin + 1e-3 on a coarser grid: the RMS difference is 1e-3 (linear
        interpolation of the reference adds at most (dt^2 / 8) max|u''| = 5e-5 on a 0.02 grid)."""
        t = np.linspace(0, 2 * math.pi, 1001)
        tr = np.linspace(0, 2 * math.pi, 315)
        self.assertAlmostEqual(rms_difference(t, np.sin(t), tr, np.sin(tr) + 1e-3), 1e-3, delta=5e-5)


if __name__ == "__main__":
    unittest.main()
