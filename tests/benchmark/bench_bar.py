#!/usr/bin/env python3
"""Benchmark (reports, never asserts timings): the bar-on-wall deck on 1 and 2 OpenMP threads.

Prints the reduction time, steps per second and the per-step cost split read from each run's HDF5
output, and the speedup of 2 threads over 1. Output every 1000 steps so that the loop is measured.
"""
import os
import sys

import h5py

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "verification"))
from epaphe_testing import parse_args, run, variant  # noqa: E402


def main():
    a = parse_args()
    rate = {}
    for threads in (1, 2):
        name = f"threads{threads}"
        deck = variant(
            a.deck,
            os.path.join(a.workdir, name + ".xml"),
            {
                "Output->File": name + ".h5",
                "Output->Every": ("1000", "int"),
                "Time->End time": ("2e-3", "double"),
                "Bodies->Bar->Reduction->Cache": ("false", "bool"),
                "Run->Progress interval": ("0", "double"),
            },
        )
        log = run([a.run, deck, "--threads", str(threads)], a.workdir).stdout
        with h5py.File(os.path.join(a.workdir, name + ".h5"), "r") as f:
            r = f["/run"].attrs
            cost = {k: v for k, v in f["/run/cost"].attrs.items()}
            steps = r["steps"]
            rate[threads] = r["steps_per_second"]
            print(
                f"{threads} thread(s): {steps} steps, {rate[threads]:.0f} steps/s, loop {r['loop_time']:.3f} s, "
                f"setup {r['setup_time']:.3f} s; per step: "
                + ", ".join(f"{k} {1e6 * v / steps:.2f} us" for k, v in sorted(cost.items()))
            )
        print("  " + "\n  ".join(l for l in log.splitlines() if l.startswith("[Bar] Craig")))
    print(f"speedup 2 threads / 1 thread: {rate[2] / rate[1]:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
