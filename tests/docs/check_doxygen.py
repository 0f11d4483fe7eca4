#!/usr/bin/env python3
"""The API documentation builds without a warning: every public class and function of the installed
headers documented, every reference and command resolved (cmake/Doxyfile.in, WARN_IF_UNDOCUMENTED).

Usage: check_doxygen.py --doxygen DOXYGEN --doxyfile DOXYFILE --workdir DIR

Runs DOXYGEN on DOXYFILE (configured by cmake/EpapheDoc.cmake: output and warning log in DIR, emptied
first) and fails listing the warnings if there is any, or if no index.html was written. Without doxygen
(an empty DOXYGEN) it exits 77, which ctest reports as skipped; ./epaphe setup installs Debian's doxygen.
"""
import argparse
import os
import shutil
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "verification"))
from epaphe_testing import verdict  # noqa: E402

SKIPPED = 77  # the test's SKIP_RETURN_CODE
TIMEOUT = 300  # doxygen over the installed headers takes a few seconds


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--doxygen", default="")
    ap.add_argument("--doxyfile", required=True)
    ap.add_argument("--workdir", required=True)
    args = ap.parse_args()
    if not args.doxygen or not os.path.exists(args.doxyfile):
        print("SKIPPED: doxygen was not found when the build was configured (./epaphe setup installs it)")
        return SKIPPED
    shutil.rmtree(args.workdir, ignore_errors=True)
    os.makedirs(args.workdir)
    start = time.monotonic()
    run = subprocess.run(
        [args.doxygen, args.doxyfile], capture_output=True, text=True, timeout=TIMEOUT, cwd=args.workdir
    )
    print("doxygen %s: exit %d in %.1f s" % (args.doxyfile, run.returncode, time.monotonic() - start))
    failures = []
    if run.returncode != 0:
        failures.append("doxygen exited with %d: %s" % (run.returncode, run.stderr.strip()[-2000:]))
    log = os.path.join(args.workdir, "warnings.txt")
    warnings = []
    if os.path.exists(log):
        with open(log, encoding="utf-8", errors="replace") as f:
            warnings = [line.rstrip() for line in f if line.strip()]
    else:
        failures.append("no warning log %s: is WARN_LOGFILE set in %s?" % (log, args.doxyfile))
    # doxygen repeats a warning per place the member is inherited or listed: report each once
    unique = list(dict.fromkeys(warnings))
    if unique:
        failures.append(
            "%d doxygen warnings (document each entity with /// in its header, fix the reference or "
            "command):\n    %s" % (len(unique), "\n    ".join(unique))
        )
    if not os.path.exists(os.path.join(args.workdir, "html", "index.html")):
        failures.append("no %s written" % os.path.join(args.workdir, "html", "index.html"))
    return verdict(failures)


if __name__ == "__main__":
    sys.exit(main())
