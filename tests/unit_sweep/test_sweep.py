#!/usr/bin/env python3
"""drivers/epaphe-sweep (python/epaphe/cli/sweep.py): studies over decks, measures, CSV and plots.

  --case study  (label study, ~15 s) a tiny time-step study of the bar on a rigid wall (End time
                1.2e-4 s; h = 4e-7, 2e-7, 1e-7 and an unstable 2e-6; reference: a run at h = 2.5e-8):
                  * the CSV has one row per run (the reference included), the expected columns, the
                    unstable step reported as "refused: unstable time step", the others complete;
                  * every error of a complete run is finite, and the displacement error falls by at
                    least 3.5x per halving of h (central difference: second order, 4x in the limit;
                    first order would give 2x);
                  * the PNGs (force, gap, displacement, work-precision) are valid, non-blank images;
                then the same runs against the exact solution (--reference exact:bar-on-wall): no run
                again (the histories are cached), an "exact" row (t0 = 2e-5 s, t1 = 1e-4 s, F = 1.6 MN,
                impulse 128 N s, rebound -100 m/s) and V1's tolerances met (contact times within 1 %
                of the duration, impulse, plateau force and rebound velocity within 2 %).
  --case bad    (label unit, ~5 s) malformed studies and command lines: exit status 1 and one line
                on stderr naming the file (and line), the key and the value.
  --case studies (label study, ~20 s) every study in inputs/studies/ is valid (--check: the study,
                its deck keys, and every variant deck through epaphe-run --check).
  --case jobs   (label study, ~20 s; 50 s on a busy machine) runs in parallel, progress and figure
                labels, on a study of 6 runs of the bar (h = 2e-6 (refused), 4e-7, 2e-7, 1e-7, 5e-8 and the reference 2.5e-8):
                  * --jobs 2 writes the same CSV as --jobs 1 (every column but the measured times,
                    same row order: the study's), and each prints one line per run ending with
                    "k of 6 done, 6 - k left, ETA m:ss (mean ... s a case, J at a time)" for k = 1..6;
                  * rerun without --force: the cached runs count as done, and the mean is the time of
                    the one run that ran (the refused step), not lowered by the cached ones;
                  * the figures (read back from the matplotlib Figure objects as the sweep saves them):
                    axis labels with units, "wall time (s)" and an error "(-)" on the work-precision
                    diagram, titles naming the study and the deck, a legend entry per series; the
                    interaction map and spectrum of epaphe-rotor (drawn from synthetic spectra):
                    "engine order (-)", "rotation speed (rad/s)", the colour bar in m, "frequency (Hz)";
                  * Ctrl-C (SIGINT to the sweep alone) with 2 long runs going: exit status 130, both
                    histories "stopped: interrupted by SIGINT" (checkpointed), the third run never
                    started, no epaphe-run left running.
                Prints the wall time of the study with --jobs 1 and --jobs 2 (reported, not asserted).
"""
import argparse
import csv
import importlib.machinery
import importlib.util
import math
import os
import re
import signal
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
failures = []


def check(cond, msg):
    if not cond:
        failures.append(msg)
    return cond


def load_png_checker():
    path = os.path.join(HERE, "..", "unit_plot", "test_plot.py")
    loader = importlib.machinery.SourceFileLoader("test_plot", path)
    spec = importlib.util.spec_from_loader("test_plot", loader)
    mod = importlib.util.module_from_spec(spec)
    saved = list(sys.path)
    loader.exec_module(mod)
    sys.path[:] = saved
    return mod.png_problems


def sweep(a, args, cwd):
    cmd = [sys.executable, a.sweep] + args + ["--run", a.run]
    proc = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True)
    return proc


def read_csv(path):
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    return rows[0], [dict(zip(rows[0], r)) for r in rows[1:]]


def fnum(s):
    return float(s) if s != "" else float("nan")


STUDY = """<ParameterList name="Study">
  <Parameter name="Name" type="string" value="tiny bar time-step study"/>
  <Parameter name="Deck" type="string" value="{deck}"/>
  <ParameterList name="Set">
    <Parameter name="Time->End time" type="double" value="1.2e-4"/>
    <Parameter name="Run->Progress interval" type="double" value="0"/>
  </ParameterList>
  <ParameterList name="Vary">
    <Parameter name="Time->Time step" type="Array(string)" value="{{2e-6, 4e-7, 2e-7, 1e-7}}"/>
  </ParameterList>
  <ParameterList name="Reference">
    <ParameterList name="Run">
      <Parameter name="Time->Time step" type="double" value="2.5e-8"/>
    </ParameterList>
  </ParameterList>
  <ParameterList name="Measures">
    <Parameter name="Node set" type="string" value="x-"/>
  </ParameterList>
  <ParameterList name="Plots">
    <Parameter name="Components" type="Array(string)" value="{{x, y}}"/>
  </ParameterList>
</ParameterList>
"""
MEASURE_COLS = [
    "contact_start_s",
    "contact_end_s",
    "impulse_Ns",
    "plateau_force_N",
    "max_penetration_m",
    "displacement_rms_m",
    "rebound_velocity_m_per_s",
    "energy_balance_rel",
]
ERROR_COLS = [
    "contact_start_error",
    "contact_end_error",
    "impulse_error",
    "plateau_force_error",
    "max_penetration_error",
    "displacement_rms_error",
    "rebound_velocity_error",
    "energy_balance_error",
]
COST_COLS = ["wall_time_s", "setup_time_s", "loop_time_s", "steps", "steps_per_second", "threads"]


def case_study(a):
    png_problems = load_png_checker()
    study = os.path.join(a.workdir, "tiny.xml")
    with open(study, "w") as fh:
        fh.write(STUDY.format(deck=a.deck))
    out = os.path.join(a.workdir, "out")
    proc = sweep(a, [study, "--out", out, "--threads", "1", "--force"], a.workdir)
    print(proc.stdout + proc.stderr)
    if not check(proc.returncode == 0, f"the sweep failed (exit {proc.returncode})"):
        return
    head, rows = read_csv(os.path.join(out, "tiny.csv"))
    for col in (
        ["run", "label", "Time->Time step", "status", "reference", "time_step_s"]
        + MEASURE_COLS
        + ERROR_COLS
        + COST_COLS
        + ["file"]
    ):
        check(col in head, f"CSV: no column {col} (columns: {head})")
    check(len(rows) == 5, f"CSV: {len(rows)} rows, expected 5 (4 variants and the reference run)")
    by_h = {r["Time->Time step"]: r for r in rows}
    check(set(by_h) == {"2e-6", "4e-7", "2e-7", "1e-7", "2.5e-8"}, f"CSV: varied values {sorted(by_h)}")
    ref = [r for r in rows if r["reference"] == "yes"]
    check(
        len(ref) == 1 and ref[0]["time_step_s"] and math.isclose(fnum(ref[0]["time_step_s"]), 2.5e-8),
        f"CSV: the reference row is not the h = 2.5e-8 run: {ref}",
    )
    bad = by_h.get("2e-6", {})
    check(
        bad.get("status", "").startswith("refused: unstable time step"),
        f"h = 2e-6: status '{bad.get('status')}', expected 'refused: unstable time step (critical ...)'",
    )
    check(all(bad.get(c, "") == "" for c in MEASURE_COLS), "h = 2e-6: a refused run has measures")
    steps = ["4e-7", "2e-7", "1e-7"]
    for h in steps:
        r = by_h.get(h, {})
        check(r.get("status") == "complete", f"h = {h}: status {r.get('status')}")
        for c in ERROR_COLS + MEASURE_COLS + ["wall_time_s", "steps_per_second"]:
            check(math.isfinite(fnum(r.get(c, ""))), f"h = {h}: {c} = '{r.get(c)}' is not finite")
        check(fnum(r.get("steps", "")) == round(1.2e-4 / float(h)), f"h = {h}: steps {r.get('steps')}")
    d = [fnum(by_h[h]["displacement_rms_error"]) for h in steps if h in by_h]
    print(
        "displacement error vs h = 2.5e-8:",
        ", ".join(f"h={h}: {x:.3e}" for h, x in zip(steps, d)),
        "; ratios",
        ", ".join(f"{d[i] / d[i + 1]:.2f}" for i in range(len(d) - 1)),
    )
    # Second order is what theory gives for this measure: the RMS displacement difference of the
    # x- face to the h = 2.5e-8 run. Between contact events central difference is second order;
    # the impact instant (t0 = 2e-5 s) is a multiple of every step, so the velocity jump falls on
    # the grid, and the Lagrange force falls continuously to zero at release (no O(h) event error).
    # Asserted: a ratio of at least 3.5 (2^1.8) per halving, which first order (2) cannot reach.
    check(
        len(d) == 3 and all(d[i] >= 3.5 * d[i + 1] for i in range(2)),
        f"the displacement error does not fall by 3.5x per halving of h (second order): {d}",
    )
    for kind in ("force", "gap", "displacement", "work-precision"):
        p = os.path.join(out, f"tiny-{kind}.png")
        if check(os.path.isfile(p) and os.path.getsize(p) > 0, f"{p} missing or empty"):
            probs = png_problems(p)
            check(not probs, f"{p}: {probs}")
            check(p in proc.stdout.splitlines(), f"{p} is not in the files printed")

    # the same runs against the exact solution: nothing runs again
    proc = sweep(a, [study, "--out", out, "--reference", "exact:bar-on-wall"], a.workdir)
    print(proc.stdout + proc.stderr)
    if not check(proc.returncode == 0, f"the exact-reference sweep failed (exit {proc.returncode})"):
        return
    for h in steps:
        check(f"Time_step={h}: cached" in proc.stdout, f"h = {h} ran again: the cache missed")
    check(
        ": running" not in proc.stdout.replace("Time_step=2e-6: running", ""),
        "a run ran again although its history is up to date",
    )
    head, rows = read_csv(os.path.join(out, "tiny.csv"))
    check(len(rows) == 5, f"CSV (exact): {len(rows)} rows, expected 5 (exact and 4 variants)")
    ex = next((r for r in rows if r["run"] == "exact"), None)
    if check(ex is not None, "CSV (exact): no 'exact' row"):
        for col, want in (
            ("contact_start_s", 2e-5),
            ("contact_end_s", 1e-4),
            ("plateau_force_N", 1.6e6),
            ("impulse_Ns", 128.0),
            ("rebound_velocity_m_per_s", -100.0),
        ):
            check(math.isclose(fnum(ex[col]), want, rel_tol=1e-9), f"exact {col} = {ex[col]}, expected {want:g}")
    for r in rows:
        if r["status"] != "complete":
            continue
        e = {c: fnum(r[c]) for c in ERROR_COLS}
        for c, tol in (
            ("contact_start_error", 0.01),
            ("contact_end_error", 0.01),
            ("impulse_error", 0.02),
            ("plateau_force_error", 0.02),
            ("rebound_velocity_error", 0.02),
            ("displacement_rms_error", 0.02),
        ):
            check(e[c] <= tol, f"{r['run']} vs exact: {c} = {e[c]:.3g} > {tol}")
        check(e["energy_balance_error"] < 1e-8, f"{r['run']}: energy balance {e['energy_balance_error']}")


# STUDY with one more time step and no Plots list
JOBS_STUDY = re.sub(
    r'  <ParameterList name="Plots">.*?</ParameterList>\n',
    "",
    STUDY.replace("tiny bar time-step study", "jobs study").replace(
        "{{2e-6, 4e-7, 2e-7, 1e-7}}", "{{2e-6, 4e-7, 2e-7, 1e-7, 5e-8}}"
    ),
    flags=re.S,
)
TIMING_COLS = ("wall_time_s", "setup_time_s", "loop_time_s", "steps_per_second")  # measured, differ run to run
# "[i/N] NAME: STATUS in X s; k of N done, L left, ETA m:ss (mean Y s a case, J at a time)"
END_LINE = re.compile(
    r"^\[(\d+)/(\d+)\] (\S+): (.+?) in ([0-9.]+) s(?: \(log: [^)]*\))?; (\d+) of (\d+) done, "
    r"(\d+) left, ETA (\d+:\d\d) \(mean ([0-9.]+) s a case, (\d+) at a time\)$"
)
CACHED_LINE = re.compile(r"^\[(\d+)/(\d+)\] (\S+): cached \([^)]*\); (\d+) of (\d+) done, (\d+) left")


def progress_ok(tag, stdout, total, jobs):
    """Every run ends with a line "k of N done, N - k left, ETA ..." (k = 1..N in order) at `jobs` at a time."""
    ends = [m for m in map(END_LINE.match, stdout.splitlines()) if m]
    ks = [int(m.group(6)) for m in ends]
    check(
        ks == list(range(1, total + 1)),
        f"{tag}: the progress lines count {ks}, expected 1..{total} "
        f"(one 'k of {total} done, ..., ETA m:ss' line per run)",
    )
    for m in ends:
        check(
            int(m.group(7)) == total and int(m.group(8)) == total - int(m.group(6)),
            f"{tag}: '{m.group(0)}': the count of runs left is not N - k",
        )
        check(int(m.group(11)) == jobs, f"{tag}: '{m.group(0)}': {m.group(11)} at a time, expected {jobs}")
    return ends


def capture_figures():
    """Records every matplotlib Figure saved ({file name: Figure}): the sweep closes its figures after
    saving them, and their axes stay readable."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    saved, original = {}, Figure.savefig

    def savefig(self, fname, *args, **kw):
        saved[os.path.basename(str(fname))] = self
        return original(self, fname, *args, **kw)

    Figure.savefig = savefig
    return saved, lambda: setattr(Figure, "savefig", original)


def has_unit(label):
    return re.search(r"\([^()]+\)$", label) is not None


def check_study_figures(figs, name, deck):
    wp = figs.get(f"{name}-work-precision.png")
    if check(wp is not None, f"no work-precision figure saved (saved: {sorted(figs)})"):
        ax = wp.axes[0]
        check(ax.get_xlabel() == "wall time (s)", f"work-precision: x label '{ax.get_xlabel()}'")
        check(
            ax.get_ylabel().startswith("error against") and ax.get_ylabel().endswith("(-)"),
            f"work-precision: y label '{ax.get_ylabel()}', expected 'error against ... (-)'",
        )
        check("jobs study" in ax.get_title() and deck in ax.get_title(), f"work-precision: title '{ax.get_title()}'")
        leg = ax.get_legend()
        texts = [t.get_text() for t in leg.get_texts()] if leg else []
        check(
            len(texts) >= 2 and all(any(t.startswith(m + ":") for t in texts) for m in ("impulse", "displacement")),
            f"work-precision: legend {texts}: expected one entry per measure, named",
        )
    for kind, nplots in (("force", 1), ("gap", 1), ("displacement", 1)):
        fig = figs.get(f"{name}-{kind}.png")
        if not check(fig is not None, f"no {kind} figure saved"):
            continue
        axes = fig.axes
        check(len(axes) == nplots, f"{kind}: {len(axes)} axes")
        check(
            re.fullmatch(r"time \((\u00b5s|ms|s)\)", axes[-1].get_xlabel()) is not None,
            f"{kind}: x label '{axes[-1].get_xlabel()}'",
        )
        for ax in axes:
            check(has_unit(ax.get_ylabel()), f"{kind}: y label '{ax.get_ylabel()}' has no unit")
        title = axes[0].get_title()
        check("jobs study" in title and deck in title, f"{kind}: title '{title}'")
        leg = axes[0].get_legend()
        n = len(leg.get_texts()) if leg else 0
        check(n == 5, f"{kind}: {n} legend entries, expected 5 (4 complete variants and the reference)")


def check_rotor_figures(workdir):
    """epaphe-rotor's interaction map and spectrum, drawn from synthetic spectra (lines at EO 4, 6, 2)."""
    import numpy as np
    from epaphe import plots

    eo = np.linspace(0, 40, 801)
    speeds = [600.0, 1000.0, 1400.0]
    amp = np.array([1e-5 * np.exp(-((eo - k) ** 2) / 0.01) + 1e-9 for k in (4, 6, 2)])
    fig = plots.draw_interaction_map(
        eo,
        speeds,
        amp,
        os.path.join(workdir, "map-tip-le.png"),
        "blade-casing.xml",
        "tip-le",
        "x",
        dominant=[4.0, 6.0, 2.0],
    )
    ax, bar = fig.axes[0], fig.axes[1]
    check(ax.get_xlabel() == "engine order (-)", f"interaction map: x label '{ax.get_xlabel()}'")
    check(ax.get_ylabel() == "rotation speed (rad/s)", f"interaction map: y label '{ax.get_ylabel()}'")
    check(bar.get_ylabel().endswith("(m)"), f"interaction map: colour bar label '{bar.get_ylabel()}'")
    check(
        "blade-casing.xml" in ax.get_title() and "tip-le" in ax.get_title(),
        f"interaction map: title '{ax.get_title()}'",
    )
    check(ax.get_legend() is not None, "interaction map: no legend for the dominant-order circles")
    fig = plots.draw_spectrum(
        eo,
        amp[0],
        "|u_x| (m)",
        "speed-600.h5, node set tip-le",
        os.path.join(workdir, "s.png"),
        rotation_hz=600.0 / (2 * math.pi),
    )
    ax = fig.axes[0]
    check(
        ax.get_xlabel().endswith("(-)") and ax.get_ylabel() == "|u_x| (m)",
        f"spectrum: labels '{ax.get_xlabel()}', " f"'{ax.get_ylabel()}'",
    )
    top = ax.child_axes[0] if ax.child_axes else None
    if check(top is not None and top.get_xlabel() == "frequency (Hz)", "spectrum: no 'frequency (Hz)' axis on top"):
        # EO 40 at 600 rad/s: 40 x 600 / (2 pi) = 3819.7 Hz
        check(
            math.isclose(top.get_xlim()[1], 40 * 600 / (2 * math.pi), rel_tol=1e-9),
            f"spectrum: the frequency axis ends at {top.get_xlim()[1]} Hz, expected 3819.7",
        )


def case_jobs(a):
    study = os.path.join(a.workdir, "jobs.xml")
    with open(study, "w") as fh:
        fh.write(JOBS_STUDY.format(deck=a.deck))
    total = 6
    out, secs = {}, {}
    for jobs in (1, 2):
        out[jobs] = os.path.join(a.workdir, f"out-j{jobs}")
        t0 = time.time()
        proc = sweep(a, [study, "--out", out[jobs], "--force", "--jobs", str(jobs)], a.workdir)
        secs[jobs] = time.time() - t0
        print(proc.stdout + proc.stderr)
        if not check(proc.returncode == 0, f"--jobs {jobs}: the sweep failed (exit {proc.returncode})"):
            return
        progress_ok(f"--jobs {jobs}", proc.stdout, total, jobs)
    print(f"wall time of the study ({total} runs, 1 thread each): --jobs 1 {secs[1]:.1f} s, --jobs 2 {secs[2]:.1f} s")
    head1, rows1 = read_csv(os.path.join(out[1], "jobs.csv"))
    head2, rows2 = read_csv(os.path.join(out[2], "jobs.csv"))
    check(head1 == head2, f"the CSV columns differ: {head1} / {head2}")
    names = [r["run"] for r in rows1]
    order = ["reference_Time_step=2.5e-8"] + [f"Time_step={h}" for h in ("2e-6", "4e-7", "2e-7", "1e-7", "5e-8")]
    check(names == order, f"--jobs 1: rows {names}, expected the study's order {order}")
    check([r["run"] for r in rows2] == names, f"--jobs 2: rows {[r['run'] for r in rows2]}, expected {names}")
    for r1, r2 in zip(rows1, rows2):
        for c in head1:
            if c not in TIMING_COLS:
                check(r1[c] == r2[c], f"{r1['run']}: {c} = '{r1[c]}' with --jobs 1, '{r2[c]}' with --jobs 2")
    check(sum(r["status"] == "complete" for r in rows2) == 5, "--jobs 2: not 5 complete runs")

    # again without --force, in this process: 5 cached, the refused step runs again; the figures read back
    saved, restore = capture_figures()
    try:
        res = in_process(a)([study, "--out", out[2], "--jobs", "2"])
    finally:
        restore()
    print(res.stdout + res.stderr)
    if check(res.returncode == 0, f"cached rerun: exit {res.returncode}: {res.stderr}"):
        cached = [m for m in map(CACHED_LINE.match, res.stdout.splitlines()) if m]
        ends = [m for m in map(END_LINE.match, res.stdout.splitlines()) if m]
        ks = sorted([int(m.group(4)) for m in cached] + [int(m.group(6)) for m in ends])
        check(
            len(cached) == 5 and ks == list(range(1, total + 1)),
            f"cached rerun: {len(cached)} cached lines, "
            f"counts {ks}: expected 5 cached runs counted as done, 1..{total}",
        )
        if check(
            len(ends) == 1 and ends[0].group(3) == "Time_step=2e-6", "cached rerun: not one run (the refused step)"
        ):
            m = ends[0]
            check(
                m.group(5) == m.group(10),
                f"cached rerun: mean {m.group(10)} s a case, the one run took "
                f"{m.group(5)} s: the cached runs changed the mean",
            )
        check_study_figures(saved, "jobs", os.path.basename(a.deck))
    check_rotor_figures(a.workdir)
    case_interrupt(a)


def running_in(directory):
    """Processes whose working directory is `directory` (the epaphe-run of a sweep run there)."""
    found = []
    for pid in os.listdir("/proc"):
        if pid.isdigit():
            try:
                if os.path.realpath(os.readlink(f"/proc/{pid}/cwd")) == os.path.realpath(directory):
                    found.append(int(pid))
            except OSError:
                pass
    return found


def case_interrupt(a):
    out = os.path.join(a.workdir, "out-interrupt")
    # 1e6, 5e5 and 3.3e5 steps (about 20, 10 and 7 s each): SIGINT once both first runs are in their time loop
    cmd = [
        sys.executable,
        a.sweep,
        a.deck,
        "--vary",
        "Time->Time step=1e-7,2e-7,3e-7",
        "--set",
        "Time->End time=0.1",
        "--set",
        "Run->Progress interval=0.2",
        "--reference",
        "none",
        "--out",
        out,
        "--force",
        "--jobs",
        "2",
        "--no-plots",
        "--run",
        a.run,
    ]
    proc = subprocess.Popen(cmd, cwd=a.workdir, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    lines, looping = [], set()
    for line in proc.stdout:
        lines.append(line)
        m = re.match(r"^    \[(\d)/3\] \S+: t = ", line)
        if m:
            looping.add(m.group(1))
        if looping == {"1", "2"}:
            break
    proc.send_signal(signal.SIGINT)
    try:
        rest, err = proc.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        proc.kill()
        rest, err = proc.communicate()
    text = "".join(lines) + rest
    print(text + err)
    check(looping == {"1", "2"}, "Ctrl-C: the first two runs were not both running")
    check(proc.returncode == 130, f"Ctrl-C: exit status {proc.returncode}, expected 130")
    runs = os.path.join(out, "runs")
    check(not running_in(runs), f"Ctrl-C: epaphe-run still running in {runs}: pids {running_in(runs)}")
    sys.path.insert(0, os.path.join(HERE, "..", "..", "python"))
    import epaphe

    for h in ("1e-7", "2e-7"):
        path = os.path.join(runs, f"Time_step={h}.h5")
        try:
            with epaphe.open(path) as run:
                status = run.status
        except Exception as e:  # noqa: BLE001 (reported as a failure)
            status = f"unreadable: {e}"
        check(status.startswith("stopped: interrupted by SIGINT"), f"Ctrl-C: {path}: status '{status}'")
    check("[3/3] Time_step=3e-7: running" not in text, "Ctrl-C: the third run started after the interrupt")
    check(
        "interrupted: 2 of 3 case(s) done; stopped Time_step=1e-7, Time_step=2e-7" in text,
        "Ctrl-C: no line naming the stopped runs",
    )


BAD = [
    (
        "unknown-list",
        """<ParameterList name="Study">
  <Parameter name="Deck" type="string" value="{deck}"/>
  <ParameterList name="Vray"/>
</ParameterList>""",
        ["unknown-list.xml:3", "'Vray'", "did you mean 'Vary'"],
    ),
    (
        "unknown-parameter",
        """<ParameterList name="Study">
  <Parameter name="Deck" type="string" value="{deck}"/>
  <Parameter name="Combien" type="string" value="Zip"/>
</ParameterList>""",
        ["unknown-parameter.xml:3", "'Combien'", "did you mean 'Combine'"],
    ),
    (
        "missing-deck",
        """<ParameterList name="Study">
  <Parameter name="Deck" type="string" value="no/such/deck.xml"/>
  <ParameterList name="Vary"><Parameter name="Time->Time step" type="Array(string)" value="{{1e-7}}"/></ParameterList>
</ParameterList>""",
        ["missing-deck.xml:2", "'Deck'", "no/such/deck.xml", "no such file"],
    ),
    (
        "unknown-deck-key",
        """<ParameterList name="Study">
  <Parameter name="Deck" type="string" value="{deck}"/>
  <ParameterList name="Vary">
    <Parameter name="Time->Time stpe" type="Array(string)" value="{{1e-7, 2e-7}}"/>
  </ParameterList>
</ParameterList>""",
        ["unknown-deck-key.xml:4", "'Time->Time stpe'", "did you mean 'Time->Time step'"],
    ),
    (
        "unknown-body",
        """<ParameterList name="Study">
  <Parameter name="Deck" type="string" value="{deck}"/>
  <ParameterList name="Vary">
    <Parameter name="Bodies->Barr->Reduction->Fixed-interface modes" type="Array(string)" value="{{10, 20}}"/>
  </ParameterList>
</ParameterList>""",
        ["unknown-body.xml:4", "'Barr'", "Bar"],
    ),
    (
        "not-a-number",
        """<ParameterList name="Study">
  <Parameter name="Deck" type="string" value="{deck}"/>
  <ParameterList name="Vary">
    <Parameter name="Time->Time step" type="Array(string)" value="{{1e-7, 2e-7x}}"/>
  </ParameterList>
</ParameterList>""",
        ["not-a-number.xml:4", "'Time->Time step'", "'2e-7x'", "double"],
    ),
    (
        "out-of-range",
        """<ParameterList name="Study">
  <Parameter name="Deck" type="string" value="{deck}"/>
  <ParameterList name="Vary">
    <Parameter name="Time->Time step" type="Array(string)" value="{{1e-7, -2e-7}}"/>
  </ParameterList>
</ParameterList>""",
        ["out-of-range.xml:4", "'Time->Time step' = '-2e-7'", "out of range"],
    ),
    (
        "bad-enum",
        """<ParameterList name="Study">
  <Parameter name="Deck" type="string" value="{deck}"/>
  <ParameterList name="Vary">
    <Parameter name="Contact->Method" type="Array(string)" value="{{Lagrange, Penalti}}"/>
  </ParameterList>
</ParameterList>""",
        ["bad-enum.xml:4", "'Penalti'", "did you mean 'Penalty'"],
    ),
    (
        "zip-lengths",
        """<ParameterList name="Study">
  <Parameter name="Deck" type="string" value="{deck}"/>
  <ParameterList name="Vary">
    <Parameter name="Time->Time step" type="Array(string)" value="{{1e-7, 2e-7}}"/>
    <Parameter name="Contact->Method" type="Array(string)" value="{{Lagrange, Penalty, Lagrange}}"/>
  </ParameterList>
</ParameterList>""",
        ["zip-lengths.xml", "Zip", "'Time->Time step': 2", "'Contact->Method': 3", "Product"],
    ),
    (
        "bad-combine",
        """<ParameterList name="Study">
  <Parameter name="Deck" type="string" value="{deck}"/>
  <Parameter name="Combine" type="string" value="Cartesian"/>
</ParameterList>""",
        ["bad-combine.xml:3", "'Study->Combine' = 'Cartesian'", "'Product'"],
    ),
    (
        "bad-exact",
        """<ParameterList name="Study">
  <Parameter name="Deck" type="string" value="{deck}"/>
  <ParameterList name="Vary"><Parameter name="Time->Time step" type="Array(string)" value="{{1e-7}}"/></ParameterList>
  <ParameterList name="Reference"><Parameter name="Exact" type="string" value="bar-on-floor"/></ParameterList>
</ParameterList>""",
        ["bad-exact.xml:4", "'Reference->Exact' = 'bar-on-floor'", "bar-on-wall"],
    ),
    (
        "exact-does-not-apply",
        """<ParameterList name="Study">
  <Parameter name="Deck" type="string" value="{deck}"/>
  <ParameterList name="Vary"><Parameter name="Time->Time step" type="Array(string)" value="{{1e-7}}"/></ParameterList>
  <ParameterList name="Reference"><Parameter name="Exact" type="string" value="two-bars"/></ParameterList>
</ParameterList>""",
        ["exact-does-not-apply.xml:4", "'two-bars' does not apply", "two bodies"],
    ),
    (
        "bad-measure",
        """<ParameterList name="Study">
  <Parameter name="Deck" type="string" value="{deck}"/>
  <ParameterList name="Vary"><Parameter name="Time->Time step" type="Array(string)" value="{{1e-7}}"/></ParameterList>
  <ParameterList name="Measures">
    <Parameter name="Compute" type="Array(string)" value="{{impulse, contact stat}}"/>
  </ParameterList>
</ParameterList>""",
        ["bad-measure.xml:5", "'contact stat'", "did you mean 'contact start'"],
    ),
    (
        "bad-nodeset",
        """<ParameterList name="Study">
  <Parameter name="Deck" type="string" value="{deck}"/>
  <ParameterList name="Vary"><Parameter name="Time->Time step" type="Array(string)" value="{{1e-7}}"/></ParameterList>
  <ParameterList name="Measures"><Parameter name="Node set" type="string" value="y+"/></ParameterList>
</ParameterList>""",
        ["bad-nodeset.xml:4", "'Measures->Node set' = 'y+'", "x+, x-"],
    ),
    (
        "not-xml",
        """<ParameterList name="Study">
  <Parameter name="Deck" type="string" value="{deck}"/>
  <ParameterList name="Vary">
</ParameterList>""",
        ["not-xml.xml:5", "not well-formed XML"],
    ),
    (
        "not-a-study",
        """<ParameterList name="Studdy">
  <Parameter name="Deck" type="string" value="{deck}"/>
</ParameterList>""",
        ["not-a-study.xml:1", '<ParameterList name="Study">'],
    ),
]


class Result:
    def __init__(self, returncode, stdout, stderr):
        self.returncode, self.stdout, self.stderr = returncode, stdout, stderr


def in_process(a):
    """The sweep's command line from the package (python/epaphe/cli/sweep.py, what drivers/epaphe-sweep
    runs): main(argv) -> exit status, its output captured (one Python start for all the cases
    instead of one each)."""
    import contextlib
    import io

    sys.path.insert(0, os.path.join(HERE, "..", "..", "python"))
    from epaphe.cli import sweep as mod

    def call(args):
        out, err = io.StringIO(), io.StringIO()
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            rc = mod.main(args + ["--run", a.run])
        return Result(rc, out.getvalue(), err.getvalue())

    return call


def case_bad(a):
    call = in_process(a)
    for i, (name, text, must) in enumerate(BAD):
        path = os.path.join(a.workdir, name + ".xml")
        with open(path, "w") as fh:
            fh.write(text.format(deck=a.deck) + "\n")
        args = [path, "--out", os.path.join(a.workdir, "out-" + name), "--check"]
        # the first case as a process: the real exit status and stderr
        expect_error(name, sweep(a, args, a.workdir) if i == 0 else call(args), must)
    # command lines
    for name, args, must in (
        ("deck-without-vary", [a.deck], ["nothing to vary"]),
        ("vary-without-equals", [a.deck, "--vary", "Time->Time step"], ["--vary 'Time->Time step'", "KEY=VALUE"]),
        (
            "reference-exact-unknown",
            [a.deck, "--vary", "Time->Time step=1e-7", "--reference", "exact:moon"],
            ["'exact:moon'", "bar-on-wall"],
        ),
        ("cli-unknown-key", [a.deck, "--vary", "Time->End tme=1e-4"], ["'Time->End tme'", "'Time->End time'"]),
        ("missing-input", ["no-such-study.xml"], ["no-such-study.xml", "no such file"]),
    ):
        expect_error(name, call(args + ["--out", os.path.join(a.workdir, "out-" + name), "--check"]), must)
    # a usage error exits from argparse: as a process
    expect_error(
        "jobs-zero",
        sweep(
            a,
            [
                a.deck,
                "--vary",
                "Time->Time step=1e-7",
                "--jobs",
                "0",
                "--check",
                "--out",
                os.path.join(a.workdir, "out-jobs-zero"),
            ],
            a.workdir,
        ),
        ["--jobs 0", "must be >= 1"],
    )


def case_studies(a):
    call = in_process(a)
    files = sorted(f for f in os.listdir(a.studies) if f.endswith(".xml"))
    check(len(files) >= 10, f"{a.studies}: {len(files)} studies")
    for f in files:
        res = call([os.path.join(a.studies, f), "--out", os.path.join(a.workdir, f[:-4]), "--check"])
        print(res.stdout.splitlines()[0] if res.stdout else "", res.stderr.strip())
        check(res.returncode == 0, f"{f}: --check exit {res.returncode}: {res.stderr.strip()}")


def expect_error(name, proc, must):
    err = proc.stderr.strip()
    print(f"{name}: exit {proc.returncode}: {err}")
    check(proc.returncode == 1, f"{name}: exit status {proc.returncode}, expected 1")
    check(
        len(err.splitlines()) == 1 and err.startswith("epaphe-sweep: error: "),
        f"{name}: stderr is not one 'epaphe-sweep: error:' line: {err!r}",
    )
    check("Traceback" not in err, f"{name}: a traceback")
    for m in must:
        check(m in err, f"{name}: the message does not name {m!r}: {err}")


def main():
    ap = argparse.ArgumentParser()
    for opt in ("--run", "--sweep", "--deck", "--workdir", "--case"):
        ap.add_argument(opt, required=True)
    ap.add_argument("--studies", help="inputs/studies (--case studies)")
    a = ap.parse_args()
    a.deck, a.sweep, a.run = (os.path.abspath(p) for p in (a.deck, a.sweep, a.run))
    os.makedirs(a.workdir, exist_ok=True)
    {"study": case_study, "bad": case_bad, "studies": case_studies, "jobs": case_jobs}[a.case](a)
    if failures:
        print("FAILED:\n  " + "\n  ".join(failures))
        return 1
    print("PASSED")
    return 0


if __name__ == "__main__":
    sys.exit(main())
