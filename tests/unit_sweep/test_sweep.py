#!/usr/bin/env python3
"""drivers/epaphe-sweep: studies over decks, measures, CSV and plots.

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
"""
import argparse
import csv
import importlib.machinery
import importlib.util
import math
import os
import subprocess
import sys

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
MEASURE_COLS = ["contact_start_s", "contact_end_s", "impulse_Ns", "plateau_force_N", "max_penetration_m",
                "displacement_rms_m", "rebound_velocity_m_per_s", "energy_balance_rel"]
ERROR_COLS = ["contact_start_error", "contact_end_error", "impulse_error", "plateau_force_error",
              "max_penetration_error", "displacement_rms_error", "rebound_velocity_error", "energy_balance_error"]
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
    for col in ["run", "label", "Time->Time step", "status", "reference", "time_step_s"] + MEASURE_COLS + \
            ERROR_COLS + COST_COLS + ["file"]:
        check(col in head, f"CSV: no column {col} (columns: {head})")
    check(len(rows) == 5, f"CSV: {len(rows)} rows, expected 5 (4 variants and the reference run)")
    by_h = {r["Time->Time step"]: r for r in rows}
    check(set(by_h) == {"2e-6", "4e-7", "2e-7", "1e-7", "2.5e-8"}, f"CSV: varied values {sorted(by_h)}")
    ref = [r for r in rows if r["reference"] == "yes"]
    check(len(ref) == 1 and ref[0]["time_step_s"] and math.isclose(fnum(ref[0]["time_step_s"]), 2.5e-8),
          f"CSV: the reference row is not the h = 2.5e-8 run: {ref}")
    bad = by_h.get("2e-6", {})
    check(bad.get("status", "").startswith("refused: unstable time step"),
          f"h = 2e-6: status '{bad.get('status')}', expected 'refused: unstable time step (critical ...)'")
    check(all(bad.get(c, "") == "" for c in MEASURE_COLS), "h = 2e-6: a refused run has measures")
    steps = ["4e-7", "2e-7", "1e-7"]
    for h in steps:
        r = by_h.get(h, {})
        check(r.get("status") == "complete", f"h = {h}: status {r.get('status')}")
        for c in ERROR_COLS + MEASURE_COLS + ["wall_time_s", "steps_per_second"]:
            check(math.isfinite(fnum(r.get(c, ""))), f"h = {h}: {c} = '{r.get(c)}' is not finite")
        check(fnum(r.get("steps", "")) == round(1.2e-4 / float(h)), f"h = {h}: steps {r.get('steps')}")
    d = [fnum(by_h[h]["displacement_rms_error"]) for h in steps if h in by_h]
    print("displacement error vs h = 2.5e-8:", ", ".join(f"h={h}: {x:.3e}" for h, x in zip(steps, d)),
          "; ratios", ", ".join(f"{d[i] / d[i + 1]:.2f}" for i in range(len(d) - 1)))
    # Second order is what theory gives for this measure: the RMS displacement difference of the
    # x- face to the h = 2.5e-8 run. Between contact events central difference is second order;
    # the impact instant (t0 = 2e-5 s) is a multiple of every step, so the velocity jump falls on
    # the grid, and the Lagrange force falls continuously to zero at release (no O(h) event error).
    # Asserted: a ratio of at least 3.5 (2^1.8) per halving, which first order (2) cannot reach.
    check(len(d) == 3 and all(d[i] >= 3.5 * d[i + 1] for i in range(2)),
          f"the displacement error does not fall by 3.5x per halving of h (second order): {d}")
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
    check(": running" not in proc.stdout.replace("Time_step=2e-6: running", ""),
          "a run ran again although its history is up to date")
    head, rows = read_csv(os.path.join(out, "tiny.csv"))
    check(len(rows) == 5, f"CSV (exact): {len(rows)} rows, expected 5 (exact and 4 variants)")
    ex = next((r for r in rows if r["run"] == "exact"), None)
    if check(ex is not None, "CSV (exact): no 'exact' row"):
        for col, want in (("contact_start_s", 2e-5), ("contact_end_s", 1e-4), ("plateau_force_N", 1.6e6),
                          ("impulse_Ns", 128.0), ("rebound_velocity_m_per_s", -100.0)):
            check(math.isclose(fnum(ex[col]), want, rel_tol=1e-9), f"exact {col} = {ex[col]}, expected {want:g}")
    for r in rows:
        if r["status"] != "complete":
            continue
        e = {c: fnum(r[c]) for c in ERROR_COLS}
        for c, tol in (("contact_start_error", 0.01), ("contact_end_error", 0.01), ("impulse_error", 0.02),
                       ("plateau_force_error", 0.02), ("rebound_velocity_error", 0.02),
                       ("displacement_rms_error", 0.02)):
            check(e[c] <= tol, f"{r['run']} vs exact: {c} = {e[c]:.3g} > {tol}")
        check(e["energy_balance_error"] < 1e-8, f"{r['run']}: energy balance {e['energy_balance_error']}")


BAD = [
    ("unknown-list", """<ParameterList name="Study">
  <Parameter name="Deck" type="string" value="{deck}"/>
  <ParameterList name="Vray"/>
</ParameterList>""", ["unknown-list.xml:3", "'Vray'", "did you mean 'Vary'"]),
    ("unknown-parameter", """<ParameterList name="Study">
  <Parameter name="Deck" type="string" value="{deck}"/>
  <Parameter name="Combien" type="string" value="Zip"/>
</ParameterList>""", ["unknown-parameter.xml:3", "'Combien'", "did you mean 'Combine'"]),
    ("missing-deck", """<ParameterList name="Study">
  <Parameter name="Deck" type="string" value="no/such/deck.xml"/>
  <ParameterList name="Vary"><Parameter name="Time->Time step" type="Array(string)" value="{{1e-7}}"/></ParameterList>
</ParameterList>""", ["missing-deck.xml:2", "'Deck'", "no/such/deck.xml", "no such file"]),
    ("unknown-deck-key", """<ParameterList name="Study">
  <Parameter name="Deck" type="string" value="{deck}"/>
  <ParameterList name="Vary">
    <Parameter name="Time->Time stpe" type="Array(string)" value="{{1e-7, 2e-7}}"/>
  </ParameterList>
</ParameterList>""", ["unknown-deck-key.xml:4", "'Time->Time stpe'", "did you mean 'Time->Time step'"]),
    ("unknown-body", """<ParameterList name="Study">
  <Parameter name="Deck" type="string" value="{deck}"/>
  <ParameterList name="Vary">
    <Parameter name="Bodies->Barr->Reduction->Fixed-interface modes" type="Array(string)" value="{{10, 20}}"/>
  </ParameterList>
</ParameterList>""", ["unknown-body.xml:4", "'Barr'", "Bar"]),
    ("not-a-number", """<ParameterList name="Study">
  <Parameter name="Deck" type="string" value="{deck}"/>
  <ParameterList name="Vary">
    <Parameter name="Time->Time step" type="Array(string)" value="{{1e-7, 2e-7x}}"/>
  </ParameterList>
</ParameterList>""", ["not-a-number.xml:4", "'Time->Time step'", "'2e-7x'", "double"]),
    ("out-of-range", """<ParameterList name="Study">
  <Parameter name="Deck" type="string" value="{deck}"/>
  <ParameterList name="Vary">
    <Parameter name="Time->Time step" type="Array(string)" value="{{1e-7, -2e-7}}"/>
  </ParameterList>
</ParameterList>""", ["out-of-range.xml:4", "'Time->Time step' = '-2e-7'", "out of range"]),
    ("bad-enum", """<ParameterList name="Study">
  <Parameter name="Deck" type="string" value="{deck}"/>
  <ParameterList name="Vary">
    <Parameter name="Contact->Method" type="Array(string)" value="{{Lagrange, Penalti}}"/>
  </ParameterList>
</ParameterList>""", ["bad-enum.xml:4", "'Penalti'", "did you mean 'Penalty'"]),
    ("zip-lengths", """<ParameterList name="Study">
  <Parameter name="Deck" type="string" value="{deck}"/>
  <ParameterList name="Vary">
    <Parameter name="Time->Time step" type="Array(string)" value="{{1e-7, 2e-7}}"/>
    <Parameter name="Contact->Method" type="Array(string)" value="{{Lagrange, Penalty, Lagrange}}"/>
  </ParameterList>
</ParameterList>""", ["zip-lengths.xml", "Zip", "'Time->Time step': 2", "'Contact->Method': 3", "Product"]),
    ("bad-combine", """<ParameterList name="Study">
  <Parameter name="Deck" type="string" value="{deck}"/>
  <Parameter name="Combine" type="string" value="Cartesian"/>
</ParameterList>""", ["bad-combine.xml:3", "'Study->Combine' = 'Cartesian'", "'Product'"]),
    ("bad-exact", """<ParameterList name="Study">
  <Parameter name="Deck" type="string" value="{deck}"/>
  <ParameterList name="Vary"><Parameter name="Time->Time step" type="Array(string)" value="{{1e-7}}"/></ParameterList>
  <ParameterList name="Reference"><Parameter name="Exact" type="string" value="bar-on-floor"/></ParameterList>
</ParameterList>""", ["bad-exact.xml:4", "'Reference->Exact' = 'bar-on-floor'", "bar-on-wall"]),
    ("exact-does-not-apply", """<ParameterList name="Study">
  <Parameter name="Deck" type="string" value="{deck}"/>
  <ParameterList name="Vary"><Parameter name="Time->Time step" type="Array(string)" value="{{1e-7}}"/></ParameterList>
  <ParameterList name="Reference"><Parameter name="Exact" type="string" value="two-bars"/></ParameterList>
</ParameterList>""", ["exact-does-not-apply.xml:4", "'two-bars' does not apply", "two bodies"]),
    ("bad-measure", """<ParameterList name="Study">
  <Parameter name="Deck" type="string" value="{deck}"/>
  <ParameterList name="Vary"><Parameter name="Time->Time step" type="Array(string)" value="{{1e-7}}"/></ParameterList>
  <ParameterList name="Measures">
    <Parameter name="Compute" type="Array(string)" value="{{impulse, contact stat}}"/>
  </ParameterList>
</ParameterList>""", ["bad-measure.xml:5", "'contact stat'", "did you mean 'contact start'"]),
    ("bad-nodeset", """<ParameterList name="Study">
  <Parameter name="Deck" type="string" value="{deck}"/>
  <ParameterList name="Vary"><Parameter name="Time->Time step" type="Array(string)" value="{{1e-7}}"/></ParameterList>
  <ParameterList name="Measures"><Parameter name="Node set" type="string" value="y+"/></ParameterList>
</ParameterList>""", ["bad-nodeset.xml:4", "'Measures->Node set' = 'y+'", "x+, x-"]),
    ("not-xml", """<ParameterList name="Study">
  <Parameter name="Deck" type="string" value="{deck}"/>
  <ParameterList name="Vary">
</ParameterList>""", ["not-xml.xml:5", "not well-formed XML"]),
    ("not-a-study", """<ParameterList name="Studdy">
  <Parameter name="Deck" type="string" value="{deck}"/>
</ParameterList>""", ["not-a-study.xml:1", "<ParameterList name=\"Study\">"]),
]


class Result:
    def __init__(self, returncode, stdout, stderr):
        self.returncode, self.stdout, self.stderr = returncode, stdout, stderr


def in_process(a):
    """The sweep imported as a module: main(argv) -> exit status, its output captured (one Python
    start for all the cases instead of one each)."""
    import contextlib
    import io
    loader = importlib.machinery.SourceFileLoader("epaphe_sweep", a.sweep)
    spec = importlib.util.spec_from_loader("epaphe_sweep", loader)
    mod = importlib.util.module_from_spec(spec)
    loader.exec_module(mod)

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
            ("reference-exact-unknown", [a.deck, "--vary", "Time->Time step=1e-7", "--reference", "exact:moon"],
             ["'exact:moon'", "bar-on-wall"]),
            ("cli-unknown-key", [a.deck, "--vary", "Time->End tme=1e-4"], ["'Time->End tme'", "'Time->End time'"]),
            ("missing-input", ["no-such-study.xml"], ["no-such-study.xml", "no such file"])):
        expect_error(name, call(args + ["--out", os.path.join(a.workdir, "out-" + name), "--check"]), must)


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
    check(len(err.splitlines()) == 1 and err.startswith("epaphe-sweep: error: "),
          f"{name}: stderr is not one 'epaphe-sweep: error:' line: {err!r}")
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
    {"study": case_study, "bad": case_bad, "studies": case_studies}[a.case](a)
    if failures:
        print("FAILED:\n  " + "\n  ".join(failures))
        return 1
    print("PASSED")
    return 0


if __name__ == "__main__":
    sys.exit(main())
