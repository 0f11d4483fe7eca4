#!/usr/bin/env python3
"""Benchmark (reports, never asserts timings): what a run-up costs against a run at fixed speed.

Usage: bench_run_up.py --run EPAPHE_RUN --deck blade-casing-run-up.xml --workdir DIR [--repeats N]

The run-up deck over 50 ms (the ramp from 2 to 48 ms) and the same deck at the fixed start speed
(Speed law Constant), same length, on 1 thread, run alternately N times (default 3; the machine's
noise falls on both). Prints per run the loop time, the stiffness refreshes and the per-step cost
split (/run/cost), then the best loop time of each and their ratio (issue 31's aim: 1.3 or less).
The reduced model comes from a shared cache (setup is not measured)."""
import os
import sys

import h5py

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "verification"))
from epaphe_testing import run, variant  # noqa: E402


def main():
    import argparse

    ap = argparse.ArgumentParser()
    for name in ("--run", "--deck", "--workdir"):
        ap.add_argument(name, required=True)
    ap.add_argument("--repeats", type=int, default=3)
    a = ap.parse_args()
    os.makedirs(a.workdir, exist_ok=True)
    loops = {"fixed": [], "ramp": []}
    for rep in range(a.repeats):
        for tag in ("fixed", "ramp"):
            name = f"{tag}-{rep}"
            deck = variant(
                a.deck,
                os.path.join(a.workdir, name + ".xml"),
                {
                    "Output->File": name + ".h5",
                    "Time->End time": "0.05",
                    "Bodies->Blade->Rotation->Speed law->Type": "Ramp" if tag == "ramp" else "Constant",
                    "Bodies->Blade->Rotation->Speed law->End time": "0.048",
                    "Run->Progress interval": ("0", "double"),
                    "Bodies->Blade->Reduction->Cache file": ("blade.rom.h5", "string"),
                },
            )
            p = run([a.run, deck, "--threads", "1"], a.workdir)
            refreshes = [l for l in p.stdout.splitlines() if "stiffness refreshes" in l]
            with h5py.File(os.path.join(a.workdir, name + ".h5"), "r") as f:
                steps, loop = float(f["/run"].attrs["steps"]), float(f["/run"].attrs["loop_time"])
                cost = {k: 1e6 * v / steps for k, v in f["/run/cost"].attrs.items()}
            loops[tag].append((loop, steps, cost))
            print(
                f"{tag:5s} run {rep}: loop {loop:.3f} s, {steps / loop:,.0f} steps/s; per step "
                + ", ".join(f"{k} {v:.3g} us" for k, v in sorted(cost.items()))
                + (f"; {refreshes[0].strip()}" if refreshes else ""),
                flush=True,
            )
    best = {tag: min(v, key=lambda x: x[0]) for tag, v in loops.items()}
    (lf, sf, cf), (lr, sr, cr) = best["fixed"], best["ramp"]
    print(
        f"best of {a.repeats}: fixed speed {lf:.3f} s ({1e6 * lf / sf:.3f} us per step), run-up {lr:.3f} s "
        f"({1e6 * lr / sr:.3f} us per step): the run-up costs {lr / lf:.3f} x the fixed-speed run (aim: 1.3 or less)"
    )
    print(
        "  where: " + ", ".join(f"{k} {cf.get(k, 0):.3g} -> {cr.get(k, 0):.3g} us" for k in sorted(set(cf) | set(cr)))
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
