#!/usr/bin/env python3
"""V7: the massless-boundary blade (inputs/rotor37-massless.xml) against a converged Craig-Bampton run.

Scene: the rotor 37 casing law on the parametric blade, 1344 rad/s, 3 revolutions, frictionless
Lagrange contact, no damping (so that both models carry the same physics: modal damping means
different things on the two bases; mass-proportional Rayleigh damping, alpha = 43 /s, 0.5 % on the
first mode, is the same on both). Reference: Craig-Bampton with 100 fixed-interface modes at
h = 1e-7 s (its massive tip nodes need h <= 4.1e-7 s; with 40 modes it is 1.4 % away from it). Measure: the largest difference of the
watched tip displacements (leading and trailing edge, 3 components), the massless run interpolated
onto the reference's records, relative to the reference's largest tip displacement.

Asserted (stated tolerances):
  - the massless model's critical step is at least 10 times the Craig-Bampton model's;
  - at the reference's step the error falls from 30 to 60 modes, and 60 modes are within 1 % of the
    reference (the two reductions converge to the same full model);
  - 20 modes at 1000, 4000 and 20,000 steps per revolution (h = 4.675e-6, 1.16875e-6, 2.3375e-7 s):
    the error falls as h falls (forward-increment contact, first order) and is below 15 % at 1000;
  - every run's energy balance within 1e-9;
  - the reduction and run on 2 MPI ranks (Tpetra maps, MUMPS, Anasazi distributed; cache off) give the
    1-rank tip history to 1e-9 of its peak (1 revolution at 1000 steps per revolution).
The figures (errors, steps per second) are printed."""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from epaphe_testing import history, parse_args, run, variant, verdict  # noqa: E402

a = parse_args("--mpiexec")
base = {"Run->Progress interval": ("0", "double"), "Time->End revolutions": ("3", "double"),
        "Contact->Friction coefficient": ("0", "double"), "Time->Damping->Type": ("Rayleigh", "string"),
        "Time->Damping->Alpha": ("43", "double")}


def simulate(name, overrides, launcher=()):
    deck = variant(a.deck, os.path.join(a.workdir, name + ".xml"),
                   dict(base, **overrides, **{"Output->File": (name + ".h5", "string"),
                                              "Bodies->Blade->Reduction->Cache file": (name + ".rom.h5", "string")}))
    run([*launcher, a.run, deck], a.workdir)
    h = history(os.path.join(a.workdir, name + ".h5"))
    u = np.concatenate([h[f"bodies/Blade/nodesets/{s}/displacement"].reshape(len(h["time"]), -1)
                        for s in ("tip-le", "tip-te")], axis=1)
    return h, u


failures = []
ref, uref = simulate("craig-bampton-100", {"Bodies->Blade->Reduction->Method": ("Craig-Bampton", "string"),
                                           "Bodies->Blade->Reduction->Fixed-interface modes": ("100", "int"),
                                          "Time->Time step": ("1e-7", "double"), "Output->Every": ("47", "int")})
tref = ref["time"]
peak = np.abs(uref).max()
print(f"reference: Craig-Bampton, 100 modes, h = 1e-7 s, critical step {ref['attrs']['critical_time_step']:.3g} s, "
      f"{ref['attrs']['steps_per_second']:.0f} steps/s; largest tip displacement {peak * 1e6:.1f} um")


def error(h, u):
    t = h["time"]
    keep = tref <= t[-1]
    ui = np.stack([np.interp(tref[keep], t, u[:, k]) for k in range(u.shape[1])], axis=1)
    return np.abs(ui - uref[keep]).max() / peak


def check_balance(name, h):
    e = np.abs(h["energy/balance_error"]).max()
    if not e <= 1e-9:
        failures.append(f"{name}: energy balance error {e:.3g} > 1e-9")


check_balance("reference", ref)
runs = {}
for modes, step, every in ((30, 1e-7, 47), (60, 1e-7, 47), (20, 4.675e-6, 1), (20, 1.16875e-6, 4),
                           (20, 2.3375e-7, 20)):
    name = f"massless-{modes}-h{step:.6g}"
    h, u = simulate(name, {"Bodies->Blade->Reduction->Fixed-interface modes": (str(modes), "int"),
                           "Time->Time step": (f"{step:.17g}", "double"), "Output->Every": (str(every), "int")})
    check_balance(name, h)
    runs[(modes, step)] = err = error(h, u)
    steps_per_rev = 2 * np.pi / 1344 / step
    print(f"massless boundary, {modes} modes, h = {step:.6g} s ({steps_per_rev:.0f} steps/rev): error {err * 100:.3g} % "
          f"of the peak ({err * peak * 1e6:.1f} um), critical step {h['attrs']['critical_time_step']:.3g} s, "
          f"{h['attrs']['steps_per_second']:.0f} steps/s, loop {h['attrs']['loop_time']:.3g} s")
    if modes == 20 and step == 4.675e-6:
        ratio = h["attrs"]["critical_time_step"] / ref["attrs"]["critical_time_step"]
        print(f"critical step: massless {ratio:.1f} times the Craig-Bampton model's")
        if not ratio >= 10:
            failures.append(f"massless critical step only {ratio:.3g} times Craig-Bampton's (expected >= 10)")

if not runs[(60, 1e-7)] < runs[(30, 1e-7)]:
    failures.append(f"h = 1e-7 s: the error does not fall from 30 to 60 modes: {runs[(30, 1e-7)]:.3g} -> "
                    f"{runs[(60, 1e-7)]:.3g}")
if not runs[(60, 1e-7)] <= 0.01:
    failures.append(f"60 modes at h = 1e-7 s: error {runs[(60, 1e-7)]:.3g} of the peak > 1 %")
e20 = [runs[(20, s)] for s in (4.675e-6, 1.16875e-6, 2.3375e-7)]
if not e20[0] > e20[1] > e20[2]:
    failures.append(f"20 modes: the error does not fall with h: {[f'{e:.3g}' for e in e20]}")
if not e20[0] <= 0.15:
    failures.append(f"20 modes at 1000 steps per revolution: error {e20[0]:.3g} of the peak > 15 %")
mpi = {"Time->End revolutions": ("1", "double"), "Bodies->Blade->Reduction->Cache": ("false", "bool")}
_, u1 = simulate("ranks-1", mpi)
_, u2 = simulate("ranks-2", mpi, launcher=(a.mpiexec, "-n", "2"))
d = np.abs(u2 - u1).max() / np.abs(u1).max()
print(f"2 MPI ranks against 1: largest tip difference {d:.3g} of the peak")
if not d <= 1e-9:
    failures.append(f"2 MPI ranks differ from 1 by {d:.3g} of the peak (> 1e-9)")
sys.exit(verdict(failures))
