#!/usr/bin/env python3
"""Wear lobes at an engine order (issue 15; Legrand, Batailly & Pierre 2012: the number of wear
lobes follows the engine order of the blade's response, as Batailly et al. 2012 saw on a rig).

Scene: inputs/blade-coating-sweep.xml, the blade in an axisymmetric coated casing reaching 5 um into
the tip's path, the incursion applied as a kick (0.4 period of the first mode), friction 0.1: the
friction drives the first mode (684.5 Hz free, locked at 691.1 Hz in contact), and where n times the
rotation frequency meets it, the vibration cuts n lobes. A speed sweep with `epaphe-rotor map` on 2
MPI ranks, 8 revolutions per speed, at Omega_n = 2 pi 691.1 / n for n = 4 and 6, at 1.1 Omega_4 and
1.1 Omega_6, and between two crossings at Omega_4.5.

Asserted, from the sweep's wear map (map.h5 /wear, the definitions of epaphe.measures.wear_lobes):
- at Omega_4 and Omega_6: n lobes, the wear's dominant harmonic n, its amplitude at least half the
  mean wear (measured 0.73 and 0.65), and the tip's dominant engine order n (within 0.1);
- off the crossings (1.1 Omega_n, Omega_4.5): no n-lobe pattern, i.e. not (n lobes and harmonic n),
  and the harmonic's amplitude at most 0.3 of the mean wear (measured 0.05-0.20).
Limits (measured on this scene, 2026-11-25, about 70 runs): without friction the tip grinds a
uniform groove (no vibration of the first mode: its radial tip motion is 4-8 % of its motion); at
friction 0.15 the rub is too violent for a clean order; a slow incursion (over more than 0.6 period)
sets no lobes (the vibration is a finite-amplitude one). The half-maximum lobe count is fragile off
a crossing, so only the pattern (count and harmonic together) is asserted there."""
import math
import os
import subprocess
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from epaphe_testing import parse_args, verdict  # noqa: E402

a = parse_args("--rotor", "--mpiexec")
crossing = {n: 2 * math.pi * 691.1063 / n for n in (4, 4.5, 6)}
cases = [
    (crossing[4], 4, True),
    (crossing[6], 6, True),
    (1.1 * crossing[4], 4, False),
    (1.1 * crossing[6], 6, False),
    (crossing[4.5], 4, False),
]
speeds = [round(w, 3) for w, _, _ in cases]
cmd = [
    sys.executable,
    a.rotor,
    "map",
    a.deck,
    "--speeds",
    ",".join(f"{w:g}" for w in speeds),
    "--revs",
    "8",
    "--skip",
    "3",
    "--ranks",
    "2",
    "--mpiexec",
    a.mpiexec,
    "--run",
    a.run,
    "--out",
    a.workdir,
]
p = subprocess.run(cmd, capture_output=True, text=True)
print(p.stdout)
if p.returncode != 0:
    sys.stderr.write(p.stderr)
    raise SystemExit(f"epaphe-rotor map failed ({p.returncode})")
failures = []
with h5py.File(os.path.join(a.workdir, "map.h5"), "r") as f:
    order, lobes, contrast = f["wear/dominant_order"][()], f["wear/lobes"][()], f["wear/contrast"][()]
    tip = f["tip-le/dominant_engine_order"][()]
for i, (w, n, at) in enumerate(cases):
    what = f"{w:.1f} rad/s ({w / crossing[n]:.2f} x Omega_{n})"
    print(
        f"{what}: {lobes[i]} lobes, wear harmonic {order[i]} at {contrast[i]:.2f} of the mean wear, "
        f"tip engine order {tip[i]:.2f}"
    )
    if at:
        if not (lobes[i] == n and order[i] == n and contrast[i] >= 0.5 and abs(tip[i] - n) <= 0.1):
            failures.append(
                f"{what}: {lobes[i]} lobes, harmonic {order[i]} at {contrast[i]:.2f}, tip EO {tip[i]:.2f}; "
                f"expected {n} lobes, harmonic {n} at 0.5 or more, tip EO {n}"
            )
    elif (lobes[i] == n and order[i] == n) or contrast[i] > 0.3:
        failures.append(
            f"{what}: {lobes[i]} lobes, harmonic {order[i]} at {contrast[i]:.2f} of the mean: an "
            f"engine-order pattern off the crossing"
        )
sys.exit(verdict(failures))
