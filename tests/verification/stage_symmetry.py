#!/usr/bin/env python3
"""Instances of one reduced model around the engine axis (docs/user/stage.md): exact checks.

On inputs/blade-casing.xml (the V7 blade at 1000 rad/s in a rigid casing) with a two- and four-lobe
clearance that repeats every 180 degrees, not every 90, half a revolution, the blade instanced 4
times ('Instances->Count' = 4: blade k stands at k x 90 degrees and sees its own copy of the casing
turned back by that angle). Asserted, with tolerances stated before measuring:
  - blade 0 of the stage is the blade alone: tip displacement, contact forces and gaps within 1e-12
    of their scale (the stage's contact is one joint solve over 4 blocks that do not couple);
  - blade 1 is the blade alone in a casing turned by -90 degrees ('Surfaces->Casing->Initial angle'),
    i.e. blade 0's configuration a quarter revolution on: within 1e-12 of the scale (the pose); and
    of 3 blades in an eccentric casing, blade 1 is the blade alone in the casing turned by 120
    degrees less (within 1e-12), not 120 more (more than 1e-2 apart: the pose's sign);
  - blades 2 and 0, 3 and 1 see the same casing (180 degrees apart): within round-off, the tolerances
    regression.gold allows (ROUND_OFF: displacements and gaps 3e-8 of their scale, forces 1e-6): the
    casing turned by another angle, whose sine and cosine round differently (measured: displacements
    1.3e-11, gaps 1.9e-11, forces 3.3e-8);
  - blades 1 and 0 differ by more than 1e-2 of the scale (the check above is not trivially true);
  - the stage's energy balance closes to 1e-6 of its largest energy;
  - its nodal diameters (python/epaphe/stage.py, the spatial DFT over the blades) at the leading
    edge's tip: 1 and 3 below 1e-9 of the largest (blades 180 degrees apart move alike), 2 above 1e-3;
  - mistuning ('Stiffness factors' {1, 1.02, 1, 1}): blade 1's reduced frequencies are sqrt(1.02)
    times blade 0's to 1e-12; tuned blades 0 and 2 still agree within round-off; blade 1's tip history moves
    by more than 1e-4 of its scale from the tuned stage's;
  - a random pattern ('Mistuning standard deviation' 0.02, 'Seed' 7) is the same on a second run;
  - epaphe.stage.model_modes (the modes of a cache file) gives the run's reduced frequencies to 1e-9.
"""
import os
import re
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from epaphe_testing import parse_args, run, variant, verdict  # noqa: E402
from epaphe.stage import instance_histories, model_modes, nodal_diameter_content  # noqa: E402

DATASETS = ("nodesets/tip-le/displacement", "nodesets/tip-te/displacement", "contact/force", "contact/gap")


def history(path, body):
    with h5py.File(path, "r") as f:
        return {d: f[f"bodies/{body}/{d}"][()] for d in DATASETS}


def frequencies(path, body):
    with h5py.File(path, "r") as f:
        return f[f"bodies/{body}/frequencies/reduced"][()]


# round-off, per kind: what regression.gold allows (tests/regression/gold.py, its ATOL of the scale)
ROUND_OFF = {"displacement": 3e-8, "gap": 3e-8, "force": 1e-6}


def difference(a, b):
    """The largest |a - b| over the datasets, each relative to its scale max |a|."""
    return max(float(np.abs(a[d] - b[d]).max() / max(np.abs(a[d]).max(), 1e-300)) for d in DATASETS)


def round_off_share(a, b):
    """The largest |a - b| / scale over the datasets, as a share of ROUND_OFF of its kind."""
    return max(
        float(np.abs(a[d] - b[d]).max() / max(np.abs(a[d]).max(), 1e-300)) / ROUND_OFF[d.split("/")[-1]]
        for d in DATASETS
    )


def main():
    a = parse_args("--rotor")
    W = a.workdir
    common = {
        "Time->End revolutions": "0.5",
        "Output->Every": "10",
        "Bodies->Blade->Reduction->Cache file": "blade.rom.h5",
        # gap = 50 um - A2 cos 2 theta - A4 cos 4 theta: open at 0 and 90 degrees (where blades 0 and 1
        # start), closed around 45 and 135 degrees; it repeats every 180 degrees, not every 90
        "Surfaces->Casing->Harmonic orders": ("{2, 4}", "Array(int)"),
        "Surfaces->Casing->Amplitudes at first end": ("{5e-5, -1e-4}", "Array(double)"),
        "Surfaces->Casing->Amplitudes at last end": ("{5e-5, -1e-4}", "Array(double)"),
    }

    def go(name, over):
        deck = variant(a.deck, os.path.join(W, f"{name}.xml"), {**common, **over})
        p = run([a.run, deck, "--output", f"{name}.h5"], W)
        return os.path.join(W, f"{name}.h5"), p.stdout

    failures = []
    alone, _ = go("alone", {})
    turned, _ = go("turned", {"Surfaces->Casing->Initial angle": ("-90", "double")})
    stage, _ = go("stage", {"Bodies->Blade->Instances->Count": ("4", "int")})
    mistuned, _ = go(
        "mistuned",
        {
            "Bodies->Blade->Instances->Count": ("4", "int"),
            "Bodies->Blade->Instances->Stiffness factors": ("{1, 1.02, 1, 1}", "Array(double)"),
        },
    )
    H = {k: history(stage, f"Blade[{k}]") for k in range(4)}
    checks = [
        ("blade 0 of the stage against the blade alone", difference(history(alone, "Blade"), H[0]), 1e-12, "<="),
        (
            "blade 1 against the blade alone in a casing turned by -90 deg",
            difference(history(turned, "Blade"), H[1]),
            1e-12,
            "<=",
        ),
        ("blade 2 against blade 0 (180 deg apart), share of round-off", round_off_share(H[0], H[2]), 1, "<="),
        ("blade 3 against blade 1 (180 deg apart), share of round-off", round_off_share(H[1], H[3]), 1, "<="),
        ("blade 1 against blade 0 (90 deg apart: another casing)", difference(H[0], H[1]), 1e-2, ">"),
    ]
    with h5py.File(stage, "r") as f:
        e = f["energy"]
        checks.append(
            (
                "stage energy balance error / largest energy",
                float(np.abs(e["balance_error"][()]).max() / np.abs(e["total"][()]).max()),
                1e-6,
                "<=",
            )
        )
    # nodal diameters (python/epaphe/stage.py): with x_2 = x_0 and x_3 = x_1 the odd ones vanish,
    # X_1 = ((x_0 - x_2) - i (x_1 - x_3)) / 4, and X_2 = (x_0 - x_1) / 2 does not
    nd = nodal_diameter_content(instance_histories(stage, "Blade", "nodesets/tip-le/displacement"))
    print("tip-le displacement, RMS of nodal diameters 0..3: " + ", ".join(f"{v:.3e}" for v in nd) + " m")
    checks += [
        ("nodal diameters 1 and 3 / the largest", float(max(nd[1], nd[3]) / nd.max()), 1e-9, "<="),
        ("nodal diameter 2 / the largest", float(nd[2] / nd.max()), 1e-3, ">"),
    ]
    # the pose's sign: 3 blades, blade 1 at +120 degrees sees the casing turned by -120 degrees. An
    # eccentric casing (gap = 50 um - 70 um cos theta: one rub per revolution), turned by 30 degrees
    # so that the three tips (at 90, 210 and 330 degrees) start clear of it; the law is even in theta,
    # so only the casing's turning (-1000 rad/s) tells +120 from -120
    eccentric = {
        "Surfaces->Casing->Harmonic orders": ("{1}", "Array(int)"),
        "Surfaces->Casing->Amplitudes at first end": ("{7e-5}", "Array(double)"),
        "Surfaces->Casing->Amplitudes at last end": ("{7e-5}", "Array(double)"),
    }
    three, _ = go(
        "three",
        {
            **eccentric,
            "Bodies->Blade->Instances->Count": ("3", "int"),
            "Surfaces->Casing->Initial angle": ("30", "double"),
        },
    )
    minus, _ = go("minus120", {**eccentric, "Surfaces->Casing->Initial angle": ("-90", "double")})
    plus, _ = go("plus120", {**eccentric, "Surfaces->Casing->Initial angle": ("150", "double")})
    T1 = history(three, "Blade[1]")
    checks += [
        (
            "3 blades: blade 1 against the blade alone, casing turned by -120 deg more",
            difference(history(minus, "Blade"), T1),
            1e-12,
            "<=",
        ),
        (
            "3 blades: blade 1 against the blade alone, casing turned by +120 deg more",
            difference(history(plus, "Blade"), T1),
            1e-2,
            ">",
        ),
    ]
    # epaphe-rotor nodal-diameters prints the same content (its u_x mean over the set's nodes: blades
    # 180 degrees apart alike, so ND 1 and 3 vanish there too) and draws its spectrum
    png = os.path.join(W, "nd.png")
    out = run([a.rotor, "nodal-diameters", stage, "--png", png], W).stdout
    printed = [float(v) for v in re.findall(r"ND +\d+: (\S+) m", out)]
    print(
        f"epaphe-rotor nodal-diameters: {printed} m, {os.path.getsize(png) if os.path.exists(png) else 0} bytes of PNG"
    )
    odd_share = max(printed[1], printed[3]) / max(printed) if len(printed) == 4 else 1.0
    checks.append(("epaphe-rotor: nodal diameters 1 and 3 / the largest", odd_share, 1e-9, "<="))
    if not os.path.exists(png):
        failures.append(f"epaphe-rotor nodal-diameters wrote no {png}")
    # model_modes (the modes the nodal-diameter classification reads) from the stage's cache file
    fr = frequencies(stage, "Blade[0]")
    fm, _, _ = model_modes(os.path.join(W, "blade.rom.h5"), len(fr))
    checks.append(
        ("model_modes: frequencies against the run's reduced ones", float(np.abs(fm / fr - 1).max()), 1e-9, "<=")
    )
    M = {k: history(mistuned, f"Blade[{k}]") for k in range(4)}
    f0, f1 = frequencies(mistuned, "Blade[0]"), frequencies(mistuned, "Blade[1]")
    checks += [
        (
            "mistuned: blade 1's frequencies / (sqrt(1.02) x blade 0's) - 1",
            float(np.abs(f1 / (np.sqrt(1.02) * f0) - 1).max()),
            1e-12,
            "<=",
        ),
        ("mistuned: tuned blades 2 against 0, share of round-off", round_off_share(M[0], M[2]), 1, "<="),
        ("mistuned: blade 1 against the tuned stage's blade 1", difference(H[1], M[1]), 1e-4, ">"),
    ]
    factors = []
    for r in range(2):
        _, out = go(
            f"random{r}",
            {
                "Bodies->Blade->Instances->Count": ("4", "int"),
                "Bodies->Blade->Instances->Mistuning standard deviation": ("0.02", "double"),
                "Bodies->Blade->Instances->Seed": ("7", "int"),
                "Time->End revolutions": "0.01",
            },
        )
        m = re.search(r"4 instances .*\(4 mistuned, stiffness factors (\S+) to (\S+)\)", out)
        factors.append(m.groups() if m else None)
    print(f"random pattern (sigma 0.02, seed 7): stiffness factors {factors[0]} and, run again, {factors[1]}")
    if factors[0] is None or factors[0] != factors[1]:
        failures.append(f"the random mistuning pattern is not reported or not reproduced: {factors}")
    for what, value, bound, op in checks:
        ok = value <= bound if op == "<=" else value > bound
        print(f"{what}: {value:.3e} (asserted {op} {bound:g}){'' if ok else '  FAIL'}")
        if not ok:
            failures.append(f"{what}: {value:.3e}, asserted {op} {bound:g}")
    sys.exit(verdict(failures))


if __name__ == "__main__":
    main()
