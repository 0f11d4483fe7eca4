#!/usr/bin/env python3
"""epaphe-frf, the stepped-sine sweep (docs/user/loads.md), on the one-mass model of den_hartog.py
(docs/theory/forced-response.md, eqs. (68)-(70)).

1. Linear limit: no friction, no contact node, Rayleigh 5 % at f_n = 10 Hz, h = 1e-4 s, at 5, 8, 10,
   12.5 and 20 Hz and drive amplitudes x1 and x2: every run stops at its detected steady state (70),
   its first harmonic (averaged over the pattern p: at 20 Hz = 2 f_n the decaying free motion repeats
   every p = 2 drive periods, and the mean over them cancels it) equals the scheme's exact frequency response (69) times the
   amplitude within TOL_LIN = 1e-6 (the criterion's tolerance; measured 1e-11), and the x2 curve is
   twice the x1 curve within the same tolerance (a linear model).
2. With friction (mu N / F_0 = 0.25, h = 5e-5 s) at r = 0.625, 0.8 and 1.25: every run is steady,
   stopped after fewer periods than the 400 allowed (the detection saves the rest of the run), and
   its first harmonic equals that of Den Hartog's exact periodic motion (68) (its closed-form half
   period, DFT on 20,000 points) within TOL_DH = 1 % in modulus and 1 % of pi in phase.
3. --jobs 2 gives the very numbers of --jobs 1 (the runs are independent, each on one thread).
Printed: each run's wall time and periods, the sweep's total wall time at 1 and 2 jobs.

    frequency_sweep.py --run EPAPHE_RUN --frf EPAPHE_FRF --workdir DIR
"""
import argparse
import math
import os
import subprocess
import sys
import time

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import den_hartog as dh  # noqa: E402
from epaphe_testing import verdict  # noqa: E402

TOL_LIN = 1e-6
TOL_DH = 0.01
NU_LIN = [5.0, 8.0, 10.0, 12.5, 20.0]
R_FR = [0.625, 0.8, 1.25]
PERIODS = 400


def base_deck(workdir, name, friction, h):
    path = os.path.join(workdir, name + ".xml")
    dh.write_deck(path, 10.0, 1.0, name + ".h5", friction, h)
    with open(path) as f:
        text = f.read()
    text = text.replace(
        '  <ParameterList name="Output">',
        """  <ParameterList name="Steady state">
    <Parameter name="Enabled" type="bool" value="true"/>
    <Parameter name="Node set" type="string" value="MASS"/>
  </ParameterList>
  <ParameterList name="Output">""",
    )
    with open(path, "w") as f:
        f.write(text)
    return path


def sweep(frf, exe, deck, out, freqs, amps, jobs):
    cmd = [sys.executable, frf, deck, "--load", "Bodies->Mass->Loads->Drive", "--run", exe, "--out", out]
    cmd += ["--frequencies", ",".join(map(repr, freqs)), "--amplitudes", ",".join(map(repr, amps))]
    cmd += ["--periods", str(PERIODS), "--jobs", str(jobs)]
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=1800)
    wall = time.perf_counter() - t0
    print(p.stdout.rstrip())
    if p.returncode != 0:
        raise SystemExit(f"epaphe-frf failed ({p.returncode}):\n{p.stderr}")
    return wall


def read(out, i):
    with h5py.File(os.path.join(out, "frf.h5"), "r") as f:
        g = f[f"response/{i}"]
        return {k: g[k][()] for k in g}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--run", required=True)
    ap.add_argument("--frf", required=True)
    ap.add_argument("--workdir", required=True)
    a = ap.parse_args()
    os.makedirs(a.workdir, exist_ok=True)
    dh.write_model(a.workdir)
    failures = []

    deck = base_deck(a.workdir, "linear", False, dh.H_LIN)
    out1 = os.path.join(a.workdir, "linear-j1")
    wall1 = sweep(a.frf, a.run, deck, out1, NU_LIN, [1.0, 2.0], 1)
    out2 = os.path.join(a.workdir, "linear-j2")
    wall2 = sweep(a.frf, a.run, deck, out2, NU_LIN, [1.0, 2.0], 2)
    print(f"linear sweep, 10 runs: {wall1:.1f} s at 1 job, {wall2:.1f} s at 2 jobs")
    r1, r2 = read(out1, 0), read(out1, 1)
    for j, nu in enumerate(NU_LIN):
        w, h = 2 * math.pi * nu, dh.H_LIN
        exact = dh.F0 / (
            dh.K - 4 / h**2 * math.sin(w * h / 2) ** 2 * dh.M + 1j * math.sin(w * h) / h * dh.ALPHA * dh.M
        )
        for amp, r in ((1.0, r1), (2.0, r2)):
            e = abs(r["harmonic_amplitude"][j, 1] - amp * abs(exact)) / (amp * abs(exact))
            ep = abs((r["harmonic_phase"][j, 1] - np.angle(exact) + math.pi) % (2 * math.pi) - math.pi)
            print(
                f"  x{amp:g} at {nu:g} Hz: |a_1| against (69) {e:.1e}, phase {ep:.1e} rad; steady {r['steady'][j]}"
                f" after {r['periods'][j]} periods (p = {r['pattern'][j]})"
            )
            if not (e <= TOL_LIN and ep <= TOL_LIN and r["steady"][j] == 1):
                failures.append(f"linear x{amp:g} at {nu} Hz: {e:.2e} / {ep:.2e} rad, steady {r['steady'][j]}")
        lin = abs(r2["harmonic_amplitude"][j, 1] - 2 * r1["harmonic_amplitude"][j, 1]) / r2["harmonic_amplitude"][j, 1]
        if not lin <= TOL_LIN:
            failures.append(f"{nu} Hz: x2 is not twice x1 ({lin:.2e})")
    for i in (0, 1):
        p, q = read(out1, i), read(out2, i)
        for k in ("harmonic_amplitude", "harmonic_phase", "steady", "periods", "pattern"):
            if not np.array_equal(p[k], q[k]):
                failures.append(f"--jobs 2 differs from --jobs 1 in response/{i}/{k}")

    deck = base_deck(a.workdir, "friction", True, dh.H)
    out = os.path.join(a.workdir, "friction")
    freqs = [r * dh.FN for r in R_FR]
    wall = sweep(a.frf, a.run, deck, out, freqs, [1.0], 2)
    res = read(out, 0)
    print(f"friction sweep, {len(freqs)} runs: {wall:.1f} s at 2 jobs")
    for j, r in enumerate(R_FR):
        exact = dh.den_hartog_first_harmonic(r)
        got = res["harmonic_amplitude"][j, 1] * np.exp(1j * res["harmonic_phase"][j, 1])
        em = abs(abs(got) - abs(exact)) / abs(exact)
        ep = abs(np.angle(got / exact))
        print(
            f"  r = {r}: first harmonic {abs(got):.6e} m against Den Hartog's {abs(exact):.6e} ({em:.1e}), phase "
            f"{np.angle(got):+.5f} against {np.angle(exact):+.5f} rad ({ep / math.pi:.1e} of pi); steady "
            f"{res['steady'][j]} after {res['periods'][j]} of {PERIODS} periods, {res['wall_time'][j]:.2f} s"
        )
        if not (res["steady"][j] == 1 and res["periods"][j] < PERIODS):
            failures.append(f"r = {r}: not steady within {PERIODS} periods")
        if not (em <= TOL_DH and ep <= TOL_DH * math.pi):
            failures.append(f"r = {r}: first harmonic {got:.6e} against Den Hartog's {exact:.6e}")
    sys.exit(verdict(failures))


if __name__ == "__main__":
    main()
