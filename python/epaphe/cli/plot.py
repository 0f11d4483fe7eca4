"""epaphe-plot: figures from Epaphe HDF5 histories (the layout in docs/user/output.md).

    epaphe-plot FILE.h5 [FILE2.h5 ...] [--out DIR] [--label L ...] [--body B] [--nodeset S]
                [--node K] [--tmin T] [--tmax T] [--what gap,force,displacement,velocity,energy]
                [--csv] [--strict]

One PNG per quantity, every file overlaid on the same axes (one curve each), so that a study
(time steps, penalty stiffnesses, reduction bases, ...) is compared on one figure:

  gap-<body>.png                 gap of the contact nodes vs time: minimum over the contact nodes
                                 (and, with --node K, contact node K, dashed)
  force-<body>.png               total contact force vs time
  displacement-<body>-<set>.png  displacement of a watched node set, X / Y / Z subplots: the mean
                                 over the set, or node K of the set with --node K
  velocity-<body>-<set>.png      velocity, likewise
  energy.png                     kinetic, strain, total energy and contact work; the relative
                                 balance error on a second axis

Without --body every body of the first file is plotted; without --nodeset every watched node
set. --node K is the index (0-based) of a node in the node set (and in the contact node set for
the gap); the title names its node id. --tmin/--tmax (s) restrict the time window. The time axis
is in us or ms (s beyond 1 s), chosen from the range; the other axes in SI units with a prefix.
Legends come from --label (one per file), else the file's root `name` attribute, else (when names
are missing or shared) the file stem. --csv also writes each figure's curves as <figure>.csv, in
SI base units (s, m, m/s, N, J), one row per record and file: label,file,time_s,<columns>.

A file whose status is not "complete" is plotted with a warning and a note on the figures
(--strict: refused). Errors (missing file, not an Epaphe history, unknown body or node set, ...)
are one line on stderr and exit status 1. The files written are printed, one a line.
"""
import argparse
import os
import sys

import matplotlib

from ..errors import EpapheError
from . import Parser, run_main

matplotlib.use("Agg")
from ..plots import History, plot_energy, plot_field, plot_force, plot_gap, time_unit  # noqa: E402

PROG = "epaphe-plot"
QUANTITIES = ("gap", "force", "displacement", "velocity", "energy")


class PlotError(EpapheError):
    """A user error: reported as one line on stderr, exit status 1."""


def warn(msg):
    sys.stderr.write(f"{PROG}: warning: {msg}\n")


def parse(argv):
    ap = Parser(
        prog=PROG,
        description=__doc__.split("\n\n")[0],
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="\n\n".join(__doc__.split("\n\n")[2:]),
    )
    ap.add_argument("files", nargs="+", metavar="FILE.h5", help="Epaphe HDF5 histories, overlaid")
    ap.add_argument("--out", default=".", metavar="DIR", help="output directory (default: current; created)")
    ap.add_argument("--label", action="append", default=[], metavar="L", help="legend of each file, in order")
    ap.add_argument("--body", help="body to plot (default: every body of the first file)")
    ap.add_argument("--nodeset", help="watched node set for displacement/velocity (default: all)")
    ap.add_argument(
        "--node",
        type=int,
        metavar="K",
        help="node index K (0-based) in the node set / contact nodes instead of the mean",
    )
    ap.add_argument("--tmin", type=float, metavar="T", help="start of the time window (s)")
    ap.add_argument("--tmax", type=float, metavar="T", help="end of the time window (s)")
    ap.add_argument("--what", metavar="LIST", help="comma list of " + ",".join(QUANTITIES) + " (default: all)")
    ap.add_argument("--csv", action="store_true", help="also write each figure's curves as CSV")
    ap.add_argument("--strict", action="store_true", help="refuse files whose status is not 'complete'")
    a = ap.parse_args(argv)
    if a.label and len(a.label) != len(a.files):
        ap.error(f"{len(a.label)} --label for {len(a.files)} files: give one per file or none")
    if a.node is not None and a.node < 0:
        ap.error(f"--node {a.node}: must be >= 0")
    if a.tmin is not None and a.tmax is not None and a.tmin >= a.tmax:
        ap.error(f"--tmin {a.tmin:g} must be below --tmax {a.tmax:g}")
    if a.what:
        what = [w.strip() for w in a.what.split(",") if w.strip()]
        bad = [w for w in what if w not in QUANTITIES]
        if bad or not what:
            ap.error(f"--what: unknown quantity {', '.join(bad) or '(none)'}; choose from {','.join(QUANTITIES)}")
        a.what_list, a.what_explicit = what, True
    else:
        a.what_list, a.what_explicit = list(QUANTITIES), False
    return a


def default_labels(hs):
    names = [h.name for h in hs]
    for h in hs:
        shared = names.count(h.name) > 1 and len(hs) > 1
        h.label = h.stem if (not h.name or shared) else h.name
    # two files with the same stem in different directories
    labels = [h.label for h in hs]
    for h in hs:
        if labels.count(h.label) > 1:
            h.label = h.path


def run(argv):
    a = parse(argv)
    hs = []
    try:
        for i, p in enumerate(a.files):
            hs.append(History(p, a.label[i] if a.label else None, a.tmin, a.tmax))
        if not a.label:
            default_labels(hs)
        for h in hs:
            if not h.complete():
                if a.strict:
                    raise PlotError(f"{h.path}: status '{h.status}', not 'complete' (--strict)")
                warn(f"{h.path}: status '{h.status}', not 'complete': plotted with a note")
            if h.t.size == 0:
                lo = "-inf" if a.tmin is None else f"{a.tmin:g}"
                hi = "inf" if a.tmax is None else f"{a.tmax:g}"
                raise PlotError(
                    f"{h.path}: no record in the time window [{lo}, {hi}] s "
                    f"(records from {h.f['time'][0]:g} to {h.f['time'][-1]:g} s)"
                )

        # bodies and node sets
        body_needed = any(w in a.what_list for w in ("gap", "force", "displacement", "velocity"))
        if a.body is not None:
            for h in hs:
                if a.body not in h.bodies():
                    raise PlotError(
                        f"{h.path}: unknown body '{a.body}' (available: " f"{', '.join(h.bodies()) or 'none'})"
                    )
            bodies = [a.body]
        else:
            bodies = hs[0].bodies() if body_needed else []
            for b in bodies:
                missing = [h.path for h in hs if b not in h.bodies()]
                if missing:
                    raise PlotError(
                        f"body '{b}' of {hs[0].path} is missing from {', '.join(missing)} " f"(choose one with --body)"
                    )
        if a.nodeset is not None:
            for b in bodies:
                for h in hs:
                    if a.nodeset not in h.nodesets(b):
                        raise PlotError(
                            f"{h.path}: unknown node set '{a.nodeset}' in body '{b}' (available: "
                            f"{', '.join(h.nodesets(b)) or 'none'})"
                        )

        if a.node is not None:  # checked before any figure is written
            for b in bodies:
                for h in hs:
                    groups = []
                    if "gap" in a.what_list and h.has_contact(b):
                        groups.append((f"bodies/{b}/contact/nodes", f"body '{b}' has {{n}} contact nodes"))
                    if "displacement" in a.what_list or "velocity" in a.what_list:
                        for s in [a.nodeset] if a.nodeset is not None else h.nodesets(b):
                            groups.append(
                                (f"bodies/{b}/nodesets/{s}/nodes", f"node set '{s}' of body '{b}' has {{n}} nodes")
                            )
                    for path, what in groups:
                        n = h.ids(path).size
                        if a.node >= n:
                            raise PlotError(
                                f"{h.path}: --node {a.node} out of range: " f"{what.format(n=n)} (0..{n - 1})"
                            )

        os.makedirs(a.out, exist_ok=True)
        span = max(float(h.t[-1]) for h in hs) - min(float(h.t[0]) for h in hs)
        tunit, tfac = time_unit(span)
        written = []
        for b in bodies:
            contact = all(h.has_contact(b) for h in hs)
            for q in ("gap", "force"):
                if q in a.what_list:
                    if contact:
                        (
                            plot_gap(hs, b, a.node, tunit, tfac, a.out, written, a.csv)
                            if q == "gap"
                            else plot_force(hs, b, tunit, tfac, a.out, written, a.csv)
                        )
                    elif a.what_explicit:
                        miss = [h.path for h in hs if not h.has_contact(b)]
                        raise PlotError(f"{', '.join(miss)}: body '{b}' has no contact data for --what {q}")
            for q in ("displacement", "velocity"):
                if q not in a.what_list:
                    continue
                sets = (
                    [a.nodeset]
                    if a.nodeset is not None
                    else [s for s in hs[0].nodesets(b) if all(s in h.nodesets(b) for h in hs)]
                )
                if not sets and a.what_explicit:
                    raise PlotError(f"{hs[0].path}: body '{b}' has no watched node set for --what {q}")
                for s in sets:
                    plot_field(hs, b, s, q, a.node, tunit, tfac, a.out, written, a.csv)
        if "energy" in a.what_list:
            plot_energy(hs, tunit, tfac, a.out, written, a.csv)
        if not written:
            raise PlotError("nothing to plot (no body with contact data or watched node sets?)")
        for p in [w for w in written if w.endswith(".png")] + [w for w in written if not w.endswith(".png")]:
            print(p)
        return 0
    finally:
        for h in hs:
            h.close()


def main(argv=None):
    return run_main(PROG, run, argv)
