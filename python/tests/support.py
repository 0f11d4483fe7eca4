"""What the package's unit tests share: the source tree, epaphe-run, a work directory, a short run.

ctest (tests/CMakeLists.txt, unit.python-*) gives EPAPHE_RUN (the epaphe-run to use) and
EPAPHE_TEST_WORKDIR; run by hand, the build tree's epaphe-run and a temporary directory are used."""
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.normpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(SOURCE, "python"))

import epaphe  # noqa: E402

RUN = os.environ.get("EPAPHE_RUN") or os.path.join(SOURCE, "build", "drivers", "epaphe-run")
BAR = os.path.join(SOURCE, "inputs", "bar-on-wall.xml")


def workdir(name):
    """A fresh directory for one test file."""
    base = os.environ.get("EPAPHE_TEST_WORKDIR") or tempfile.mkdtemp(prefix="epaphe-python-")
    path = os.path.join(base, name)
    os.makedirs(path, exist_ok=True)
    return path


def short_bar_run(where, end_time="4e-5", name="bar-on-wall"):
    """Runs inputs/bar-on-wall.xml to `end_time` s (contact starts at 2e-5 s) in `where` on one
    thread; returns the output's path (where/<name>.h5)."""
    schema = epaphe.Schema.of(RUN)
    deck = epaphe.variant(
        BAR,
        os.path.join(where, name + ".xml"),
        {"Time->End time": end_time, "Output->File": name + ".h5", "Run->Progress interval": "0"},
        schema,
    )
    out = os.path.join(where, name + ".h5")
    if os.path.exists(out):
        os.remove(out)
    proc = subprocess.run([RUN, deck, "--threads", "1"], cwd=where, capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError(f"{RUN} {deck} failed ({proc.returncode}): {proc.stderr.strip()}")
    return out
