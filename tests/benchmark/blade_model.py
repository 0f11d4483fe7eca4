#!/usr/bin/env python3
"""A blade-like CalculiX model: a twisted plate of 20-node hexahedra (C3D20), clamped at its root.

The plate spans x in [0, L] (root at x = 0), its chord y in [-c/2, c/2] and its thickness z in
[-t/2, t/2]; the section at x is twisted by twist * x / L about the x axis. Written:

  mesh.inp    *NODE, *ELEMENT (C3D20, ELSET EALL), node sets ROOT (x = 0), TIP (x = L),
              TIP16 (16 corner nodes of the tip's upper edge, evenly spread along the chord)
  mat.inp     steel, *BOUNDARY ROOT 1-3, *FREQUENCY, SOLVER=MATRIXSTORAGE (ccx writes mat.sti/.mas/.dof)
  freq.inp    the same model with *FREQUENCY (ccx's own eigenvalues in freq.dat), with --modes N;
              with --storage, STORAGE=YES: ccx writes freq.eig, the eigenvalues as binary doubles

Usage: blade_model.py DIR [--cells NX NY NZ] [--lengths L C T] [--twist DEG] [--modes N] [--run CCX [--freq [--storage]]]
"""
import argparse
import math
import os
import subprocess
import sys
import time

# C3D20 nodes in (i, j, k) half-cell offsets, CalculiX/Abaqus order.
C3D20 = [(0, 0, 0), (2, 0, 0), (2, 2, 0), (0, 2, 0), (0, 0, 2), (2, 0, 2), (2, 2, 2), (0, 2, 2),
         (1, 0, 0), (2, 1, 0), (1, 2, 0), (0, 1, 0), (1, 0, 2), (2, 1, 2), (1, 2, 2), (0, 1, 2),
         (0, 0, 1), (2, 0, 1), (2, 2, 1), (0, 2, 1)]


def write_model(d, cells, lengths, twist_deg, modes, storage=False):
    nx, ny, nz = cells
    L, c, t = lengths
    ids = {}

    def node(p):
        n = ids.get(p)
        if n is None:
            n = ids[p] = len(ids) + 1
        return n

    elements = []
    for k in range(0, 2 * nz, 2):
        for j in range(0, 2 * ny, 2):
            for i in range(0, 2 * nx, 2):
                elements.append([node((i + a, j + b, k + e)) for a, b, e in C3D20])
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, "mesh.inp"), "w") as f:
        # ccx reads a number from at most 20 characters: 13 significant digits fit with sign and exponent.
        f.write("** twisted plate of C3D20 written by blade_model.py\n*NODE, NSET=NALL\n")
        for (i, j, k), n in sorted(ids.items(), key=lambda kv: kv[1]):
            x = L * i / (2 * nx)
            y = c * (j / (2 * ny) - 0.5)
            z = t * (k / (2 * nz) - 0.5)
            a = math.radians(twist_deg) * x / L
            f.write(f"{n}, {x:.13g}, {y * math.cos(a) - z * math.sin(a):.13g}, {y * math.sin(a) + z * math.cos(a):.13g}\n")
        f.write("*ELEMENT, TYPE=C3D20, ELSET=EALL\n")
        for e, nodes in enumerate(elements, 1):
            f.write(f"{e}, " + ", ".join(map(str, nodes[:15])) + ",\n" + ", ".join(map(str, nodes[15:])) + "\n")

        def nset(name, members):
            f.write(f"*NSET, NSET={name}\n")
            for s in range(0, len(members), 12):
                f.write(", ".join(map(str, members[s:s + 12])) + ",\n")

        nset("ROOT", sorted(n for (i, j, k), n in ids.items() if i == 0))
        nset("TIP", sorted(n for (i, j, k), n in ids.items() if i == 2 * nx))
        # 16 retained nodes: corner nodes of the tip's upper edge, evenly spread along the chord.
        corners = list(range(0, 2 * ny + 1, 2))
        pick = sorted({corners[round(q * (len(corners) - 1) / 15)] for q in range(16)}) if len(corners) >= 16 else corners
        nset("TIP16", [ids[(2 * nx, j, 2 * nz)] for j in pick])
    common = ("*INCLUDE, INPUT=mesh.inp\n*MATERIAL, NAME=STEEL\n*ELASTIC\n2.1e11, 0.3\n*DENSITY\n7800.\n"
              "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n*BOUNDARY\nROOT, 1, 3\n*STEP\n")
    with open(os.path.join(d, "mat.inp"), "w") as f:
        f.write(common + "*FREQUENCY, SOLVER=MATRIXSTORAGE\n*END STEP\n")
    with open(os.path.join(d, "freq.inp"), "w") as f:
        # STORAGE=YES: ccx also writes freq.eig, its eigenvalues in binary double precision.
        f.write(common + f"*FREQUENCY{', STORAGE=YES' if storage else ''}\n{modes}\n*END STEP\n")
    return len(ids), len(elements)


def run_ccx(ccx, d, job):
    env = dict(os.environ, OMP_NUM_THREADS="1")
    with open(os.path.join(d, job + ".log"), "w") as log:
        subprocess.run([ccx, "-i", job], cwd=d, stdout=log, stderr=subprocess.STDOUT, env=env, check=True)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("dir")
    p.add_argument("--cells", type=int, nargs=3, default=[100, 30, 1])
    p.add_argument("--lengths", type=float, nargs=3, default=[0.1, 0.03, 0.003])
    p.add_argument("--twist", type=float, default=30.0)
    p.add_argument("--modes", type=int, default=10)
    p.add_argument("--run", default="", help="ccx binary: run mat.inp (matrices) and, with --freq, freq.inp")
    p.add_argument("--freq", action="store_true", help="also run freq.inp (ccx's eigenvalues)")
    p.add_argument("--storage", action="store_true", help="freq.inp with STORAGE=YES (freq.eig: exact eigenvalues)")
    a = p.parse_args()
    nodes, elements = write_model(a.dir, a.cells, a.lengths, a.twist, a.modes, a.storage)
    print(f"[blade] {elements} C3D20, {nodes} nodes, {3 * nodes} DOFs (before the root is clamped) in {a.dir}")
    if a.run:
        for job in ["mat"] + (["freq"] if a.freq else []):
            t0 = time.time()
            run_ccx(a.run, a.dir, job)
            print(f"[blade] ccx {job}: {time.time() - t0:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
