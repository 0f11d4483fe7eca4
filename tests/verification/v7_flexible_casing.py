#!/usr/bin/env python3
"""V7 with a flexible casing (thesis section 5.2.2), inputs/blade-flexible-casing.xml: the blade of
blade-casing.xml in a casing body (Mesh Type Casing, Craig-Bampton on its inner face, clamped at its
flanges) whose inner face turns at -1000 rad/s, 5 revolutions, Lagrange. Asserted:
  - the run completes its 5 revolutions, with no NaN or Inf in any series;
  - the blade rubs: total contact force > 0 at some records, and the leading edge touches the casing
    twice in each full revolution after the first, as with the rigid casing;
  - the casing's inner face moves: largest |u| of its watched nodes above 1 um (about 1e10 times
    the round-off of a 0.3 m coordinate);
  - the energy balance closes to 1e-8 (the casing's deformation energy included);
  - the tip never penetrates the casing by more than 1e-9 m after the correction.
Compared with the rigid casing of the same clearance law (inputs/blade-casing.xml, same time step,
same 5 revolutions), the contact impulse (time integral of the total force):
  - is strictly lower with the flexible casing (ratio < 1), and so is the peak force. Argument: the
    clearance law imposes the interference; the casing's compliance acts in series with the
    blade's, so the same interference takes a smaller force (quasi-statically
    F = delta / (c_blade + c_casing) against delta / c_blade), over the same rubbing arcs;
  - is a converged property of the casing's reduction: the ratio with the deck's 10 fixed-interface
    modes of the casing differs from the ratio with 20 by less than 10 % of the casing's effect
    (1 - ratio at 20 modes). The casing's inner face is all retained, so its static compliance is
    exact at any number of modes; the modes add its inertia, and the effect of the casing must not
    depend on how many are kept.
The ratios, the peak forces, the wall times and the blade's amplitudes are printed."""
import math
import os
import re
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from epaphe_testing import deck_value, history, parse_args, run, variant, verdict  # noqa: E402
import epaphe  # noqa: E402  (epaphe_testing put python/ on the path)
from epaphe import measures as rotor  # noqa: E402  (epaphe-rotor's contact events)


def finite(path):
    """Datasets holding NaN or Inf, but the checkpoints' warm starts (NaN there: a cold start)."""
    with epaphe.open(path) as out:
        data = out.flat("f", select=lambda n: not n.endswith("warm_start"))
    return [n for n, v in data.items() if not np.isfinite(v).all()]


def main():
    a = parse_args("--rigid-deck", "--rotor")
    failures = []
    h = float(deck_value(a.deck, "Time->Time step"))
    revs = float(deck_value(a.deck, "Time->End revolutions"))
    every = deck_value(a.deck, "Output->Every")
    common = {"Run->Progress interval": ("0", "double")}
    runs = {
        "flexible": variant(
            a.deck, os.path.join(a.workdir, "flexible.xml"), dict(common, **{"Output->File": "flexible.h5"})
        ),
        "rigid": variant(
            a.rigid_deck,
            os.path.join(a.workdir, "rigid.xml"),
            dict(
                common,
                **{
                    "Output->File": "rigid.h5",
                    "Time->Time step": (repr(h), "double"),
                    "Time->End revolutions": (repr(revs), "double"),
                    "Output->Every": (every, "int"),
                },
            ),
        ),
        "flexible-20": variant(
            a.deck,
            os.path.join(a.workdir, "flexible-20.xml"),
            dict(
                common,
                **{"Output->File": "flexible-20.h5", "Bodies->Casing->Reduction->Fixed-interface modes": ("20", "int")},
            ),
        ),
    }
    res = {}
    for name, deck in runs.items():
        start = time.time()
        out = run([a.run, deck, "--threads", "1"], a.workdir)
        wall = time.time() - start
        rate = re.search(r"([0-9.e+]+) steps/s", out.stdout)
        print(
            f"{name}: {wall:.1f} s wall, {rate.group(1) if rate else '?'} steps/s; "
            + "; ".join(l.strip() for l in out.stdout.splitlines() if "per-step" in l or "critical" in l)
        )
        path = os.path.join(a.workdir, name + ".h5")
        bad = finite(path)
        if bad:
            failures.append(f"{name}: NaN or Inf in {', '.join(bad[:5])}")
        hist = history(path)
        F, t = hist["bodies/Blade/contact/total_force"], hist["time"]
        dt = t[1] - t[0]
        res[name] = dict(h=hist, impulse=F.sum() * dt, peak=F.max(), F=F)
        amp = max(np.abs(hist[f"bodies/Blade/nodesets/{s}/displacement"]).max() for s in ("tip-le", "tip-te"))
        bal = np.abs(hist["energy/balance_error"]).max()
        pen = max(0.0, -hist["bodies/Blade/contact/gap"].min())
        print(
            f"{name}: impulse {res[name]['impulse']:.4g} N s, peak force {F.max():.4g} N, in contact at "
            f"{100 * np.mean(F > 0):.1f} % of the records, blade tip amplitude {1e3 * amp:.4f} mm, "
            f"energy balance {bal:.1e}, largest penetration {pen:.1e} m"
        )
        period = 2 * math.pi / 1000.0
        steps = hist["attrs"]["steps"]
        if not abs(steps * h - revs * period) <= h:
            failures.append(f"{name}: {steps} steps of {h} s do not make {revs} revolutions")
        if not (F > 0).any():
            failures.append(f"{name}: no contact at any record")
        if not bal <= 1e-8:
            failures.append(f"{name}: energy balance error {bal:.2e} above 1e-8")
        if not pen <= 1e-9:
            failures.append(f"{name}: penetration {pen:.2e} m above 1e-9 m")
        ev = rotor.contact_events(path, "Blade", ["tip-le", "tip-te"], skip=1)
        print(
            f"{name}: contacts per revolution (revolutions 1+): leading edge {ev['tip-le']['per_rev']}, "
            f"trailing edge {ev['tip-te']['per_rev']}"
        )
        if not ev["tip-le"]["per_rev"] or ev["tip-le"]["per_rev"] != [2] * len(ev["tip-le"]["per_rev"]):
            failures.append(f"{name}: leading-edge contacts per revolution {ev['tip-le']['per_rev']}, expected 2")
    u = res["flexible"]["h"]["bodies/Casing/nodesets/inner/displacement"]
    umax = np.abs(u).max()
    print(
        f"casing inner face: largest |u| {1e6 * umax:.3f} um over {u.shape[1]} nodes "
        f"({umax / (0.3 * np.finfo(float).eps):.1e} x the round-off of a 0.3 m coordinate)"
    )
    if not umax > 1e-6:
        failures.append(f"the casing's inner face moves by {umax:.2e} m only (expected > 1 um)")
    ratio = res["flexible"]["impulse"] / res["rigid"]["impulse"]
    ratio20 = res["flexible-20"]["impulse"] / res["rigid"]["impulse"]
    print(
        f"flexible / rigid casing: contact impulse {ratio:.4f} (casing 10 modes), {ratio20:.4f} (20 modes); "
        f"peak force {res['flexible']['peak'] / res['rigid']['peak']:.3f}, "
        f"{res['flexible-20']['peak'] / res['rigid']['peak']:.3f}"
    )
    if not ratio < 1:
        failures.append(
            f"flexible / rigid contact impulse {ratio:.4f}: not below 1 (a compliance in series with the "
            "contact must lower the force)"
        )
    if not res["flexible"]["peak"] < res["rigid"]["peak"]:
        failures.append(
            f"peak contact force {res['flexible']['peak']:.4g} N with the flexible casing, not below the "
            f"rigid casing's {res['rigid']['peak']:.4g} N"
        )
    change = abs(ratio - ratio20)
    print(
        f"casing modes 10 -> 20: the ratio changes by {change:.2e}, {change / max(1 - ratio20, 1e-300):.3f} of the "
        f"casing's effect 1 - ratio = {1 - ratio20:.4f} (allowed 0.1)"
    )
    if not change <= 0.1 * (1 - ratio20):
        failures.append(
            f"the impulse ratio is not converged in the casing's modes: {ratio:.4f} (10) against "
            f"{ratio20:.4f} (20), more than 10 % of 1 - ratio = {1 - ratio20:.4f}"
        )
    return verdict(failures)


if __name__ == "__main__":
    sys.exit(main())
