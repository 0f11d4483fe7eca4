"""Helpers for Epaphe's verification tests: write deck variants, run them, read histories."""
import importlib.machinery
import importlib.util
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

import h5py
import numpy as np

# The tests check with `assert` too: under python -O (or PYTHONOPTIMIZE) those checks vanish and a
# test would pass whatever it measures. Refuse to run rather than lie.
if sys.flags.optimize:
    raise SystemExit("epaphe tests: Python runs with -O / PYTHONOPTIMIZE, which strips `assert`: "
                     "unset PYTHONOPTIMIZE and run again")


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


def deck_child(node, tag, name):
    """The child <tag name="name"> of an XML deck node, matched by attribute, not by an XPath predicate
    (names hold quotes: "Young's modulus"); None when absent."""
    return next((c for c in node.findall(tag) if c.get("name") == name), None)


def deck_value(root, path):
    """The value of the deck parameter at `path` ("Bodies->Bar->Mesh->Lengths") under the XML root:
    a list of floats for an array "{...}", else the string."""
    node = root
    *lists, name = path.split("->")
    for l in lists:
        node = deck_child(node, "ParameterList", l)
        assert node is not None, f"deck: no list '{l}' on the way to '{path}'"
    p = deck_child(node, "Parameter", name)
    assert p is not None, f"deck: no parameter '{path}'"
    v = p.get("value")
    return [float(x) for x in v.strip("{}").split(",")] if v.startswith("{") else v


def variant(base_deck, out_path, overrides):
    """Writes a copy of base_deck with overrides {"Time->Time step": "5e-8", ...}.

    A path names nested ParameterLists and ends with a Parameter; the value replaces the old one
    (the parameter is created with `type` when absent: pass (value, type))."""
    tree = ET.parse(base_deck)
    root = tree.getroot()
    for path, value in overrides.items():
        ptype = None
        if isinstance(value, tuple):
            value, ptype = value
        *lists, name = path.split("->")
        node = root
        for l in lists:
            child = deck_child(node, "ParameterList", l)
            if child is None:
                child = ET.SubElement(node, "ParameterList", name=l)
            node = child
        p = deck_child(node, "Parameter", name)
        if p is None:
            p = ET.SubElement(node, "Parameter", name=name, type=ptype or "string", value=str(value))
        p.set("value", str(value))
        if ptype:
            p.set("type", ptype)
    tree.write(out_path)
    return out_path


def run(cmd, cwd, expect_ok=True):
    os.makedirs(cwd, exist_ok=True)
    proc = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True)
    if expect_ok and proc.returncode != 0:
        sys.stderr.write(proc.stdout + proc.stderr)
        raise SystemExit(f"command failed ({proc.returncode}): {' '.join(cmd)}")
    return proc


def history(path):
    """The arrays of an Epaphe HDF5 output, as a dict of numpy arrays (plus attributes)."""
    out = {}
    with h5py.File(path, "r") as f:
        assert f.attrs["status"] in ("complete", b"complete"), f"{path}: status {f.attrs['status']}"

        def visit(name, obj):
            if isinstance(obj, h5py.Dataset) and obj.dtype.kind in "fi":
                out[name] = obj[()]

        f.visititems(visit)
        out["attrs"] = {k: v for k, v in f["/run"].attrs.items()}
        for b in f["/bodies"]:
            out[f"bodies/{b}/attrs"] = {k: v for k, v in f[f"/bodies/{b}"].attrs.items()}
    return out


def load_script(path, name):
    """A driver script without a .py suffix (drivers/epaphe-rotor, ...) imported as module `name`."""
    loader = importlib.machinery.SourceFileLoader(name, path)
    module = importlib.util.module_from_spec(importlib.util.spec_from_loader(name, loader))
    loader.exec_module(module)
    return module


def exact_solution(name, run, deck):
    """epaphe-sweep's exact solution `name` ('bar-on-wall', 'two-bars'; docs/verification.md V1, V2) for
    a deck, read through epaphe-run's schema: the one the studies measure against."""
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "drivers", "epaphe-sweep")
    sweep = load_script(path, "epaphe_sweep")
    return sweep.EXACT[name](sweep.Deck(deck), sweep.Schema(run), deck)


def verdict(failures):
    """Prints PASSED, or FAILED with one line per failure; returns the exit code (0 or 1)."""
    print("FAILED:\n  " + "\n  ".join(failures) if failures else "PASSED")
    return 1 if failures else 0



def engine_order_lines(eo, amp, revolutions, low=0.5, top=40):
    """Reads an engine-order spectrum (epaphe-rotor spectrum over `revolutions` whole revolutions:
    bins 1/revolutions of an order apart, so neighbouring whole orders are `revolutions` bins apart;
    Hann window: a line spreads over its bin and one bin either side). Above EO `low` (the mean and
    slow drift sit below) returns dict(
      peak   the EO of the largest bin, order: the nearest whole order, off: |peak - order| in bins;
      lines  {k: the amplitude on the bin of whole order k} for k = 1..top;
      even_fraction  the share of the spectral energy within one bin of even whole orders;
      off_line_ratio the largest bin / the largest bin farther than one bin from every even order)."""
    sel = eo > low
    eo, amp = eo[sel], amp[sel]
    k = int(np.argmax(amp))
    order = int(round(eo[k]))
    bins = eo * revolutions
    lines = {}
    for o in range(1, top + 1):
        on = np.abs(bins - o * revolutions) <= 0.5
        lines[o] = float(amp[on].max()) if on.any() else 0.0
    even = np.abs(bins - 2 * np.round(eo / 2) * revolutions) <= 1.01
    off = amp[~even]
    return dict(peak=float(eo[k]), order=order, off=abs(eo[k] - order) * revolutions, lines=lines,
                even_fraction=float((amp[even] ** 2).sum() / (amp ** 2).sum()),
                off_line_ratio=float(amp[k] / off.max()) if off.size else float("inf"))
