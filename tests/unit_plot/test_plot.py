#!/usr/bin/env python3
"""drivers/epaphe-plot (python/epaphe/cli/plot.py): figures from Epaphe HDF5 histories.

Runs two short variants of the bar-on-wall deck (Lagrange and penalty contact, End time 1.2e-4 s),
plots them overlaid and checks:
  * the files it prints are the expected PNGs (and CSVs with --csv), and every PNG is a valid PNG
    (signature, chunk CRCs, IHDR size, IDAT inflating to height x (1 + width x bytes per pixel),
    IEND) of a sensible size, and not blank;
  * the plotted data are right: the CSV curves (force, gap minimum and node K, displacement and
    velocity of node K or of the set mean, energies) equal the HDF5 datasets, for each file;
    --tmin/--tmax keep exactly the records of the window; legends default to the root `name`,
    or to the file stems when the names are shared;
  * the time unit and SI prefixes chosen from the ranges (epaphe.plots);
  * errors are exit status 1 with one line on stderr: unknown node set (naming the valid ones),
    unknown body (naming the bodies), missing file, a non-HDF5 file, an HDF5 file without /time,
    --node out of range, --label count; a file whose status is not "complete" is plotted with a
    warning, and refused with --strict.
"""
import csv
import os
import shutil
import struct
import subprocess
import sys
import zlib

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "verification"))
from epaphe_testing import parse_args, run, variant  # noqa: E402

END_TIME = 1.2e-4
NODE = 1
failures = []


def check(cond, msg):
    if not cond:
        failures.append(msg)
    return cond


# ---- PNG validation -----------------------------------------------------------------------------
def png_problems(path):
    """Empty list when `path` is a well-formed PNG of a sensible size; else what is wrong."""
    with open(path, "rb") as fh:
        data = fh.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        return ["no PNG signature"]
    pos, chunks, idat = 8, [], b""
    while pos < len(data):
        if pos + 8 > len(data):
            return ["truncated chunk header"]
        length, ctype = struct.unpack(">I4s", data[pos : pos + 8])
        body = data[pos + 8 : pos + 8 + length]
        crc = data[pos + 8 + length : pos + 12 + length]
        if len(body) != length or len(crc) != 4:
            return [f"truncated {ctype!r} chunk"]
        if struct.unpack(">I", crc)[0] != zlib.crc32(ctype + body) & 0xFFFFFFFF:
            return [f"bad CRC in {ctype!r} chunk"]
        chunks.append(ctype)
        if ctype == b"IHDR":
            width, height, depth, ctype_px = struct.unpack(">IIBB", body[:10])
        if ctype == b"IDAT":
            idat += body
        pos += 12 + length
    problems = []
    if not chunks or chunks[0] != b"IHDR":
        return ["first chunk is not IHDR"]
    if chunks[-1] != b"IEND":
        problems.append("no IEND chunk")
    if not (400 <= width <= 4000 and 300 <= height <= 4000):
        problems.append(f"odd size {width}x{height}")
    channels = {0: 1, 2: 3, 4: 2, 6: 4}.get(ctype_px)
    if depth != 8 or channels is None:
        problems.append(f"unexpected pixel format depth {depth} colour type {ctype_px}")
    else:
        raw = zlib.decompress(idat)
        if len(raw) != height * (1 + width * channels):
            problems.append(f"IDAT inflates to {len(raw)} bytes, expected {height * (1 + width * channels)}")
    if not 10_000 <= len(data) <= 5_000_000:
        problems.append(f"file size {len(data)} bytes")
    if not problems:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        img = plt.imread(path)[..., :3]
        inked = np.mean(np.any(img < 0.9, axis=-1))
        if not 0.01 < inked < 0.6:
            problems.append(f"{inked:.1%} of the pixels are not near white (blank or smeared figure?)")
    return problems


# ---- running the tool ---------------------------------------------------------------------------
def plot(tool, args, cwd):
    return subprocess.run([tool] + args, cwd=cwd, capture_output=True, text=True)


def read_csv(path):
    """{label: {column: array}} of a CSV written by epaphe-plot --csv."""
    out = {}
    with open(path, newline="") as fh:
        r = csv.reader(fh)
        header = next(r)
        for row in r:
            d = out.setdefault(row[0], {"file": row[1], **{c: [] for c in header[2:]}})
            for c, v in zip(header[2:], row[2:]):
                d[c].append(float(v))
    for d in out.values():
        for c in list(d):
            if c != "file":
                d[c] = np.array(d[c])
    return out


def expect_error(tool, args, cwd, what, must_name=(), out_dir=None):
    p = plot(tool, args, cwd)
    lines = p.stderr.strip().splitlines()
    ok = check(p.returncode == 1, f"{what}: exit status {p.returncode}, expected 1 (stderr: {p.stderr.strip()!r})")
    ok &= check(len(lines) == 1, f"{what}: {len(lines)} lines on stderr, expected one: {p.stderr!r}")
    ok &= check("Traceback" not in p.stderr, f"{what}: traceback on stderr")
    for word in must_name:
        ok &= check(word in p.stderr, f"{what}: message does not name {word!r}: {p.stderr.strip()!r}")
    if out_dir is not None:
        check(not os.path.isdir(out_dir) or not os.listdir(out_dir), f"{what}: files written before the error")
    print(f"  {'ok ' if ok else 'BAD'} {what}: {lines[0] if lines else '(no message)'}")


def main():
    a = parse_args("--plot")
    tool = os.path.abspath(a.plot)
    wd = os.path.abspath(a.workdir)
    for name in os.listdir(wd):
        p = os.path.join(wd, name)
        shutil.rmtree(p) if os.path.isdir(p) else os.remove(p)
    check(os.access(tool, os.X_OK), f"{tool} is not executable")

    # two short runs: the study to compare
    h5 = {}
    for name, extra in (("lagrange", {}), ("penalty", {"Contact->Method": "Penalty"})):
        deck = variant(
            a.deck,
            os.path.join(wd, name + ".xml"),
            dict(
                {
                    "Output->File": name + ".h5",
                    "Time->End time": (f"{END_TIME:g}", "double"),
                    "Run->Progress interval": ("0", "double"),
                },
                **extra,
            ),
        )
        run([a.run, deck, "--threads", "1"], wd)
        h5[name] = os.path.join(wd, name + ".h5")
    ref = {}
    for name, path in h5.items():
        with h5py.File(path, "r") as f:
            ref[name] = {
                k: f[k][()]
                for k in (
                    "time",
                    "bodies/Bar/contact/total_force",
                    "bodies/Bar/contact/gap",
                    "bodies/Bar/nodesets/x+/displacement",
                    "bodies/Bar/nodesets/x-/velocity",
                    "energy/kinetic",
                    "energy/strain",
                    "energy/total",
                    "energy/contact_work",
                    "energy/balance_error",
                )
            }
            ref[name]["name"] = f.attrs["name"].decode() if isinstance(f.attrs["name"], bytes) else f.attrs["name"]
    labels = {"lagrange": "Lagrange", "penalty": "Penalty"}

    # ---- 1. everything, overlaid, with CSVs and node K ----------------------------------------
    print("all figures, two files overlaid, --node 1 --csv")
    out = os.path.join(wd, "all")
    p = plot(
        tool,
        [
            h5["lagrange"],
            h5["penalty"],
            "--out",
            out,
            "--label",
            "Lagrange",
            "--label",
            "Penalty",
            "--csv",
            "--node",
            str(NODE),
        ],
        wd,
    )
    check(p.returncode == 0, f"plot failed ({p.returncode}): {p.stderr.strip()}")
    check(p.stderr.strip() == "", f"unexpected stderr: {p.stderr.strip()!r}")
    stems = [
        "gap-Bar",
        "force-Bar",
        "displacement-Bar-x+",
        "displacement-Bar-x-",
        "velocity-Bar-x+",
        "velocity-Bar-x-",
        "energy",
    ]
    printed = p.stdout.split()
    expected = [os.path.join(out, s + ".png") for s in stems] + [os.path.join(out, s + ".csv") for s in stems]
    check(sorted(printed) == sorted(expected), f"printed files {printed}, expected {expected}")
    for s in stems:
        png = os.path.join(out, s + ".png")
        if check(os.path.isfile(png), f"{png} missing"):
            probs = png_problems(png)
            check(not probs, f"{png}: {'; '.join(probs)}")
            print(f"  {s}.png: {os.path.getsize(png)} bytes{', ' + '; '.join(probs) if probs else ', valid'}")
        check(os.path.isfile(os.path.join(out, s + ".csv")), f"{s}.csv missing")

    def same(got, want, what):
        got, want = np.asarray(got), np.asarray(want)
        ok = got.shape == want.shape and np.array_equal(got, want)
        if not ok and got.shape == want.shape:
            ok = np.allclose(got, want, rtol=1e-13, atol=0)
        check(ok, f"{what}: CSV differs from the HDF5 data (shapes {got.shape} / {want.shape})")
        return ok

    if not failures:
        curves = {s: read_csv(os.path.join(out, s + ".csv")) for s in stems}
        for name, lab in labels.items():
            r = ref[name]
            for s in stems:
                if check(lab in curves[s], f"{s}.csv: no curve labelled {lab}"):
                    same(curves[s][lab]["time_s"], r["time"], f"{s} {lab} time")
            same(curves["force-Bar"][lab]["total_force_N"], r["bodies/Bar/contact/total_force"], f"force {lab}")
            same(curves["gap-Bar"][lab]["gap_min_m"], r["bodies/Bar/contact/gap"].min(axis=1), f"gap min {lab}")
            same(curves["gap-Bar"][lab][f"gap_node{NODE}_m"], r["bodies/Bar/contact/gap"][:, NODE], f"gap node {lab}")
            d = curves["displacement-Bar-x+"][lab]
            same(
                np.stack([d["ux_m"], d["uy_m"], d["uz_m"]], axis=1),
                r["bodies/Bar/nodesets/x+/displacement"][:, NODE],
                f"displacement x+ node {NODE} {lab}",
            )
            v = curves["velocity-Bar-x-"][lab]
            same(
                np.stack([v["vx_m_per_s"], v["vy_m_per_s"], v["vz_m_per_s"]], axis=1),
                r["bodies/Bar/nodesets/x-/velocity"][:, NODE],
                f"velocity x- node {NODE} {lab}",
            )
            e = curves["energy"][lab]
            for k in ("kinetic", "strain", "total", "contact_work"):
                same(e[k + "_J"], r["energy/" + k], f"energy {k} {lab}")
            same(e["balance_error"], r["energy/balance_error"], f"balance error {lab}")
            check(os.path.basename(h5[name]) == curves["force-Bar"][lab]["file"], f"force {lab}: file column")
        f_l = curves["force-Bar"]["Lagrange"]["total_force_N"]
        f_p = curves["force-Bar"]["Penalty"]["total_force_N"]
        check(f_l.shape == f_p.shape and not np.array_equal(f_l, f_p), "the two overlaid force curves are identical")
        check(f_l.max() > 1e6, f"force curve peak {f_l.max():g} N: no contact plotted?")
        print(
            f"  CSV curves equal the HDF5 data for both files ({f_l.size} records each)"
            if not failures
            else "  CSV checks FAILED"
        )

    # ---- 2. mean of the set, default labels ----------------------------------------------------
    print("mean of a node set; default labels")
    out2 = os.path.join(wd, "mean")
    p = plot(
        tool, [h5["lagrange"], h5["penalty"], "--out", out2, "--what", "displacement", "--nodeset", "x+", "--csv"], wd
    )
    if check(p.returncode == 0, f"mean-of-set plot failed: {p.stderr.strip()}"):
        check(
            p.stdout.split()
            == [os.path.join(out2, "displacement-Bar-x+.png"), os.path.join(out2, "displacement-Bar-x+.csv")],
            f"printed {p.stdout.split()}",
        )
        c = read_csv(os.path.join(out2, "displacement-Bar-x+.csv"))
        # both variants share the deck's Run->Name: the legends fall back to the file stems
        check(sorted(c) == ["lagrange", "penalty"], f"default labels {sorted(c)}, expected the file stems")
        for name in h5:
            if name in c:
                d = c[name]
                got = np.stack([d["ux_m"], d["uy_m"], d["uz_m"]], axis=1)
                want = ref[name]["bodies/Bar/nodesets/x+/displacement"].mean(axis=1)
                check(np.allclose(got, want, rtol=1e-12, atol=1e-18), f"mean displacement {name} differs")
    p = plot(tool, [h5["lagrange"], "--out", os.path.join(wd, "single"), "--what", "force", "--csv"], wd)
    if check(p.returncode == 0, f"single-file plot failed: {p.stderr.strip()}"):
        c = read_csv(os.path.join(wd, "single", "force-Bar.csv"))
        check(list(c) == [ref["lagrange"]["name"]], f"single file label {list(c)}, expected the root name attribute")

    # ---- 3. time window ------------------------------------------------------------------------
    print("time window --tmin 2e-5 --tmax 6e-5")
    out3 = os.path.join(wd, "window")
    p = plot(
        tool, [h5["penalty"], "--out", out3, "--what", "force,energy", "--tmin", "2e-5", "--tmax", "6e-5", "--csv"], wd
    )
    if check(p.returncode == 0, f"windowed plot failed: {p.stderr.strip()}"):
        t = ref["penalty"]["time"]
        keep = (t >= 2e-5 - 1e-13) & (t <= 6e-5 + 1e-13)
        c = read_csv(os.path.join(out3, "force-Bar.csv"))
        d = next(iter(c.values()))
        same(d["time_s"], t[keep], "windowed time")
        same(d["total_force_N"], ref["penalty"]["bodies/Bar/contact/total_force"][keep], "windowed force")
        print(f"  {keep.sum()} records kept, from {d['time_s'][0]:.4g} to {d['time_s'][-1]:.4g} s")
        probs = png_problems(os.path.join(out3, "energy.png"))
        check(not probs, f"windowed energy.png: {probs}")

    # ---- 4. units, from the package (python/epaphe/plots.py, what epaphe-plot draws with) -------
    from epaphe import plots as mod  # epaphe_testing put python/ on the path

    for span, unit in ((END_TIME, "\u00b5s"), (5e-3, "ms"), (0.5, "ms"), (3.0, "s")):
        check(mod.time_unit(span)[0] == unit, f"time_unit({span:g}) = {mod.time_unit(span)}, expected {unit}")
    for vals, u, want in (
        ([1.6e6], "N", "MN"),
        ([2e-3, -4e-5], "m", "mm"),
        ([3200.0], "J", "kJ"),
        ([4e-5], "m", "\u00b5m"),
        ([0.0], "m", "m"),
        ([5.0], "m/s", "m/s"),
    ):
        got = mod.si_scale([np.array(vals)], u)[0]
        check(got == want, f"si_scale({vals}, {u}) = {got}, expected {want}")
    print("  time units and SI prefixes as expected" if not failures else "  unit checks done")

    # ---- 5. errors and warnings ----------------------------------------------------------------
    print("errors")
    expect_error(
        tool,
        [h5["lagrange"], "--nodeset", "nosuch", "--out", os.path.join(wd, "e1")],
        wd,
        "unknown node set",
        must_name=("nosuch", "x+", "x-"),
        out_dir=os.path.join(wd, "e1"),
    )
    expect_error(
        tool,
        [h5["lagrange"], "--body", "Wheel", "--out", os.path.join(wd, "e2")],
        wd,
        "unknown body",
        must_name=("Wheel", "Bar"),
        out_dir=os.path.join(wd, "e2"),
    )
    expect_error(tool, [os.path.join(wd, "absent.h5")], wd, "missing file", must_name=("absent.h5",))
    expect_error(tool, [os.path.join(wd, "lagrange.xml")], wd, "not an HDF5 file", must_name=("lagrange.xml",))
    notime = os.path.join(wd, "notime.h5")
    with h5py.File(notime, "w") as f:
        f["energy/kinetic"] = np.zeros(3)
    expect_error(tool, [notime], wd, "HDF5 file without /time", must_name=("notime.h5", "/time"))
    expect_error(
        tool,
        [h5["lagrange"], "--node", "9", "--out", os.path.join(wd, "e3")],
        wd,
        "--node out of range",
        must_name=("9",),
        out_dir=os.path.join(wd, "e3"),
    )
    expect_error(tool, [h5["lagrange"], h5["penalty"], "--label", "only one"], wd, "--label count")
    expect_error(tool, [h5["lagrange"], "--what", "gap,pressure"], wd, "unknown --what", must_name=("pressure",))

    stopped = os.path.join(wd, "stopped.h5")
    shutil.copy(h5["lagrange"], stopped)
    with h5py.File(stopped, "a") as f:
        f.attrs["status"] = "stopped: test"
    out5 = os.path.join(wd, "stopped")
    p = plot(tool, [stopped, "--out", out5, "--what", "force"], wd)
    ok = check(p.returncode == 0, f"incomplete file: exit {p.returncode}, expected 0 with a warning")
    ok &= check(
        len(p.stderr.strip().splitlines()) == 1 and "warning" in p.stderr and "stopped: test" in p.stderr,
        f"incomplete file: expected one warning line naming the status, got {p.stderr!r}",
    )
    png = os.path.join(out5, "force-Bar.png")
    ok &= check(os.path.isfile(png) and not png_problems(png), "incomplete file: no valid PNG")
    print(f"  {'ok ' if ok else 'BAD'} incomplete file plotted: {p.stderr.strip()}")
    expect_error(
        tool,
        [stopped, "--strict", "--out", os.path.join(wd, "e4")],
        wd,
        "incomplete file with --strict",
        must_name=("stopped: test",),
        out_dir=os.path.join(wd, "e4"),
    )

    if failures:
        print("FAILED:\n  " + "\n  ".join(failures))
        return 1
    print("PASSED")
    return 0


if __name__ == "__main__":
    sys.exit(main())
