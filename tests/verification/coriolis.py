#!/usr/bin/env python3
"""The Coriolis terms kept on a rotating blade in contact (docs/user/rotating-bodies.md#coriolis-terms).

On inputs/blade-casing-at-speed.xml (the V7 blade at 1000 rad/s from its parametric model, Lagrange
contact with a two- and six-lobe casing, modal damping), one revolution with 'Rotation->Coriolis' true
and one without, asserted with tolerances stated before measuring:
  - the run with the Coriolis terms closes its energy balance to 1e-6 of the largest energy, as the run
    without them: the gyroscopic force does no work (docs/theory/integration.md, eq. 54), and the
    contact correction with the non-symmetric flexibility P = [M/h^2 + (D + Omega G_r)/2h]^-1 does work
    only through the contact force, which the balance counts;
  - the blade touches the casing (contact work above 1e-3 of the largest energy), so the correction runs;
  - the summary reports the terms' effect on the lowest frequencies, a change above 0 and below 10 %
    (Omega / omega_1 is about 0.2 here: a split of that order at most);
  - the two runs differ: the tip's largest displacement difference is above 1e-6 of its motion.
The summary's figure and the tip difference are printed (the size of the Coriolis coupling on this blade).
"""
import argparse
import os
import re
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from epaphe_testing import run, variant, verdict  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--run", required=True)
    ap.add_argument("--deck", required=True)
    ap.add_argument("--workdir", required=True)
    a = ap.parse_args()
    W = a.workdir
    os.makedirs(W, exist_ok=True)
    failures = []
    tips = {}
    for kept in (True, False):
        name = "coriolis" if kept else "without"
        deck = variant(
            a.deck,
            os.path.join(W, f"{name}.xml"),
            {
                "Time->End revolutions": "1",
                "Output->Every": "10",
                "Bodies->Blade->Rotation->Coriolis": ("true" if kept else "false", "bool"),
                "Bodies->Blade->Reduction->Cache file": (f"{name}.rom.h5", "string"),
            },
        )
        p = run([a.run, deck, "--output", f"{name}.h5"], W)
        with h5py.File(os.path.join(W, f"{name}.h5"), "r") as f:
            e = f["energy"]
            bal = float(np.abs(e["balance_error"][()]).max())
            top = float(np.abs(e["total"][()]).max())
            contact = float(np.abs(e["contact_work"][()]).max())
            tips[name] = f["bodies/Blade/nodesets/tip-le/displacement"][()]
        print(
            f"{name}: energy balance error {bal:.2e} (1e-6 asserted), contact work {contact:.3e} J = "
            f"{contact / top:.2e} of the largest energy {top:.3e} J"
        )
        if not bal <= 1e-6:
            failures.append(f"{name}: energy balance error {bal:.2e} > 1e-6")
        if not contact > 1e-3 * top:
            failures.append(f"{name}: contact work {contact:.2e} J is not above 1e-3 of the largest energy")
        if kept:
            m = re.search(r"Coriolis terms kept .*?move by up to ([0-9.eE+-]+) %(.*)", p.stdout)
            if not m:
                failures.append("the summary does not report the kept Coriolis terms")
            else:
                change = float(m.group(1))
                print(f"summary: the Coriolis terms move the lowest frequencies by up to {change:.3g} %{m.group(2)}")
                if not 0 < change < 10:
                    failures.append(f"the Coriolis terms move the frequencies by {change} %, not in (0, 10) %")
    a_, b_ = tips["coriolis"], tips["without"]
    n = min(len(a_), len(b_))
    diff = float(np.abs(a_[:n] - b_[:n]).max())
    scale = float(np.abs(b_[:n] - b_[:1]).max())
    print(
        f"tip-le: largest displacement difference with and without the Coriolis terms {diff:.3e} m, "
        f"{diff / scale:.2e} of its motion {scale:.3e} m"
    )
    if not diff > 1e-6 * scale:
        failures.append(f"the runs with and without the Coriolis terms do not differ ({diff:.2e} m)")
    return verdict(failures)


if __name__ == "__main__":
    sys.exit(main())
