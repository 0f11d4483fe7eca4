#!/usr/bin/env python3
"""Bad decks are refused before anything runs, each with one message naming the problem.

Every case in cases/ is a deck (`<name>.xml`) whose first line is an XML comment
`<!-- expect: REGEX -->`; epaphe-run must exit non-zero, print a message matching REGEX on
stderr, and leave no output file behind that could pass for a result. A few decks that cannot be
case files (a missing deck, a directory, an empty file) are made in the work directory.
"""
import argparse
import glob
import os
import re
import subprocess
import sys


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
    for path, regex in cases:
        for f in glob.glob(os.path.join(a.workdir, "*.h5")):
            os.remove(f)
        proc = subprocess.run([a.run, path], cwd=a.workdir, capture_output=True, text=True)
        err = proc.stderr.strip()
        outputs = [f for f in os.listdir(a.workdir) if f.endswith(".h5") and not f.endswith(".rom.h5")]
        ok = proc.returncode != 0 and re.search(regex, err) and len(err.splitlines()) == 1 and not outputs
        print(f"{'ok  ' if ok else 'FAIL'} {os.path.basename(path)}: exit {proc.returncode}: {err}")
        if not ok:
            failed += 1
            print(f"     expected a one-line message matching /{regex}/, no output file (found {outputs})")
    print(f"{len(cases) - failed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
