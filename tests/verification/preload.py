#!/usr/bin/env python3
"""'Time->Initial state' = Static equilibrium (docs/theory/forced-response.md, eqs. (71)-(72)): a run that
starts from the static contact solve under its preload stands still.

The scene: a steel cantilever 0.2 x 0.02 x 0.02 m (10 x 1 x 1 hexahedra) clamped at x-, resting at its
tip on a rigid plane z = 0 (its bottom tip nodes touch it: the contact node set x+, whose top nodes are
0.02 m above), pressed down by a Constant load on its top face z+ of (0, 0.05, -1) N per node (42 nodes:
a propped cantilever under a distributed load, with a small sideways push), Lagrange contact with
mu = 2: the bent bar's tip pulls its bottom nodes along x with more than the normal force (the static
solve finds them sliding below mu = 1.2 or so; at mu = 0.3 they do, and a start from that impending slip
moves 1 % of the static displacement over the first steps, printed, not asserted). For Craig-Bampton (12
modes) and the full model with lumped mass, and for the massless boundary (12 modes) with mu = 0 (with
friction its stuck start leaves the equilibrium within a step, a shortfall: refused, case
static-preload-massless-friction.xml):

1. Standing still: over the first 2000 steps every watched displacement (the faces x+ and z+) stays at
   its value at t = 0 within STILL = 1e-9 of the largest static displacement (round-off: the correction
   closes the gap and the stick exactly each step; measured 1e-13 and less), while the same deck started
   'At rest' moves by the order of the static deflection itself (at least 0.1 of it: the test can fail).
2. The equilibrium is the contact problem's: the tip's bottom nodes are at the plane (|z| <= 1e-12 m),
   held by a normal force (the history's contact force > 0 at t = 0) with the friction force inside the
   cone, and the static tip deflections (the top tip nodes' z) of Craig-Bampton and the lumped model
   agree within AGREE = 1e-6 (the same full model's static response on the retained DOFs, both stuck;
   measured 7e-13).
3. inputs/oblique-contact.xml (NLstep's example 04 setting): the same start, then an oblique Table load
   (0, 2, 1) g(t) N per tip node, g from 0 to 10 over 20 ms, mu = 0.3. Statics of the whole tip: its held
   (bottom) nodes slide when the tangential force 8 g exceeds mu (20 - 4 g), at g = 0.652 (t = 1.30 ms),
   and the tip lifts off when 4 g = 20 (t = 10 ms). Asserted: the held nodes stay stuck (|u_y| <= 1e-15 m;
   measured 2.6e-22 m) up to 1 ms, start sliding (|u_y| > 1e-12 m) within 10 % before the whole tip's
   estimate (one of the two held nodes, pressed less, saturates first; measured 1.240 ms) and not after
   it, and the last recorded contact (records every 40 us) is within 1 % of 10 ms (measured 9.960 ms).
4. Refused: a preload that pulls the tip off the plane ((0, 0, +1) N per node) with one message naming
   the node and its normal force (case static-preload-opens-contact.xml of tests/badinput).

    preload.py --run EPAPHE_RUN --workdir DIR [--inputs INPUTS]
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from epaphe_testing import history, run, verdict  # noqa: E402

STILL = 1e-9
AGREE = 1e-6
H = 1e-6
STEPS = 2000
METHODS = ["Craig-Bampton", "Massless boundary", "Full, lumped mass"]
MU = {"Massless boundary": 0.0}  # the others stuck at mu = 2

DECK = """<ParameterList name="Epaphe">
  <ParameterList name="Run"><Parameter name="Progress interval" type="double" value="0"/>
    <Parameter name="Divergence step check" type="bool" value="false"/></ParameterList>
  <ParameterList name="Bodies">
    <ParameterList name="Bar">
      <ParameterList name="Mesh">
        <Parameter name="Type" type="string" value="Box"/>
        <Parameter name="Lengths" type="Array(double)" value="{{0.2, 0.02, 0.02}}"/>
        <Parameter name="Elements" type="Array(int)" value="{{10, 1, 1}}"/>
      </ParameterList>
      <ParameterList name="Material">
        <Parameter name="Density" type="double" value="8000"/>
        <Parameter name="Young's modulus" type="double" value="2e11"/>
        <Parameter name="Poisson's ratio" type="double" value="0.3"/>
      </ParameterList>
      <Parameter name="Clamped node set" type="string" value="x-"/>
      <Parameter name="Contact node set" type="string" value="x+"/>
      <Parameter name="Watched node sets" type="Array(string)" value="{{x+, z+}}"/>
      <ParameterList name="Loads">
        <ParameterList name="Weight">
          <Parameter name="Node set" type="string" value="z+"/>
          <Parameter name="Force" type="Array(double)" value="{{{force}}}"/>
        </ParameterList>
      </ParameterList>
      <ParameterList name="Reduction">
        <Parameter name="Method" type="string" value="{method}"/>
        {retained}
        <Parameter name="Fixed-interface modes" type="int" value="12"/>
        <Parameter name="Frequency check" type="int" value="0"/>
        <Parameter name="Cache" type="bool" value="false"/>
      </ParameterList>
    </ParameterList>
  </ParameterList>
  <ParameterList name="Surfaces">
    <ParameterList name="Support">
      <Parameter name="Type" type="string" value="Plane"/>
      <Parameter name="Origin" type="Array(double)" value="{{0.15, -0.05, 0}}"/>
      <Parameter name="U" type="Array(double)" value="{{0.1, 0, 0}}"/>
      <Parameter name="V" type="Array(double)" value="{{0, 0.1, 0}}"/>
      <Parameter name="Points" type="Array(int)" value="{{5, 5}}"/>
    </ParameterList>
  </ParameterList>
  <ParameterList name="Contact">
    <Parameter name="Method" type="string" value="Lagrange"/>
    <Parameter name="Friction coefficient" type="double" value="{mu}"/>
  </ParameterList>
  <ParameterList name="Time">
    <Parameter name="Time step" type="double" value="{h}"/>
    <Parameter name="End time" type="double" value="{end}"/>
    <Parameter name="Initial state" type="string" value="{start}"/>
  </ParameterList>
  <ParameterList name="Output">
    <Parameter name="File" type="string" value="{name}.h5"/>
    <Parameter name="Every" type="int" value="10"/>
  </ParameterList>
</ParameterList>
"""


def write_deck(workdir, name, method, start, force="0, 0.05, -1", mu=2.0):
    retained = '<Parameter name="Retained node set" type="string" value="x+"/>' if method != "Full, lumped mass" else ""
    path = os.path.join(workdir, name + ".xml")
    with open(path, "w") as f:
        f.write(
            DECK.format(
                mu=mu, force=force, method=method, retained=retained, h=H, end=STEPS * H, start=start, name=name
            )
        )
    return path


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--run", required=True)
    ap.add_argument("--workdir", required=True)
    ap.add_argument("--inputs", default=None, help="the inputs/ folder (oblique-contact.xml)")
    a = ap.parse_args()
    os.makedirs(a.workdir, exist_ok=True)
    failures = []
    tips = {}
    for method in METHODS:
        tag = method.replace(",", "").replace(" ", "-").lower()
        moved = {}
        for start in ("Static equilibrium", "At rest"):
            name = f"{tag}-{'static' if start[0] == 'S' else 'rest'}"
            mu = MU.get(method, 2.0)
            p = run([a.run, write_deck(a.workdir, name, method, start, mu=mu), "--threads", "1"], a.workdir)
            if start[0] == "S" and mu > 0 and "2 stuck, 0 sliding" not in p.stdout:
                failures.append(f"{method}: the static solve does not stick both bottom tip nodes")
            hist = history(os.path.join(a.workdir, name + ".h5"))
            u = np.concatenate(
                [hist["bodies/Bar/nodesets/x+/displacement"], hist["bodies/Bar/nodesets/z+/displacement"]], axis=1
            )
            if start[0] == "S":
                static = np.abs(u[0]).max()
                moved[start] = float(np.abs(u - u[0]).max()) / static
                xp = hist["bodies/Bar/nodesets/x+/displacement"][0]
                bottom = float(np.sort(np.abs(xp[:, 2]))[:2].max())  # the two bottom tip nodes, on the plane
                tips[method] = float(xp[:, 2].min())  # the top tip nodes, pressed down
                force = hist["bodies/Bar/contact/total_force"][0]
                print(
                    f"{method:18s} static start: largest displacement {static:.6e} m, bottom tip |z| {bottom:.1e} m, "
                    f"contact force at t = 0 {force:.4f} N; moved over {STEPS} steps {moved[start]:.2e} of it"
                )
                if not moved[start] <= STILL:
                    failures.append(f"{method}: the static start moves {moved[start]:.2e} of its displacement")
                if not bottom <= 1e-12:
                    failures.append(f"{method}: the bottom tip nodes are {bottom:.2e} m off the plane at t = 0")
                if not force > 0:
                    failures.append(f"{method}: no contact force at t = 0 ({force})")
            else:
                moved[start] = float(np.abs(u - u[0]).max()) / static
                print(f"{method:18s} started at rest: moves {moved[start]:.2e} of the static displacement")
                if not moved[start] >= 0.1:
                    failures.append(f"{method}: started at rest it moves only {moved[start]:.2e}: the check is blind")
    ref = tips["Craig-Bampton"]
    for method, z in tips.items():
        if method in MU:
            continue  # frictionless: another equilibrium
        rel = abs(z - ref) / abs(ref)
        print(f"{method:18s} top tip z {z:.9e} m, against Craig-Bampton's {rel:.1e}")
        if not rel <= AGREE:
            failures.append(f"{method}: static tip {z:.6e} m against Craig-Bampton's {ref:.6e} ({rel:.2e})")
    if a.inputs:
        deck = os.path.join(a.inputs, "oblique-contact.xml")
        run([a.run, deck, "--threads", "1"], a.workdir)
        hist = history(os.path.join(a.workdir, "oblique-contact.h5"))
        t = hist["time"]
        held = np.abs(hist["bodies/Beam/contact/gap"][0]) <= 1e-12  # the bottom tip nodes, on the plane at t = 0
        uy = np.abs(hist["bodies/Beam/nodesets/x+/displacement"][:, held, 1]).max(axis=1)  # (x+ = the contact set)
        force = hist["bodies/Beam/contact/total_force"]
        onset = t[np.argmax(uy > 1e-12)]
        stuck = uy[t <= 1e-3].max()
        last = t[np.nonzero(force > 0)[0][-1]]
        slip_est = 0.02 * (6.0 / 9.2) / 10.0  # g = 6 / (8 + 1.2), over 20 ms to g = 10
        print(
            f"oblique contact: stuck to {stuck:.1e} m up to 1 ms, sliding from {onset * 1e3:.3f} ms (the whole tip's "
            f"estimate {slip_est * 1e3:.3f} ms), last contact {last * 1e3:.3f} ms (lift-off at 10 ms)"
        )
        if not stuck <= 1e-15:
            failures.append(f"oblique contact: the tip moves {stuck:.2e} m along y in its first ms")
        if not (0.9 * slip_est <= onset <= slip_est):
            failures.append(f"oblique contact: slides from {onset:.5f} s, the estimate {slip_est:.5f} s")
        if not abs(last - 0.01) <= 0.01 * 0.01:
            failures.append(f"oblique contact: last contact at {last:.5f} s, lift-off at 0.01 s")
    p = run(
        [a.run, write_deck(a.workdir, "opens", "Craig-Bampton", "Static equilibrium", "0, 0, 1")],
        a.workdir,
        expect_ok=False,
    )
    text = p.stdout + p.stderr
    if p.returncode == 0 or "the preload opens the contact" not in text:
        failures.append(f"a preload pulling the tip off the plane was not refused ({p.returncode}): {text[-300:]}")
    else:
        print("refused:", [l for l in text.splitlines() if "error" in l][0])
    sys.exit(verdict(failures))


if __name__ == "__main__":
    main()
