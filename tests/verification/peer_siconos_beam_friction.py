#!/usr/bin/env python3
"""Siconos 4.4 (Debian python3-siconos) on the friction-damped cantilever of inputs/beam-friction.xml:
the steady forced response at given drive frequencies, for verification.siconos-beam-friction
(peer_beam_friction.py). Reports, never asserts.

The model is Epaphe's own, read from the reduced-model cache an Epaphe run of the deck wrote
(`<run>.Beam.rom.h5`: K, M, the recovery rows R of every node, the node sets, the coordinates), and
the rest from the deck:
  - LagrangianLinearTIDS(q, v, M) with K and the modal damping D = M V diag(2 xi omega_i) V^T M of the
    deck's 'Damping->Ratio' xi (V the M-orthonormal modes of (K, M): what Epaphe_Damping.cpp builds);
  - the loads by virtual work, f = sum_i R_i^T F over each load's node set (docs/theory/forced-response.md,
    eq. (66)): the Constant preload and the Harmonic drive F cos(2 pi nu t + phi);
  - per contact node touching the deck's plane at t = 0: a LagrangianLinearTIR y = H q + b with
    H = [n^T R_i; t1^T R_i; t2^T R_i] (normal, then the two tangents), b = [gap, 0, 0], and
    NewtonImpactFrictionNSL(e = 0, e_t = 0, mu, 3): Coulomb friction with the deck's coefficient;
  - MoreauJeanOSI(theta = 0.5) (the trapezoidal rule for the smooth part), FrictionContact(3) solved
    by Siconos' default solver (NSGS) to 1e-12, TimeStepping at h = 1 / (nu N), N steps per drive
    period. The force of a step is theta f(t_k+1) + (1 - theta) f(t_k), set before the step: what a
    time-dependent fExt gives Moreau-Jean.
The start is the deck's: the static equilibrium under the preload with the touching nodes stuck
(eq. (71), [K C^T; C 0] [q0; lambda] = [f(0); 0]), at rest; with `start` (q, v) another state (the
previous frequency's end: a stepped sine).
The response watched is Epaphe's 'Steady state' one, x = d . (mean displacement of the node set); its
first harmonic over each drive period, a_1 = (2/N) sum_s x_s exp(-i omega t_s) at the steps' ends t_s,
and the run is steady when a_1 repeats after p <= 4 periods, max_{j < p + W} |a_j - a_j+p| <= eps |a_0|
(eq. (70), W = 4, here eps = 1e-4), the harmonic reported the mean over the last p periods, its phase
relative to the drive's (arg a_1 - phi).

Run as a script: ROM DECK STEPS_PER_PERIOD MAX_PERIODS NU1,NU2,... prints one JSON line, a stepped sine
over the frequencies in order, each started from the previous one's end (the first from the static
equilibrium).
"""
import json
import math
import os
import sys
import time

import numpy as np

_here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, _here)
from epaphe_testing import deck_value  # noqa: E402

EPS, WINDOW, LONGEST = 1e-4, 4, 4


def loads_of(deck, body):
    """{name: (node set, force, time function, frequency, phase)} of the body's Loads."""
    import xml.etree.ElementTree as ET

    root = ET.parse(deck).getroot()
    out = {}
    for b in root.iter("ParameterList"):
        if b.get("name") != body:
            continue
        for loads in b.findall("ParameterList"):
            if loads.get("name") != "Loads":
                continue
            for load in loads.findall("ParameterList"):
                p = {e.get("name"): e.get("value") for e in load.findall("Parameter")}
                force = [float(v) for v in p["Force"].strip("{}").split(",")]
                out[load.get("name")] = (
                    p["Node set"],
                    np.array(force),
                    p.get("Time function", "Constant"),
                    float(p.get("Frequency", "0")),
                    float(p.get("Phase", "0")),
                )
    return out


def beam_model(rom_file, deck, body="Beam", drive="Drive"):
    """The cantilever of `deck` on Epaphe's reduced model `rom_file`: matrices, load vectors, the contact
    rows, the watched row and the static start (see the module's docstring)."""
    import h5py

    with h5py.File(rom_file, "r") as f:
        K, M, R, X = (f[k][()] for k in ("K", "M", "recovery", "coordinates"))
        sets = {k: f["nodeSets/" + k][()] for k in f["nodeSets"]}
    K, M = 0.5 * (K + K.T), 0.5 * (M + M.T)
    n = K.shape[0]
    xi = float(deck_value(deck, "Time->Damping->Ratio"))
    assert deck_value(deck, "Time->Damping->Type") == "Modal", "the peer builds modal damping only"
    L = np.linalg.cholesky(M)
    Li = np.linalg.inv(L)
    w2, Y = np.linalg.eigh(Li @ K @ Li.T)
    V = Li.T @ Y  # M-orthonormal modes
    MV = M @ V
    D = MV @ np.diag(2 * xi * np.sqrt(np.maximum(w2, 0.0))) @ MV.T

    def rows(i):
        return R[3 * i : 3 * i + 3]

    f_const, f_drive, nu0, phi = np.zeros(n), None, None, 0.0
    for name, (nset, F, g, nu, ph) in loads_of(deck, body).items():
        f = sum(rows(i).T @ F for i in sets[nset])  # eq. (66)
        if name == drive:
            assert g == "Harmonic", f"load {name}: Harmonic expected, {g}"
            f_drive, nu0, phi = f, nu, ph
        else:
            assert g == "Constant", f"load {name}: the peer takes Constant preloads, not {g}"
            f_const += f
    watched = str(deck_value(deck, "Steady state->Node set"))
    d = np.array([float(v) for v in deck_value(deck, "Steady state->Direction")])
    watch = sum(d @ rows(i) for i in sets[watched]) / len(sets[watched])
    # the plane: origin, normal U x V, tangents U / |U| and n x t1
    o = np.array(deck_value(deck, "Surfaces->Support->Origin"), dtype=float)
    U = np.array(deck_value(deck, "Surfaces->Support->U"), dtype=float)
    Vs = np.array(deck_value(deck, "Surfaces->Support->V"), dtype=float)
    nrm = np.cross(U, Vs)
    nrm /= np.linalg.norm(nrm)
    t1 = U / np.linalg.norm(U)
    t2 = np.cross(nrm, t1)
    contact = str(deck_value(deck, f"Bodies->{body}->Contact node set"))
    touching = [i for i in sets[contact] if abs((X[i] - o) @ nrm) < 1e-9]
    H = [np.vstack([nrm @ rows(i), t1 @ rows(i), t2 @ rows(i)]) for i in touching]
    gaps = [(X[i] - o) @ nrm for i in touching]
    # eq. (71): the touching nodes stuck, the loads at t = 0
    C = np.vstack([rows(i) for i in touching])
    m = C.shape[0]
    A = np.block([[K, C.T], [C, np.zeros((m, m))]])
    f0 = f_const + math.cos(phi) * f_drive
    q0 = np.linalg.solve(A, np.concatenate([f0, np.zeros(m)]))[:n]
    mu = float(deck_value(deck, "Contact->Friction coefficient"))
    return dict(
        K=K,
        M=M,
        D=D,
        f_const=f_const,
        f_drive=f_drive,
        phi=phi,
        nu0=nu0,
        watch=watch,
        H=H,
        gaps=gaps,
        q0=q0,
        mu=mu,
        n=n,
        touching=touching,
    )


def steady_response(model, nu, steps, max_periods, start=None):
    """The stepped-sine point at `nu` Hz: runs until the criterion of the module's docstring holds or
    `max_periods` drive periods; returns the mean first harmonic over the pattern (complex, relative to
    the drive's phase), the periods run, the pattern, whether steady, the criterion, the end state and
    the loop's wall time."""
    import siconos.kernel as sk

    n, h, om, phi = model["n"], 1.0 / (nu * steps), 2 * math.pi * nu, model["phi"]
    q0, v0 = (model["q0"], np.zeros(n)) if start is None else start
    beam = sk.LagrangianLinearTIDS(np.array(q0, dtype=float), np.array(v0, dtype=float), model["M"])
    beam.setKPtr(model["K"])
    beam.setCPtr(model["D"])
    beam.setFExtPtr(model["f_const"] + math.cos(phi) * model["f_drive"])
    nsds = sk.NonSmoothDynamicalSystem(0.0, max_periods / nu)
    nsds.insertDynamicalSystem(beam)
    for H, g in zip(model["H"], model["gaps"]):
        law = sk.NewtonImpactFrictionNSL(0.0, 0.0, model["mu"], 3)
        nsds.link(sk.Interaction(law, sk.LagrangianLinearTIR(H, np.array([g, 0.0, 0.0]))), beam)
    osi = sk.MoreauJeanOSI(0.5)
    fc = sk.FrictionContact(3)
    fc.numericsSolverOptions().iparam[0] = 1000
    fc.numericsSolverOptions().dparam[0] = 1e-12
    sim = sk.TimeStepping(nsds, sk.TimeDiscretisation(0.0, h), osi, fc)
    sim.initialize()
    t0 = time.perf_counter()
    watch, fc_, fd = model["watch"], model["f_const"], model["f_drive"]
    g_prev = math.cos(phi)
    rot = np.exp(-1j * om * h * np.arange(1, steps + 1))  # e^{-i omega t_s} over a period, t_s = (s+1) h
    a, x = [], np.empty(steps)
    steady, pattern, crit = False, 1, math.inf
    for period in range(max_periods):
        for s in range(steps):
            g = math.cos(om * h * (s + 1) + phi)
            beam.setFExtPtr(fc_ + (0.5 * (g + g_prev)) * fd)  # theta = 0.5
            g_prev = g
            sim.computeOneStep()
            x[s] = watch @ beam.q()
            sim.nextStep()
        a.insert(0, 2.0 / steps * (x @ rot))  # a_j, j periods before the last
        best = math.inf
        for p in range(1, LONGEST + 1):
            if len(a) < 2 * p + WINDOW:
                break
            c = max(abs(a[j] - a[j + p]) for j in range(p + WINDOW)) / abs(a[0])
            if c < best:
                best, pattern = c, p
        crit = best
        if crit <= EPS:
            steady = True
            break
    a1 = np.mean(a[:pattern]) * np.exp(-1j * phi)
    return dict(
        a1=a1,
        periods=len(a),
        pattern=pattern,
        steady=steady,
        criterion=crit,
        end=(np.array(beam.q()), np.array(beam.velocity())),
        loop_seconds=time.perf_counter() - t0,
    )


def stepped_sine(rom, deck, steps, max_periods, freqs):
    model = beam_model(rom, deck)
    out, start = [], None
    for nu in freqs:
        r = steady_response(model, nu, steps, max_periods, start)
        start = r.pop("end")
        a1 = r.pop("a1")
        out.append(dict(frequency=nu, amplitude=abs(a1), phase=float(np.angle(a1)), **r))
    return out


def main():
    rom, deck, steps, max_periods, freqs = sys.argv[1:6]
    res = stepped_sine(rom, deck, int(steps), int(max_periods), [float(v) for v in freqs.split(",")])
    print(json.dumps(res))
    return 0


if __name__ == "__main__":
    sys.exit(main())
