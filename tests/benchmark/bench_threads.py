#!/usr/bin/env python3
"""Benchmark (reports, never asserts timings): any deck on 1 and 2 OpenMP threads.

Usage: bench_threads.py --run EPAPHE_RUN --deck DECK --workdir DIR --end END_TIME
Prints steps per second, the per-step cost split (from /run/cost of each run's HDF5 output) and the
speedup of 2 threads over 1. Output every 1000 steps so that the loop is measured; the reduced
model comes from the cache after the first run (setup is not part of the figures)."""
import os
import sys

import h5py

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "verification"))
from epaphe_testing import parse_args, run, variant  # noqa: E402


def main():
    a = parse_args("--end")
    rate = {}
    name = os.path.splitext(os.path.basename(a.deck))[0]
    for threads in (1, 2):
        tag = f"{name}-threads{threads}"
        deck = variant(
            a.deck,
            os.path.join(a.workdir, tag + ".xml"),
            {
                "Output->File": tag + ".h5",
                "Output->Every": ("1000", "int"),
                "Time->End time": (a.end, "double"),
                "Time->End revolutions": ("0", "double"),
                "Run->Progress interval": ("0", "double"),
            },
        )
        run([a.run, deck, "--threads", str(threads)], a.workdir)
        with h5py.File(os.path.join(a.workdir, tag + ".h5"), "r") as f:
            r = f["/run"].attrs
            cost = {k: v for k, v in f["/run/cost"].attrs.items()}
            steps = r["steps"]
            rate[threads] = r["steps_per_second"]
            split = ", ".join(f"{k} {1e6 * v / steps:.2f} us" for k, v in sorted(cost.items()))
            print(f"{name}: {threads} thread(s): {steps} steps, {rate[threads]:.0f} steps/s; per step: {split}")
    print(f"{name}: speedup on 2 threads: {rate[2] / rate[1]:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
