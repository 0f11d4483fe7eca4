#!/usr/bin/env python3
"""A 50-speed interaction map over a rotating blade reduces nothing per speed (issue 31, item 7 and its
performance section).

Runs `epaphe-rotor map` on inputs/blade-casing-at-speed.xml (parametric model over 0-1500 rad/s) at 50
speeds from 500 to 1500 rad/s, one revolution each (the map's spectrum needs one), in an empty
directory (no reduced-model cache to start from), and asserts from the runs' own log lines and
summaries:
  - the parametric model is built exactly once ("parametric model over ... Craig-Bampton reductions");
  - every one of the 50 runs takes its model from it ("... at W rad/s from the parametric model") and
    the 49 after the first reuse it from the cache ("reused from"; their summaries say "from cache");
  - no run builds a full model or reduces one directly (no "full model:" line, no "Craig-Bampton: N
    retained DOFs" line: the lines a direct reduction prints);
  - the map (map.h5, /speeds of 50 entries) is written."""
import argparse
import glob
import os
import re
import shutil
import subprocess
import sys

import h5py

SPEEDS = [500 + 1000 * k / 49 for k in range(50)]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rotor", required=True)
    ap.add_argument("--run", required=True)
    ap.add_argument("--deck", required=True)
    ap.add_argument("--workdir", required=True)
    a = ap.parse_args()
    out = os.path.join(a.workdir, "map")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(a.workdir, exist_ok=True)
    cmd = [
        sys.executable,
        a.rotor,
        "map",
        a.deck,
        "--speeds",
        ",".join(f"{w:g}" for w in SPEEDS),
        "--revs",
        "1",
        "--skip",
        "0",
        "--run",
        a.run,
        "--out",
        out,
    ]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=900)
    log = p.stdout
    if p.returncode != 0:
        print(log, p.stderr)
        sys.exit(f"FAILED: epaphe-rotor map exited with {p.returncode}")
    built = len(re.findall(r"\] parametric model over .* Craig-Bampton reductions", log))
    taken = len(re.findall(r"\] Craig-Bampton at \S+ rad/s from the parametric model", log))
    reused = log.count("reused from")
    direct = len(re.findall(r"\] full model: |\] Craig-Bampton: \d+ retained DOFs", log))
    summaries = sorted(glob.glob(os.path.join(out, "speed-*.summary.txt")))
    cached = sum(", from cache" in open(s).read() for s in summaries)
    with h5py.File(os.path.join(out, "map.h5"), "r") as f:
        mapped = len(f["speeds"][()])
    print(
        f"{len(SPEEDS)} speeds: parametric model built {built} time(s) (1 asserted), taken from it by {taken} runs "
        f"(50), reused from the cache by {reused} (49; {cached} summaries say so), direct reductions {direct} (0); "
        f"map over {mapped} speeds"
    )
    failures = []
    if built != 1:
        failures.append(f"the parametric model was built {built} times, not once")
    if taken != len(SPEEDS):
        failures.append(f"{taken} of {len(SPEEDS)} runs took their model from the parametric model")
    if reused != len(SPEEDS) - 1 or cached != len(SPEEDS) - 1:
        failures.append(f"{reused} runs (log) and {cached} summaries reused the cache, {len(SPEEDS) - 1} expected")
    if direct:
        failures.append(f"{direct} log lines of a full model built or reduced directly")
    if mapped != len(SPEEDS):
        failures.append(f"map.h5 holds {mapped} speeds, not {len(SPEEDS)}")
    for m in failures:
        print("FAIL " + m)
    print("FAILED" if failures else "PASSED")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
