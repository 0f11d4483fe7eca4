#!/usr/bin/env python3
"""Bad decks are refused before anything runs, each with one message naming the problem.

Every case in cases/ is a deck (`<name>.xml`) whose first line is an XML comment
`<!-- expect: REGEX -->`; epaphe-run must exit non-zero, print a message matching REGEX on
stderr, and leave no output file behind that could pass for a result. A few decks that cannot be
case files (a missing deck, a directory, an empty file) are made in the work directory.

`epaphe-run --check DECK` must refuse every case with the very message of the run (one validation,
Epaphe_SceneCheck.hpp), except the few in RUN_TIME_ONLY, whose fault only the setup can see; those
must pass --check, so that the list stays exact.
"""
import argparse
import concurrent.futures
import glob
import os
import re
import shutil
import subprocess
import sys


# Faults that need the reduced model or the contact detection, which --check does not build.
RUN_TIME_ONLY = {
    # the critical step is the reduced model's highest frequency (with the penalty springs):
    # known once the body is reduced (or its lumped mass model's eigenvalue computed)
    "unstable-time-step.xml": "critical step of the reduced model",
    "full-lumped-unstable-time-step.xml": "critical step of the lumped full model",
    "penalty-too-stiff.xml": "critical step of the reduced model with the penalty springs",
    # the closest-point projection of every contact node on the B-spline surfaces at t = 0
    "bodies-start-interpenetrating.xml": "contact detection at t = 0",
    "wall-facing-away.xml": "contact detection at t = 0",
    # the smallest patch of the B-spline surfaces, against |v0| h
    "tunnelling-initial-velocity.xml": "patch sizes of the built B-spline surfaces",
}


def one_case(run, workdir, path, regex):
    """Runs one bad deck, then --check on it; the report lines (a line starting FAIL is a failure)."""
    name = os.path.basename(path)
    work = os.path.join(workdir, "cases", os.path.splitext(name)[0])
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    proc = subprocess.run([run, path], cwd=work, capture_output=True, text=True)
    err = proc.stderr.strip()
    outputs = [f for f in os.listdir(work) if f.endswith(".h5") and not f.endswith(".rom.h5")]
    ok = proc.returncode != 0 and re.search(regex, err) and len(err.splitlines()) == 1 and not outputs
    lines = [f"{'ok  ' if ok else 'FAIL'} {name}: exit {proc.returncode}: {err}"]
    if not ok:
        lines.append(f"     expected a one-line message matching /{regex}/, no output file (found {outputs})")
    chk = subprocess.run([run, "--check", path], cwd=work, capture_output=True, text=True)
    if name in RUN_TIME_ONLY:
        if chk.returncode != 0:
            lines.append(f"FAIL {name}: listed as seen only at run time ({RUN_TIME_ONLY[name]}), but --check refuses "
                         f"it now: {chk.stderr.strip()}; remove it from RUN_TIME_ONLY")
    elif chk.returncode == 0 or chk.stderr.strip() != err:
        lines.append(f"FAIL {name}: --check exit {chk.returncode}, message\n       {chk.stderr.strip()}\n     the "
                     f"run's\n       {err}")
    return lines


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--run", required=True)
    ap.add_argument("--cases", required=True)
    ap.add_argument("--workdir", required=True)
    a = ap.parse_args()
    os.makedirs(a.workdir, exist_ok=True)
    failed = 0
    cases = []
    for path in sorted(glob.glob(os.path.join(a.cases, "*.xml"))):
        first = open(path).readline()
        m = re.match(r"<!-- expect: (.*) -->", first.strip())
        assert m, f"{path}: first line must be <!-- expect: REGEX -->"
        cases.append((path, m.group(1)))
    made = os.path.join(a.workdir, "made")
    os.makedirs(os.path.join(made, "directory.xml"), exist_ok=True)
    open(os.path.join(made, "empty.xml"), "w").close()
    cases += [(os.path.join(made, "missing.xml"), r"deck '.*missing.xml' cannot be opened"),
              (os.path.join(made, "directory.xml"), r"deck '.*directory.xml' is a directory"),
              (os.path.join(made, "empty.xml"), r"empty.xml' is empty")]
    # Each case in its own directory, two at a time (each run is one process on one thread).
    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        results = list(pool.map(lambda c: one_case(a.run, a.workdir, *c), cases))
    for lines in results:
        print("\n".join(lines))
        failed += any(line.startswith("FAIL") for line in lines)
    print(f"{len(cases) - failed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
