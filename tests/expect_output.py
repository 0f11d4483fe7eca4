#!/usr/bin/env python3
"""Runs a command and passes only if it exits 0 AND its standard output contains a given text.

    expect_output.py --expect TEXT -- COMMAND [ARGS...]

ctest's PASS_REGULAR_EXPRESSION ignores the exit code (a program that prints the text and then
crashes would pass); this wrapper checks both. The command's output is echoed."""
import subprocess
import sys


def main():
    args = sys.argv[1:]
    if len(args) < 4 or args[0] != "--expect" or args[2] != "--":
        sys.stderr.write("usage: expect_output.py --expect TEXT -- COMMAND [ARGS...]\n")
        return 2
    text, cmd = args[1], args[3:]
    p = subprocess.run(cmd, capture_output=True, text=True)
    sys.stdout.write(p.stdout)
    sys.stderr.write(p.stderr)
    failures = []
    if p.returncode != 0:
        failures.append(f"{cmd[0]} exited with {p.returncode}, expected 0")
    if text not in p.stdout:
        failures.append(f"the output of {' '.join(cmd)} does not contain '{text}'")
    print("FAILED:\n  " + "\n  ".join(failures) if failures else "PASSED")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
