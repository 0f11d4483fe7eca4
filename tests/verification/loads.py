#!/usr/bin/env python3
"""Bodies' 'Loads' (docs/theory/forced-response.md, eqs. 65-67): the same loads on the same clamped
cantilever, projected into each model kind, give the same motion, and the energy balance closes with
their work.

The cantilever: a steel bar 0.2 x 0.02 x 0.02 m (10 x 1 x 1 hexahedra), clamped at x-, its tip x+
retained (Craig-Bampton with 12 modes, Massless boundary with 12 modes, 'None' (the full model,
consistent mass, dense) and 'Full, lumped mass'). Its first bending mode is near 400 Hz; Rayleigh
damping alpha M (1000 /s: 20 % on the first mode) lets transients die.

1. Static part (the projection R^T F, eq. 66). A Ramp load (T = 10 ms, four first periods) of
   F = (0, 0, -10) N on each of the tip's 4 nodes, then held: at 40 ms the transient has decayed by
   exp(-alpha t / 2) ~ 1e-6 and every model stands in its static equilibrium K q = R^T F. The four
   models share the full model's static response at the tip exactly (Craig-Bampton's constraint modes
   and the massless boundary's G hold it; 'None' and the lumped model are the full model), so their tip
   deflections must agree within STATIC_TOL = 1e-8 (measured: 2e-10 and less; what is left of the
   transient). The lumped model takes F on each tip node's DOFs directly (R = I): the reduced models'
   R^T F is checked against the plain nodal force. A wrong projection (a load on the wrong DOF, a
   factor 2 on the massless boundary's modal part) moves it by 1e-2 or more.
2. Energy and motion (eq. 67). A Harmonic load (300 Hz, phase 0.3 rad) on the tip and a Table load
   on the tip and the face y+ (interior nodes too: the massless boundary's modal part), 4000 steps:
   the energy balance |E + D - W_ext| (E_0 = 0: the bar starts at rest) stays below BALANCE = 1e-9 of
   the run's largest energy (the identity is exact; measured 1e-11 and less), and the external work
   is of the order of the energy (it is what drives the bar). The tip's motion of each reduced model
   agrees with the full model's within DYNAMIC_TOL of its largest value: 2e-3 for Craig-Bampton and the
   massless boundary (12 modes against a 300 Hz drive: measured 2e-4 and 7e-4), 2e-2 for the lumped
   mass (its frequencies differ from the consistent mass's: measured 6e-3).
3. Loads on the model's coordinates ('Reduced DOFs', 'Reduced forces'). On Craig-Bampton and the massless
   boundary the tip's 4 nodes are the retained ones, their DOFs the model's coordinates 0-11 (x, y, z of
   each, R_i = [I 0]): the Shaker of part 2 given as forces on those 12 coordinates is the same R^T F, so
   the driven runs must repeat part 2's motion to REDUCED_TOL = 1e-12 of its largest value (measured: 0, bit
   for bit). A force on one mode (coordinate 12, Constant 1) must do work (a load on a mode acts).
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from epaphe_testing import history, run, verdict  # noqa: E402

E, NU, RHO = 2e11, 0.3, 8000.0
L, B = 0.2, 0.02
F_NODE = -10.0  # N on each of the 4 tip nodes, along z
ALPHA = 1000.0  # 1/s, Rayleigh alpha
H = 1e-6
STATIC_TOL = 1e-8
BALANCE = 1e-9
REDUCED_TOL = 1e-12
DYNAMIC_TOL = {"Craig-Bampton": 2e-3, "Massless boundary": 2e-3, "Full, lumped mass": 2e-2}
METHODS = ["Craig-Bampton", "Massless boundary", "None", "Full, lumped mass"]

DECK = """<ParameterList name="Epaphe">
  <ParameterList name="Run"><Parameter name="Progress interval" type="double" value="0"/>
    <Parameter name="Divergence step check" type="bool" value="false"/></ParameterList>
  <ParameterList name="Bodies">
    <ParameterList name="Bar">
      <ParameterList name="Mesh">
        <Parameter name="Type" type="string" value="Box"/>
        <Parameter name="Lengths" type="Array(double)" value="{{{L}, {B}, {B}}}"/>
        <Parameter name="Elements" type="Array(int)" value="{{10, 1, 1}}"/>
      </ParameterList>
      <ParameterList name="Material">
        <Parameter name="Density" type="double" value="{rho}"/>
        <Parameter name="Young's modulus" type="double" value="{E}"/>
        <Parameter name="Poisson's ratio" type="double" value="{nu}"/>
      </ParameterList>
      <Parameter name="Clamped node set" type="string" value="x-"/>
      <Parameter name="Watched node sets" type="Array(string)" value="{{x+}}"/>
      <ParameterList name="Loads">
{loads}
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
  <ParameterList name="Contact"><Parameter name="Method" type="string" value="Lagrange"/></ParameterList>
  <ParameterList name="Time">
    <Parameter name="Time step" type="double" value="{h}"/>
    <Parameter name="End time" type="double" value="{end}"/>
    <ParameterList name="Damping">
      <Parameter name="Type" type="string" value="Rayleigh"/>
      <Parameter name="Alpha" type="double" value="{alpha}"/>
    </ParameterList>
  </ParameterList>
  <ParameterList name="Output">
    <Parameter name="File" type="string" value="{name}.h5"/>
    <Parameter name="Every" type="int" value="{every}"/>
  </ParameterList>
</ParameterList>
"""

RAMP = """        <ParameterList name="Tip">
          <Parameter name="Node set" type="string" value="x+"/>
          <Parameter name="Force" type="Array(double)" value="{{0, 0, {f}}}"/>
          <Parameter name="Time function" type="string" value="Ramp"/>
          <Parameter name="Ramp time" type="double" value="0.01"/>
        </ParameterList>"""

DRIVEN = """        <ParameterList name="Shaker">
          <Parameter name="Node set" type="string" value="x+"/>
          <Parameter name="Force" type="Array(double)" value="{{0, 3, {f}}}"/>
          <Parameter name="Time function" type="string" value="Harmonic"/>
          <Parameter name="Frequency" type="double" value="300"/>
          <Parameter name="Phase" type="double" value="0.3"/>
        </ParameterList>
        <ParameterList name="Push">
          <Parameter name="Node set" type="string" value="x+, y+"/>
          <Parameter name="Force" type="Array(double)" value="{{1, 0, 2}}"/>
          <Parameter name="Time function" type="string" value="Table"/>
          <Parameter name="Times" type="Array(double)" value="{{0.0005, 0.001, 0.002}}"/>
          <Parameter name="Values" type="Array(double)" value="{{0, 4, -1}}"/>
        </ParameterList>"""


REDUCED = (
    """        <ParameterList name="Shaker">
          <Parameter name="Reduced DOFs" type="Array(int)" value="{{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11}}"/>
          <Parameter name="Reduced forces" type="Array(double)" value="{{{forces}}}"/>
          <Parameter name="Time function" type="string" value="Harmonic"/>
          <Parameter name="Frequency" type="double" value="300"/>
          <Parameter name="Phase" type="double" value="0.3"/>
        </ParameterList>"""
    + DRIVEN[DRIVEN.index('        <ParameterList name="Push">') :]
)

MODAL = """        <ParameterList name="Mode">
          <Parameter name="Reduced DOFs" type="Array(int)" value="{12}"/>
          <Parameter name="Reduced forces" type="Array(double)" value="{1}"/>
        </ParameterList>"""


def write_deck(workdir, name, method, loads, end, every):
    retained = '<Parameter name="Retained node set" type="string" value="x+"/>'
    text = DECK.format(
        retained=retained if method in ("Craig-Bampton", "Massless boundary") else "",
        L=L,
        B=B,
        rho=RHO,
        E=E,
        nu=NU,
        loads=loads,
        method=method,
        h=H,
        end=end,
        alpha=ALPHA,
        name=name,
        every=every,
    )
    path = os.path.join(workdir, name + ".xml")
    with open(path, "w") as f:
        f.write(text)
    return path


def main():
    import argparse

    ap = argparse.ArgumentParser()
    ap.add_argument("--run", required=True)
    ap.add_argument("--workdir", required=True)
    a = ap.parse_args()
    os.makedirs(a.workdir, exist_ok=True)
    failures = []

    tips = {}
    for method in METHODS:
        label = "ramp-" + method.replace(",", "").replace(" ", "-").lower()
        deck = write_deck(a.workdir, label, method, RAMP.format(f=F_NODE), 0.04, 1000)
        run([a.run, deck, "--threads", "1"], a.workdir)
        hist = history(os.path.join(a.workdir, label + ".h5"))
        u = hist["bodies/Bar/nodesets/x+/displacement"]  # records x nodes x 3
        tips[method] = float(u[-1, :, 2].mean())
        drift = float(np.abs(u[-1, :, 2] - u[-2, :, 2]).max() / abs(u[-1, :, 2]).max())
        print(f"{method:18s} static tip deflection {tips[method]:.9e} m (last record's change {drift:.2e})")
    ref = tips["None"]
    for method, w in tips.items():
        rel = abs(w - ref) / abs(ref)
        print(f"{method:18s} against the full model: {rel:.2e} (tolerance {STATIC_TOL:g})")
        if rel > STATIC_TOL:
            failures.append(f"{method}: static tip deflection {w:.6e} m, the full model's {ref:.6e} ({rel:.2e})")
    motion = {}
    for method in METHODS:
        label = "driven-" + method.replace(",", "").replace(" ", "-").lower()
        deck = write_deck(a.workdir, label, method, DRIVEN.format(f=F_NODE), 4000 * H, 10)
        run([a.run, deck, "--threads", "1"], a.workdir)
        hist = history(os.path.join(a.workdir, label + ".h5"))
        e = {k: hist["energy/" + k] for k in ("total", "damping", "contact_work", "external_work")}
        total = np.abs(e["total"]).max()
        bal = np.abs(e["total"] + e["damping"] - e["contact_work"] - e["external_work"]).max() / total
        work = np.abs(e["external_work"]).max()
        motion[method] = hist["bodies/Bar/nodesets/x+/displacement"]
        print(
            f"{method:18s} harmonic + table: balance error {bal:.2e} of the largest energy {total:.3e} J, "
            f"external work up to {work:.3e} J"
        )
        if not bal <= BALANCE:
            failures.append(f"{method}: energy balance error {bal:.3e} > {BALANCE:g} with loads")
        if not work > 0.1 * total:
            failures.append(f"{method}: external work {work:.3e} J, not what drives the bar (energy {total:.3e} J)")
    ref = motion["None"]
    for method, tol in DYNAMIC_TOL.items():
        rel = float(np.abs(motion[method] - ref).max() / np.abs(ref).max())
        print(f"{method:18s} driven tip motion against the full model's: {rel:.2e} (tolerance {tol:g})")
        if not rel <= tol:
            failures.append(f"{method}: driven tip motion {rel:.2e} from the full model's (tolerance {tol:g})")
    forces = ", ".join(["0", "3", repr(F_NODE)] * 4)
    for method in ("Craig-Bampton", "Massless boundary"):
        label = "reduced-" + method.replace(" ", "-").lower()
        deck = write_deck(a.workdir, label, method, REDUCED.format(forces=forces), 4000 * H, 10)
        run([a.run, deck, "--threads", "1"], a.workdir)
        u = history(os.path.join(a.workdir, label + ".h5"))["bodies/Bar/nodesets/x+/displacement"]
        rel = float(np.abs(u - motion[method]).max() / np.abs(motion[method]).max())
        print(
            f"{method:18s} the Shaker on reduced DOFs 0-11 against on the node set: {rel:.2e} (tolerance {REDUCED_TOL:g})"
        )
        if not rel <= REDUCED_TOL:
            failures.append(f"{method}: the load on reduced DOFs moves the tip {rel:.2e} off the node-set load's")
        label = "modal-" + method.replace(" ", "-").lower()
        deck = write_deck(a.workdir, label, method, MODAL, 1000 * H, 10)
        run([a.run, deck, "--threads", "1"], a.workdir)
        work = float(np.abs(history(os.path.join(a.workdir, label + ".h5"))["energy/external_work"]).max())
        print(f"{method:18s} a unit force on coordinate 12 (a mode): external work up to {work:.3e} J")
        if not work > 0:
            failures.append(f"{method}: a force on coordinate 12 (a mode) did no work")
    sys.exit(verdict(failures))


if __name__ == "__main__":
    main()
