#!/usr/bin/env python3
"""Modal interaction on inputs/stage-flexible-casing.xml (docs/user/stage.md): where Legrand et al.'s
condition says, tuned and mistuned.

The condition (Legrand, Pierre, Cartraud & Lombard, JSV 319, 2009; epaphe.stage.interaction_speeds):
the casing's forward wave of n nodal diameters and the blades' backward one turn together at
Omega_n = (omega_b + omega_c,n) / n. The deck's 8 blades and 4 lobes keep nodal diameters 0, 4 and 8
only; its blade (first mode omega_b) and casing (its 4-diameter pair omega_c,4) give Omega_4, computed
here from the run's own models (the blade's reduced frequencies, the casing's cache file, each casing
mode's nodal diameter), not typed in; `epaphe-rotor nodal-diameters --casing` must print the same.

The sweep: the two multiples of 100 rad/s that bracket Omega_4 (the sweep's resolution), and the
speeds 300 rad/s below and above them; 6 revolutions each ('Run->Divergence step check' off: a
diverging run just stops). A speed "interacts" when the casing's 4-diameter radial amplitude grows by
more than 100x from the first revolution to the largest of the others, or the run stops diverging;
it is "quiet" when the run completes and grows by less than 10x. Asserted:
  - tuned: both bracketing speeds interact; both outer speeds are quiet;
  - mistuned (stiffness factors 1 + delta_k, delta_k normal with deviation 0.05, seed 1): both
    bracketing speeds still interact, the lower outer speed is quiet; the mistuning spreads the
    casing's motion into odd nodal diameters (above 1e-3 of its 4-diameter amplitude, where the
    tuned stage's are below 1e-6: its symmetry forbids them; measured 2e-10 to 6e-10 tuned, 0.08 to
    0.2 mistuned).
Measured (6 revolutions): Omega_4 = 2357.1 rad/s; tuned, the 4-diameter amplitude grows 2.1e3x at 2300
and 2.2e3x at 2400 rad/s, 0.8x at 2000 and 1x at 2700; mistuned, 2.0e3x at 2300 and 2400, 0.8x at
2000 and 3.4x at 2700 (in odd diameters).
The upper outer speed of the mistuned stage is printed, not asserted (measured: it grows in 3 nodal
diameters over 8 revolutions, an interaction the mistuning opens).
"""
import math
import os
import re
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from epaphe_testing import parse_args, run, variant, verdict  # noqa: E402
from epaphe.stage import interaction_speeds, model_modes, nodal_diameter_of, ring_nodal_diameters  # noqa: E402

REVS = 6


def main():
    a = parse_args("--rotor")
    W = a.workdir
    caches = {
        "Bodies->Blade->Reduction->Cache file": (os.path.join(W, "blade.rom.h5"), "string"),
        "Bodies->Casing->Reduction->Cache file": (os.path.join(W, "casing.rom.h5"), "string"),
        "Run->Progress interval": ("0", "double"),
        "Run->Divergence step check": ("false", "bool"),
    }
    failures = []

    # the condition from the models: a few steps make the cache files and the reduced frequencies
    first = variant(
        a.deck, os.path.join(W, "models.xml"), {**caches, "Time->End revolutions": "0.05", "Output->Every": "1"}
    )
    run([a.run, first, "--output", "models.h5"], W)
    with h5py.File(os.path.join(W, "models.h5"), "r") as f:
        blade_hz = f["bodies/Blade[0]/frequencies/reduced"][()]
    fc, u, coords = model_modes(os.path.join(W, "casing.rom.h5"), 28)
    modes = [(float(fc[k]), nodal_diameter_of(u[k], coords)[0]) for k in range(len(fc))]
    rows = [r for r in interaction_speeds([float(blade_hz[0])], modes) if r[1] == 4]
    omega4 = rows[0][0]
    print(f"Omega_4 = 2 pi ({rows[0][2]:.1f} + {rows[0][3]:.1f}) / 4 = {omega4:.1f} rad/s")
    out = run(
        [a.rotor, "nodal-diameters", os.path.join(W, "models.h5"), "--casing", os.path.join(W, "casing.rom.h5")], W
    ).stdout
    printed = [float(m) for m in re.findall(r"ND +4: +(\S+) rad/s \(blade " + f"{rows[0][2]:.1f}", out)]
    if not printed or abs(printed[0] - omega4) > 0.1:
        failures.append(f"epaphe-rotor nodal-diameters prints Omega_4 = {printed} rad/s, the condition {omega4:.1f}")

    lo = 100 * math.floor(omega4 / 100)
    speeds = [lo - 300, lo, lo + 100, lo + 400]

    def sweep(tag, extra):
        result = {}
        for w in speeds:
            name = f"{tag}-{w}"
            deck = variant(
                a.deck,
                os.path.join(W, f"{name}.xml"),
                {**caches, **extra, "Surfaces->Casing->Rotation speed": str(-w), "Time->End revolutions": str(REVS)},
            )
            p = run([a.run, deck, "--output", f"{name}.h5"], W, expect_ok=False)
            t, X = ring_nodal_diameters(os.path.join(W, f"{name}.h5"), os.path.join(W, "casing.rom.h5"))
            T = 2 * math.pi / w
            per_rev = [
                X[4][(t >= k * T) & (t < (k + 1) * T)].max()
                for k in range(REVS)
                if ((t >= k * T) & (t < (k + 1) * T)).any()
            ]
            growth = max(per_rev[1:]) / per_rev[0] if len(per_rev) > 1 else float("inf")
            diverged = p.returncode != 0
            last = X[:, -1]
            odd = max(last[1::2]) / last[4]
            others = max(v for n, v in enumerate(last) if n % 4)
            print(
                f"{tag} {w} rad/s: 4-diameter amplitude {per_rev[0]:.2e} m in revolution 1, growth {growth:.3g}x"
                f"{', stopped diverging' if diverged else ''}; at the end, odd diameters {odd:.2e} of the 4-diameter "
                f"amplitude, the largest of the diameters not multiples of 4 {others / last[4]:.2e} of it"
            )
            result[w] = dict(
                interacts=diverged or growth > 100, quiet=not diverged and growth < 10, odd=odd, others=others / last[4]
            )
        return result

    tuned = sweep("tuned", {})
    mistuned = sweep(
        "mistuned",
        {
            "Bodies->Blade->Instances->Mistuning standard deviation": ("0.05", "double"),
            "Bodies->Blade->Instances->Seed": ("1", "int"),
        },
    )
    for w in (lo, lo + 100):
        if not tuned[w]["interacts"]:
            failures.append(f"tuned, {w} rad/s (next to Omega_4 = {omega4:.1f}): no interaction")
        if not mistuned[w]["interacts"]:
            failures.append(f"mistuned, {w} rad/s (next to Omega_4 = {omega4:.1f}): no interaction")
        if not tuned[w]["odd"] < 1e-6:
            failures.append(
                f"tuned, {w} rad/s: odd diameters {tuned[w]['odd']:.2e} of the 4-diameter amplitude (> 1e-6)"
            )
        if not mistuned[w]["odd"] > 1e-3:
            failures.append(
                f"mistuned, {w} rad/s: odd diameters {mistuned[w]['odd']:.2e} of the 4-diameter amplitude (< 1e-3)"
            )
    for w in (lo - 300, lo + 400):
        if not tuned[w]["quiet"]:
            failures.append(f"tuned, {w} rad/s (300 rad/s off the bracket): not quiet")
    if not mistuned[lo - 300]["quiet"]:
        failures.append(f"mistuned, {lo - 300} rad/s: not quiet")
    sys.exit(verdict(failures))


if __name__ == "__main__":
    main()
