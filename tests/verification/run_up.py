#!/usr/bin/env python3
"""A run-up across a critical speed (issue 31, docs/user/rotating-bodies.md#run-ups).

On inputs/blade-casing-run-up.xml (the V7 blade sped up from 720 to 800 rad/s, a six-lobe casing
turning with the same law, soft penalty contact), asserted with tolerances stated before measuring:
  - the crossing: the Campbell diagram of the same deck (epaphe-campbell, the parametric model) puts
    engine order 6 on the first mode at a speed Omega_c inside the ramp; the response of the tip in
    the first mode's band (the leading-edge tip node's displacement demodulated at f_1(Omega_c),
    averaged over 5 ms: a band of about +/-100 Hz, which leaves out the engine orders 5 and 7 of the
    run's speeds) peaks within 3 % of Omega_c, at least twice as high as in the first and last 10 ms
    of the ramp (a ramp lags its resonance: the peak comes after the crossing by about 2 %);
  - the energy balance of the run, drive work included, closes to 1e-6 of the largest energy, while
    the drive work is more than 1e-3 of it (left out, the balance would miss by more than 1000 times
    the tolerance); the same on a Lagrange-contact variant (strong contact, 20 ms).
"""
import argparse
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from epaphe_testing import run, variant, verdict  # noqa: E402


def law(f):
    """The speed law of the deck stored in the output, as (w0, w1, t0, t1)."""
    import xml.etree.ElementTree as ET

    root = ET.fromstring(f["run/deck"][()].decode() if isinstance(f["run/deck"][()], bytes) else f["run/deck"][()])
    vals = {
        p.get("name"): float(p.get("value"))
        for p in root.iter("Parameter")
        if p.get("name") in ("Start speed", "End speed", "Start time", "End time") and p.get("type") == "double"
    }
    sl = [x for x in root.iter("ParameterList") if x.get("name") == "Speed law"][0]
    v = {p.get("name"): float(p.get("value")) for p in sl.iter("Parameter") if p.get("type") == "double"}
    return v["Start speed"], v["End speed"], v["Start time"], v["End time"]


def energy_check(path, name, failures):
    with h5py.File(path, "r") as f:
        e = f["energy"]
        bal = float(np.abs(e["balance_error"][()]).max())
        drive = float(np.abs(e["drive_work"][()]).max())
        top = float(np.abs(e["total"][()]).max())
    print(
        f"{name}: energy balance error {bal:.2e} (1e-6 asserted), drive work {drive:.3e} J = {drive / top:.2e} of the "
        f"largest energy {top:.3e} J (> 1e-3 asserted)"
    )
    if not bal <= 1e-6:
        failures.append(f"{name}: energy balance error {bal:.2e} > 1e-6")
    if not drive > 1e-3 * top:
        failures.append(f"{name}: drive work {drive:.2e} J is not above 1e-3 of the largest energy {top:.2e} J")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--run", required=True)
    ap.add_argument("--campbell", required=True)
    ap.add_argument("--deck", required=True)
    ap.add_argument("--workdir", required=True)
    a = ap.parse_args()
    W = a.workdir
    os.makedirs(W, exist_ok=True)
    failures = []
    run([a.campbell, a.deck, "--output", "campbell.h5", "--count", "2", "--speeds", "61"], W)
    run([a.run, a.deck, "--output", "run-up.h5"], W)
    with h5py.File(os.path.join(W, "campbell.h5"), "r") as f:
        s, F = f["speeds"][()], f["frequencies"][()][:, 0]
    g = 6 * s / (2 * np.pi) - F
    j = np.where(np.diff(np.sign(g)) != 0)[0]
    with h5py.File(os.path.join(W, "run-up.h5"), "r") as f:
        w0, w1, t0, t1 = law(f)
        t = f["time"][()]
        u = f["bodies/Blade/nodesets/tip-le/displacement"][()][:, 0, :]
    if len(j) == 0:
        failures.append("engine order 6 does not cross the first mode on the Campbell diagram")
        return verdict(failures)
    k = j[0]
    wc = s[k] - g[k] * (s[k + 1] - s[k]) / (g[k + 1] - g[k])
    fc = float(np.interp(wc, s, F))
    print(
        f"Campbell: engine order 6 crosses mode 1 at {wc:.1f} rad/s ({fc:.1f} Hz); the ramp runs {w0:g} to {w1:g} "
        f"rad/s from {t0:g} to {t1:g} s"
    )
    if not min(w0, w1) < wc < max(w0, w1):
        failures.append(f"the ramp does not cross {wc:.1f} rad/s")
    speed = np.interp(t, [t0, t1], [w0, w1])
    n = int(round(0.005 / (t[1] - t[0])))
    amp2 = np.zeros(len(t))
    for d in range(3):
        z = np.convolve(u[:, d] * np.exp(-2j * np.pi * fc * t), np.ones(n) / n, mode="same")
        amp2 += np.abs(z) ** 2
    amp = 2 * np.sqrt(amp2)
    inside = (t > t0 + 0.005) & (t < t1 - 0.005)  # the average sees the ramp only
    i = int(np.argmax(np.where(inside, amp, 0)))
    first = amp[inside & (t < t0 + 0.015)].max()
    last = amp[inside & (t > t1 - 0.015)].max()
    rel = speed[i] / wc - 1
    print(
        f"the first mode's band peaks at t = {t[i]:.4f} s, {speed[i]:.1f} rad/s ({100 * rel:+.2f} % of the crossing, "
        f"3 % asserted), amplitude {amp[i]:.3e} m against {first:.3e} m and {last:.3e} m in the first and last 10 ms "
        f"(2x asserted)"
    )
    if not abs(rel) <= 0.03:
        failures.append(f"the response peaks at {speed[i]:.1f} rad/s, {100 * rel:+.2f} % from the crossing {wc:.1f}")
    if not amp[i] >= 2 * max(first, last):
        failures.append(f"no peak: {amp[i]:.3e} m against {first:.3e} and {last:.3e} m at the ramp's ends")
    energy_check(os.path.join(W, "run-up.h5"), "run-up (penalty)", failures)
    lag = variant(
        a.deck,
        os.path.join(W, "lagrange.xml"),
        {
            "Contact->Method": "Lagrange",
            "Time->End time": "0.02",
            "Bodies->Blade->Rotation->Speed law->Start time": "0.001",
            "Bodies->Blade->Rotation->Speed law->End time": "0.019",
            "Output->File": "lagrange.h5",
        },
    )
    run([a.run, lag, "--output", "lagrange.h5"], W)
    energy_check(os.path.join(W, "lagrange.h5"), "run-up (Lagrange)", failures)
    return verdict(failures)


if __name__ == "__main__":
    sys.exit(main())
