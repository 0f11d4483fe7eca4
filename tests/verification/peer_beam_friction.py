#!/usr/bin/env python3
"""Peer check: the frequency-response peak of the friction-damped cantilever (inputs/beam-friction.xml)
by Siconos 4.4 and by epaphe-frf, on the same model, load and friction contact (issue 36).

Epaphe: epaphe-frf on the deck as it is (Craig-Bampton, 22 reduced DOFs; Lagrange contact with Coulomb
friction mu = 0.3 on the two tip nodes that rest on the plane; the 20 N preload, the run started from
its static equilibrium, stuck; the 10 N drive along y; modal damping 0.8 %; h = 2.5e-6 s), each frequency
run from that start to its detected steady state (eq. (70), eps = 1e-6), 2 at a time.
Siconos (peer_siconos_beam_friction.py): the same reduced model read from the reduced-model cache the
Epaphe runs wrote, the same loads by virtual work (eq. (66)), the same modal damping matrix, the same
start; a 3-D Coulomb contact (NewtonImpactFrictionNSL, e = 0) on the same two nodes; Moreau-Jean
theta = 0.5 at STEPS = 400 steps per drive period, FrictionContact(3) to 1e-12; a stepped sine (each
frequency from the previous one's end), the frequencies split into two halves run in two processes.
Frequencies: FREQS, 400000/N Hz for N = 6480, 6450, ..., 6360 (a whole number of Epaphe's steps per
period), 0.29 Hz apart around the peak. The first harmonic of the tip's mean y displacement, as both
codes' steady-state criteria take it; the peak of each curve is the vertex of the parabola through its
largest sample and the two beside it (asserted inside the grid).

What else was measured while building this test (not re-run here): on the same model without friction
(mu = 0, the tip held along the normal only) the three agree at 62.31 Hz, the resonance: the exact
response of the constrained model (69's continuous form) 3.27718e-3 m, Epaphe 3.27716e-3, Siconos
(N = 400) 3.27788e-3 (2.2e-4): the matrices, loads, damping and watched motion are the same. Siconos
with friction at 62.70 Hz: 7.284e-4 m (N = 200), 7.324e-4 (400), 7.3404e-4 (800 and 1600): its
discretization error at N = 400 is 0.2 %; at 62.31 Hz, N = 3200 and 6400 (h = 5e-6 s and 2.5e-6 s, Epaphe's
own step): 7.774e-4 and 7.773e-4 against 7.784e-4 at N = 400. Epaphe at h and h/2 at
62.70 Hz: 7.8468e-4 and 7.8475e-4 (1e-4).
Siconos on Den Hartog's oscillator (den_hartog.py's, r = 0.8, N = 1600): 6e-5 of the exact first
harmonic, as Epaphe (8.1e-4 at its step).

Asserted:
  - every Epaphe run is steady; every Siconos point is steady to its criterion (eps = 1e-4: the
    transient left is then below 2e-3 of the amplitude) or the
    change over its last period is below 1e-3;
  - the peak frequencies agree within TOL_F = 2e-3 relative (0.12 Hz, 0.4 of the grid step). The
    sources of a difference: Siconos' trapezoidal rule lengthens the period by (omega h)^2 / 12 = 2e-5
    at N = 400, the central difference's by (omega h)^2 / 24 = 1e-8; the criteria's residual
    transients move a sample by up to 2e-3 of the amplitude, which moves a parabola's vertex by a few
    hundredths of the 0.29 Hz grid step. Measured: 1.6e-4 (62.331 Hz against 62.321 Hz).
  - the peak amplitudes agree within TOL_A = 5e-3 relative: Siconos' discretization at N = 400 is
    0.14 % (above), Epaphe's 1e-4, the criteria's residual transients 2e-3. Measured: 4e-5
    (7.78483e-4 m against 7.78451e-4 m). This needs a sliding node's friction against its slip when
    its tangential flexibility is not isotropic (docs/theory/contact.md, eq. (74)): the tip's two nodes
    are stiff along the beam and supple across it, and a radial return along the force that would
    stop the node left the force at an angle to the slip. Then Epaphe's friction dissipated 0.978 x
    4 mu N A a period against Siconos' 0.999 x (mu sum_k N_k |v_t,k| from its own records 0.02002 J a
    period, its contact work 0.01957 J), and as the drive so nearly balances the friction at the peak
    (the balance 31.4 A = 9.5e3 A^2 + 24 r A), the 2.2 % raised the peak amplitude by 7.1 %.
Run time: 51-70 s on the 2 shared cores (epaphe-frf 31-43 s, Siconos 19-27 s); the labels
`verification` and `long` (`./epaphe test --rest`).

    peer_beam_friction.py --run EPAPHE_RUN --frf EPAPHE_FRF --deck inputs/beam-friction.xml --workdir DIR
"""
import json
import os
import subprocess
import sys
import time

# One thread for Siconos' dense algebra; set before numpy loads OpenBLAS.
for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"

import h5py  # noqa: E402
import numpy as np  # noqa: E402

_here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, _here)
from epaphe_testing import parse_args, verdict  # noqa: E402

FREQS = [400000.0 / n for n in range(6480, 6359, -30)]
STEPS = 400  # Siconos' steps per drive period
MAX_PERIODS = 300  # Siconos' longest run per frequency
TOL_F = 2e-3  # peak frequency, relative (docstring)
TOL_A = 5e-3  # peak amplitude, relative (docstring)
LOAD = "Bodies->Beam->Loads->Drive"


def peak(freqs, amps):
    """(frequency, amplitude) of the vertex of the parabola through the largest sample and its two
    neighbours; None when the largest is at an end of the grid."""
    i = int(np.argmax(amps))
    if i == 0 or i == len(amps) - 1:
        return None
    f, a = np.asarray(freqs[i - 1 : i + 2]), np.asarray(amps[i - 1 : i + 2])
    c = np.polyfit(f - f[1], a, 2)
    x = -c[1] / (2 * c[0])
    return f[1] + x, float(np.polyval(c, x))


def siconos(rom, deck, workdir):
    """Two processes, each a stepped sine over half of FREQS (the first ascending, the second
    descending, each from the static start); the results in FREQS' order and the wall time."""
    script = os.path.join(_here, "peer_siconos_beam_friction.py")
    half = (len(FREQS) + 1) // 2
    parts = [FREQS[:half], FREQS[half:][::-1]]
    t0 = time.perf_counter()
    procs = [
        subprocess.Popen(
            [sys.executable, script, rom, deck, str(STEPS), str(MAX_PERIODS), ",".join(repr(f) for f in p)],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            cwd=workdir,
        )
        for p in parts
    ]
    rows = []
    for p in procs:
        out, err = p.communicate(timeout=1800)
        if p.returncode != 0:
            sys.stderr.write(err[-3000:])
            raise SystemExit(f"Siconos failed ({p.returncode})")
        rows += json.loads(out.strip().splitlines()[-1])
    rows.sort(key=lambda r: r["frequency"])
    return rows, time.perf_counter() - t0


def main():
    a = parse_args("--frf")
    failures = []
    out = os.path.join(a.workdir, "epaphe")
    cmd = [sys.executable, a.frf, a.deck, "--load", LOAD, "--frequencies", ",".join(repr(f) for f in FREQS)]
    cmd += ["--jobs", "2", "--out", out, "--run", os.path.abspath(a.run)]
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=3600)
    t_epaphe = time.perf_counter() - t0
    print(p.stdout)
    if p.returncode != 0:
        sys.stderr.write(p.stderr[-3000:])
        raise SystemExit(f"epaphe-frf failed ({p.returncode})")
    with h5py.File(os.path.join(out, "frf.h5"), "r") as f:
        g = f["response/0"]
        ea, ep, steady = g["harmonic_amplitude"][:, 1], g["harmonic_phase"][:, 1], g["steady"][()]
    rom = os.path.join(out, "runs", "a0-f0.Beam.rom.h5")  # the reduced model Epaphe ran on
    rows, t_siconos = siconos(rom, a.deck, a.workdir)
    sa = np.array([r["amplitude"] for r in rows])
    print(
        f"{'frequency Hz':>13} | {'Epaphe |a1| m':>13} {'phase':>8} | {'Siconos |a1| m':>14} {'phase':>8} "
        f"{'periods':>7} {'criterion':>9} | {'ratio':>7}"
    )
    for j, nu in enumerate(FREQS):
        r = rows[j]
        print(
            f"{nu:13.4f} | {ea[j]:13.6e} {ep[j]:+8.4f} | {sa[j]:14.6e} {r['phase']:+8.4f} {r['periods']:7d} "
            f"{r['criterion']:9.1e} | {ea[j] / sa[j]:7.4f}"
        )
        if not steady[j]:
            failures.append(f"Epaphe at {nu:.4f} Hz: not steady after 400 periods")
        if not (r["steady"] or r["criterion"] < 1e-3):
            failures.append(f"Siconos at {nu:.4f} Hz: changing by {r['criterion']:.1e} a period after {r['periods']}")
    pe, ps = peak(FREQS, ea), peak(FREQS, sa)
    if pe is None or ps is None:
        failures.append(f"a peak at an end of the grid {FREQS[0]:.3f}-{FREQS[-1]:.3f} Hz (Epaphe {pe}, Siconos {ps})")
        return verdict(failures)
    df, da = pe[0] / ps[0] - 1, pe[1] / ps[1] - 1
    print(
        f"\npeak: Epaphe {pe[0]:.4f} Hz, {pe[1]:.5e} m; Siconos {ps[0]:.4f} Hz, {ps[1]:.5e} m; "
        f"frequency {df:+.2e} (tolerance {TOL_F:g}), amplitude {da:+.2e} (tolerance {TOL_A:g})"
    )
    print(
        f"wall time: epaphe-frf {t_epaphe:.1f} s ({len(FREQS)} runs, 2 at a time), Siconos {t_siconos:.1f} s "
        f"(2 processes)"
    )
    if abs(df) > TOL_F:
        failures.append(f"peak frequency: Epaphe {pe[0]:.4f} Hz, Siconos {ps[0]:.4f} Hz: {df:+.2e} beyond {TOL_F:g}")
    if abs(da) > TOL_A:
        failures.append(
            f"peak amplitude: Epaphe {pe[1]:.5e} m over Siconos {ps[1]:.5e} m - 1 = {da:+.2e}, beyond {TOL_A:g}"
        )
    return verdict(failures)


if __name__ == "__main__":
    sys.exit(main())
