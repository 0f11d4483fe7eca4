"""Plumbing of Epaphe's test scripts: the common command line, running commands, the verdict. The
reading, deck and exact-solution helpers are the package's (python/epaphe), re-exported here:
history, variant, deck_value, deck_child, exact_solution, engine_order_lines."""
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python")))
from epaphe.deck import deck_child, deck_value, variant  # noqa: E402,F401
from epaphe.exact import exact_solution  # noqa: E402,F401
from epaphe.measures import engine_order_lines  # noqa: E402,F401
from epaphe.results import history  # noqa: E402,F401

# The tests check with `assert` too: under python -O (or PYTHONOPTIMIZE) those checks vanish and a
# test would pass whatever it measures. Refuse to run rather than lie.
if sys.flags.optimize:
    raise SystemExit(
        "epaphe tests: Python runs with -O / PYTHONOPTIMIZE, which strips `assert`: "
        "unset PYTHONOPTIMIZE and run again"
    )


# verification.coating's bar: bar-on-wall.xml at 10 m/s (32 J) into its wall coated with 2 mm of an
# elastic-plastic coating (yield 100 MPa, E = 10 GPa, H = 1 GPa, 10 x 10 elements of 1 cm^2)
COATED_BAR = {
    "Surfaces->Wall->Origin": ("{0.204, -0.04, -0.04}", "Array(double)"),  # the front at 0.202
    "Surfaces->Wall->Coating->Thickness": ("2e-3", "double"),
    "Surfaces->Wall->Coating->Young's modulus": ("1e10", "double"),
    "Surfaces->Wall->Coating->Yield stress": ("1e8", "double"),
    "Surfaces->Wall->Coating->Hardening modulus": ("1e9", "double"),
    "Surfaces->Wall->Coating->Elements": ("{10, 10}", "Array(int)"),
    "Bodies->Bar->Initial velocity": ("{10, 0, 0}", "Array(double)"),
    "Time->End time": ("1e-3", "double"),
    "Output->Every": ("10", "int"),
}


def parse_args(*extra):
    """The common command line of the test scripts: --run EPAPHE_RUN --deck DECK --workdir DIR
    (plus `extra` option names); the work directory is created."""
    import argparse

    ap = argparse.ArgumentParser()
    for name in ("--run", "--deck", "--workdir") + extra:
        ap.add_argument(name, required=True)
    a = ap.parse_args()
    os.makedirs(a.workdir, exist_ok=True)
    return a


def run(cmd, cwd, expect_ok=True, timeout=1800):
    """Runs `cmd` in `cwd`; a run that outlasts `timeout` seconds is killed and fails the test with
    its command line (ctest's TIMEOUT would kill the whole script without saying which run hung)."""
    os.makedirs(cwd, exist_ok=True)
    try:
        proc = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        raise SystemExit(f"command still running after {timeout} s, killed: {' '.join(cmd)}")
    if expect_ok and proc.returncode != 0:
        sys.stderr.write(proc.stdout + proc.stderr)
        raise SystemExit(f"command failed ({proc.returncode}): {' '.join(cmd)}")
    return proc


def verdict(failures):
    """Prints PASSED, or FAILED with one line per failure; returns the exit code (0 or 1)."""
    print("FAILED:\n  " + "\n  ".join(failures) if failures else "PASSED")
    return 1 if failures else 0


# A kernel's line of epaphe-run --kernel-times: name, launches, % on the team, ms, us a launch, % of the loop
KERNEL_ROW = re.compile(r"^  (\S+)\s+(\d+)\s+([\d.]+)%\s+([\d.]+)\s+([\d.]+)\s+([\d.]+)%$")


def kernel_rows(stdout):
    """The kernels' lines epaphe-run --kernel-times printed after its "kernels:" line, in order: per
    kernel its name, launches, share of them on the team (0-1), ms, us a launch and % of the loop."""
    table = stdout.split("\nkernels:", 1)[1] if "\nkernels:" in stdout else ""
    rows = [KERNEL_ROW.match(line) for line in table.splitlines()]
    return [
        {
            "name": r.group(1),
            "launches": int(r.group(2)),
            "on_team": float(r.group(3)) / 100,
            "ms": float(r.group(4)),
            "us_per_launch": float(r.group(5)),
            "loop_percent": float(r.group(6)),
        }
        for r in rows
        if r
    ]


def write_point_mass(workdir, stiffness, mass):
    """A one-node model for the Matrix Market importer, written to workdir: K.mtx from `stiffness`
    (the lower triangle as (row, column, value), 1-based over the DOFs x, y, z), M.mtx = mass I, the
    DOF, node (at the origin) and node-set files (the set MASS holds the node). POINT_MASS_MESH is
    the body's Mesh list that reads them."""
    files = {
        "K.mtx": "%%MatrixMarket matrix coordinate real symmetric\n"
        + f"3 3 {len(stiffness)}\n"
        + "".join(f"{i} {j} {v:.17g}\n" for i, j, v in stiffness),
        "M.mtx": "%%MatrixMarket matrix coordinate real symmetric\n3 3 3\n"
        + "".join(f"{i} {i} {mass:.17g}\n" for i in (1, 2, 3)),
        "dofs.txt": "1 x\n1 y\n1 z\n",
        "nodes.txt": "# id x y z\n1 0 0 0\n",
        "sets.txt": "MASS 1\n",
    }
    for name, text in files.items():
        with open(os.path.join(workdir, name), "w") as f:
            f.write(text)


POINT_MASS_MESH = """<ParameterList name="Mesh">
        <Parameter name="Type" type="string" value="Matrix Market"/>
        <Parameter name="Stiffness file" type="string" value="K.mtx"/>
        <Parameter name="Mass file" type="string" value="M.mtx"/>
        <Parameter name="DOF file" type="string" value="dofs.txt"/>
        <Parameter name="Node file" type="string" value="nodes.txt"/>
        <Parameter name="Node set file" type="string" value="sets.txt"/>
      </ParameterList>
      <ParameterList name="Reduction">
        <Parameter name="Method" type="string" value="None"/>
        <Parameter name="Frequency check" type="int" value="0"/>
        <Parameter name="Cache" type="bool" value="false"/>
      </ParameterList>"""
