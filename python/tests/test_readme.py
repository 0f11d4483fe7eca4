"""README.md, section "Python": its quick start (the ```python block after "Quick start") is five
lines and works: run on a fresh short output of the bar on a rigid wall (End time 4e-5 s, contact
from 2e-5 s) in place of build/run/bar-on-wall.h5, it writes a non-empty PNG and prints a peak
contact force that is positive and equals the largest /bodies/Bar/contact/total_force of the file
(read here with h5py, not with the package)."""
import os
import re
import subprocess
import sys
import unittest

import h5py

import support

DEFAULT_OUTPUT = "build/run/bar-on-wall.h5"  # where ./epaphe run writes (cd build/run; the deck's File)


def quick_start():
    with open(os.path.join(support.SOURCE, "README.md"), encoding="utf-8") as fh:
        text = fh.read()
    section = text[text.index("\n## Python\n") :]
    section = section[: section.index("\n## ", 1)]
    after = section[section.index("Quick start") :]
    m = re.search(r"```python\n(.*?)```", after, re.S)
    return m.group(1)


class QuickStart(unittest.TestCase):
    def test_quick_start(self):
        code = quick_start()
        self.assertEqual(len(code.strip().splitlines()), 5, code)
        self.assertIn(DEFAULT_OUTPUT, code)
        where = support.workdir("readme")
        h5 = support.short_bar_run(where)
        png = os.path.join(where, "contact-force.png")
        if os.path.exists(png):
            os.remove(png)
        env = dict(os.environ, PYTHONPATH=os.path.join(support.SOURCE, "python"), MPLBACKEND="Agg")
        proc = subprocess.run(
            [sys.executable, "-c", code.replace(DEFAULT_OUTPUT, h5)], cwd=where, env=env, capture_output=True, text=True
        )
        self.assertEqual(proc.returncode, 0, proc.stderr)
        self.assertTrue(os.path.isfile(png), f"no {png}")
        with open(png, "rb") as fh:
            data = fh.read()
        self.assertEqual(data[:8], b"\x89PNG\r\n\x1a\n")
        self.assertGreater(len(data), 1000)
        m = re.search(r"peak contact force ([0-9.eE+-]+) N", proc.stdout)
        self.assertIsNotNone(m, proc.stdout)
        with h5py.File(h5, "r") as f:
            peak = float(f["bodies/Bar/contact/total_force"][()].max())
        self.assertGreater(float(m.group(1)), 0.0)
        self.assertAlmostEqual(float(m.group(1)), peak, delta=1e-3 * peak)  # printed with 4 digits


if __name__ == "__main__":
    unittest.main()
