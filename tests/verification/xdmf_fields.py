#!/usr/bin/env python3
"""Field output for ParaView: the XDMF file written beside the history points at datasets that
exist, with the shapes it declares, and every frame's positions are the mesh coordinates plus the
displacements (frame 0: the undeformed mesh). When ParaView's pvpython is given, the file is also
opened by ParaView's own XDMF reader and its time steps and bounds are checked."""
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from epaphe_testing import parse_args, run, variant, verdict  # noqa: E402


def main():
    a = parse_args("--pvpython")
    deck = variant(a.deck, os.path.join(a.workdir, "fields.xml"), {
        "Output->File": "fields.h5", "Output->Fields every": ("1000", "int"), "Time->End time": ("6e-4", "double"),
        "Time->Time step": ("2e-7", "double"), "Bodies->Cube->Initial velocity": ("{0, -10, 0}", "Array(double)")})
    run([a.run, deck, "--threads", "1"], a.workdir)
    failures = []
    xmf = os.path.join(a.workdir, "fields.xmf")
    root = ET.parse(xmf).getroot()
    with h5py.File(os.path.join(a.workdir, "fields.h5"), "r") as f:
        for item in root.iter("DataItem"):
            if item.get("Format") != "HDF":
                continue
            fname, path = item.text.strip().split(":")
            dims = tuple(int(d) for d in item.get("Dimensions").split())
            if path not in f or f[path].shape != dims:
                failures.append(f"{path}: declared {dims}, file has {f[path].shape if path in f else 'nothing'}")
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
    if a.pvpython != "none":
        script = os.path.join(a.workdir, "read.py")
        with open(script, "w") as s:
            s.write("from paraview.simple import *\n"
                    f"r = XDMFReader(FileNames=[{xmf!r}])\n"
                    "r.UpdatePipeline()\n"
                    "print('TIMES', len(r.TimestepValues))\n"
                    "r.UpdatePipeline(r.TimestepValues[-1])\n"
                    "print('BOUNDS', r.GetDataInformation().GetBounds())\n")
        out = subprocess.run([a.pvpython, script], capture_output=True, text=True)
        lines = [l for l in out.stdout.splitlines() if l.startswith(("TIMES", "BOUNDS"))]
        print("ParaView:", "; ".join(lines) or out.stderr[-500:])
        if not lines or int(lines[0].split()[1]) != frames:
            failures.append(f"ParaView's reader did not see {frames} time steps")
    return verdict(failures)


if __name__ == "__main__":
    sys.exit(main())
