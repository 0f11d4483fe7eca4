#!/usr/bin/env python3
"""Craig-Bampton on 2 MPI ranks gives the same reduced model as on 1 rank.

Runs the bar deck with the cache off and a few steps, on 1 and on 2 ranks (Tpetra maps split the
model, MUMPS factors K_CC in parallel, Anasazi runs distributed), and compares the frequencies of
the reduced models, the fixed-interface modes and the full-model check: 1e-8 relative.
"""
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from epaphe_testing import parse_args, run, variant  # noqa: E402

TOL = 1e-8


def main():
    a = parse_args("--mpiexec")
    freqs = {}
    for np_ in (1, 2):
        name = f"np{np_}"
        deck = variant(
            a.deck,
            os.path.join(a.workdir, name + ".xml"),
            {
                "Output->File": name + ".h5",
                "Time->End time": ("1e-6", "double"),
                "Bodies->Bar->Reduction->Cache": ("false", "bool"),
                "Bodies->Bar->Reduction->Fixed-interface modes": ("30", "int"),
            },
        )
        proc = run([a.mpiexec, "-np", str(np_), a.run, deck, "--threads", "1"], a.workdir)
        print(f"--- {np_} rank(s)\n" + "\n".join(l for l in proc.stdout.splitlines() if "Craig-Bampton" in l))
        with h5py.File(os.path.join(a.workdir, name + ".h5"), "r") as f:
            freqs[np_] = {k: f[f"/bodies/Bar/frequencies/{k}"][()] for k in ("reduced", "fixed_interface", "full")}
    worst = 0.0
    for k in ("reduced", "fixed_interface", "full"):
        f1, f2 = freqs[1][k], freqs[2][k]
        assert f1.shape == f2.shape and f1.size > 0, f"{k}: shapes {f1.shape} vs {f2.shape}"
        # Rigid-body modes are zero up to round-off (a few mHz here): both runs must call them
        # rigid (below 1e-4 of the highest frequency); the elastic modes are compared relatively.
        rigid = f1 < 1e-4 * f1.max()
        if not np.array_equal(rigid, f2 < 1e-4 * f2.max()):
            print(f"{k}: rigid-body modes differ: {f1[rigid]} vs {f2[f2 < 1e-4 * f2.max()]}")
            worst = np.inf
        rel = np.max(np.abs(f1[~rigid] - f2[~rigid]) / f1[~rigid])
        worst = max(worst, rel)
        print(
            f"{k:16s} {f1.size:3d} frequencies ({rigid.sum()} rigid-body), max relative difference of the "
            f"elastic ones, 1 vs 2 ranks: {rel:.2e}"
        )
    print("PASSED" if worst <= TOL else f"FAILED: {worst:.2e} > {TOL:g}")
    return 0 if worst <= TOL else 1


if __name__ == "__main__":
    sys.exit(main())
