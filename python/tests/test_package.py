"""python/pyproject.toml: `pip install ./python` into a fresh virtual environment, offline, works.

The environment is made with `--system-site-packages` (numpy, h5py and matplotlib come from Debian,
as docs/user/python.md says) and the package built with Debian's setuptools (`--no-build-isolation
--no-index`: no download; `--no-deps`, since Debian names h5py's distribution h5py._debian_h5py_serial
and pip would look for an "h5py" it cannot download: the imports below show the dependencies are
there). Then, with no PYTHONPATH and the environment's bin/ first on PATH:
epaphe-sweep, epaphe-plot and epaphe-rotor are entry points in that bin/ and answer --help; `import
epaphe` comes from the environment, with the version of packages/core/src/Epaphe_Version.hpp
(also the version of pyproject.toml); README's Python quick start, on a short bar-on-wall run, writes a PNG
and prints the file's peak contact force; epaphe-plot on the same run writes its force figure."""
import os
import re
import shutil
import subprocess
import sys
import unittest

import h5py

import support
import test_readme

PYTHON_DIR = os.path.join(support.SOURCE, "python")
COMMANDS = ("epaphe-sweep", "epaphe-plot", "epaphe-rotor")


def header_version():
    path = os.path.join(support.SOURCE, "packages", "core", "src", "Epaphe_Version.hpp")
    with open(path, encoding="utf-8") as fh:
        m = re.search(r'version\s*=\s*"([^"]+)"', fh.read())
    return m.group(1)


def pyproject_version():
    with open(os.path.join(PYTHON_DIR, "pyproject.toml"), encoding="utf-8") as fh:
        m = re.search(r'^version\s*=\s*"([^"]+)"', fh.read(), re.M)
    return m.group(1)


def is_png(path):
    with open(path, "rb") as fh:
        data = fh.read()
    return data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 1000


class Package(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.where = support.workdir("package")
        cls.venv = os.path.join(cls.where, "venv")
        src = os.path.join(cls.where, "src")  # a copy: pip builds in the tree it is given
        for d in (cls.venv, src):
            shutil.rmtree(d, ignore_errors=True)
        shutil.copytree(PYTHON_DIR, src, ignore=shutil.ignore_patterns("tests", "build", "*.egg-info", "__pycache__"))
        cls.env = {
            k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME") and not k.startswith("PIP_")
        }
        cls.env.update(
            PATH=os.path.join(cls.venv, "bin") + os.pathsep + os.environ.get("PATH", ""),
            MPLBACKEND="Agg",
            PIP_DISABLE_PIP_VERSION_CHECK="1",
            PIP_NO_CACHE_DIR="1",
        )
        cls.run_ok([sys.executable, "-m", "venv", "--system-site-packages", cls.venv])
        cls.python = os.path.join(cls.venv, "bin", "python")
        cls.pip = cls.run_ok(
            [cls.python, "-m", "pip", "install", "--no-build-isolation", "--no-index", "--no-deps", src]
        )

    @classmethod
    def run_ok(cls, cmd, **kw):
        proc = subprocess.run(cmd, env=getattr(cls, "env", None), capture_output=True, text=True, **kw)
        if proc.returncode != 0:
            raise AssertionError(f"{' '.join(cmd)} failed ({proc.returncode}):\n{proc.stdout}\n{proc.stderr}")
        return proc

    def test_versions_agree(self):
        self.assertEqual(pyproject_version(), header_version())

    def test_entry_points(self):
        self.assertIn("Successfully installed epaphe", self.pip.stdout)
        for cmd in COMMANDS:
            path = shutil.which(cmd, path=self.env["PATH"])
            self.assertEqual(path, os.path.join(self.venv, "bin", cmd))
            with open(path, encoding="utf-8") as fh:
                script = fh.read()
            self.assertIn(f"from epaphe.cli.{cmd.split('-')[1]} import main", script)  # pip's entry point
            proc = self.run_ok([cmd, "--help"], cwd=self.where)
            self.assertTrue(proc.stdout.startswith(f"usage: {cmd}"), proc.stdout[:200])

    def test_import_from_venv(self):
        proc = self.run_ok(
            [
                self.python,
                "-c",
                "import epaphe, importlib.metadata as m; import numpy, h5py, "
                "matplotlib; print(epaphe.__file__); print(m.version('epaphe'))",
            ],
            cwd=self.where,
        )
        where, version = proc.stdout.split()
        self.assertTrue(os.path.realpath(where).startswith(os.path.realpath(self.venv)), where)
        self.assertEqual(version, header_version())

    def test_quick_start_and_plot(self):
        code = test_readme.quick_start()
        h5 = support.short_bar_run(self.where)
        png = os.path.join(self.where, "contact-force.png")
        if os.path.exists(png):
            os.remove(png)
        proc = self.run_ok([self.python, "-c", code.replace(test_readme.DEFAULT_OUTPUT, h5)], cwd=self.where)
        self.assertTrue(os.path.isfile(png) and is_png(png), png)
        m = re.search(r"peak contact force ([0-9.eE+-]+) N", proc.stdout)
        self.assertIsNotNone(m, proc.stdout)
        with h5py.File(h5, "r") as f:
            peak = float(f["bodies/Bar/contact/total_force"][()].max())
        self.assertGreater(peak, 0.0)
        self.assertAlmostEqual(float(m.group(1)), peak, delta=1e-3 * peak)  # printed with 4 digits
        out = os.path.join(self.where, "plots")
        shutil.rmtree(out, ignore_errors=True)
        self.run_ok(["epaphe-plot", h5, "--out", out, "--what", "force"], cwd=self.where)
        self.assertTrue(is_png(os.path.join(out, "force-Bar.png")), os.listdir(out))


if __name__ == "__main__":
    unittest.main()
