#!/usr/bin/env python3
"""./epaphe reaches its commands on a machine without numpy (a new machine, before setup installs it).

Usage: check_entry_script.py --source DIR --workdir DIR

./epaphe runs under `set -euo pipefail`: a probe that fails at its top level (before the command is
dispatched) stops every command with status 1 and no message, setup included, on exactly the machines
that need setup. CI reuses a machine that has numpy, so this check hides numpy from Python (a package
`numpy` first on PYTHONPATH whose import fails) and runs `./epaphe help` without OPENBLAS_CORETYPE:
it must exit 0 and print the commands.
"""
import argparse
import os
import subprocess
import sys


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--source", required=True)
    parser.add_argument("--workdir", required=True)
    args = parser.parse_args()
    shadow = os.path.join(args.workdir, "no-numpy")
    os.makedirs(os.path.join(shadow, "numpy"), exist_ok=True)
    with open(os.path.join(shadow, "numpy", "__init__.py"), "w") as f:
        f.write('raise ImportError("numpy hidden by check_entry_script.py: a machine before setup")\n')
    env = dict(os.environ)
    env.pop("OPENBLAS_CORETYPE", None)
    env["PYTHONPATH"] = shadow
    hidden = subprocess.run(["/usr/bin/python3", "-c", "import numpy"], env=env, capture_output=True)
    if hidden.returncode == 0:
        sys.exit("check_entry_script: numpy still imports with PYTHONPATH=%s; the check would prove nothing" % shadow)
    run = subprocess.run(
        [os.path.join(args.source, "epaphe"), "help"], env=env, capture_output=True, text=True, timeout=60
    )
    if run.returncode != 0 or "./epaphe setup" not in run.stdout:
        sys.exit(
            "./epaphe help without numpy: exit status %d (expected 0 and the list of commands)\n"
            "stdout:\n%s\nstderr:\n%s\nA probe at the script's top level fails on a machine without numpy: "
            "run it after setup (as blas_coretype is)." % (run.returncode, run.stdout, run.stderr)
        )
    print("./epaphe help without numpy: exit status 0, the commands listed")


if __name__ == "__main__":
    main()
