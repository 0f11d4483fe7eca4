"""Makes sure the interpreter has the modules the command lines need, importing nothing heavy.

`python3` first on PATH may be another interpreter (pyenv, venv) without numpy, h5py or
matplotlib: Debian's /usr/bin/python3 has them (python3-h5py, python3-matplotlib). The launchers
in drivers/ call `need()` before importing anything else of the package."""
import importlib.util
import os
import sys

DEBIAN = "/usr/bin/python3"
MODULES = ("numpy", "h5py", "matplotlib")


def need(prog, script, modules=MODULES):
    """Returns when every module of `modules` can be imported; else re-executes `script` with
    Debian's python3 (once: $EPAPHE_REEXEC_<PROG> marks the second try) or exits with one line on
    stderr."""
    mark = "EPAPHE_REEXEC_" + prog.upper().replace("-", "_")
    missing = [m for m in modules if importlib.util.find_spec(m) is None]
    if not missing:
        return
    if (
        os.path.realpath(sys.executable) != os.path.realpath(DEBIAN)
        and os.access(DEBIAN, os.X_OK)
        and not os.environ.get(mark)
    ):
        os.environ[mark] = "1"
        os.execv(DEBIAN, [DEBIAN, os.path.abspath(script)] + sys.argv[1:])
    sys.stderr.write(
        f"{prog}: error: python module {missing[0]} missing from {sys.executable} "
        "(needs h5py, numpy, matplotlib: Debian's python3-h5py python3-matplotlib)\n"
    )
    sys.exit(1)
