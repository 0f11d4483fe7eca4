#!/usr/bin/env python3
"""Mode-coupling instability: the minimal model of Hoffmann, Fischer, Allgaier & Gaul (Mech. Res.
Commun. 29 (2002) 197-205), a point mass on a moving belt held by springs that couple its tangential
and normal motions, against its analytic flutter boundary (issue 37; docs/theory/divergence.md).

The model. One node of mass m (an imported Matrix Market model: K and M 3 x 3, 'Reduction->Method'
'None'), DOFs x along the belt, y normal to it, z held by a spring of its own. The springs give

    K_s = [[k11, k12], [k12, k22]]  (x, y),    k11 = k22 + k_c,  k12 < 0,

and the belt is a plane turning about its normal at radius R (its velocity V along +x under the
node), pressed into the node by an interference fit: the plane passes DELTA beyond the node at
rest, pushed in by 'Contact->Initial penetration' = 'Resolve gently' over RAMP. Penalty contact
('Penalty stiffness' k_c: the normal force N = k_c (DELTA - y)) with Coulomb friction: while the
node slides, the belt drags it with mu N along +x. About the sliding equilibrium,

    m x'' + k11 x + (k12 + mu k_c) y = 0,     m y'' + k12 x + (k22 + k_c) y = 0,

whose two frequencies merge and become complex (flutter) when (k11 - k22 - k_c)^2 + 4 k12 (k12 + mu
k_c) < 0, i.e. here (k11 - k22 = k_c) at

    mu_c = -k12 / k_c  (= 0.3).

The preload is the interference fit (the loads of the forced-response issue do not exist yet).
Neither the belt speed nor the preload enters mu_c: the map over the belt speed is flat.

Criterion. A run is *diverging* when it stops with its energy growing without bound (epaphe-run's
diagnosis), or when the oscillation of the contact force about its mean grows: its RMS over the
last fifth of the run after the ramp exceeds GROWTH times that over the first fifth; else it is
*bounded*. Below mu_c the undamped oscillation the ramp leaves keeps its amplitude; above it grows
as exp(Im(omega) t), Im(omega) ~ sqrt(-D) / (4 m omega_0), about 1.2 /s at 1.01 mu_c over the
2 s runs here (the energy grows 2x there within the run). At mu_c itself (a double root) the
response grows linearly, and just below it the two modes beat with a period longer than the run: the
criterion counts both as growth, so the boundary it finds lies slightly below mu_c (-0.9 % measured).
Per belt speed, the bracket [mu_lo, mu_hi] (bounded, diverging) is halved until (mu_hi - mu_lo) <=
TOL mu_hi; the boundary's mid-point is asserted within TOL_MU of mu_c.

    hoffmann.py --run EPAPHE_RUN --workdir DIR [--speeds 5,10] [--bracket 0.2,0.4]

Written: <workdir>/hoffmann-map.h5 (/speed, /mu_bounded, /mu_diverging, /mu_c and every run's
/runs/{speed, mu, diverging, growth}). Exit status 0 when every speed's boundary is within TOL_MU."""
import argparse
import os
import subprocess
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "verification"))
from epaphe_testing import POINT_MASS_MESH, write_point_mass  # noqa: E402

# the model (SI): mass, springs, contact stiffness; mu_c = -K12 / KC
M = 1.0
KC = 1.0e4
K22 = 1.0e4
K11 = K22 + KC
K12 = -3.0e3
KZ = 1.0e4
MU_C = -K12 / KC
DELTA = 1e-3  # m: the interference fit
R = 10.0  # m: the belt plane turns about its normal at this radius from the node
H = 2e-5  # s: omega_max h = 0.003
RAMP = 0.05  # s: the interference ramped in over about one period (2 pi / 141 rad/s = 0.045 s)
END = 2.0  # s after the ramp
GROWTH = 2.0
TOL = 0.005
TOL_MU = 0.02  # the 2 %


def write_model(workdir):
    """The node's model files (Matrix Market import)."""
    write_point_mass(workdir, [(1, 1, K11), (2, 1, K12), (2, 2, K22), (3, 3, KZ)], M)


def write_deck(path, mu, speed, out):
    """The deck: the belt plane y = DELTA (normal U x V = +y: the node at y = 0 is DELTA inside it),
    turning about +y through (0, DELTA, -R) at speed / R, so that it moves along +x under the node; the
    patch is centred on the axis (half-width 2 R), so that the node stays on it as it turns."""
    half = 2 * R
    return open(path, "w").write(
        f"""<ParameterList name="Epaphe">
  <ParameterList name="Run"><Parameter name="Name" type="string" value="Hoffmann mass on a belt, mu {mu:.6g}"/>
    <Parameter name="Progress interval" type="double" value="0"/>
    <Parameter name="Divergence step check" type="bool" value="false"/>
  </ParameterList>
  <ParameterList name="Bodies">
    <ParameterList name="Mass">
      {POINT_MASS_MESH}
      <Parameter name="Contact node set" type="string" value="MASS"/>
      <Parameter name="Watched node sets" type="Array(string)" value="{{MASS}}"/>
    </ParameterList>
  </ParameterList>
  <ParameterList name="Surfaces">
    <ParameterList name="Belt">
      <Parameter name="Type" type="string" value="Plane"/>
      <Parameter name="Origin" type="Array(double)" value="{{{-half}, {DELTA}, {half - R}}}"/>
      <Parameter name="U" type="Array(double)" value="{{{2 * half}, 0, 0}}"/>
      <Parameter name="V" type="Array(double)" value="{{0, 0, {-2 * half}}}"/>
      <Parameter name="Rotation speed" type="double" value="{speed / R:.17g}"/>
      <Parameter name="Rotation axis" type="Array(double)" value="{{0, 1, 0}}"/>
      <Parameter name="Rotation center" type="Array(double)" value="{{0, {DELTA}, {-R}}}"/>
    </ParameterList>
  </ParameterList>
  <ParameterList name="Contact">
    <Parameter name="Method" type="string" value="Penalty"/>
    <Parameter name="Penalty stiffness" type="double" value="{KC}"/>
    <Parameter name="Friction coefficient" type="double" value="{mu:.17g}"/>
    <Parameter name="Initial penetration" type="string" value="Resolve gently"/>
    <Parameter name="Penetration ramp time" type="double" value="{RAMP}"/>
  </ParameterList>
  <ParameterList name="Time">
    <Parameter name="Time step" type="double" value="{H}"/>
    <Parameter name="End time" type="double" value="{RAMP + END}"/>
  </ParameterList>
  <ParameterList name="Output">
    <Parameter name="File" type="string" value="{out}"/>
    <Parameter name="Every" type="int" value="10"/>
  </ParameterList>
</ParameterList>
"""
    )


def outcome(exe, workdir, speed, mu):
    """(diverging, growth, text) of one run at belt speed `speed` (m/s) and coefficient mu."""
    name = f"hoffmann-v{speed:g}-mu{mu:.6f}"
    deck = os.path.join(workdir, name + ".xml")
    write_deck(deck, mu, speed, name + ".h5")
    p = subprocess.run([exe, deck, "--threads", "1"], capture_output=True, text=True, cwd=workdir)
    text = p.stdout + p.stderr
    with h5py.File(os.path.join(workdir, name + ".h5"), "r") as f:
        t = f["time"][()]
        force = f["bodies/Mass/contact/total_force"][()]
    after = t >= RAMP
    t, force = t[after], force[after]
    span = t[-1] - t[0] if len(t) > 1 else 0.0
    first, last = t <= t[0] + 0.2 * span, t >= t[-1] - 0.2 * span
    rms = lambda x: float(np.sqrt(np.mean((x - x.mean()) ** 2)))  # noqa: E731
    growth = rms(force[last]) / max(rms(force[first]), 1e-300)
    stopped = p.returncode != 0
    if stopped and "grows without bound" not in text:
        raise RuntimeError(f"{name}: epaphe-run stopped for another reason:\n{text}")
    return stopped or growth > GROWTH, growth, text


def main():
    a = argparse.ArgumentParser()
    a.add_argument("--run", required=True)
    a.add_argument("--workdir", required=True)
    a.add_argument("--speeds", default="5,10")  # m/s
    a.add_argument("--bracket", default="0.2,0.4")
    args = a.parse_args()
    os.makedirs(args.workdir, exist_ok=True)
    write_model(args.workdir)
    speeds = [float(s) for s in args.speeds.split(",")]
    lo0, hi0 = (float(x) for x in args.bracket.split(","))
    runs, bounds, failures = [], [], []
    for v in speeds:
        lo, hi = lo0, hi0
        for mu, want in ((lo, False), (hi, True)):
            d, g, text = outcome(args.run, args.workdir, v, mu)
            runs.append((v, mu, d, g))
            if d != want:
                failures.append(f"speed {v} m/s: mu = {mu} is {'diverging' if d else 'bounded'} (growth {g:.3g})")
        if failures:
            break
        while hi - lo > TOL * hi:
            mu = 0.5 * (lo + hi)
            d, g, text = outcome(args.run, args.workdir, v, mu)
            runs.append((v, mu, d, g))
            if d:
                hi = mu
            else:
                lo = mu
        bounds.append((lo, hi))
        mid = 0.5 * (lo + hi)
        print(
            f"belt at {v:g} m/s: bounded at mu = {lo:.5f}, diverging at {hi:.5f}; mid-point {mid:.5f} against "
            f"mu_c = {MU_C:.5f} ({100 * (mid / MU_C - 1):+.2f} %)"
        )
        if abs(mid / MU_C - 1) > TOL_MU:
            failures.append(f"speed {v} m/s: boundary {mid:.5f} is not within {TOL_MU:.0%} of mu_c = {MU_C}")
    for v, mu, d, g in runs:
        print(f"  v {v:g} m/s, mu {mu:.5f}: {'diverging' if d else 'bounded'}, force oscillation grew {g:.3g}x")
    with h5py.File(os.path.join(args.workdir, "hoffmann-map.h5"), "w") as f:
        f["speed"] = np.array(speeds[: len(bounds)])
        f["mu_bounded"] = np.array([b[0] for b in bounds])
        f["mu_diverging"] = np.array([b[1] for b in bounds])
        f["mu_c"] = MU_C
        r = np.array([(v, mu, float(d), g) for v, mu, d, g in runs]).reshape(-1, 4)
        for i, key in enumerate(("speed", "mu", "diverging", "growth")):
            f[f"runs/{key}"] = r[:, i]
    if failures:
        print("FAILED:\n  " + "\n  ".join(failures))
        return 1
    print("PASSED")
    return 0


if __name__ == "__main__":
    sys.exit(main())
