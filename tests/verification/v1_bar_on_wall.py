#!/usr/bin/env python3
"""V1 (docs/verification.md): elastic bar on a rigid wall, the setting of code_aster's SDNV100.

Exact 1-D solution: contact from t0 = U0/v0 = 2.0e-5 s to t1 = t0 + 2L/c = 1.0e-4 s, force plateau
F = rho c S v0 = 1.6e6 N, contact-face velocity zero during contact, rebound at v0 = 100 m/s.

Checked here, for the Lagrange and the penalty method:
  contact start and end within 1 % of t0 and t1, mean plateau force (impulse / measured duration)
  within 2 % of F, rebound velocity (linear momentum / rigid mass after release) within 2 % of v0;
and that the error falls when fixed-interface modes are added (against the exact solution) and when
h shrinks (against the same model at a 16x smaller step: the time-discretization error alone).
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from epaphe_testing import history, parse_args, run, variant, verdict  # noqa: E402

T0, T1, F, V0 = 2.0e-5, 1.0e-4, 1.6e6, 100.0
TOL_TIME, TOL_FORCE, TOL_VEL = 0.01, 0.02, 0.02
# Penalty stiffness per contact node. The bar face (4 nodes) carries 1.6 MN: 4e5 N per node, so
# kp = 1e10 N/m lets the face penetrate 40 um (0.2 % of the 2 mm gap), and its spring stays below
# the stable-step limit at h = 1e-7 s (Epaphe checks that before running).
KP = 1e10
ORDER2_RATIO = 3.5  # least error ratio per halving of h for second order (4 in the limit; first order: 2)


def measure(path):
    h = history(path)
    t = h["time"]
    dt = t[1] - t[0]
    f = h["bodies/Bar/contact/total_force"]
    # Contact is where the force is physical: above 1e-6 of the plateau. When a node reaches the wall
    # exactly at a step (t0 is a multiple of h here), round-off alone can give a force of 1e-4 N
    # one step early, whose sign depends on the last bits of the reduced model.
    on = np.nonzero(f > 1e-6 * F)[0]
    assert on.size > 0, f"{path}: no contact at all"
    start = t[on[0]]
    end = t[on[-1]] + dt  # first record without force
    impulse = f.sum() * dt
    plateau = impulse / (end - start)
    m = h["bodies/Bar/attrs"]["rigid_mass"]
    p = h["bodies/Bar/momentum"][:, 0]
    after = t > end + 5e-6
    rebound = -p[after].mean() / m
    face_v = h["bodies/Bar/nodesets/x+/velocity"][:, :, 0].mean(axis=1)
    during = (t > start + 2e-6) & (t < end - 2e-6)
    face_mean = face_v[during].mean()
    balance = np.abs(h["energy/balance_error"]).max()
    sps = h["attrs"]["steps_per_second"]
    errs = {
        "start": abs(start - T0) / T0,
        "end": abs(end - T1) / T1,
        "force": abs(plateau - F) / F,
        "rebound": abs(rebound - V0) / V0,
    }
    return dict(
        start=start,
        end=end,
        plateau=plateau,
        rebound=rebound,
        face=face_mean,
        balance=balance,
        sps=sps,
        errs=errs,
        total=sum(errs.values()),
    )


def report(label, m):
    e = m["errs"]
    print(
        f"{label:34s} start {m['start']:.4e} ({e['start']:.2%})  end {m['end']:.4e} ({e['end']:.2%})  "
        f"plateau {m['plateau']:.4e} N ({e['force']:.2%})  rebound {m['rebound']:.3f} m/s ({e['rebound']:.2%})  "
        f"face v {m['face']:+.3f} m/s  balance {m['balance']:.1e}  {m['sps']:.0f} steps/s"
    )


def main():
    a = parse_args()
    failures = []

    def case(name, overrides):
        deck = variant(
            a.deck,
            os.path.join(a.workdir, name + ".xml"),
            dict({"Output->File": name + ".h5", "Run->Progress interval": ("0", "double")}, **overrides),
        )
        run([a.run, deck, "--threads", "2"], a.workdir)
        return measure(os.path.join(a.workdir, name + ".h5"))

    def check(label, m):
        report(label, m)
        e = m["errs"]
        for key, tol in (("start", TOL_TIME), ("end", TOL_TIME), ("force", TOL_FORCE), ("rebound", TOL_VEL)):
            if not e[key] <= tol:
                failures.append(f"{label}: {key} error {e[key]:.3%} > {tol:.0%}")
        if not abs(m["face"]) <= 0.02 * V0:
            failures.append(f"{label}: contact-face mean velocity {m['face']:.3f} m/s during contact, expected ~0")

    print("V1 bar on a rigid wall: exact start 2.0e-5 s, end 1.0e-4 s, plateau 1.6e6 N, rebound 100 m/s")
    check("Lagrange, CB 100 modes, h=1e-7", case("lagrange", {}))
    check(
        f"Penalty kp={KP:g}, CB 100 modes, h=1e-7",
        case("penalty", {"Contact->Method": "Penalty", "Contact->Penalty stiffness": (f"{KP:g}", "double")}),
    )

    # The massless boundary on the free bar: its 6 rigid-body modes with the 100 lowest elastic ones,
    # the static part the inertia-relief residual flexibility, at h = 4e-7 s (its stable step is the
    # last kept mode's, 2.2e-6 s; Craig-Bampton's massive face needs 1e-7). The initial velocity, a
    # rigid translation, is exact in those modes: the log's lost kinetic energy is round-off (1e-9 %
    # stated), and in free flight before the impact the momentum is m v0 and the contact face moves
    # at v0 (1e-9). Then V1's tolerances.
    def massless(name, h):
        deck = variant(
            a.deck,
            os.path.join(a.workdir, name + ".xml"),
            {
                "Output->File": name + ".h5",
                "Run->Progress interval": ("0", "double"),
                "Bodies->Bar->Reduction->Method": "Massless boundary",
                "Time->Time step": (f"{h:g}", "double"),
                "Bodies->Bar->Reduction->Fixed-interface modes": ("100", "int"),
            },
        )
        return run([a.run, deck, "--threads", "2"], a.workdir).stdout, history(os.path.join(a.workdir, name + ".h5"))

    log, hm = massless("massless", 4e-7)
    lost = [l for l in log.splitlines() if "initial velocity projected onto the 106 modes" in l]
    if len(lost) != 1:
        failures.append("massless boundary: no line 'initial velocity projected onto the 106 modes' in the log")
    else:
        pct = float(lost[0].split("(")[-1].split("%")[0])
        print("massless boundary:", lost[0].strip())
        if not abs(pct) <= 1e-9:
            failures.append(f"massless boundary: the initial velocity lost {pct} % of its kinetic energy, expected 0")
    before = hm["time"] < T0 - 4e-7
    mass = hm["bodies/Bar/attrs"]["rigid_mass"]
    p_err = np.abs(hm["bodies/Bar/momentum"][before, 0] - mass * V0).max() / (mass * V0)
    v_err = np.abs(hm["bodies/Bar/nodesets/x+/velocity"][before, :, 0] - V0).max() / V0
    print(f"massless boundary, free flight: momentum error {p_err:.1e}, contact-face velocity error {v_err:.1e}")
    if not (p_err <= 1e-9 and v_err <= 1e-9):
        failures.append(
            f"massless boundary free flight: momentum error {p_err:.2e}, face velocity error {v_err:.2e} "
            "(> 1e-9): the initial velocity is not the rigid translation"
        )
    check("Lagrange, massless 100 modes, h=4e-7", measure(os.path.join(a.workdir, "massless.h5")))

    # Energy: the massless boundary's residual is driven by the average of the forces at t_n-1 and
    # t_n+1 (Epaphe_CentralDifference.cpp), which conserves the energy through a lasting contact; only
    # the steps where the contact starts and ends err, by O(h). At h = 1e-7 s the energy after the
    # rebound is the initial 3200 J to 1e-4 (measured 1.2e-5; a residual driven by f_n alone lost
    # 71 J here, 2.2 %; Craig-Bampton loses 59 J, its face's kinetic energy at impact).
    _, hm = massless("massless-h1e-7", 1e-7)
    e0, e1 = hm["energy/total"][0], hm["energy/total"][-1]
    print(
        f"massless boundary, h = 1e-7 s: energy {e0:.3f} J at the start, {e1:.3f} J after the rebound "
        f"({(e1 - e0) / e0:+.1e})"
    )
    if not abs(e1 - e0) <= 1e-4 * e0:
        failures.append(f"massless boundary: energy {e0:.3f} J -> {e1:.3f} J, off by more than 1e-4")

    # Convergence in the number of fixed-interface modes (h = 5e-8 s), towards the full model.
    modes = [10, 40, 100]
    totals = []
    for nm in modes:
        m = case(
            f"modes{nm}",
            {"Bodies->Bar->Reduction->Fixed-interface modes": (str(nm), "int"), "Time->Time step": ("5e-8", "double")},
        )
        report(f"Lagrange, CB {nm} modes, h=5e-8", m)
        totals.append(m["total"])
    full = case(
        "full",
        {
            "Bodies->Bar->Reduction->Method": "None",
            "Time->Time step": ("5e-8", "double"),
            "Time->End time": ("1.3e-4", "double"),
        },
    )
    report("Lagrange, full model, h=5e-8", full)
    print(
        "sum of relative errors vs modes:",
        ", ".join(f"{n}: {t:.4f}" for n, t in zip(modes, totals)),
        f", full: {full['total']:.4f}",
    )
    if not all(totals[i + 1] < totals[i] for i in range(len(totals) - 1)):
        failures.append(f"error does not fall as modes are added: {totals}")

    # Convergence in the time step (CB 100 modes). Against the exact solution the error here is the
    # model's (modes, mesh), not the time step's; so the time discretization is measured against
    # the same model run with a 16x smaller step: the largest difference of the free-end
    # displacement over the run, at the instants the runs share. Central difference is second
    # order for the smooth motion between contact events. The events cost no order here: the impact
    # instant t0 = U0 / v0 = 2e-5 s is a multiple of every step tested (50, 100, 200 and 800 steps),
    # so the velocity jump falls on the time grid (an impact between two steps would shift the
    # motion by O(h) and make the displacement first order); the release needs no event location,
    # as the Lagrange force falls continuously to zero, so missing it by less than a step changes
    # the impulse by O(h^2). The difference must therefore fall by about 4 per halving: asserted at
    # least ORDER2_RATIO = 3.5 (2^1.8), which first order (2) cannot reach.
    steps = [4e-7, 2e-7, 1e-7]
    ref_h = 2.5e-8

    def free_end(h):
        name = f"h{h:g}"
        deck = variant(
            a.deck,
            os.path.join(a.workdir, name + ".xml"),
            {
                "Output->File": name + ".h5",
                "Time->Time step": (f"{h:g}", "double"),
                "Run->Progress interval": ("0", "double"),
            },
        )
        run([a.run, deck, "--threads", "1"], a.workdir)
        hist = history(os.path.join(a.workdir, name + ".h5"))
        return hist["time"], hist["bodies/Bar/nodesets/x-/displacement"][:, :, 0].mean(axis=1)

    t_ref, u_ref = free_end(ref_h)
    diffs = []
    for h in steps:
        t, u = free_end(h)
        stride, ref_stride = int(round(steps[0] / h)), int(round(steps[0] / ref_h))
        n = min(len(t[::stride]), len(t_ref[::ref_stride]))
        diffs.append(np.abs(u[::stride][:n] - u_ref[::ref_stride][:n]).max())
    print(
        "largest free-end displacement difference to h = 2.5e-8:",
        ", ".join(f"h={h:g}: {d:.3e} m" for h, d in zip(steps, diffs)),
        "; ratios",
        ", ".join(f"{diffs[i] / diffs[i + 1]:.2f}" for i in range(len(diffs) - 1)),
    )
    ratios = [diffs[i] / diffs[i + 1] for i in range(len(diffs) - 1)]
    if not all(r >= ORDER2_RATIO for r in ratios):
        failures.append(
            f"time-step error falls by {', '.join(f'{r:.2f}' for r in ratios)} per halving of h, "
            f"not the >= {ORDER2_RATIO} of a second-order method: {diffs}"
        )

    return verdict(failures)


if __name__ == "__main__":
    sys.exit(main())
