#!/usr/bin/env python3
"""Craig-Bampton convergence (the check behind thesis Table 5.1), on the clamped ring of chapter 4.

For 0 (Guyan), 5, 20 and 60 fixed-interface modes, the first 10 frequencies of the reduced model are
compared with the full model's (Anasazi). Checked: every reduced frequency is at or above the full
one (Craig-Bampton is a Rayleigh-Ritz projection: an upper bound, to round-off), and the largest
relative error falls as modes are added.
"""
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from epaphe_testing import parse_args, run, variant, verdict  # noqa: E402


def main():
    a = parse_args()
    failures, worst = [], []
    for modes in (0, 5, 20, 60):
        name = f"cb{modes}"
        deck = variant(
            a.deck,
            os.path.join(a.workdir, name + ".xml"),
            {
                "Output->File": name + ".h5",
                "Bodies->Ring->Reduction->Fixed-interface modes": (str(modes), "int"),
                "Bodies->Ring->Reduction->Cache": ("false", "bool"),
            },
        )
        run([a.run, deck], a.workdir)
        with h5py.File(os.path.join(a.workdir, name + ".h5"), "r") as f:
            full = f["/bodies/Ring/frequencies/full"][()]
            red = f["/bodies/Ring/frequencies/reduced"][: full.size]
        err = (red - full) / full
        worst.append(err.max())
        print(
            f"{modes:3d} modes: relative errors of the first {full.size} frequencies: "
            + " ".join(f"{e:.2e}" for e in err)
        )
        if not (err >= -1e-9).all():
            failures.append(f"{modes} modes: a reduced frequency is below the full model's ({err.min():.2e})")
    if not all(worst[i + 1] < worst[i] for i in range(len(worst) - 1)):
        failures.append(f"the largest error does not fall with modes: {worst}")
    return verdict(failures)


if __name__ == "__main__":
    sys.exit(main())
