#!/usr/bin/env python3
"""Benchmark (reports, never asserts timings): what an abradable coating costs per step.

Usage: bench_coating.py --run EPAPHE_RUN --deck blade-coating.xml --rigid-deck blade-casing.xml
                        --workdir DIR [--revs R] [--repeats N]

The blade in its casing (blade-casing.xml) and the same blade in the same casing with a coating in
front of it (blade-coating.xml), R revolutions each (default 5), on 1 thread, run alternately N times
(default 3; the machine's noise falls on both). Prints per run the loop time, steps per second and
the per-step cost split (/run/cost), then the best loop time of each and the coating's extra cost per
step in % of the rigid casing's (the issue's aim: 25 % or less), and where it goes (contact, projection,
output). The reduced model comes from a shared cache (setup is not measured)."""
import os
import sys

import h5py

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "verification"))
from epaphe_testing import parse_args, run, variant  # noqa: E402


def main():
    a = parse_args("--rigid-deck", "--revs", "--repeats")
    loops = {"rigid": [], "coated": []}
    split = {}
    for rep in range(int(a.repeats)):
        for tag, base in (("rigid", a.rigid_deck), ("coated", a.deck)):
            name = f"{tag}-{rep}"
            deck = variant(
                base,
                os.path.join(a.workdir, name + ".xml"),
                {
                    "Output->File": name + ".h5",
                    "Time->End revolutions": (a.revs, "double"),
                    "Run->Progress interval": ("0", "double"),
                    "Bodies->Blade->Reduction->Cache file": ("blade.rom.h5", "string"),
                },
            )
            run([a.run, deck, "--threads", "1"], a.workdir)
            with h5py.File(os.path.join(a.workdir, name + ".h5"), "r") as f:
                steps, loop = float(f["/run"].attrs["steps"]), float(f["/run"].attrs["loop_time"])
                cost = {k: 1e6 * v / steps for k, v in f["/run/cost"].attrs.items()}
            loops[tag].append((loop, steps, cost))
            print(
                f"{tag:6s} run {rep}: loop {loop:.3f} s, {steps / loop:,.0f} steps/s; per step "
                + ", ".join(f"{k} {v:.3g} us" for k, v in sorted(cost.items())),
                flush=True,
            )
    best = {tag: min(v, key=lambda x: x[0]) for tag, v in loops.items()}
    (lr, sr, cr), (lc, sc, cc) = best["rigid"], best["coated"]
    extra = 100.0 * (lc / sc - lr / sr) / (lr / sr)
    print(
        f"best of {a.repeats}: rigid casing {1e6 * lr / sr:.3f} us per step, coated {1e6 * lc / sc:.3f} us per step: "
        f"the coating costs {extra:+.1f} % per step (aim: 25 % or less)"
    )
    print(
        "  where: " + ", ".join(f"{k} {cr.get(k, 0):.3g} -> {cc.get(k, 0):.3g} us" for k in sorted(set(cr) | set(cc)))
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
