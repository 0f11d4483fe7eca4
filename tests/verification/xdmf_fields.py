#!/usr/bin/env python3
"""Field output for ParaView, in two parts (two ctest tests):

  --part fields    (always runs) the XDMF file written beside the history points at datasets that
                   exist, with the shapes it declares, and every frame's positions are the mesh
                   coordinates plus the displacements (frame 0: the undeformed mesh); with an abradable
                   coating (--coating-deck, half a revolution of the blade), the coating's grid has a
                   frame per wear record, its quadrilaterals lie at the coating's unworn front (the
                   casing's radius less the thickness, within the clearance law's 0.2 mm), each frame's wear attribute
                   selects that record of /coating/<s>/wear;
  --part paraview  ParaView's own XDMF reader (pvpython) opens the file: as many time steps as field
                   frames, and the bounds of the last frame those of the positions in the HDF5 file.
                   Without pvpython (--pvpython none and none on PATH) it prints SKIPPED and exits 77,
                   which ctest reports as skipped (SKIP_RETURN_CODE 77), never as passed."""
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from epaphe_testing import parse_args, run, variant, verdict  # noqa: E402

SKIP = 77  # ctest SKIP_RETURN_CODE of verification.xdmf-paraview


def write_fields(a):
    """Runs the cube between the rings with field output; returns the .xmf path."""
    deck = variant(
        a.deck,
        os.path.join(a.workdir, "fields.xml"),
        {
            "Output->File": "fields.h5",
            "Output->Fields every": ("1000", "int"),
            "Time->End time": ("6e-4", "double"),
            "Time->Time step": ("2e-7", "double"),
            "Bodies->Cube->Initial velocity": ("{0, -10, 0}", "Array(double)"),
        },
    )
    run([a.run, deck, "--threads", "1"], a.workdir)
    return os.path.join(a.workdir, "fields.xmf")


def check_paraview(a):
    pv = a.pvpython if a.pvpython not in ("none", "") and os.access(a.pvpython, os.X_OK) else shutil.which("pvpython")
    if not pv:
        print(
            "SKIPPED: ParaView's pvpython is not installed, so its XDMF reader is not checked "
            "(Debian: apt-get install paraview python3-paraview, then configure again)"
        )
        return SKIP
    xmf = write_fields(a)
    failures = []
    with h5py.File(os.path.join(a.workdir, "fields.h5"), "r") as f:
        frames = len(f["/fields/time"])
        # what the reader shows at the last time: every body's last frame and the static surface
        # grids (the rings' points), as the .xmf declares them
        last = np.concatenate(
            [f[f"/bodies/{b}/fields/position"][-1] for b in f["/bodies"] if f"/bodies/{b}/fields/position" in f]
            + [f[f"/surfaces/{g}/points"][()] for g in f.get("/surfaces", {}) if f"/surfaces/{g}/points" in f]
        )
    lo, hi = last.min(axis=0), last.max(axis=0)
    script = os.path.join(a.workdir, "read.py")
    with open(script, "w") as s:
        s.write(
            "from paraview.simple import *\n"
            f"r = XDMFReader(FileNames=[{xmf!r}])\n"
            "r.UpdatePipeline()\n"
            "print('TIMES', len(r.TimestepValues))\n"
            "r.UpdatePipeline(r.TimestepValues[-1])\n"
            "print('BOUNDS', *r.GetDataInformation().GetBounds())\n"
        )
    out = subprocess.run([pv, script], capture_output=True, text=True)
    lines = [l for l in out.stdout.splitlines() if l.startswith(("TIMES", "BOUNDS"))]
    print(f"ParaView ({pv}, exit {out.returncode}):", "; ".join(lines) or out.stderr[-1000:])
    times = [int(l.split()[1]) for l in lines if l.startswith("TIMES")]
    bounds = [[float(x) for x in l.split()[1:]] for l in lines if l.startswith("BOUNDS")]
    if out.returncode != 0:
        failures.append(f"pvpython exited with {out.returncode}: {out.stderr[-500:]}")
    if times != [frames]:
        failures.append(f"ParaView's reader saw {times} time steps, the file has {frames} field frames")
    # bounds (xmin, xmax, ymin, ymax, zmin, zmax) of the last frame against the positions stored in
    # the HDF5 file: the reader must show the same numbers (1e-9 of the extent: float round-off)
    want = np.ravel(np.column_stack([lo, hi]))
    tol = 1e-9 * max(1.0, float(np.max(hi - lo)))
    if len(bounds) != 1 or len(bounds[0]) != 6 or np.max(np.abs(np.array(bounds[0]) - want)) > tol:
        failures.append(f"ParaView's bounds of the last frame {bounds} differ from the file's {want.tolist()}")
    return verdict(failures)


def check_hdf_items(root, f, failures):
    """Every HDF DataItem of the XDMF tree names a dataset of `f` with the dimensions it declares."""
    for item in root.iter("DataItem"):
        if item.get("Format") != "HDF":
            continue
        fname, path = item.text.strip().split(":")
        dims = tuple(int(d) for d in item.get("Dimensions").split())
        if path not in f or f[path].shape != dims:
            failures.append(f"{path}: declared {dims}, file has {f[path].shape if path in f else 'nothing'}")


def check_coating(a, failures):
    """The coating's grid in the XDMF file of half a revolution of the coated blade."""
    deck = variant(
        a.coating_deck,
        os.path.join(a.workdir, "coating.xml"),
        {
            "Output->File": "coating.h5",
            "Output->Fields every": ("5000", "int"),
            "Output->Wear every": ("5000", "int"),
            "Time->End revolutions": ("0.5", "double"),
        },
    )
    run([a.run, deck, "--threads", "1"], a.workdir)
    root = ET.parse(os.path.join(a.workdir, "coating.xmf")).getroot()
    with h5py.File(os.path.join(a.workdir, "coating.h5"), "r") as f:
        check_hdf_items(root, f, failures)
        g = f["coating/Casing"]
        wear, points = g["wear"][()], g["mesh/points"][()]
        grids = root.findall("./Domain/Grid[@Name='Casing coating']/Grid")
        if len(grids) != wear.shape[0]:
            failures.append(f"coating: {len(grids)} XDMF frames for {wear.shape[0]} wear records")
        for k, grid in enumerate(grids):
            start = grid.find("./Attribute[@Name='wear']/DataItem/DataItem").text.split()
            if int(start[0]) != k:
                failures.append(f"coating: frame {k} shows wear record {start[0]}")
        front = 0.3002 - g.attrs["thickness"]  # blade-coating.xml: Radius 0.3002, no clearance law change
        r = np.hypot(points[:, 0], points[:, 1])
        # the clearance law moves the casing by up to 0.15 mm from its Radius: within 0.2 mm of the front
        if not (np.abs(r - front).max() < 2e-4):
            failures.append(
                f"coating: quadrilateral corners at radii {r.min():.6f}-{r.max():.6f} m, front near {front}"
            )
        print(
            f"coating: {len(grids)} frames of {g['mesh/quads'].shape[0]} quadrilaterals at radii "
            f"{r.min():.6f}-{r.max():.6f} m; largest wear {wear.max() * 1e6:.3g} um"
        )


def main():
    a = parse_args("--pvpython", "--part", "--coating-deck")
    if a.part == "paraview":
        return check_paraview(a)
    if a.part != "fields":
        raise SystemExit(f"--part {a.part}: expected fields or paraview")
    xmf = write_fields(a)
    failures = []
    root = ET.parse(xmf).getroot()
    with h5py.File(os.path.join(a.workdir, "fields.h5"), "r") as f:
        check_hdf_items(root, f, failures)
        X = f["/bodies/Cube/mesh/coordinates"][()]
        P = f["/bodies/Cube/fields/position"][()]
        U = f["/bodies/Cube/fields/displacement"][()]
        frames = len(f["/fields/time"])
        if not np.allclose(P, X[None] + U, rtol=0, atol=1e-15):
            failures.append("positions are not coordinates + displacements")
        if not np.allclose(P[0], X, rtol=0, atol=1e-15):
            failures.append("frame 0 is not the undeformed mesh")
        grids = root.findall("./Domain/Grid[@Name='Cube']/Grid")
        if len(grids) != frames:
            failures.append(f"{len(grids)} XDMF frames for {frames} field records")
        print(f"{frames} frames of {X.shape[0]} nodes; largest displacement {np.abs(U).max():.3e} m")
    check_coating(a, failures)
    return verdict(failures)


if __name__ == "__main__":
    sys.exit(main())
