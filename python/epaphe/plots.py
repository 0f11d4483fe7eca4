"""Figures of runs and studies (matplotlib, imported here and not by `import epaphe`): the unit
helpers (a time axis in us/ms/s, SI prefixes), epaphe-plot's figures (gap, force, displacement,
velocity, energy; every file overlaid), epaphe-sweep's overlays (a curve per run, the reference
dashed) and its work-precision diagram. The command lines select the Agg backend first."""
import csv
import math
import os
import re

import matplotlib.pyplot as plt
import numpy as np

from .errors import EpapheError
from .measures import DEFAULT_MEASURES, ERROR_DEFINITIONS, work_precision_series
from .results import Run
from .study import CURVES

ENERGIES = (("kinetic", "kinetic"), ("strain", "strain"), ("total", "total"), ("contact_work", "contact work"))
LINESTYLES = ("-", "--", ":", "-.", (0, (5, 1, 1, 1, 1, 1)), (0, (1, 3)), (0, (8, 3)))
PREFIXES = {-12: "p", -9: "n", -6: "\u00b5", -3: "m", 0: "", 3: "k", 6: "M", 9: "G", 12: "T"}
ROUND_OFF = 1e-12  # errors below are round-off: not drawn on the work-precision diagram


# ---- units ------------------------------------------------------------------------------------
def time_unit(span):
    """(unit, factor) for a time axis covering `span` seconds: us below 1 ms, ms below 1 s, else s."""
    if span < 1e-3:
        return "\u00b5s", 1e6
    if span < 1.0:
        return "ms", 1e3
    return "s", 1.0


def si_scale(values, unit):
    """(label unit, factor) so that the largest |value| reads between 1 and 1000: 2e-3 m -> mm."""
    vmax = 0.0
    for v in values:
        v = np.asarray(v, dtype=float)
        if v.size:
            finite = v[np.isfinite(v)]
            if finite.size:
                vmax = max(vmax, float(np.abs(finite).max()))
    if vmax == 0.0:
        return unit, 1.0
    e = int(math.floor(math.log10(vmax) / 3.0)) * 3
    e = max(-12, min(12, e))
    return PREFIXES[e] + unit, 10.0 ** (-e)


def slug(name):
    s = re.sub(r"[^A-Za-z0-9+._-]+", "_", name).strip("_")
    return s or "unnamed"


# ---- a run in a time window -------------------------------------------------------------------
class History:
    """A run (epaphe.results.Run) with a legend label, its record arrays cut to the time window
    [tmin, tmax] s (None: open)."""

    def __init__(self, path, label=None, tmin=None, tmax=None):
        self.run = Run(path)
        self.path, self.f = path, self.run.file
        self.status = self.run.status
        self.name = self.run.name
        self.stem = os.path.splitext(os.path.basename(path))[0]
        self.label = label
        t = self.run.time
        self.nrec = t.size
        if self.nrec == 0:
            raise EpapheError(f"{path}: no records in /time")
        sel = np.ones(t.size, dtype=bool)
        steps = np.diff(t)
        steps = steps[steps > 0]
        tol = 1e-6 * steps.min() if steps.size else 0.0  # --tmin 2e-5 keeps the record at 2e-5
        if tmin is not None:
            sel &= t >= tmin - tol
        if tmax is not None:
            sel &= t <= tmax + tol
        self.sel = sel
        self.t = t[sel]

    def complete(self):
        return self.run.complete

    def bodies(self):
        return list(self.run.bodies)

    def nodesets(self, body):
        return list(self.run.bodies[body].nodesets) if body in self.run.bodies else []

    def has_contact(self, body):
        return body in self.run.bodies and self.run.bodies[body].has_contact

    def records(self, path):
        """The record dataset at `path` in the window (rows missing from an unfinished file: NaN)."""
        return self.run.records_of(path)[self.sel]

    def ids(self, path):
        return self.run.ids(path)

    def close(self):
        self.run.close()


# ---- figures ----------------------------------------------------------------------------------
class Figure:
    """Collects curves and CSV rows for one output figure."""

    def __init__(self, stem, csv_columns):
        self.stem = stem
        self.csv_columns = csv_columns
        self.rows = []

    def add_rows(self, h, t, cols):
        for i in range(t.size):
            self.rows.append([h.label, os.path.basename(h.path), repr(float(t[i]))] + [repr(float(c[i])) for c in cols])


def incomplete_note(fig, hs):
    bad = [h for h in hs if not h.complete()]
    if bad:
        msg = "; ".join(f"{h.label}: status '{h.status}' (not a finished result)" for h in bad)
        fig.text(0.01, 0.005, "note: " + msg, color="firebrick", fontsize=7, ha="left", va="bottom")


def finish(fig, ax_list, hs, tunit, out, fd, written, want_csv):
    """Labels, grid and the note on unfinished runs; writes out/<fd.stem>.png (and .csv)."""
    path = os.path.join(out, fd.stem + ".png")
    ax_list[-1].set_xlabel(f"time ({tunit})")
    for ax in ax_list:
        ax.grid(True, alpha=0.3)
    fig.tight_layout(rect=(0, 0.03, 1, 1) if any(not h.complete() for h in hs) else None)
    incomplete_note(fig, hs)
    fig.savefig(path, dpi=120, bbox_inches="tight", pad_inches=0.1)
    plt.close(fig)
    written.append(path)
    if want_csv:
        write_figure_csv(fd, os.path.join(out, fd.stem + ".csv"), written)


def write_figure_csv(figdata, path, written):
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["label", "file", "time_s"] + figdata.csv_columns)
        w.writerows(figdata.rows)
    written.append(path)


def colors(n):
    cyc = plt.rcParams["axes.prop_cycle"].by_key().get("color", ["C0"])
    return [cyc[i % len(cyc)] for i in range(n)]


def plot_gap(hs, body, node, tunit, tfac, out, written, want_csv):
    data = []
    for h in hs:
        g = h.records(f"bodies/{body}/contact/gap")
        ids = h.ids(f"bodies/{body}/contact/nodes")
        gmin = np.nanmin(g, axis=1) if g.shape[1] else np.full(h.t.size, np.nan)
        gk = None
        if node is not None:
            if node >= g.shape[1]:
                raise EpapheError(
                    f"{h.path}: --node {node} out of range: body '{body}' has "
                    f"{g.shape[1]} contact nodes (0..{g.shape[1] - 1})"
                )
            gk = (g[:, node], int(ids[node]))
        data.append((h, gmin, gk, g.shape[1]))
    unit, fac = si_scale([d[1] for d in data] + [d[2][0] for d in data if d[2]], "m")
    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    cols = colors(len(hs))
    fd = Figure(f"gap-{slug(body)}", ["gap_min_m"] + ([f"gap_node{node}_m"] if node is not None else []))
    for (h, gmin, gk, n), c in zip(data, cols):
        ax.plot(h.t * tfac, gmin * fac, color=c, lw=1.4, label=f"{h.label}: min over {n} nodes")
        csvcols = [gmin]
        if gk is not None:
            ax.plot(h.t * tfac, gk[0] * fac, color=c, lw=1.0, ls="--", label=f"{h.label}: node {node} (id {gk[1]})")
            csvcols.append(gk[0])
        fd.add_rows(h, h.t, csvcols)
    ax.axhline(0.0, color="k", lw=0.7)
    ax.set_ylabel(f"gap ({unit})")
    ax.set_title(f"{body}: gap of the contact nodes")
    ax.legend(fontsize=8)
    finish(fig, [ax], hs, tunit, out, fd, written, want_csv)


def plot_force(hs, body, tunit, tfac, out, written, want_csv):
    curves = [(h, h.records(f"bodies/{body}/contact/total_force").reshape(h.t.size, -1)[:, 0]) for h in hs]
    unit, fac = si_scale([c[1] for c in curves], "N")
    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    fd = Figure(f"force-{slug(body)}", ["total_force_N"])
    for (h, f), c in zip(curves, colors(len(hs))):
        ax.plot(h.t * tfac, f * fac, color=c, lw=1.2, label=h.label)
        fd.add_rows(h, h.t, [f])
    ax.set_ylabel(f"total contact force ({unit})")
    ax.set_title(f"{body}: total contact force")
    ax.legend(fontsize=8)
    finish(fig, [ax], hs, tunit, out, fd, written, want_csv)


def plot_field(hs, body, nset, what, node, tunit, tfac, out, written, want_csv):
    base_unit = "m" if what == "displacement" else "m/s"
    sym = "u" if what == "displacement" else "v"
    curves = []
    for h in hs:
        d = h.records(f"bodies/{body}/nodesets/{nset}/{what}")
        ids = h.ids(f"bodies/{body}/nodesets/{nset}/nodes")
        n = d.shape[1]
        if node is not None:
            if node >= n:
                raise EpapheError(
                    f"{h.path}: --node {node} out of range: node set '{nset}' of body '{body}' "
                    f"has {n} nodes (0..{n - 1})"
                )
            v = d[:, node, :]
            which = f"node {node} (id {int(ids[node])})"
        else:
            v = np.nanmean(d, axis=1) if n else np.full((h.t.size, 3), np.nan)
            which = f"mean of {n} nodes"
        curves.append((h, v, which))
    # each component its own prefix: a 100 m/s X next to a round-off Y stays readable
    scales = [si_scale([c[1][:, k] for c in curves], base_unit) for k in range(3)]
    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(7.5, 7.5))
    fd = Figure(f"{what}-{slug(body)}-{slug(nset)}", [f"{sym}{x}_{base_unit.replace('/', '_per_')}" for x in "xyz"])
    for (h, v, which), c in zip(curves, colors(len(hs))):
        for k, ax in enumerate(axes):
            ax.plot(h.t * tfac, v[:, k] * scales[k][1], color=c, lw=1.2, label=h.label)
        fd.add_rows(h, h.t, [v[:, 0], v[:, 1], v[:, 2]])
    for k, ax in enumerate(axes):
        ax.set_ylabel(f"{sym}$_{'xyz'[k]}$ ({scales[k][0]})")
    whiches = sorted({c[2] for c in curves})
    axes[0].set_title(f"{body}, node set {nset}: {what}, {'; '.join(whiches)}")
    axes[0].legend(fontsize=8)
    finish(fig, list(axes), hs, tunit, out, fd, written, want_csv)


def plot_energy(hs, tunit, tfac, out, written, want_csv):
    data = []
    for h in hs:
        e = {k: h.records(f"energy/{k}") for k, _ in ENERGIES}
        e["balance_error"] = h.records("energy/balance_error")
        data.append((h, e))
    unit, fac = si_scale([e[k] for _, e in data for k, _ in ENERGIES], "J")
    fig, ax = plt.subplots(figsize=(7.5, 4.8))
    ax2 = ax.twinx()
    qcol = colors(len(ENERGIES))
    fd = Figure("energy", [f"{k}_J" for k, _ in ENERGIES] + ["balance_error"])
    many = len(hs) > 1
    for i, (h, e) in enumerate(data):
        ls = LINESTYLES[i % len(LINESTYLES)]
        for (k, name), c in zip(ENERGIES, qcol):
            ax.plot(h.t * tfac, e[k] * fac, color=c, ls=ls, lw=1.2, label=name if i == 0 else None)
        ax2.plot(
            h.t * tfac,
            e["balance_error"],
            color="0.45",
            ls=ls,
            lw=0.9,
            label="balance error (right)" if i == 0 else None,
        )
        fd.add_rows(h, h.t, [e[k] for k, _ in ENERGIES] + [e["balance_error"]])
    ax.set_ylabel(f"energy ({unit})")
    ax2.set_ylabel("relative balance error (-)", color="0.35")
    ax2.tick_params(axis="y", colors="0.35")
    ax2.ticklabel_format(axis="y", style="sci", scilimits=(-2, 3))
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = ax2.get_legend_handles_labels()
    # legends under the axes, where they hide no curve: quantities (colours), files (line styles)
    leg = ax.legend(
        h1 + h2, l1 + l2, fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=5, frameon=False
    )
    if many:
        ax.add_artist(leg)
        from matplotlib.lines import Line2D

        fh = [Line2D([], [], color="k", ls=LINESTYLES[i % len(LINESTYLES)]) for i in range(len(hs))]
        ax.legend(
            fh,
            [h.label for h in hs],
            fontsize=8,
            loc="upper center",
            bbox_to_anchor=(0.5, -0.2),
            ncol=min(len(hs), 4),
            frameon=False,
        )
    title = "energies"
    names = {h.name for h in hs}
    if len(names) == 1 and next(iter(names)):
        title += f": {next(iter(names))}"
    ax.set_title(title)
    finish(fig, [ax], hs, tunit, out, fd, written, want_csv)


# ---- studies (epaphe-sweep) -------------------------------------------------------------------
def curve_data(r, kind, w, comp=None):
    h = r.hist
    if kind == "force":
        return h["force"]
    if kind == "gap":
        return None if h["gap"] is None else np.nanmin(h["gap"], axis=1)
    return None if h["u"] is None else h["u"][:, w.comp if comp is None else comp]


def plot_curves(study, runs, ref, w, plot_comps, out, stem, window, written):
    """One PNG per curve kind, every run overlaid (the reference dashed black); the displacement
    has one subplot per component."""
    done = [r for r in runs if r.hist is not None and not (r.is_reference and r.alone)]
    if not done:
        return
    tmax = max(float(r.hist["t"][-1]) for r in done)
    tmin = 0.0
    if window:
        tmin, tmax = window
    tunit, tfac = time_unit(tmax - tmin)
    sel = lambda t: (t >= tmin - 1e-15) & (t <= tmax + 1e-15)  # noqa: E731
    for kind in study.plots.get("Curves", list(CURVES)):
        comps = plot_comps if kind == "displacement" else [None]
        panels = []
        for comp in comps:
            series = []
            for r in done:
                y = curve_data(r, kind, w, comp)
                if y is not None:
                    series.append((r.label + ("  [reference]" if r.is_reference else ""), r.hist["t"], y, {}))
            if not series:
                continue
            if ref is not None and ref[0] == "exact":
                ex, ids = ref[1], done[0].hist["ids"]
                tt = np.union1d(np.linspace(0, tmax, 4001), ex.breaks)
                y = (
                    ex.force(tt)
                    if kind == "force"
                    else ex.gap(tt)
                    if kind == "gap"
                    else (ex.watched(tt, ids, comp, w.node) if ids is not None else None)
                )
                if y is not None:
                    series.append((ex.label, tt, y, dict(color="k", ls="--", lw=1.0)))
            elif ref is not None and ref[1].alone:
                rr = ref[1]
                y = curve_data(rr, kind, w, comp)
                if y is not None:
                    series.append((f"reference: {rr.label}", rr.hist["t"], y, dict(color="k", ls="--", lw=1.0)))
            panels.append((comp, series))
        if not panels:
            continue
        fig, axes = plt.subplots(
            len(panels),
            1,
            sharex=True,
            squeeze=False,
            figsize=(8, 4.8 if len(panels) == 1 else 2.2 + 2.4 * len(panels)),
        )
        axes = axes[:, 0]
        for ax, (comp, series) in zip(axes, panels):
            unit, fac = si_scale([y[sel(t)] for _, t, y, _ in series], "N" if kind == "force" else "m")
            cols = colors(len(series))
            for i, (lab, t, y, style) in enumerate(series):
                s = sel(t)
                kw = dict(color=cols[i], lw=1.2, ls=LINESTYLES[(i // 10) % len(LINESTYLES)])
                if r_is_ref(lab):
                    kw.update(lw=2.0, alpha=0.6)
                kw.update(style)
                ax.plot(t[s] * tfac, y[s] * fac, label=lab, **kw)
            if kind == "displacement":
                ax.set_ylabel(f"u$_{'xyz'[comp]}$ ({unit})")
            else:
                ax.set_ylabel(("total contact force" if kind == "force" else "minimum gap") + f" ({unit})")
            if kind == "gap":
                ax.axhline(0.0, color="0.3", lw=0.6)
            ax.grid(True, alpha=0.3)
        if kind == "displacement":
            which = f"node {w.node} (id {int(done[0].hist['ids'][w.node])}) of" if w.node >= 0 else "mean of"
            title = f"{w.body}: displacement, {which} node set {w.nodeset}"
        else:
            title = f"{w.body}: " + ("total contact force" if kind == "force" else "minimum gap of the contact nodes")
        axes[0].set_title(f"{study_title(study, stem)}\n{title}", fontsize=10)
        axes[0].legend(fontsize=7, ncol=1 if len(panels[0][1]) < 8 else 2)
        axes[-1].set_xlabel(f"time ({tunit})")
        fig.tight_layout()
        path = os.path.join(out, f"{stem}-{kind}.png")
        fig.savefig(path, dpi=120)
        plt.close(fig)
        written.append(path)


def r_is_ref(label):
    return label.endswith("[reference]")


def study_title(study, stem):
    """The study's name (else the stem of its file) and its deck: "bar time step (bar-on-wall.xml)"."""
    deck = os.path.basename(study.deck_path) if getattr(study, "deck_path", None) else None
    return (study.name or stem) + (f" ({deck})" if deck else "")


def plot_work_precision(study, runs, cost_key, out, stem, written):
    """The study's work-precision diagram, out/<stem>-work-precision.png: the error of each measure
    (dimensionless, its definition in the legend) against the cost of the run (wall or loop time,
    s). The Figure, or None when no error is drawable."""
    done = [r for r in runs if r.status == "complete" and r.errors and not (r.is_reference and r.alone)]
    series = work_precision_series(done, study.measures.get("Compute") or DEFAULT_MEASURES, cost_key)
    series = [(f"{k}: {ERROR_DEFINITIONS[k]}" if k in ERROR_DEFINITIONS else k, pts) for k, pts in series]
    if study.reference and study.reference[0] == "exact":
        against = f"the exact solution {study.reference[1]}"
    else:
        ref = next((r for r in runs if r.is_reference), None)
        against = f"the run {ref.label}" if ref is not None else "the reference"
    path = os.path.join(out, f"{stem}-work-precision.png")
    fig = draw_work_precision(
        series,
        f"{cost_key.replace('_', ' ')} (s)",
        f"error against {against} (-)",
        f"{study_title(study, stem)}: work-precision",
        path,
    )
    if fig is None:
        return None
    written.append(path)
    return fig


def draw_work_precision(series, xlabel, ylabel, title, path):
    """Error (log) against cost (log): one line per [(name, [(cost, error, point label)])], each point
    labelled once; errors at or below ROUND_OFF and non-finite points are left out. The Figure
    (written to `path` and closed: its axes stay readable), or None (no file) when no point is
    left."""
    fig, ax = plt.subplots(figsize=(8, 5.2))
    markers = "osD^v<>pPX*h"
    annotated, any_point = set(), False
    for i, (name, points) in enumerate(series):
        pts = [(x, y, lab) for x, y, lab in points if np.isfinite(x) and np.isfinite(y) and x > 0 and y > ROUND_OFF]
        if not pts:
            continue
        any_point = True
        ax.plot([p[0] for p in pts], [p[1] for p in pts], marker=markers[i % len(markers)], lw=1.0, ms=5, label=name)
        for x, y, lab in pts:
            if lab not in annotated:
                annotated.add(lab)
                ax.annotate(lab, (x, y), textcoords="offset points", xytext=(4, 4), fontsize=6, color="0.3")
    if not any_point:
        plt.close(fig)
        return None
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title + f"\n(errors below {ROUND_OFF:g}, round-off, not drawn)", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return fig


# ---- rotating blades (epaphe-rotor) -----------------------------------------------------------
def draw_interaction_map(eo_grid, speeds, amplitude, path, deck, nodeset, component="x", dominant=None):
    """The interaction map of a speed sweep (thesis figures 5.12-5.15): the spectrum amplitude of the
    mean displacement of `nodeset` along `component` (m, log colour scale, 6 decades below the
    largest) against engine order (x, -) and rotation speed (y, rad/s), titled with the deck's
    name; `dominant` (the largest line above EO 0.5 at each speed) drawn as circles, in the legend.
    The Figure (written to `path` and closed)."""
    import matplotlib.colors as mcolors

    fig, ax = plt.subplots(figsize=(7.5, 4.8))
    a = np.asarray(amplitude, dtype=float)
    top = float(np.nanmax(a)) if a.size and np.nanmax(a) > 0 else 1.0
    mesh = ax.pcolormesh(
        eo_grid,
        np.array(speeds, dtype=float),
        np.maximum(a, top * 1e-6),
        shading="nearest",
        norm=mcolors.LogNorm(vmin=top * 1e-6, vmax=top),
    )
    fig.colorbar(mesh, ax=ax, label=f"amplitude of the mean u$_{component}$ (m)")
    if dominant is not None:
        ax.plot(
            dominant,
            speeds,
            "o",
            mfc="none",
            mec="w",
            mew=1.2,
            ms=7,
            ls="none",
            label="dominant engine order (largest line above EO 0.5)",
        )
        ax.legend(fontsize=7, loc="upper right")
    ax.set_xlabel("engine order (-)")
    ax.set_ylabel("rotation speed (rad/s)")
    ax.set_title(f"{deck}: interaction map, node set {nodeset}", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return fig


def draw_wear_speed_map(angle, speeds, profile, dominant, path, deck, surface):
    """The wear map of a speed sweep with an abradable coating: the final wear depth (um, colour) of
    each column of the coating (the deepest over the axial rows) against the angle (x, degrees, the
    casing's frame) and the rotation speed (y, rad/s), each speed's dominant harmonic of the wear
    written at the right. The Figure (written to `path` and closed)."""
    fig, ax = plt.subplots(figsize=(7.5, 4.8))
    speeds = np.array(speeds, dtype=float)
    order = np.argsort(speeds)
    mesh = ax.pcolormesh(
        np.degrees(angle), np.arange(len(speeds)), np.asarray(profile)[order] * 1e6, shading="nearest", cmap="viridis"
    )
    fig.colorbar(mesh, ax=ax, label="wear depth (um)", pad=0.12)
    ax.set_yticks(np.arange(len(speeds)))
    ax.set_yticklabels([f"{w:g}" for w in speeds[order]])
    right = ax.secondary_yaxis("right")
    right.set_yticks(np.arange(len(speeds)))
    right.set_yticklabels([str(int(dominant[i])) for i in order])
    right.set_ylabel("dominant harmonic of the wear")
    ax.set_xlabel("angle about the casing axis (deg, casing frame)")
    ax.set_ylabel("rotation speed (rad/s)")
    ax.set_xlim(0, 360)
    ax.set_title(f"{deck}: wear of the coating on {surface} against rotation speed", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return fig


def draw_spectrum(eo, amp, ylabel, title, path, rotation_hz=None):
    """Amplitude (log) against engine order (-), up to order 40; with the rotation frequency
    `rotation_hz` (Hz), a frequency axis (Hz) on top. The Figure (written to `path` and closed)."""
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.semilogy(eo, amp)
    ax.set_xlabel("engine order: frequency / rotation frequency (-)")
    ax.set_ylabel(ylabel)
    ax.set_xlim(0, min(eo[-1], 40))
    if rotation_hz:
        top = ax.secondary_xaxis("top", functions=(lambda x: x * rotation_hz, lambda f: f / rotation_hz))
        top.set_xlabel("frequency (Hz)")
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return fig
