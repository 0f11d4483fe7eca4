#!/usr/bin/env python3
"""A blade-like CalculiX model: a twisted plate of 20-node hexahedra (C3D20) or 15-node wedges
(C3D15), clamped at its root.

The plate spans x in [0, L] (root at x = 0), its chord y in [-c/2, c/2] and its thickness z in
[-t/2, t/2]; the section at x is twisted by twist * x / L about the x axis. Written:

  mesh.inp    *NODE, *ELEMENT (ELSET EALL), node sets ROOT (x = 0), TIP (x = L),
              TIP16 (16 corner nodes of the tip's upper edge, evenly spread along the chord)
  mat.inp     steel, *BOUNDARY ROOT 1-3, *FREQUENCY, SOLVER=MATRIXSTORAGE (ccx writes mat.sti/.mas/.dof)
  freq.inp    the same model with *FREQUENCY (ccx's own eigenvalues in freq.dat), with --modes N;
              with --storage, STORAGE=YES: ccx writes freq.eig, the eigenvalues as binary doubles

--element C3D20 (default): one 20-node hexahedron per cell. --element C3D15: each cell split by its
diagonal (0,0)-(1,1) in the (x, y) plane into two 15-node wedges extruded through the thickness z
(triangles counter-clockwise seen from +z, so both wedges have a positive Jacobian); the diagonal's
mid-edge nodes (bottom and top face) are added to the C3D20 cell's nodes, no face-centre node.
CalculiX C3D15 order: corners 1-3 bottom triangle, 4-6 top, 7-9 bottom mid-edges (1-2, 2-3, 3-1),
10-12 top mid-edges, 13-15 vertical mid-edges (1-4, 2-5, 3-6).
Checked with ccx 2.20 *FREQUENCY (--freq --storage), 20 x 6 x 1 cells, default lengths and twist
(measured 2026-11-24): the first 10 frequencies of C3D15 are within 0.18 % of C3D20's on the same
cells (C3D15 lower: f1 256.7098 vs 256.7245 Hz, the largest difference mode 3, 1762.489 vs
1765.701 Hz), well inside 2 %; every wedge's corner Jacobian is positive (ccx refuses a negative
one). tests/benchmark/bench_setup.py imports a C3D15 blade into Epaphe and checks its frequencies
against ccx's.

--units m (default): lengths in m, E in Pa, density in kg/m^3 (steel 2.1e11 Pa, 7800 kg/m^3).
--units mm: the mm-tonne-s system of real blade models: lengths in mm, E in MPa = N/mm^2 (2.1e5),
density in t/mm^3 (7.8e-9); frequencies in Hz are the same (ccx, 20 x 6 x 1 cells, C3D20 and
C3D15: the first 10 agree to 5.4e-10 relative between m and mm). --lengths are in the chosen unit
(defaults 0.1 0.03 0.003 m, or 100 30 3 mm).

Usage: blade_model.py DIR [--cells NX NY NZ] [--lengths L C T] [--twist DEG] [--element C3D20|C3D15]
                      [--units m|mm] [--modes N] [--run CCX [--freq [--storage]]]
"""
import argparse
import math
import os
import subprocess
import sys
import time

# C3D20 nodes in (i, j, k) half-cell offsets, CalculiX/Abaqus order.
C3D20 = [
    (0, 0, 0),
    (2, 0, 0),
    (2, 2, 0),
    (0, 2, 0),
    (0, 0, 2),
    (2, 0, 2),
    (2, 2, 2),
    (0, 2, 2),
    (1, 0, 0),
    (2, 1, 0),
    (1, 2, 0),
    (0, 1, 0),
    (1, 0, 2),
    (2, 1, 2),
    (1, 2, 2),
    (0, 1, 2),
    (0, 0, 1),
    (2, 0, 1),
    (2, 2, 1),
    (0, 2, 1),
]

# The two C3D15 wedges of a cell: triangles in (i, j) half-cell offsets, counter-clockwise seen from
# +z, extruded through the thickness (k offsets 0, 2); the diagonal (0, 0)-(2, 2) is shared.
WEDGE_TRIANGLES = [((0, 0), (2, 0), (2, 2)), ((0, 0), (2, 2), (0, 2))]


def c3d15(tri):
    """The 15 nodes of a wedge over triangle `tri` in (i, j, k) half-cell offsets, CalculiX order."""
    corners = [(a, b, k) for k in (0, 2) for a, b in tri]  # 1-3, 4-6
    mids = [
        ((tri[n][0] + tri[(n + 1) % 3][0]) // 2, (tri[n][1] + tri[(n + 1) % 3][1]) // 2, k)
        for k in (0, 2)
        for n in range(3)
    ]  # 7-9, 10-12
    vertical = [(a, b, 1) for a, b in tri]  # 13-15
    return corners + mids + vertical


# Material and default lengths per unit system (lengths, E, density): SI, and mm-tonne-s.
UNITS = {"m": ([0.1, 0.03, 0.003], "2.1e11", "7800."), "mm": ([100.0, 30.0, 3.0], "2.1e5", "7.8e-9")}


def write_model(d, cells, lengths, twist_deg, modes, storage=False, element="C3D20", units="m"):
    nx, ny, nz = cells
    L, c, t = lengths
    ids = {}

    def node(p):
        n = ids.get(p)
        if n is None:
            n = ids[p] = len(ids) + 1
        return n

    shapes = [C3D20] if element == "C3D20" else [c3d15(tri) for tri in WEDGE_TRIANGLES]
    elements = []
    for k in range(0, 2 * nz, 2):
        for j in range(0, 2 * ny, 2):
            for i in range(0, 2 * nx, 2):
                for shape in shapes:
                    elements.append([node((i + a, j + b, k + e)) for a, b, e in shape])
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, "mesh.inp"), "w") as f:
        # ccx reads a number from at most 20 characters: 13 significant digits fit with sign and exponent.
        f.write(
            f"** twisted plate of {element}{' in mm-tonne-s units' if units == 'mm' else ''} written by blade_model.py\n"
            "*NODE, NSET=NALL\n"
        )
        for (i, j, k), n in sorted(ids.items(), key=lambda kv: kv[1]):
            x = L * i / (2 * nx)
            y = c * (j / (2 * ny) - 0.5)
            z = t * (k / (2 * nz) - 0.5)
            a = math.radians(twist_deg) * x / L
            f.write(
                f"{n}, {x:.13g}, {y * math.cos(a) - z * math.sin(a):.13g}, {y * math.sin(a) + z * math.cos(a):.13g}\n"
            )
        f.write(f"*ELEMENT, TYPE={element}, ELSET=EALL\n")
        first = 15 if element == "C3D20" else 10  # a data line holds at most 16 entries; a trailing comma continues
        for e, nodes in enumerate(elements, 1):
            f.write(f"{e}, " + ", ".join(map(str, nodes[:first])) + ",\n" + ", ".join(map(str, nodes[first:])) + "\n")

        def nset(name, members):
            f.write(f"*NSET, NSET={name}\n")
            for s in range(0, len(members), 12):
                f.write(", ".join(map(str, members[s : s + 12])) + ",\n")

        nset("ROOT", sorted(n for (i, j, k), n in ids.items() if i == 0))
        nset("TIP", sorted(n for (i, j, k), n in ids.items() if i == 2 * nx))
        # 16 retained nodes: corner nodes of the tip's upper edge, evenly spread along the chord.
        corners = list(range(0, 2 * ny + 1, 2))
        pick = (
            sorted({corners[round(q * (len(corners) - 1) / 15)] for q in range(16)}) if len(corners) >= 16 else corners
        )
        nset("TIP16", [ids[(2 * nx, j, 2 * nz)] for j in pick])
    _, young, density = UNITS[units]
    common = (
        f"*INCLUDE, INPUT=mesh.inp\n*MATERIAL, NAME=STEEL\n*ELASTIC\n{young}, 0.3\n*DENSITY\n{density}\n"
        "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n*BOUNDARY\nROOT, 1, 3\n*STEP\n"
    )
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
    p.add_argument(
        "--lengths",
        type=float,
        nargs=3,
        default=None,
        help="span, chord, thickness in --units (default 0.1 0.03 0.003 m = 100 30 3 mm)",
    )
    p.add_argument("--twist", type=float, default=30.0)
    p.add_argument(
        "--element",
        choices=["C3D20", "C3D15"],
        default="C3D20",
        help="C3D20: a hexahedron per cell; C3D15: two wedges per cell",
    )
    p.add_argument(
        "--units", choices=sorted(UNITS), default="m", help="m: SI (m, Pa, kg/m^3); mm: mm-tonne-s (mm, MPa, t/mm^3)"
    )
    p.add_argument("--modes", type=int, default=10)
    p.add_argument("--run", default="", help="ccx binary: run mat.inp (matrices) and, with --freq, freq.inp")
    p.add_argument("--freq", action="store_true", help="also run freq.inp (ccx's eigenvalues)")
    p.add_argument("--storage", action="store_true", help="freq.inp with STORAGE=YES (freq.eig: exact eigenvalues)")
    a = p.parse_args()
    lengths = a.lengths if a.lengths is not None else UNITS[a.units][0]
    nodes, elements = write_model(a.dir, a.cells, lengths, a.twist, a.modes, a.storage, a.element, a.units)
    print(
        f"[blade] {elements} {a.element}, {nodes} nodes, {3 * nodes} DOFs (before the root is clamped) in {a.dir} "
        f"(units {a.units})"
    )
    if a.run:
        for job in ["mat"] + (["freq"] if a.freq else []):
            t0 = time.time()
            run_ccx(a.run, a.dir, job)
            print(f"[blade] ccx {job}: {time.time() - t0:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
