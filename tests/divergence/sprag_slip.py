#!/usr/bin/env python3
"""Sprag-slip of an inclined elastic strut (docs/theory/divergence.md, eqs. (50)-(51)).

A steel bar (L x w x w, 20 x 1 x 1 hexahedra, massless boundary) is clamped at x = 0; its tip corner
(L, 0, 0) presses, with an interference ramped in over 'Penetration ramp time', on a plane whose
outward normal makes the angle theta with the bar's axis, tilted along the section's diagonal e so
that that corner alone touches. The plane turns about its normal through a centre R away: at the
corner it moves along -s, s = sin(theta) a + cos(theta) e, so friction drives the tip back under the
clamp. The critical coefficient (51) from the beam's tip compliance with the corner's eccentricity
d = w / sqrt(2) (S_aa = L/EA + d^2 L/EI, S_bb = L^3/3EI, S_ab = d L^2/2EI):

    mu_c = S_nn / (s^T S n),   S_nn = S_aa cos^2 - 2 S_ab sin cos + S_bb sin^2,
                               s^T S n = (S_bb - S_aa) sin cos - S_ab cos(2 theta)

Checked, one thread:
  1. a short run at mu0 = 0.25: the run's least quasi-static margin m0 gives the model's own
     mu*_c = mu0 / (1 - m0) (eq. (50)); it is within TOL_MU of the beam's mu_c;
  2. at 0.95 mu*_c the run completes, its energy stays bounded (the largest kinetic + strain energy of
     the second half of the run at most GROWTH_BOUND times the first half's) and no node locks (least
     margin > 0);
  3. at 1.05 mu*_c the first lock is recorded with a margin of about -0.05, and the corner jams: its
     normal force grows about linearly with the plane's travel (a rate proportional to its speed,
     measured: twice at twice the speed), FORCE_RATIO times the steady force of 0.95 mu*_c and more
     by END_ABOVE, fed by the contact work (the energy equals it: on a plane that only slides past,
     the normal force of a closed gap does no work, so friction's does), and the same at h/2
     within STEP_TOL: a physical instability, whatever the step. The run does not stop (no guard
     fires on a jam that grows at the plane's speed), so the stop's diagnosis does not apply; the
     run's summary and /run attributes carry the lock.

    sprag_slip.py --run EPAPHE_RUN --workdir DIR"""
import argparse
import math
import os
import subprocess
import sys

import h5py
import numpy as np

L, W = 0.1, 0.01  # m
E, RHO = 2e11, 8000.0
THETA = math.radians(25.0)
DELTA = 2e-5  # m, interference
RADIUS, SPEED = 0.05, 1.0  # m, m/s: the plane's turning centre away from the corner, its speed there
H = 1e-6  # s
RAMP = 2e-3  # s
MU0 = 0.25
TOL_MU = 0.05  # the beam's mu_c against the model's (hexahedra in bending, the corner's local compliance)
GROWTH_BOUND = 3.0
END_ABOVE = 8e-3  # s: before the section's other corners reach the plane (about 10 ms)
FORCE_RATIO = 20.0  # the corner force at END_ABOVE against the steady one at 0.95 mu_c, at least
LINEAR = (1.7, 2.4)  # the force at END_ABOVE over that at END_ABOVE / 2: grows about linearly (the jam)
STEP_TOL = 1e-2  # the corner force at h/2 against h, relative to its peak
CORNER = 0  # the corner (L, 0, 0), the first node of the contact set x+


def force_at(workdir, name, t, after):
    with h5py.File(os.path.join(workdir, name + ".h5"), "r") as f:
        force, time = f["bodies/Strut/contact/force"][()][:, CORNER], f["time"][()]
    return force[time >= after].max()


def beam_mu_c():
    A, I = W * W, W**4 / 12
    d = W / math.sqrt(2)
    saa, sbb, sab = L / (E * A) + d * d * L / (E * I), L**3 / (3 * E * I), d * L * L / (2 * E * I)
    sn, cs = math.sin(THETA), math.cos(THETA)
    snn = saa * cs * cs - 2 * sab * sn * cs + sbb * sn * sn
    ssn = (sbb - saa) * sn * cs - sab * math.cos(2 * THETA)
    return snn / ssn


def geometry():
    a = np.array([1.0, 0.0, 0.0])
    e = np.array([0.0, 1.0, 1.0]) / math.sqrt(2)
    n = -math.cos(THETA) * a + math.sin(THETA) * e  # outward normal of the plane, towards the bar
    s = math.sin(THETA) * a + math.cos(THETA) * e  # the corner slides along s relative to the plane
    p = np.array([L, 0.0, 0.0])
    foot = p + DELTA * n  # the plane passes DELTA beyond the corner
    v = np.cross(n, s)  # U x V = s x (n x s) = n
    centre = foot - RADIUS * v  # velocity omega n x (foot - centre) = -omega R s
    half = 2 * RADIUS
    origin = centre - half * s - half * v
    return n, centre, origin, 2 * half * s, 2 * half * v


def vec(x):
    return "{" + ", ".join(f"{c:.17g}" for c in x) + "}"


def write_deck(path, mu, end, out, h, speed=None):
    speed = SPEED if speed is None else speed
    n, centre, origin, U, V = geometry()
    text = f"""<ParameterList name="Epaphe">
  <ParameterList name="Run"><Parameter name="Name" type="string" value="sprag-slip strut mu {mu:.6g}"/></ParameterList>
  <ParameterList name="Bodies">
    <ParameterList name="Strut">
      <ParameterList name="Mesh">
        <Parameter name="Type" type="string" value="Box"/>
        <Parameter name="Lengths" type="Array(double)" value="{{{L}, {W}, {W}}}"/>
        <Parameter name="Elements" type="Array(int)" value="{{20, 1, 1}}"/>
      </ParameterList>
      <ParameterList name="Material">
        <Parameter name="Density" type="double" value="{RHO}"/>
        <Parameter name="Young's modulus" type="double" value="{E}"/>
        <Parameter name="Poisson's ratio" type="double" value="0"/>
      </ParameterList>
      <Parameter name="Clamped node set" type="string" value="x-"/>
      <Parameter name="Contact node set" type="string" value="x+"/>
      <ParameterList name="Reduction">
        <Parameter name="Method" type="string" value="Massless boundary"/>
        <Parameter name="Fixed-interface modes" type="int" value="10"/>
      </ParameterList>
    </ParameterList>
  </ParameterList>
  <ParameterList name="Surfaces">
    <ParameterList name="Plane">
      <Parameter name="Type" type="string" value="Plane"/>
      <Parameter name="Origin" type="Array(double)" value="{vec(origin)}"/>
      <Parameter name="U" type="Array(double)" value="{vec(U)}"/>
      <Parameter name="V" type="Array(double)" value="{vec(V)}"/>
      <Parameter name="Rotation speed" type="double" value="{speed / RADIUS:.17g}"/>
      <Parameter name="Rotation axis" type="Array(double)" value="{vec(n)}"/>
      <Parameter name="Rotation center" type="Array(double)" value="{vec(centre)}"/>
    </ParameterList>
  </ParameterList>
  <ParameterList name="Contact">
    <Parameter name="Method" type="string" value="Lagrange"/>
    <Parameter name="Friction coefficient" type="double" value="{mu:.17g}"/>
    <Parameter name="Initial penetration" type="string" value="Resolve gently"/>
    <Parameter name="Penetration ramp time" type="double" value="{RAMP}"/>
  </ParameterList>
  <ParameterList name="Time">
    <Parameter name="Time step" type="double" value="{h}"/>
    <Parameter name="End time" type="double" value="{end}"/>
  </ParameterList>
  <ParameterList name="Output">
    <Parameter name="File" type="string" value="{out}"/>
    <Parameter name="Every" type="int" value="20"/>
  </ParameterList>
</ParameterList>
"""
    open(path, "w").write(text)


def run(exe, workdir, name, mu, end, h=H, speed=None):
    deck = os.path.join(workdir, name + ".xml")
    write_deck(deck, mu, end, name + ".h5", h, speed)
    p = subprocess.run([exe, deck], capture_output=True, text=True, cwd=workdir)
    sys.stdout.write(p.stdout + p.stderr)
    h5 = os.path.join(workdir, name + ".h5")
    with h5py.File(h5, "r") as f:
        attrs = dict(f["run"].attrs)
        energy = f["energy/kinetic"][()] + f["energy/strain"][()]
        t = f["time"][()]
    return p.returncode, p.stdout + p.stderr, attrs, t, energy


def main():
    a = argparse.ArgumentParser()
    a.add_argument("--run", required=True)
    a.add_argument("--workdir", required=True)
    o = a.parse_args()
    os.makedirs(o.workdir, exist_ok=True)
    failures = []
    mu_beam = beam_mu_c()

    code, _, attrs, _, _ = run(o.run, o.workdir, "strut-mu0", MU0, 6e-3)
    m0 = float(attrs.get("self_locking_margin", float("nan")))
    mu_c = MU0 / (1.0 - m0)
    print(
        f"beam mu_c (51) {mu_beam:.5f}; model mu*_c {mu_c:.5f} (margin {m0:.5f} at mu {MU0}); "
        f"relative difference {mu_c / mu_beam - 1:+.3e} (tolerance {TOL_MU})"
    )
    if code != 0 or not abs(mu_c / mu_beam - 1) <= TOL_MU:
        failures.append(f"mu0 run: exit {code}, model mu*_c {mu_c} against the beam's {mu_beam}")

    code, m, attrs, t, energy = run(o.run, o.workdir, "strut-below", 0.95 * mu_c, 30e-3)
    half = t >= 0.5 * t[-1]
    growth = energy[half].max() / energy[~half].max()
    margin = float(attrs.get("self_locking_margin", float("nan")))
    print(
        f"0.95 mu_c: exit {code}, energy growth second/first half {growth:.3f}, least margin {margin:.5f}, "
        f"first lock node {attrs.get('self_locking_first_node')}"
    )
    if code != 0:
        failures.append("0.95 mu_c: the run did not complete")
    if not growth <= GROWTH_BOUND:
        failures.append(f"0.95 mu_c: energy grew by {growth}")
    if not (0.0 < margin < 0.1) or attrs.get("self_locking_first_node") != -1:
        failures.append(f"0.95 mu_c: least margin {margin}, expected about 0.05 and no lock")

    steady = force_at(o.workdir, "strut-below", t, 0.5 * t[-1])
    above = []
    for name, h in (("strut-above", H), ("strut-above-h2", H / 2)):
        code, m, attrs, t, energy = run(o.run, o.workdir, name, 1.05 * mu_c, END_ABOVE, h)
        with h5py.File(os.path.join(o.workdir, name + ".h5"), "r") as f:
            work = f["energy/contact_work"][()][-1]
            force = f["bodies/Strut/contact/force"][()][:, CORNER]
        above.append((t, force))
        first = float(attrs.get("self_locking_first_margin", float("nan")))
        f4, f8 = np.interp([0.5 * END_ABOVE, END_ABOVE], t, force)
        print(
            f"1.05 mu_c, h = {h:g} s: exit {code}, corner force {f4:.4g} N at {0.5 * END_ABOVE:g} s, {f8:.4g} N at "
            f"{END_ABOVE:g} s ({f8 / steady:.1f} times the steady force at 0.95 mu_c), energy {energy[-1]:.4g} J, "
            f"contact work {work:.4g} J; first lock node {attrs.get('self_locking_first_node')} at "
            f"{attrs.get('self_locking_first_time')} s, margin {first:.5f}"
        )
        if code != 0:
            failures.append(f"1.05 mu_c, h = {h}: the run stopped")
        if not (f8 >= FORCE_RATIO * steady and LINEAR[0] <= f8 / f4 <= LINEAR[1]):
            failures.append(f"1.05 mu_c, h = {h}: corner force {f4} then {f8}, not growing as the jam does")
        if not abs(energy[-1] - work) <= 0.01 * work:
            failures.append(f"1.05 mu_c, h = {h}: energy {energy[-1]} not fed by the contact work {work}")
        if not (-0.1 < first <= 0.0):
            failures.append(f"1.05 mu_c, h = {h}: first lock margin {first}, expected about -0.05")
    (t1, f1), (t2, f2) = above
    diff = np.max(np.abs(np.interp(t1, t2, f2) - f1)) / np.max(np.abs(f1))
    print(f"1.05 mu_c: the corner force at h/2 differs from h's by {diff:.2e} of its peak (tolerance {STEP_TOL})")
    if not diff <= STEP_TOL:
        failures.append(f"1.05 mu_c: the step changes the force by {diff} of its peak")

    print("FAILED:\n  " + "\n  ".join(failures) if failures else "3 passed, 0 failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
