#!/usr/bin/env python3
"""epaphe-run --kernel-times (label unit, ~3 s): the run's loop timed kernel by kernel.

    kernel_times.py --run EPAPHE_RUN --deck inputs/bar-on-wall.xml --workdir DIR

Runs the deck on 2 threads with every loop a kernel (EPAPHE_SERIAL_WORK_NS=0), with and without the
flag, and checks the table printed after the summary:
  * "kernels: N launches, T ms of the loop's L ms": N > 0 and 0 < T <= L (the kernels are timed
    inside the loop), L the summary's own loop time;
  * one line per kernel: launches >= 1, on team within [0, 100] %, us/launch = time / launches and
    % loop = time / L (to the printed digits), the launches and times summing to N and T;
  * the longest first, and the scene's contact kernels (epaphe::contact::detect, ::correction) and
    the integration's (epaphe::dynamics::gemv) among them, some of their launches on the team;
  * without the flag, no table, and the same results (the timing changes nothing).
"""
import os
import re
import sys

import h5py

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "verification"))
from epaphe_testing import kernel_rows, parse_args, run, verdict  # noqa: E402


def histories(path):
    """Every dataset under /bodies and /energy, as bytes."""
    out = {}
    with h5py.File(path, "r") as f:
        for group in ("bodies", "energy"):
            f[group].visititems(
                lambda name, obj: out.__setitem__(f"{group}/{name}", obj[()].tobytes())
                if isinstance(obj, h5py.Dataset)
                else None
            )
    return out


def main():
    a = parse_args()
    os.environ.update(EPAPHE_SERIAL_WORK_NS="0", OMP_PROC_BIND="false")
    cmd = [a.run, a.deck, "--threads", "2", "--output"]
    timed = run(cmd + [os.path.join(a.workdir, "timed.h5"), "--kernel-times"], a.workdir, timeout=300).stdout
    plain = run(cmd + [os.path.join(a.workdir, "plain.h5")], a.workdir, timeout=300).stdout
    print(timed)
    failures = []

    def check(ok, what):
        if not ok:
            failures.append(what)

    loop = re.search(r"loop ([\d.]+) (m?s),", timed)
    head = re.search(r"^kernels: (\d+) launches, ([\d.]+) ms of the loop's ([\d.]+) ms", timed, re.M)
    check(loop and head, "the summary's loop time and the kernels' line")
    if not failures:
        loop_ms = float(loop.group(1)) * (1 if loop.group(2) == "ms" else 1e3)
        n, total, of = int(head.group(1)), float(head.group(2)), float(head.group(3))
        check(n > 0 and 0 < total <= of * 1.001, f"{n} launches, {total} ms of {of} ms")
        check(abs(of - loop_ms) <= 0.1 + 1e-3 * loop_ms, f"the table's loop {of} ms, the summary's {loop_ms} ms")
        rows = kernel_rows(timed)
        check(len(rows) >= 4, f"{len(rows)} kernel lines")
        names = [k["name"] for k in rows]
        ms = [k["ms"] for k in rows]
        for k in rows:
            name, l, t, m = k["name"], k["launches"], k["on_team"], k["ms"]
            us, share = k["us_per_launch"], k["loop_percent"]
            check(l >= 1 and 0 <= t <= 1, f"{name}: {l} launches, {100 * t} % on the team")
            check(abs(us - 1e3 * m / l) <= 0.01 + 0.01 * us, f"{name}: {us} us a launch, {m} ms / {l}")
            check(abs(share - 100 * m / of) <= 0.1, f"{name}: {share} % of the loop, {m} ms of {of}")
        check(ms == sorted(ms, reverse=True), "the longest first")
        launches = sum(k["launches"] for k in rows)
        check(launches == n, f"launches {launches} against {n}")
        check(abs(sum(ms) - total) <= 0.01 * len(ms) + 1e-3 * total, f"times {sum(ms)} ms against {total}")
        for k in ("epaphe::contact::detect", "epaphe::contact::correction", "epaphe::dynamics::gemv"):
            check(k in names, f"{k} timed")
        check(any(k["on_team"] > 0 for k in rows), "some launches on the team")
    check("kernels:" not in plain, "no table without --kernel-times")
    check(
        histories(os.path.join(a.workdir, "timed.h5")) == histories(os.path.join(a.workdir, "plain.h5")),
        "the same histories (bodies, energy) with and without --kernel-times",
    )
    return verdict(failures)


if __name__ == "__main__":
    sys.exit(main())
