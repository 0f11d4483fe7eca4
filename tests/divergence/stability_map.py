#!/usr/bin/env python3
"""Stability map: the critical friction coefficient at each speed of a list, by bisection on mu
between a bounded run and a diverging one (issue 37, item 3; first applied to the strut of
sprag_slip.py, whose plane speed is the speed).

Criterion. A run is *diverging* when it stops with its energy growing without bound (epaphe-run's
diagnosis, "grows without bound"), or when it completes with the bodies' energy (kinetic + strain) at
its end more than GROWTH times the largest over the first half of the run after the interference's
ramp; else it is *bounded*. Per
speed the bracket [mu_lo, mu_hi] (bounded, diverging) is halved until (mu_hi - mu_lo) <= TOL mu_hi;
the boundary is reported as both ends. Each run is one epaphe-run on one thread; --jobs J runs up to J
at once: the speeds' brackets are independent, so each round runs the mid-points of every speed still
open together (the result does not depend on J: each speed sees the same sequence of runs).

Written: <workdir>/stability-map.h5 (/speed, /mu_bounded, /mu_diverging, and /runs/{speed, mu,
diverging, growth} of every run) and <workdir>/stability-map.png (mu against speed, the bounded and
diverging runs and the boundary). For the strut the quasi-static sprag (eq. (50)) does not depend on
the speed, so the map is flat at mu_c (checked against (51) within TOL_MAP). Up to 2 m/s: faster, the
jam reaches the section's other corners within the window and the criterion no longer separates.

With --rotor37 INPUTS: inputs/rotor37-massless.xml over its casing speed (rad/s), --revolutions each
(10), a run that stops, whatever stops it, being diverging (docs/user/divergence.md).

With --blade DECK: a blade deck of inputs/ (blade-casing.xml, blade-casing-at-speed.xml) over its
casing speed (rad/s), at the deck's own time step, --revolutions each, judged as rotor 37's runs.

    stability_map.py --run EPAPHE_RUN --workdir DIR [--speeds 0.5,1,2] [--bracket 0.25,0.5] [--jobs J]
                     [--rotor37 INPUTS | --blade DECK] [--revolutions 10]"""
import argparse
import importlib.util
import os
import re
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

import h5py
import numpy as np

GROWTH = 2.0
TOL = 0.01
TOL_MAP = 0.02  # the boundary's mid-point against (51) (the model's own mu*_c is 1.1 % above it)
# m: each run lasts the interference ramp and TRAVEL / speed, the same plane travel (the jam grows with
# the travel, and the section's other corners reach the plane after about 10 mm of it)
TRAVEL = 6e-3

HERE = os.path.dirname(os.path.abspath(__file__))
_spec = importlib.util.spec_from_file_location("sprag_slip", os.path.join(HERE, "sprag_slip.py"))
strut = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(strut)


def outcome(exe, workdir, speed, mu):
    """(diverging, growth) of the strut at plane speed `speed` (m/s) and coefficient mu."""
    name = f"map-v{speed:g}-mu{mu:.6f}"
    code, text, attrs, t, energy = strut.run(exe, workdir, name, mu, strut.RAMP + TRAVEL / speed, speed=speed)
    first = (t >= strut.RAMP) & (t <= strut.RAMP + 0.5 * TRAVEL / speed)
    growth = float(energy[-1] / max(energy[first].max(), 1e-300))
    return (code != 0 and "grows without bound" in text) or growth > GROWTH, growth


def run_deck(exe, workdir, name, text):
    """(diverging, growth) of the deck `text` run as <workdir>/<name>.xml on one thread: diverging when
    the run stops, whatever stops it, or when the bodies' final energy exceeds GROWTH times the largest
    of the run's first half."""
    path = os.path.join(workdir, name + ".xml")
    open(path, "w").write(text)
    p = subprocess.run([exe, path, "--threads", "1"], capture_output=True, text=True, cwd=workdir)
    with h5py.File(os.path.join(workdir, name + ".h5"), "r") as f:
        t = f["time"][()]
        energy = f["energy/kinetic"][()] + f["energy/strain"][()]
    first = t <= 0.5 * t[-1]
    growth = float(energy[-1] / max(energy[first].max(), 1e-300))
    return p.returncode != 0 or growth > GROWTH, growth


def rotor_outcome(exe, workdir, inputs, speed, mu, revolutions):
    """(diverging, growth) of inputs/rotor37-massless.xml with the casing at `speed` (rad/s, the deck's
    sense), 'Friction coefficient' mu, `revolutions` revolutions (the step keeps 1000 per revolution):
    here a run that stops, whatever stops it, is diverging."""
    text = open(os.path.join(inputs, "rotor37-massless.xml")).read()
    name = f"map-r37-w{speed:g}-mu{mu:.6f}"
    for old, new in [
        (
            'name="Friction coefficient" type="double" value="0.15"',
            f'name="Friction coefficient" type="double" value="{mu!r}"',
        ),
        (
            'name="Rotation speed" type="double" value="-1344"',
            f'name="Rotation speed" type="double" value="{-speed!r}"',
        ),
        (
            'name="Time step" type="double" value="4.675e-6"',
            f'name="Time step" type="double" value="{2 * np.pi / speed / 1000!r}"',
        ),
        (
            'name="End revolutions" type="double" value="50"',
            f'name="End revolutions" type="double" value="{revolutions!r}"',
        ),
        ('value="rotor37-massless.h5"', f'value="{name}.h5"'),
        (
            '<ParameterList name="Run">',
            '<ParameterList name="Run"><Parameter name="Divergence step check" type="bool" value="false"/>',
        ),
    ]:
        assert old in text, old
        text = text.replace(old, new)
    return run_deck(exe, workdir, name, text)


def blade_outcome(exe, workdir, deck, speed, mu, revolutions):
    """(diverging, growth) of a blade deck (a casing turning at the deck's 'Rotation speed', Lagrange
    contact) with the casing at `speed` (rad/s, the deck's sense), 'Friction coefficient' mu and
    `revolutions` revolutions at the deck's time step; a run that stops, whatever stops it, is diverging."""
    text = open(deck).read()
    stem = os.path.splitext(os.path.basename(deck))[0]
    name = f"map-{stem}-w{speed:g}-mu{mu:.6f}"
    sense = -1.0 if re.search(r'name="Rotation speed" type="double" value="-', text) else 1.0
    text, n = re.subn(
        r'name="Rotation speed" type="double" value="[^"]*"',
        f'name="Rotation speed" type="double" value="{sense * speed!r}"',
        text,
    )
    assert n == 1, f"{deck}: one surface 'Rotation speed' expected, {n} found"
    text, n = re.subn(
        r'name="End revolutions" type="double" value="[^"]*"',
        f'name="End revolutions" type="double" value="{revolutions!r}"',
        text,
    )
    assert n == 1, f"{deck}: 'Time->End revolutions' expected"
    text, n = re.subn(r'(<Parameter name="File" type="string" value=")[^"]*(")', rf"\g<1>{name}.h5\2", text)
    assert n == 1, f"{deck}: 'Output->File' expected"
    text = re.sub(r'\s*<Parameter name="Friction coefficient"[^>]*/>', "", text)
    text, n = re.subn(
        r'(<ParameterList name="Contact">)',
        rf'\1<Parameter name="Friction coefficient" type="double" value="{mu!r}"/>',
        text,
    )
    assert n == 1, f"{deck}: a Contact list expected"
    text = text.replace(
        '<ParameterList name="Run">',
        '<ParameterList name="Run"><Parameter name="Divergence step check" type="bool" value="false"/>',
        1,
    )
    return run_deck(exe, workdir, name, text)


def main():
    a = argparse.ArgumentParser()
    a.add_argument("--run", required=True)
    a.add_argument("--workdir", required=True)
    a.add_argument("--speeds", default="0.5,1,2")  # m/s
    a.add_argument("--bracket", default="0.25,0.5")
    a.add_argument("--rotor37", metavar="INPUTS", help="map inputs/rotor37-massless.xml instead (speeds in rad/s)")
    a.add_argument("--blade", metavar="DECK", help="map a blade deck instead (speeds in rad/s)")
    a.add_argument("--revolutions", type=float, default=10.0)
    a.add_argument("--jobs", type=int, default=1, help="runs at once (each on one thread)")
    o = a.parse_args()
    os.makedirs(o.workdir, exist_ok=True)
    speeds = [float(s) for s in o.speeds.split(",")]
    lo0, hi0 = (float(x) for x in o.bracket.split(","))
    runs = []

    def case(speed, mu):
        if o.rotor37:
            return rotor_outcome(o.run, o.workdir, o.rotor37, speed, mu, o.revolutions)
        if o.blade:
            return blade_outcome(o.run, o.workdir, o.blade, speed, mu, o.revolutions)
        return outcome(o.run, o.workdir, speed, mu)

    def batch(pool, cases):
        """The outcomes of (speed, mu) cases run together, recorded in `runs` in the cases' order."""
        results = list(pool.map(lambda c: case(*c), cases))
        for (v, mu), (d, g) in zip(cases, results):
            runs.append((v, mu, d, g))
        return [d for d, _ in results]

    bracket = {v: [lo0, hi0] for v in speeds}
    with ThreadPoolExecutor(max_workers=max(1, o.jobs)) as pool:
        ends = batch(pool, [(v, mu) for v in speeds for mu in (lo0, hi0)])
        for i, v in enumerate(speeds):
            dlo, dhi = ends[2 * i], ends[2 * i + 1]
            if dlo or not dhi:
                sys.exit(f"speed {v}: the bracket {lo0}, {hi0} is not (bounded, diverging): {dlo}, {dhi}")
        while True:
            open_ = [v for v, (lo, hi) in bracket.items() if hi - lo > TOL * hi]
            if not open_:
                break
            mids = [0.5 * (bracket[v][0] + bracket[v][1]) for v in open_]
            for v, mid, d in zip(open_, mids, batch(pool, list(zip(open_, mids)))):
                bracket[v][1 if d else 0] = mid
    lo = np.array([bracket[v][0] for v in speeds])
    hi = np.array([bracket[v][1] for v in speeds])
    with h5py.File(os.path.join(o.workdir, "stability-map.h5"), "w") as f:
        f["speed"], f["mu_bounded"], f["mu_diverging"] = np.array(speeds), lo, hi
        f.attrs["criterion"] = (
            f"diverging: stopped with energy growing without bound, or final energy > {GROWTH} "
            f"times the first half's largest; bisection to {TOL} relative"
        )
        r = np.array(runs, dtype=float)
        for i, key in enumerate(["speed", "mu", "diverging", "growth"]):
            f["runs/" + key] = r[:, i]
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5, 3.5))
    r = np.array(runs)
    ax.plot(r[r[:, 2] == 0, 0], r[r[:, 2] == 0, 1], "o", color="tab:green", label="bounded")
    ax.plot(r[r[:, 2] == 1, 0], r[r[:, 2] == 1, 1], "x", color="tab:red", label="diverging")
    ax.fill_between(speeds, 0.5 * (lo + hi), max(hi0, hi.max()), color="tab:red", alpha=0.1)
    ax.plot(speeds, 0.5 * (lo + hi), "k-", label="boundary")
    ax.set_xlabel("casing speed (rad/s)" if o.rotor37 or o.blade else "plane speed (m/s)")
    ax.set_ylabel("friction coefficient")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(o.workdir, "stability-map.png"), dpi=120)
    if o.rotor37 or o.blade:
        what = "rotor 37" if o.rotor37 else os.path.basename(o.blade)
        for v, l, h in zip(speeds, lo, hi):
            print(f"{what} at {v:g} rad/s: bounded at mu {l:.4f}, diverging at {h:.4f}")
        return 0
    mu_beam, failures = strut.beam_mu_c(), []
    for v, l, h in zip(speeds, lo, hi):
        off = 0.5 * (l + h) / mu_beam - 1
        print(
            f"speed {v:g} m/s: bounded at mu {l:.4f}, diverging at {h:.4f}; mid-point {off:+.2e} from (51)'s "
            f"{mu_beam:.4f} (tolerance {TOL_MAP})"
        )
        if not abs(off) <= TOL_MAP:
            failures.append(f"speed {v:g} m/s: boundary {l}, {h} off the closed form {mu_beam}")
    print("FAILED:\n  " + "\n  ".join(failures) if failures else f"{len(speeds)} passed, 0 failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
