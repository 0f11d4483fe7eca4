#!/usr/bin/env python3
"""The reduced model is cached in HDF5 and reused while the model and reduction are unchanged.

Run 1 reduces and writes the cache; run 2 (same deck) must say it reused the cache and give a
bit-identical history; run 3 (one more mode) must reduce again.
"""
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "verification"))
from epaphe_testing import parse_args, run, variant  # noqa: E402


def main():
    a = parse_args()
    for f in os.listdir(a.workdir):
        os.remove(os.path.join(a.workdir, f))
    common = {
        "Time->End time": ("3e-5", "double"),
        "Bodies->Bar->Reduction->Fixed-interface modes": ("20", "int"),
        "Bodies->Bar->Reduction->Cache file": "bar.rom.h5",
    }
    logs, files = [], []
    for i, extra in enumerate([{}, {}, {"Bodies->Bar->Reduction->Fixed-interface modes": ("21", "int")}]):
        deck = variant(
            a.deck, os.path.join(a.workdir, f"run{i}.xml"), dict(common, **extra, **{"Output->File": f"run{i}.h5"})
        )
        logs.append(run([a.run, deck, "--threads", "1"], a.workdir).stdout)
        files.append(os.path.join(a.workdir, f"run{i}.h5"))
    failures = []
    if "Craig-Bampton:" not in logs[0]:
        failures.append("run 1 did not reduce")
    if "reused from bar.rom.h5" not in logs[1]:
        failures.append("run 2 did not reuse the cache")
    if "Craig-Bampton:" not in logs[2] or "reused" in logs[2]:
        failures.append("run 3 (21 modes) reused a cache made for 20 modes")
    with h5py.File(files[0], "r") as f0, h5py.File(files[1], "r") as f1:
        for path in ("bodies/Bar/contact/force", "bodies/Bar/nodesets/x+/displacement", "energy/total"):
            if not np.array_equal(f0[path][()], f1[path][()]):
                failures.append(f"{path} differs between the reduced run and the cached run")
    print("\n".join(l for log in logs for l in log.splitlines() if l.startswith("[Bar]")))
    print("FAILED:\n  " + "\n  ".join(failures) if failures else "PASSED")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
