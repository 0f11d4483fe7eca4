#!/usr/bin/env python3
"""Siconos 4.4 (Debian python3-siconos) on V3, the bouncing bar of Doyen, Ern & Piperno (SIAM J. Sci.
Comput. 33 (2011) 223-249, Section 3; tests/verification/v3_bouncing_bar.py), for the peer benchmark
peer_bouncing_bar.py. Reports, never asserts.

V3: bar L = 10 m, A = 1 m^2, E = 900 Pa, rho = 1 kg/m^3 (c = 30 m/s), under gravity g = 10 m/s^2,
dropped from rest with its lower end h0 = 5 m above a rigid plane. Exact: periodic with period 16/3 s,
two contacts of 2L/c = 2/3 s each per period, energy conserved.

Siconos model (one 1-D bar, axial displacement u only, x upwards from the lower end):
  - LagrangianLinearTIDS: 'elements' two-node linear elements, stiffness E A / le [[1, -1], [-1, 1]],
    consistent mass rho A le / 6 [[2, 1], [1, 2]] (or lumped rho A le / 2 I), gravity as the constant
    external force F = -g M 1;
  - LagrangianLinearTIR on the lower node: gap y = h0 + u_0 >= 0;
  - NewtonImpactNSL with restitution e = 0, MoreauJeanOSI(theta = 0.5), LCP (Lemke), TimeStepping.
Recorded every step, at the step's end: the contact impulse (lambda(1)) and the energy
E = v^T M v / 2 + u^T K u / 2 - F^T u (kinetic, strain, gravity's potential).

Wall time: setup = assembly and TimeStepping.initialize(); loop = the stepping loop with its per-step
recording (the energy's two dense products are part of it, as Epaphe's energy records are of its
loop). Run as a script with ELEMENTS H PERIODS it prints one JSON line (peer_bouncing_bar.py times the
whole process).
"""
import json
import sys
import time

import numpy as np

from peer_siconos_bar import bar_matrices  # numpy only: Siconos is imported when a run starts

L, A, E, RHO, G, H0 = 10.0, 1.0, 900.0, 1.0, 10.0, 5.0
C = np.sqrt(E / RHO)
PERIOD = 16.0 / 3.0


def siconos_bouncing_bar(elements, h, periods=10, theta=0.5, mass="consistent"):
    """Runs V3 in Siconos; returns times, the contact force (impulse / h) and the energy per step,
    with the setup and loop wall times in seconds."""
    import siconos.kernel as sk  # once per process; outside the timed setup

    t = time.perf_counter()
    K, M = bar_matrices(elements, mass, length=L, area=A, young=E, rho=RHO)
    n = elements + 1
    bar = sk.LagrangianLinearTIDS(np.zeros(n), np.zeros(n), M)
    bar.setKPtr(K)
    f = -G * M.sum(axis=1)  # gravity: -g M 1
    bar.setFExtPtr(f)
    H = np.zeros((1, n))
    H[0, 0] = 1.0  # y = u_0 + h0
    ground = sk.Interaction(sk.NewtonImpactNSL(0.0), sk.LagrangianLinearTIR(H, np.array([H0])))
    nsds = sk.NonSmoothDynamicalSystem(0.0, periods * PERIOD)
    nsds.insertDynamicalSystem(bar)
    nsds.link(ground, bar)
    sim = sk.TimeStepping(nsds, sk.TimeDiscretisation(0.0, h), sk.MoreauJeanOSI(theta), sk.LCP())
    sim.initialize()
    setup = time.perf_counter() - t

    times, impulse, energy = [], [], []
    t = time.perf_counter()
    while sim.hasNextEvent():
        sim.computeOneStep()
        q, v = bar.q(), bar.velocity()
        times.append(sim.nextTime())
        impulse.append(ground.lambda_(1)[0])
        energy.append(0.5 * v @ (M @ v) + 0.5 * q @ (K @ q) - f @ q)
        sim.nextStep()
    loop = time.perf_counter() - t
    return dict(
        time=np.array(times),
        force=np.array(impulse) / h,
        energy=np.array(energy),
        setup_seconds=setup,
        loop_seconds=loop,
    )


def main():
    elements, h, periods = int(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3])
    r = siconos_bouncing_bar(elements, h, periods)
    print(
        json.dumps(
            dict(
                time=r["time"].tolist(),
                force=r["force"].tolist(),
                energy=r["energy"].tolist(),
                setup_seconds=r["setup_seconds"],
                loop_seconds=r["loop_seconds"],
            )
        )
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
