#!/usr/bin/env python3
"""epaphe-modes reduces a body by its deck's 'Reduction->Method' (the one ReductionRegistry method epaphe-run uses).

On inputs/rotor37-massless.xml (16 tip nodes retained):
  1. Massless boundary: its modes are the full model's lowest normal modes (retained nodes free), so
     every reduced frequency equals the full model's to Anasazi's tolerance: |relative error| <= 1e-8
     (both sides converge to a relative residual of 1e-10; a frequency's error is of that order or
     less), and each reduced model has 48 + modes DOFs. A Craig-Bampton reduction of the same body
     with 5 modes is off by far more (its first frequency alone by about 1e-4 or more).
  2. Guyan (Craig-Bampton without modes): every mode count gives the same model (48 DOFs) and the
     same frequencies, each an upper bound of the full model's (Rayleigh-Ritz).
"""
import csv
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from epaphe_testing import parse_args, variant, verdict  # noqa: E402

RETAINED_DOFS = 48  # 16 tip nodes x 3


def modes_table(exe, deck, workdir, tag, modes):
    path = os.path.join(workdir, f"{tag}.csv")
    proc = subprocess.run(
        [
            os.path.abspath(exe),
            os.path.abspath(deck),
            "--modes",
            ",".join(map(str, modes)),
            "--count",
            "6",
            "--csv",
            path,
        ],
        cwd=workdir,
        capture_output=True,
        text=True,
        env=dict(os.environ, OMP_NUM_THREADS="1"),
    )
    if proc.returncode != 0:
        raise SystemExit(f"epaphe-modes failed on {deck}: {proc.stderr.strip()}")
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return proc.stdout, rows


def main():
    a = parse_args("--modes")
    failures = []
    # 1. Massless boundary
    out, rows = modes_table(a.modes, a.deck, a.workdir, "massless", [5, 10])
    if "Massless boundary convergence" not in out:
        failures.append("epaphe-modes did not reduce by the deck's 'Massless boundary'")
    worst = max(abs(float(r["relative_error"])) for r in rows)
    print(f"massless boundary: largest |relative error| {worst:.2e} over {len(rows)} frequencies")
    if not worst <= 1e-8:
        failures.append(f"massless boundary frequencies differ from the full model's by {worst:.2e} > 1e-8")
    for line in out.splitlines():
        if line.strip().startswith("reduced DOFs"):
            sizes = [int(x) for x in line.split()[2:]]
            if sizes != [RETAINED_DOFS + 5, RETAINED_DOFS + 10]:
                failures.append(
                    f"massless boundary reduced DOFs {sizes}, expected {[RETAINED_DOFS + 5, RETAINED_DOFS + 10]}"
                )
    cb = variant(a.deck, os.path.join(a.workdir, "cb.xml"), {"Bodies->Blade->Reduction->Method": "Craig-Bampton"})
    _, cb_rows = modes_table(a.modes, cb, a.workdir, "cb", [5])
    cb_first = abs(float(cb_rows[0]["relative_error"]))
    print(f"Craig-Bampton 5 modes: first frequency off by {cb_first:.2e}")
    if not cb_first > 100 * max(worst, 1e-12):
        failures.append(
            f"Craig-Bampton with 5 modes is as exact as the massless boundary ({cb_first:.2e}): the "
            "comparison does not tell the two reductions apart"
        )
    # 2. Guyan
    guyan = variant(a.deck, os.path.join(a.workdir, "guyan.xml"), {"Bodies->Blade->Reduction->Method": "Guyan"})
    out, rows = modes_table(a.modes, guyan, a.workdir, "guyan", [5, 10])
    by_modes = {}
    for r in rows:
        by_modes.setdefault(r["modes"], []).append(float(r["reduced_hz"]))
    g5, g10 = by_modes.get("5", []), by_modes.get("10", [])
    print(
        f"Guyan: f1 {g5[0] if g5 else float('nan'):.6g} Hz with '5' and {g10[0] if g10 else float('nan'):.6g} Hz with '10' modes"
    )
    if not g5 or g5 != g10:
        failures.append(f"Guyan depends on the mode count: {g5} against {g10}")
    if any(float(r["relative_error"]) < -1e-10 for r in rows):
        failures.append("a Guyan frequency lies below the full model's: not a Rayleigh-Ritz upper bound")
    for line in out.splitlines():
        if line.strip().startswith("reduced DOFs") and [int(x) for x in line.split()[2:]] != [RETAINED_DOFS] * 2:
            failures.append(f"Guyan reduced DOFs: {line.strip()}, expected {RETAINED_DOFS} for every mode count")
    return verdict(failures)


if __name__ == "__main__":
    sys.exit(main())
