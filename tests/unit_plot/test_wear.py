#!/usr/bin/env python3
"""drivers/epaphe-rotor wear (python/epaphe/cli/rotor.py) and epaphe.measures.wear_lobes: the lobes
worn in an abradable coating, on synthetic HDF5 files in the layout epaphe-run writes (/coating/<s>:
angle, axial, time, wear; /energy/plastic_dissipation). No run of epaphe-run is needed.

Checks:
  (a) k = 3, 5, 7 equal bumps, evenly spaced from an angle between column centres, on 120 x 4
      elements (each bump deepest on a different axial row, over a uniform rub and a little noise):
      lobe_count == k, dominant_order == k, the lobe angles and the harmonic's peaks within half an
      element of the bump centres, the profile the deepest wear of each column of the last record;
      the same with the columns numbered from 180 deg;
  (b) a bump straddling 0/360 deg is one lobe, at the bump; so is one on the last and first columns
      when the file numbers its columns from 180 deg;
  (c) zero wear: lobe_count 0, dominant_order 0, max_wear 0; the same wear all round: one lobe,
      no harmonic;
  (d) `epaphe-rotor wear F --png P --csv C`: exit 0, the printed lobe count and plastic dissipation,
      a valid PNG, the CSV profile equal to the deepest wear of each column of the last record;
  (e) errors, exit 1 with one line on stderr: a file without /coating (naming the file, "has no
      coating"), two coated surfaces and no --surface (naming both), an unknown --surface.

    test_wear.py --rotor drivers/epaphe-rotor --workdir DIR
"""
import argparse
import contextlib
import io
import math
import os
import re
import subprocess
import sys

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)  # test_plot's PNG check
sys.path.insert(0, os.path.join(HERE, "..", "verification"))  # epaphe_testing: python/ on the path
from epaphe_testing import verdict  # noqa: E402
from test_plot import png_problems  # noqa: E402
from epaphe.cli import rotor  # noqa: E402
from epaphe.measures import wear_lobes  # noqa: E402

N_U, N_V = 120, 4  # elements around x along the axis
STEP = 360.0 / N_U  # deg: half an element is the tolerance on angles
PEAK = 20e-6  # m, depth of a bump
failures = []


def check(cond, msg):
    if not cond:
        failures.append(msg)
    return cond


def circ(a, b):
    """Circular distance between angles in degrees."""
    return abs((a - b + 180.0) % 360.0 - 180.0)


def columns(start=0.0):
    """Centre angles (rad, in [0, 2 pi)) of the N_U columns, numbered from the column at start + STEP / 2."""
    return np.radians(np.mod(start + (np.arange(N_U) + 0.5) * STEP, 360.0))


def bumps(angle, centres, half_width=15.0, rub=2e-6, noise=0.2e-6, seed=1):
    """(N_U, N_V) wear: cos^2 bumps of depth PEAK and half-width `half_width` deg at `centres` (deg),
    bump j deepest on axial row j mod N_V (half as deep on the others), over a uniform rub and
    uniform noise in [0, noise]."""
    deg = np.degrees(angle)
    w = np.full((N_U, N_V), rub)
    for j, c in enumerate(centres):
        d = np.array([circ(a, c) for a in deg])
        shape = np.where(d < half_width, np.cos(0.5 * math.pi * d / half_width) ** 2, 0.0)
        rows = np.full(N_V, 0.5)
        rows[j % N_V] = 1.0
        w += PEAK * shape[:, None] * rows[None, :]
    return w + noise * np.random.default_rng(seed).random((N_U, N_V))


def coating_file(path, surfaces, records=5, coating=True):
    """An Epaphe-like history: /time, /energy, /run/deck, status complete and, with `coating`, one
    /coating/<s> group per {s: (angle, wear at the end)}, the wear growing linearly over `records`."""
    t = np.linspace(0.0, 1e-2, 41)
    with h5py.File(path, "w") as f:
        f.attrs["status"] = "complete"
        f.attrs["name"] = "synthetic wear"
        f["time"] = t
        f["run/deck"] = '<ParameterList name="Epaphe"/>'
        f["energy/kinetic"] = np.zeros_like(t)
        f["energy/plastic_dissipation"] = 1.25e-3 * t / t[-1]
        f["energy/coating_elastic"] = 1e-5 * np.ones_like(t)
        if not coating:
            return path
        for s, (angle, wear) in surfaces.items():
            g = f.create_group(f"coating/{s}")
            g.attrs["thickness"] = 2e-3
            g.attrs["youngs_modulus"] = 5e9
            g.attrs["yield_stress"] = 20e6
            g.attrs["hardening_modulus"] = 1e8
            g.attrs["elements"] = np.array([N_U, N_V], dtype=np.int32)
            g["angle"] = angle
            g["axial"] = np.linspace(-7.5e-3, 7.5e-3, N_V)
            g["time"] = np.linspace(t[-1] / records, t[-1], records)
            g["wear"] = np.stack([wear * (r + 1) / records for r in range(records)])
    return path


def lobes_of(path, surface=None):
    """The WearLobes of a file through the package's reader (epaphe-rotor wear, its output kept)."""
    with contextlib.redirect_stdout(io.StringIO()):
        return rotor.wear(path, surface)[1]


def near_all(got_rad, want_deg, what):
    """Every angle of `want_deg` within half an element of one of `got_rad`, as many of each."""
    got = np.degrees(np.asarray(got_rad))
    ok = check(len(got) == len(want_deg), f"{what}: {len(got)} angles {np.round(got, 1)}, expected {len(want_deg)}")
    for c in want_deg:
        ok &= check(
            min((circ(g, c) for g in got), default=1e9) <= 0.5 * STEP,
            f"{what}: no angle within {0.5 * STEP:g} deg of {c:g} (got {np.round(got, 2)})",
        )
    return ok


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rotor", required=True)
    ap.add_argument("--workdir", required=True)
    a = ap.parse_args()
    wd = os.path.abspath(a.workdir)
    os.makedirs(wd, exist_ok=True)
    tool = os.path.abspath(a.rotor)

    # ---- (a) k bumps at known angles ------------------------------------------------------------
    print("(a) k evenly spaced bumps, 120 x 4 elements")
    for start in (0.0, 180.0):
        for k in (3, 5, 7):
            centres = [(20.7 + 360.0 * j / k) % 360.0 for j in range(k)]  # 20.7: between column centres
            angle = columns(start)
            w = bumps(angle, centres)
            f = coating_file(os.path.join(wd, f"bumps{k}-from{start:g}.h5"), {"Casing": (angle, w)})
            r = lobes_of(f)
            ok = check(r.lobe_count == k, f"k={k}, columns from {start:g}: lobe_count {r.lobe_count}")
            ok &= check(r.dominant_order == k, f"k={k}, columns from {start:g}: dominant_order {r.dominant_order}")
            ok &= near_all(r.lobe_angles, centres, f"k={k}, columns from {start:g}: lobe angles")
            ok &= near_all(r.harmonic_angles, centres, f"k={k}, columns from {start:g}: harmonic angles")
            ok &= check(
                np.allclose(r.profile, w.max(axis=1), rtol=1e-12, atol=0)
                and math.isclose(r.max_wear, w.max(), rel_tol=1e-12),
                f"k={k}, columns from {start:g}: profile or max_wear ({r.max_wear:g}) differ from the wear's",
            )
            print(
                f"  {'ok ' if ok else 'BAD'} k={k}, columns from {start:g} deg: {r.lobe_count} lobes at "
                f"{np.round(np.degrees(r.lobe_angles), 1)}, harmonic {r.dominant_order}"
            )

    # ---- (b) a bump across 0/360 -----------------------------------------------------------------
    print("(b) a bump straddling 0/360 deg")
    for start, centres in ((0.0, [0.4]), (0.0, [359.2, 150.0]), (180.0, [0.4]), (180.0, [180.4])):
        angle = columns(start)
        r = wear_lobes(angle, bumps(angle, centres))
        ok = check(
            r.lobe_count == len(centres),
            f"bumps at {centres}, columns from {start:g}: " f"lobe_count {r.lobe_count}, expected {len(centres)}",
        )
        ok &= near_all(r.lobe_angles, centres, f"bumps at {centres}, columns from {start:g}: lobe angles")
        print(
            f"  {'ok ' if ok else 'BAD'} bumps at {centres} deg, columns from {start:g} deg: {r.lobe_count} "
            f"lobe(s) at {np.round(np.degrees(r.lobe_angles), 1)}"
        )

    # ---- (b2) contrast: a pure cosine of order 3 of amplitude 0.5 over the mean -----------------------
    angle = columns(0.0)
    cosine = 1e-5 * (1 + 0.5 * np.cos(3 * angle))[:, None] * np.ones((1, 4))
    r = wear_lobes(angle, cosine)
    check(
        r.dominant_order == 3 and math.isclose(r.contrast, 0.5, rel_tol=1e-9),
        f"cosine of order 3, amplitude 0.5 of the mean: order {r.dominant_order}, contrast {r.contrast}",
    )
    print(f"(b2) a cosine of order 3 at half the mean: contrast {r.contrast:.12f}")

    # ---- (c) no wear, uniform wear -----------------------------------------------------------------
    print("(c) zero and uniform wear")
    f = coating_file(os.path.join(wd, "zero.h5"), {"Casing": (columns(), np.zeros((N_U, N_V)))})
    r = lobes_of(f)
    ok = check(
        (r.lobe_count, r.dominant_order, r.max_wear) == (0, 0, 0.0),
        f"zero wear: lobe_count {r.lobe_count}, dominant_order {r.dominant_order}, max_wear {r.max_wear}",
    )
    ok &= check(r.lobe_angles.size == 0 and r.harmonic_angles.size == 0, "zero wear: angles given")
    r = wear_lobes(columns(), np.full((N_U, N_V), 3e-6))
    ok &= check(
        (r.lobe_count, r.dominant_order) == (1, 0),
        f"uniform wear: lobe_count {r.lobe_count}, dominant_order {r.dominant_order}, expected 1, 0",
    )
    print(f"  {'ok ' if ok else 'BAD'} zero wear: no lobe, no harmonic; uniform wear: one lobe, no harmonic")

    # ---- (d) the command line --------------------------------------------------------------------
    print("(d) epaphe-rotor wear --png --csv")
    f = os.path.join(wd, "bumps5-from0.h5")
    png, csv = os.path.join(wd, "wear5.png"), os.path.join(wd, "wear5.csv")
    for p in (png, csv):
        if os.path.exists(p):
            os.remove(p)
    p = subprocess.run([tool, "wear", f, "--png", png, "--csv", csv], cwd=wd, capture_output=True, text=True)
    ok = check(p.returncode == 0, f"epaphe-rotor wear: exit {p.returncode}: {p.stderr.strip()}")
    ok &= check(p.stderr.strip() == "", f"epaphe-rotor wear: stderr {p.stderr.strip()!r}")
    m = re.search(r"^lobes: (\d+)", p.stdout, re.M)
    ok &= check(m is not None and int(m.group(1)) == 5, f"printed lobe count: {m.group(1) if m else None}, expected 5")
    ok &= check(re.search(r"^dominant harmonic: order 5 ", p.stdout, re.M) is not None, "printed harmonic is not 5")
    ok &= check("plastic dissipation at the end: 0.00125 J" in p.stdout, "printed plastic dissipation")
    ok &= check(re.search(r"^max wear: 2\d\.?\d* um", p.stdout, re.M) is not None, "printed max wear (~20 um)")
    if check(os.path.isfile(png), f"{png} not written"):
        probs = png_problems(png)
        ok &= check(not probs, f"{png}: {'; '.join(probs)}")
    if check(os.path.isfile(csv), f"{csv} not written"):
        with open(csv) as fh:
            head = fh.readline().strip()
        data = np.loadtxt(csv, delimiter=",", skiprows=1)
        with h5py.File(f, "r") as h:
            want_a = np.degrees(h["coating/Casing/angle"][()])
            want_w = h["coating/Casing/wear"][-1].max(axis=1)
        ok &= check(head == "angle_deg,wear_m", f"CSV header {head!r}")
        ok &= check(
            data.shape == (N_U, 2) and np.array_equal(data[:, 0], want_a) and np.array_equal(data[:, 1], want_w),
            "CSV profile differs from the deepest wear of each column of the last record",
        )
    print(f"  {'ok ' if ok else 'BAD'} " + " / ".join(p.stdout.strip().splitlines()[1:3]))

    # ---- (e) errors ------------------------------------------------------------------------------
    print("(e) errors")

    def expect_error(args, what, must_name):
        p = subprocess.run([tool, "wear"] + args, cwd=wd, capture_output=True, text=True)
        lines = p.stderr.strip().splitlines()
        ok = check(p.returncode == 1, f"{what}: exit status {p.returncode}, expected 1 ({p.stderr.strip()!r})")
        ok &= check(len(lines) == 1 and "Traceback" not in p.stderr, f"{what}: stderr {p.stderr!r}, expected one line")
        for word in must_name:
            ok &= check(word in p.stderr, f"{what}: message does not say {word!r}: {p.stderr.strip()!r}")
        print(f"  {'ok ' if ok else 'BAD'} {what}: {lines[0] if lines else '(no message)'}")

    bare = coating_file(os.path.join(wd, "uncoated.h5"), {}, coating=False)
    expect_error([bare], "no /coating", (bare, "has no coating"))
    angle = columns()
    two = coating_file(
        os.path.join(wd, "two.h5"), {"Casing": (angle, bumps(angle, [90.0])), "Shroud": (angle, bumps(angle, [10.0]))}
    )
    expect_error([two], "two coated surfaces, no --surface", (two, "Casing", "Shroud", "--surface"))
    expect_error([two, "--surface", "Hub"], "unknown --surface", ("Hub", "Casing", "Shroud"))
    r = lobes_of(two, "Shroud")
    check(r.lobe_count == 1 and near_all(r.lobe_angles, [10.0], "--surface Shroud"), "--surface Shroud: wrong lobes")

    return verdict(failures)


if __name__ == "__main__":
    sys.exit(main())
