#!/usr/bin/env python3
"""V6, section 4.2.1: convergence in the ring mesh. The rigid rings of inputs/cube-rings.xml are
interpolated through grids of the sizes of the thesis' four ring meshes' contact faces (very coarse
126 nodes: 14 x 3 on the face, here 14 x 4 since a bicubic needs 4; coarse 264: 22 x 4; fine 1050:
50 x 7; very fine 1872: 52 x 9). Measure (thesis Fig. 4.8a): the distance between the cube and the
rings (the smallest gap over the cube's contact nodes) against time; its largest difference to the
very fine mesh's. Asserted: it decreases monotonically from the very coarse to the fine mesh (the
thesis: 6.205, 1.208, 0.0016 mm), and each run's energy balance closes to 1e-8."""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from epaphe_testing import history, parse_args, run, variant  # noqa: E402

MESHES = [("very coarse", 14, 4), ("coarse", 22, 4), ("fine", 50, 7), ("very fine", 52, 9)]


def main():
    a = parse_args()
    dist = {}
    for name, nu, nv in MESHES:
        tag = name.replace(" ", "-")
        over = {
            "Output->File": tag + ".h5",
            "Time->End time": ("6e-4", "double"),
            "Output->Every": ("5", "int"),
            "Run->Progress interval": ("0", "double"),
        }
        for ring in ("Left ring", "Right ring"):
            over[f"Surfaces->{ring}->Points"] = (f"{{{nu}, {nv}}}", "Array(int)")
        deck = variant(a.deck, os.path.join(a.workdir, tag + ".xml"), over)
        run([a.run, deck, "--threads", "1"], a.workdir)
        h = history(os.path.join(a.workdir, tag + ".h5"))
        dist[name] = h["bodies/Cube/contact/gap"].min(axis=1)
        assert np.abs(h["energy/balance_error"]).max() <= 1e-8, f"{name}: energy balance"
    ref = dist["very fine"]
    diffs = []
    print("mesh          grid     max |distance - very fine| (mm)   thesis (mm)")
    for (name, nu, nv), thesis in zip(MESHES[:3], (6.205, 1.208, 0.0016)):
        d = 1e3 * np.abs(dist[name] - ref).max()
        diffs.append(d)
        print(f"{name:12s}  {nu:2d} x {nv}   {d:12.3e}                    {thesis}")
    ok = diffs[0] > diffs[1] > diffs[2]
    print("PASSED" if ok else f"FAILED: not monotone {diffs}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
