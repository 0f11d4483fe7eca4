#!/usr/bin/env python3
"""Every ctest has a TIMEOUT (cmake/EpapheTestTimeouts.cmake), so that nothing can hang a run.

    check_timeouts.py --build DIR --times tests/test-times.txt

Lists the build's tests with `ctest --show-only=json-v1` and asserts that each has a TIMEOUT > 0, and
that each test of the default run (every label but benchmark, long, study and finding) has a measured
time in test-times.txt, so that its timeout is a few times what it takes rather than a label default
(run tools/update-test-times after the tests to record new ones); this check and tests that may skip
(SKIP_RETURN_CODE) are exempt. Prints the tests with the smallest
margin between the timeout and the measured time.
"""
import argparse
import json
import subprocess
import sys

REST = ("benchmark", "long", "study", "finding")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", required=True)
    ap.add_argument("--times", required=True)
    a = ap.parse_args()
    out = subprocess.run(
        ["ctest", "--test-dir", a.build, "--show-only=json-v1"], capture_output=True, text=True, timeout=120, check=True
    ).stdout
    tests = json.loads(out)["tests"]
    times = {}
    for line in open(a.times, encoding="utf-8"):
        parts = line.split()
        if len(parts) == 2 and not line.startswith("#"):
            times[parts[0]] = float(parts[1])
    failures, margins = [], []
    for t in tests:
        props = {p["name"]: p["value"] for p in t.get("properties", [])}
        labels = props.get("LABELS", [])
        timeout = float(props.get("TIMEOUT", 0) or 0)
        if timeout <= 0:
            failures.append(f"{t['name']}: no TIMEOUT (call epaphe_test_timeouts() at the end of its CMakeLists.txt)")
            continue
        # not timed: this check itself (it passes only once the others have times), and a test that
        # skips on this machine (SKIP_RETURN_CODE; ctest records no time for a skipped run)
        default_run = (
            not any(label in REST for label in labels)
            and t["name"] != "unit.test-timeouts"
            and "SKIP_RETURN_CODE" not in props
        )
        if t["name"] in times:
            margins.append((timeout / max(times[t["name"]], 1e-3), t["name"], timeout, times[t["name"]]))
        elif default_run:
            failures.append(
                f"{t['name']}: no measured time in {a.times} (its TIMEOUT is the label default "
                f"{timeout:.0f} s); run it, then tools/update-test-times"
            )
    for ratio, name, timeout, seconds in sorted(margins)[:5]:
        print(f"smallest margins: {name}: TIMEOUT {timeout:.0f} s, measured {seconds:.1f} s ({ratio:.1f}x)")
    print(f"{len(tests)} tests, {len(tests) - len(failures)} with a TIMEOUT and, in the default run, a measured time")
    for f in failures:
        print("FAIL " + f)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
