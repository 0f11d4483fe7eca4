#!/usr/bin/env python3
"""Speed sweep of inputs/blade-casing.xml (epaphe-rotor map): 600, 1000 and 1400 rad/s, 6 revolutions
each, spectra over the last 3, the speeds dealt to 2 MPI ranks. Asserted: both ranks ran speeds
(rank 0: 600 and 1400, rank 1: 1000), the interaction map is written (HDF5 with one spectrum per
speed and node set, PNGs), and at every speed the dominant engine order of each tip edge is an
integer to 0.05 (the periodic contact forcing drives the steady response at whole engine orders;
free vibration at a natural frequency would show a fractional order). Prints the dominant orders."""
import argparse
import os
import subprocess
import sys

import h5py
import numpy as np

ap = argparse.ArgumentParser()
for k in ("--rotor", "--run", "--deck", "--workdir", "--mpiexec"):
    ap.add_argument(k, required=True)
a = ap.parse_args()
os.makedirs(a.workdir, exist_ok=True)
p = subprocess.run([sys.executable, a.rotor, "map", a.deck, "--speeds", "600,1000,1400", "--revs", "6", "--skip", "3",
                    "--ranks", "2", "--mpiexec", a.mpiexec, "--run", a.run, "--out", a.workdir], capture_output=True, text=True)
print(p.stdout)
if p.returncode != 0:
    sys.exit(p.stderr)
failures = []
for rank, w in ((0, 600), (1, 1000), (0, 1400)):
    if f"rank {rank}: {w} rad/s" not in p.stdout:
        failures.append(f"no run of {w} rad/s reported by rank {rank}")
with h5py.File(os.path.join(a.workdir, "map.h5"), "r") as f:
    for s in ("tip-le", "tip-te"):
        amp, eo = f[f"{s}/amplitude"][()], f[f"{s}/dominant_engine_order"][()]
        if amp.shape[0] != 3 or not np.isfinite(amp).all():
            failures.append(f"{s}: map shape {amp.shape} or non-finite values")
        if np.abs(eo - np.round(eo)).max() > 0.05:
            failures.append(f"{s}: dominant engine orders {eo} are not whole")
        if not os.path.getsize(os.path.join(a.workdir, f"map-{s}.png")) > 1000:
            failures.append(f"{s}: no map picture")
print("FAILED:\n  " + "\n  ".join(failures) if failures else "PASSED")
sys.exit(1 if failures else 0)
