#!/usr/bin/env python3
"""V6, section 4.3.1 (inputs/cube-flexible-rings.xml): the cube at 50 m/s between two flexible
rings, each reduced by Craig-Bampton on its outer (contact) face and carrying that face as a
B-spline rebuilt from its moved nodes at every step; cube and rings corrected together.

Checked against the same scene with rigid rings (inputs/cube-rings.xml, same step):
  - the rings move (their contact face deflects by more than 0.1 mm);
  - the contact forces are lower, "about half the rigid case" (VERIFICATION.md V6): the mean
    total force while in contact is between 0.3 and 0.8 of the rigid rings', and the contact lasts
    longer;
  - the scene stays symmetric: the two rings' contact faces mirror each other (x -> -x), and mirror
    nodes of the cube's bottom face have opposite X and Z and equal Y, to 1e-6 of the largest
    displacement;
  - no node penetrates more than 1e-9 m after the correction, and the energy balance closes to 1e-8.
The thesis' "the cube passes through" is not asserted: with VERIFICATION.md's rings (3 cm of steel
over a 90 degree arc clamped at both ends) the rings' stiffness is of order 4e8 N/m, and the cube's
1.2 kJ deflects them by about half a millimetre, far from the 5 mm each must open (it bounces back at
48.5 m/s; see the issue notes).
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from epaphe_testing import history, parse_args, run, variant, verdict  # noqa: E402


def main():
    a = parse_args("--rigid-deck")
    failures = []
    common = {"Time->End time": ("6e-4", "double"), "Run->Progress interval": ("0", "double"),
              "Output->Every": ("10", "int")}
    res = {}
    for name, base in (("rigid", a.rigid_deck), ("flexible", a.deck)):
        deck = variant(base, os.path.join(a.workdir, name + ".xml"), dict(common, **{"Output->File": name + ".h5"}))
        out = run([a.run, deck, "--threads", "1"], a.workdir)
        print([l for l in out.stdout.splitlines() if "per-step" in l or "steps/s" in l])
        h = history(os.path.join(a.workdir, name + ".h5"))
        F = h["bodies/Cube/contact/total_force"]
        t = h["time"]
        c = F > 1e-6 * F.max()
        res[name] = (F[c].mean(), t[c][-1] - t[c][0], h)
        print(f"{name:8s}: mean contact force {F[c].mean():.4e} N, max {F.max():.4e} N, contact {1e3 * (t[c][-1] - t[c][0]):.4f} ms, "
              f"energy balance {np.abs(h['energy/balance_error']).max():.1e}")
        if np.abs(h["energy/balance_error"]).max() > 1e-8:
            failures.append(f"{name}: energy balance error above 1e-8")
    ratio = res["flexible"][0] / res["rigid"][0]
    print(f"flexible / rigid mean contact force {ratio:.3f}; contact duration {res['flexible'][1] / res['rigid'][1]:.2f} x")
    if not 0.3 <= ratio <= 0.8:
        failures.append(f"mean contact force ratio {ratio:.3f} outside [0.3, 0.8]")
    if not res["flexible"][1] > res["rigid"][1]:
        failures.append("the contact does not last longer with flexible rings")
    h = res["flexible"][2]
    uL, uR = h["bodies/Left ring/nodesets/outer/displacement"], h["bodies/Right ring/nodesets/outer/displacement"]
    print(f"ring face deflection: max {1e3 * np.abs(uL).max():.4f} mm (left), {1e3 * np.abs(uR).max():.4f} mm (right)")
    if not np.abs(uL).max() > 1e-4:
        failures.append("the flexible rings do not move")
    # Mirror x -> -x maps one ring's face onto the other's: at every record, the X displacements
    # of the two faces, sorted, are opposite.
    scale = max(np.abs(uL).max(), 1e-300)
    worst = np.abs(np.sort(uL[:, :, 0], axis=1) - np.sort(-uR[:, :, 0], axis=1)).max()
    print(f"ring mirror symmetry (sorted X displacements): {worst:.2e} m of {scale:.2e} m")
    if not worst <= 1e-6 * scale:
        failures.append(f"the rings' responses are not mirror images ({worst / scale:.2e})")
    u = h["bodies/Cube/nodesets/y-/displacement"]
    nodes = list(h["bodies/Cube/nodesets/y-/nodes"])
    idx = {node: k for k, node in enumerate(nodes)}
    n, p = 6, 7
    worst, cs = 0.0, np.abs(u).max()
    for i in range(p):
        for k in range(p):
            q1, q2 = idx[i + p * (p * k)], idx[(n - i) + p * (p * (n - k))]
            worst = max(worst, np.abs(u[:, q1, 0] + u[:, q2, 0]).max(), np.abs(u[:, q1, 2] + u[:, q2, 2]).max(),
                        np.abs(u[:, q1, 1] - u[:, q2, 1]).max())
    print(f"cube bottom-face symmetry: {worst:.2e} m of {cs:.2e} m")
    if not worst <= 1e-6 * cs:
        failures.append(f"cube symmetry violated ({worst / cs:.2e})")
    g = h["bodies/Cube/contact/gap"]
    print(f"largest penetration after correction {max(0.0, -g.min()):.2e} m")
    if -g.min() > 1e-9:
        failures.append(f"penetration {-g.min():.2e} m > 1e-9 m")
    return verdict(failures)


if __name__ == "__main__":
    sys.exit(main())
