#!/usr/bin/env python3
"""V6 (thesis chapter 4), the part this release reproduces: a 5 cm steel cube falling between two
rigid rings (inputs/cube-rings.xml), Lagrange multipliers, no friction, no damping.

Checked:
  - 10 m/s and 50 m/s: the cube bounces back (final vertical velocity upward, within 1 % of the
    impact speed: no friction, no damping), the 50 m/s cube goes deeper between the rings;
  - symmetry (thesis 4.1.3): mirror nodes of the bottom face, (x, z) <-> (-x, -z), have opposite X
    and Z displacements and equal Y displacements, to 1e-6 of the largest displacement;
  - the energy balance of the run closes to 1e-8.
Not yet reproduced (see the issue notes): the 100 m/s pass-through, which needs far more
deformation energy than the cube carries with E = 210 GPa.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from epaphe_testing import history, parse_args, run, variant, verdict  # noqa: E402


def main():
    a = parse_args()
    failures = []
    depth = {}
    for v in (10, 50):
        name = f"v{v}"
        deck = variant(
            a.deck,
            os.path.join(a.workdir, name + ".xml"),
            {
                "Output->File": name + ".h5",
                "Time->Time step": ("2e-7", "double"),
                "Time->End time": ("1e-3", "double"),
                "Bodies->Cube->Initial velocity": (f"{{0, -{v}, 0}}", "Array(double)"),
                "Run->Progress interval": ("0", "double"),
            },
        )
        run([a.run, deck, "--threads", "1"], a.workdir)
        h = history(os.path.join(a.workdir, name + ".h5"))
        m = h["bodies/Cube/attrs"]["rigid_mass"]
        vy = h["bodies/Cube/momentum"][:, 1] / m
        uy = h["bodies/Cube/nodesets/all/displacement"][:, :, 1].mean(axis=1)
        depth[v] = -uy.min()
        balance = np.abs(h["energy/balance_error"]).max()
        print(
            f"{v:3d} m/s: final vertical velocity {vy[-1]:+.3f} m/s, deepest mean displacement {uy.min():.5f} m, "
            f"energy balance {balance:.1e}"
        )
        if not (vy[-1] > 0 and abs(vy[-1] - v) <= 0.01 * v):
            failures.append(f"{v} m/s: the cube does not bounce back at {v} m/s (final {vy[-1]:.3f} m/s)")
        if not balance <= 1e-8:
            failures.append(f"{v} m/s: energy balance error {balance:.2e} > 1e-8")
        if v == 50:
            # Mirror pairs of the bottom face: node (i, k) <-> (n-i, n-k) of the structured 6x6x6 box.
            nodes = list(h["bodies/Cube/nodesets/y-/nodes"])
            u = h["bodies/Cube/nodesets/y-/displacement"]
            n = 6
            idx = {node: c for c, node in enumerate(nodes)}
            px, py = n + 1, n + 1
            worst = 0.0
            scale = np.abs(u).max()
            for i in range(px):
                for k in range(px):
                    p, q = idx[i + px * (py * k)], idx[(n - i) + px * (py * (n - k))]
                    worst = max(
                        worst,
                        np.abs(u[:, p, 0] + u[:, q, 0]).max(),
                        np.abs(u[:, p, 2] + u[:, q, 2]).max(),
                        np.abs(u[:, p, 1] - u[:, q, 1]).max(),
                    )
            print(
                f"symmetry of the bottom face: largest violation {worst:.2e} m of {scale:.2e} m "
                f"({worst / scale:.1e})"
            )
            if not worst <= 1e-6 * scale:
                failures.append(f"symmetry violated: {worst / scale:.2e} > 1e-6")
    if not depth[50] > depth[10]:
        failures.append(f"the 50 m/s cube does not go deeper ({depth[50]:.4f} m) than at 10 m/s ({depth[10]:.4f} m)")
    return verdict(failures)


if __name__ == "__main__":
    sys.exit(main())
