#!/usr/bin/env python3
"""Skipping the projection of distant nodes changes no result (Contact->Skip distant nodes).

Usage: skip_equivalence.py --run EPAPHE_RUN --inputs DIR --workdir DIR

Runs every deck of inputs/ twice, with skipping on (the default) and off, over a horizon that
contains its contacts (the deck's own, or the first revolutions of a rotating scene), and compares
every numeric dataset of the two outputs: contact forces, gaps, active counts, displacements,
energies. Round-off may differ (a skipped node's next Newton projection starts from an older foot
point, and converges to the same point within the Newton tolerance), so each dataset must agree to
RTOL of its largest magnitude. Skipping must also have skipped something on the contact decks,
else the test would prove nothing: the run's summary counts projections.
"""
import argparse
import glob
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "verification"))
from epaphe_testing import run, variant  # noqa: E402
import epaphe  # noqa: E402  (epaphe_testing put python/ on the path)

RTOL = 1e-7  # of each dataset's largest magnitude (the balance error: absolute, it is already relative)
# horizons: long decks are cut to what holds their first contacts
HORIZON = {
    "blade-casing": {"Time->End revolutions": ("1", "double")},
    "blade-coating": {"Time->End revolutions": ("1", "double")},
    "blade-coating-sweep": {"Time->End revolutions": ("1", "double")},
    "blade-flexible-casing": {"Time->End revolutions": ("0.5", "double")},
    "rotor37-casing": {"Time->End revolutions": ("1", "double")},
    "rotor37-massless": {"Time->End revolutions": ("10", "double")},
    "cube-flexible-rings": {"Time->End time": ("6e-4", "double")},
    # the thesis-regime decks (E = 2.1 GPa, h = 1e-6 s): contacts from 0.06 ms to about 2 ms
    "cube-rings-thesis": {"Time->End time": ("3e-3", "double")},
    "cube-flexible-rings-thesis": {"Time->End time": ("3e-3", "double")},
}
# datasets that are not results: wall-clock costs, Newton iteration counts (a warm start from an
# older foot point takes other iterations to the same point)
IGNORE = ("cost", "iterations", "wall", "seconds", "projected")


def datasets(path):
    with epaphe.open(path) as f:
        assert f.complete, f"{path}: status {f.status}"
        out = f.flat("fi", select=lambda name: not any(s in name for s in IGNORE) and not name.startswith("checkpoint"))
        return out, dict(f.attrs)


def main():
    ap = argparse.ArgumentParser()
    for name in ("--run", "--inputs", "--workdir"):
        ap.add_argument(name, required=True)
    a = ap.parse_args()
    os.makedirs(a.workdir, exist_ok=True)
    failures = 0
    decks = sorted(glob.glob(os.path.join(a.inputs, "*.xml")))
    for deck in decks:
        name = os.path.splitext(os.path.basename(deck))[0]
        results = {}
        for skip in ("true", "false"):
            tag = f"{name}-skip-{skip}"
            over = {"Output->File": tag + ".h5", "Run->Progress interval": ("0", "double")}
            over.update(HORIZON.get(name, {}))
            if name != "ring-modes":
                over["Contact->Skip distant nodes"] = (skip, "bool")
            d = variant(deck, os.path.join(a.workdir, tag + ".xml"), over)
            run([a.run, d, "--threads", "2"], a.workdir)
            results[skip] = datasets(os.path.join(a.workdir, tag + ".h5"))
        on, attrs_on = results["true"]
        off, attrs_off = results["false"]
        if set(on) != set(off):
            print(f"{name}: FAIL: datasets differ: {sorted(set(on) ^ set(off))}")
            failures += 1
            continue
        worst, where = 0.0, ""
        for key in on:
            x, y = np.asarray(on[key], float), np.asarray(off[key], float)
            if x.shape != y.shape:
                print(f"{name}: FAIL: {key} has shape {x.shape} with skipping, {y.shape} without")
                failures += 1
                continue
            # the balance error is itself a relative round-off measure: compared in absolute terms
            scale = 1.0 if "balance_error" in key else max(np.max(np.abs(y)) if y.size else 0.0, 1e-300)
            err = np.max(np.abs(x - y)) / scale if y.size else 0.0
            if err > worst:
                worst, where = err, key
        skipped = attrs_on.get("projections_skipped", 0)
        total = attrs_on.get("projections", 0) + skipped
        share = f"{100.0 * skipped / total:.1f} %" if total else "n/a"
        verdict = "ok" if worst <= RTOL else "FAIL"
        failures += verdict != "ok"
        print(
            f"{name}: {len(on)} datasets, largest difference {worst:.2e} of its scale ({where or '-'}); "
            f"projections skipped: {share}: {verdict}"
        )
    print(f"{len(decks) - failures} passed, {failures} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
