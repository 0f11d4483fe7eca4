#!/usr/bin/env python3
"""Peer benchmark (reports, never asserts): Siconos 4.4 (Debian python3-siconos) on V1, the elastic
bar on a rigid wall (tests/verification/v1_bar_on_wall.py), to set beside Epaphe's own run.

V1: bar L = 0.2 m, S = 4e-4 m^2, E = 2e11 Pa, rho = 8000 kg/m^3 (c = 5000 m/s), moving at v0 = 100 m/s
towards a rigid wall U0 = 2 mm away, far end free, run to 2e-4 s. Exact: contact from t0 = U0/v0 =
2.0e-5 s to t1 = t0 + 2L/c = 1.0e-4 s, force plateau F = rho c S v0 = 1.6e6 N, rebound at v0.

Siconos model (one 1-D bar, axial displacement only, x towards the wall):
  - LagrangianLinearTIDS: 'elements' two-node linear elements, stiffness E S / le [[1, -1], [-1, 1]],
    consistent mass rho S le / 6 [[2, 1], [1, 2]] (default) or lumped rho S le / 2 I; no damping;
  - LagrangianLinearTIR on the wall-side node: gap y = U0 - u_N >= 0;
  - NewtonImpactNSL with restitution e = 0: the bar rebounds by its own elasticity, not by the law;
  - MoreauJeanOSI(theta), theta = 0.5 by default (theta = 1 damps: see the table);
  - LCP one-step problem, Siconos' default solver (Lemke), TimeDiscretisation + TimeStepping.

Measured as v1_bar_on_wall.measure does, with one record per step at the end of the step, t_k+1,
the force being the step's impulse over h (inter.lambda_(1) / h):
  start  = first record with force > 1e-6 F. Moreau-Jean activates the contact when the gap
           predicted at mid-step is closed; t0 is a multiple of h here, so the first impulse is
           that of the step [t0, t0 + h], recorded at t0 + h: the start error is h / t0 exactly.
  end    = last such record + h. The last impulse is in the step ending at 9.98e-5 s (100 and 200
           elements) or 9.99e-5 s (400): the contact releases up to 0.2 % early, and end, one step
           after that step's record, lands on t1 or up to h before it.
  force  = total impulse / (end - start). The total impulse is m (v0 + rebound): its error is that
           of the rebound halved, plus that of the measured duration.
  rebound = -(1^T M v) / m averaged over t > end + 5e-6 s, m = rho S L. Its error is the
           discretization's (1.03, 0.65, 0.41 % at 100, 200, 400 elements, c h / le = 0.5): it falls
           by about 1.6 per halving of le and h together. The restitution barely changes it (e = 1:
           0.98 % at 100 elements, but the force then chatters on every other step); theta = 1 adds
           the implicit Euler's damping (8 % at 100 elements).
The figures measured before (100 elements, h = 2e-7: end 0.20 %, force 0.51 %, rebound 1.03 %;
200, 1e-7: 0.20 %, 0.32 %, 0.65 %) are this model, consistent mass and theta = 0.5, measured with the
impulse recorded at the step's start t_k and the force taken as total impulse / (t1 - t0).
Wall time: setup = assembly of K, M and the Siconos objects plus TimeStepping.initialize();
loop = the time-stepping loop with the per-step recording (1-2 % of it). Siconos stores K, M and
the iteration matrix dense, so a step costs O(elements^2): 400 elements take about 7 s.
"""
import sys
import time

import numpy as np

# siconos.kernel (about 0.1 s to load) is imported by siconos_bar() when it first runs, so that importing
# this module (peer_bar.py does, for siconos_bar) runs nothing and needs no Siconos.

L, S, E, RHO = 0.2, 4e-4, 2e11, 8000.0
V0, U0, T_END = 100.0, 2e-3, 2e-4
C = np.sqrt(E / RHO)
T0, T1, F = U0 / V0, U0 / V0 + 2 * L / C, RHO * C * S * V0
RESTITUTION = 0.0


def bar_matrices(elements, mass, length=L, area=S, young=E, rho=RHO):
    """Stiffness and mass matrices (dense) of the bar of 'elements' linear elements (V1's bar unless
    given)."""
    le = length / elements
    ke = young * area / le * np.array([[1.0, -1.0], [-1.0, 1.0]])
    if mass == "consistent":
        me = rho * area * le / 6 * np.array([[2.0, 1.0], [1.0, 2.0]])
    elif mass == "lumped":
        me = rho * area * le / 2 * np.eye(2)
    else:
        raise ValueError(f"mass must be 'consistent' or 'lumped', not {mass!r}")
    K = np.zeros((elements + 1, elements + 1))
    M = np.zeros_like(K)
    for i in range(elements):
        K[i : i + 2, i : i + 2] += ke
        M[i : i + 2, i : i + 2] += me
    return K, M


def siconos_bar(elements, h, theta=0.5, mass="consistent"):
    """Runs V1 in Siconos; returns the measured start, end, plateau, rebound, their relative errors
    (errs: start, end, force, rebound) and the setup and loop wall times in seconds."""
    import siconos.kernel as sk  # once per process; outside the timed setup

    t = time.perf_counter()
    K, M = bar_matrices(elements, mass)
    n = elements + 1
    bar = sk.LagrangianLinearTIDS(np.zeros(n), np.full(n, V0), M)
    bar.setKPtr(K)
    H = np.zeros((1, n))
    H[0, -1] = -1.0  # y = H q + b = U0 - u_N
    wall = sk.Interaction(sk.NewtonImpactNSL(RESTITUTION), sk.LagrangianLinearTIR(H, np.array([U0])))
    nsds = sk.NonSmoothDynamicalSystem(0.0, T_END)
    nsds.insertDynamicalSystem(bar)
    nsds.link(wall, bar)
    sim = sk.TimeStepping(nsds, sk.TimeDiscretisation(0.0, h), sk.MoreauJeanOSI(theta), sk.LCP())
    sim.initialize()
    setup = time.perf_counter() - t

    row_mass = M.sum(axis=0)  # 1^T M: momentum = row_mass . v
    times, impulse, momentum = [], [], []
    t = time.perf_counter()
    while sim.hasNextEvent():
        sim.computeOneStep()
        times.append(sim.nextTime())  # the record is the state at the step's end
        impulse.append(wall.lambda_(1)[0])  # the contact impulse over the step, N s
        momentum.append(row_mass @ bar.velocity())
        sim.nextStep()
    loop = time.perf_counter() - t

    times, impulse, momentum = np.array(times), np.array(impulse), np.array(momentum)
    on = np.nonzero(impulse / h > 1e-6 * F)[0]
    if on.size == 0:
        raise RuntimeError(f"no contact with {elements} elements, h = {h:g}")
    start = times[on[0]]
    end = times[on[-1]] + h  # first record without force
    plateau = impulse.sum() / (end - start)
    rebound = -momentum[times > end + 5e-6].mean() / (RHO * S * L)
    errs = {
        "start": abs(start - T0) / T0,
        "end": abs(end - T1) / T1,
        "force": abs(plateau - F) / F,
        "rebound": abs(rebound - V0) / V0,
    }
    return dict(
        start=start, end=end, plateau=plateau, rebound=rebound, errs=errs, setup_seconds=setup, loop_seconds=loop
    )


# (elements, h, theta, mass): the model at three resolutions (Courant number c h / le = 0.5),
# then the lumped mass and theta = 1 at the two coarser ones.
ROWS = [
    (100, 2e-7, 0.5, "consistent"),
    (200, 1e-7, 0.5, "consistent"),
    (400, 5e-8, 0.5, "consistent"),
    (100, 2e-7, 0.5, "lumped"),
    (200, 1e-7, 0.5, "lumped"),
    (100, 2e-7, 1.0, "consistent"),
    (200, 1e-7, 1.0, "consistent"),
]


def main():
    if len(sys.argv) == 3:  # one row in this fresh process, as JSON (peer_bar.py times the whole process)
        import json

        r = siconos_bar(int(sys.argv[1]), float(sys.argv[2]))
        print(json.dumps(dict(errs=r["errs"], setup_seconds=r["setup_seconds"], loop_seconds=r["loop_seconds"])))
        return 0
    print(
        "V1 bar on a rigid wall, Siconos 4.4 (Moreau-Jean, LCP Lemke, e = 0): exact start 2.0e-5 s, "
        "end 1.0e-4 s, plateau 1.6e6 N, rebound 100 m/s"
    )
    print(
        f"{'elements':>8} {'h':>6} {'theta':>5} {'mass':>10} | {'start':>6} {'end':>6} {'force':>6} "
        f"{'rebound':>7} | {'setup s':>7} {'loop s':>7}"
    )
    for elements, h, theta, mass in ROWS:
        r = siconos_bar(elements, h, theta=theta, mass=mass)
        e = r["errs"]
        print(
            f"{elements:8d} {h:6.0e} {theta:5.1f} {mass:>10} | {e['start']:6.2%} {e['end']:6.2%} "
            f"{e['force']:6.2%} {e['rebound']:7.2%} | {r['setup_seconds']:7.3f} {r['loop_seconds']:7.3f}",
            flush=True,
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
