"""epaphe-sweep: parameter studies and work-precision diagrams over Epaphe decks.

    epaphe-sweep STUDY.xml [--out DIR] [--run EPAPHE_RUN] [--threads N] [--jobs J] [--force] [--check]
                 [--vary "KEY=V1,V2,..." ...] [--zip | --product] [--set "KEY=V" ...]
                 [--reference REF] [--no-plots]
    epaphe-sweep DECK.xml --vary "Time->Time step=4e-7,2e-7,1e-7" [--reference exact:bar-on-wall] [...]

A study (inputs/studies/*.xml, format in docs/user/studies.md) names a base deck, the deck
parameters to vary (zipped lists of the same length, or their product), overrides applied to every
run, a reference (an exact solution: `bar-on-wall` (docs/verification.md V1) or `two-bars` (V2), computed
from each run's deck; or a run named by its overrides), the measures and the plots.
Each variant deck is written to DIR/runs/<run>.xml and run with epaphe-run; a run whose history
DIR/runs/<run>.h5 is complete and holds the same deck text (/run/deck) is not run again.
J runs go at a time (--jobs; default: the cores this process may use divided by --threads, at
least 1), the decks are checked J at a time too; the CSV and the figures keep the study's order
whatever order the runs end in. Each run prints "[i/N] RUN: running (LABEL)" and, when it ends,
its status and time, the runs done and left and the ETA:
  [3/12] Time_step=2e-7: complete in 4.1 s; 3 of 12 done, 9 left, ETA 0:37 (mean 4.3 s a case, 2 at a time)
(cached runs count as done and not in the mean). A run that fails does not stop the others. Ctrl-C
passes one SIGINT to every running epaphe-run (each stops at the end of its step with a
checkpoint), starts no other run and exits with status 130. With J > 1 the runs get
OMP_PROC_BIND=false, and each run's wall time is measured while the others run: for a
work-precision diagram of wall times on a busy machine, --jobs 1.

Written to DIR (default: ./<study stem>):
  <stem>.csv                    one row per run: the varied values, status, each measure's value
                                and error against the reference, the costs (wall, setup and loop
                                time, steps, steps per second, threads)
  <stem>-force.png              total contact force vs time, one curve per run (reference dashed)
  <stem>-gap.png                minimum gap of the contact nodes vs time
  <stem>-displacement.png       displacement of the watched node (or node-set mean), one component
  <stem>-work-precision.png     error (log) against wall time (log), one series per measure

Measures (value; error against the reference):
  contact start, contact end    first record whose total contact force exceeds `Contact threshold`
                                x the reference's peak force; the record after the last one (s);
                                error |t - t_ref| / reference contact duration
  impulse                       integral of the total contact force (N s); relative error
  plateau force                 impulse / contact duration (N); relative error
  peak force                    largest total contact force (N); relative error
  max penetration               minus the most negative gap over the contact nodes (m); error
                                |p - p_ref| / the reference's largest watched displacement
  displacement                  RMS difference of the watched displacement to the reference,
                                interpolated on the common times (m); error: RMS / the reference's
                                largest watched displacement
  rebound velocity              final momentum / rigid mass along the watched component (m/s);
                                relative error
  energy balance                largest |/energy/balance_error| of the run; the error is the value
A run refused by epaphe-run (an unstable time step) or stopped is a CSV row with that status and
no measure; the sweep goes on. Exit status 1 on a study error (one line on stderr naming the file,
the key and the value), a run that failed otherwise, or a reference that did not complete.
"""
import argparse
import os
import sys
import time

import matplotlib
import numpy as np

from ..deck import Deck, numbers, read_xml, split_top
from ..exact import EXACT
from ..measures import DEFAULT_MEASURES, MEASURES, errors, raw_measures, rms_difference
from ..runner import Case, CaseRunner, check_decks, default_jobs, find_run, say
from ..schema import Schema
from ..study import CURVES, Study, StudyError, Watch, read_history, slug, suggest, write_csv
from . import Parser, run_main

matplotlib.use("Agg")
from ..plots import plot_curves, plot_work_precision  # noqa: E402

PROG = "epaphe-sweep"


def parse(argv):
    ap = Parser(
        prog=PROG,
        description=__doc__.split("\n\n")[0],
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="\n\n".join(__doc__.split("\n\n")[2:]),
    )
    ap.add_argument("input", metavar="STUDY.xml|DECK.xml", help="a study, or a deck (then --vary)")
    ap.add_argument("--out", metavar="DIR", help="output directory (default: ./<stem>)")
    ap.add_argument(
        "--run",
        metavar="EPAPHE_RUN",
        help="epaphe-run (default: next to this script, " "$EPAPHE_BUILD_DIR/drivers, build/drivers, PATH)",
    )
    ap.add_argument("--threads", type=int, default=1, metavar="N", help="threads per run (default 1)")
    ap.add_argument(
        "--jobs",
        type=int,
        metavar="J",
        help="runs at a time (default: the cores available / " "--threads, at least 1; 1: one after another)",
    )
    ap.add_argument(
        "--vary",
        action="append",
        default=[],
        metavar="KEY=V1,V2",
        help="vary a deck parameter (repeatable; replaces the study's entry of that key)",
    )
    ap.add_argument("--set", action="append", default=[], metavar="KEY=V", help="override for every run")
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--zip", action="store_true", help="zip the varied lists (the default)")
    g.add_argument("--product", action="store_true", help="every combination of the varied values")
    ap.add_argument(
        "--reference",
        metavar="REF",
        help="'exact:bar-on-wall', 'exact:two-bars', 'none', or the overrides naming the reference run: "
        "\"Time->Time step=2.5e-8\" (several joined by ';')",
    )
    ap.add_argument("--force", action="store_true", help="rerun even the runs whose history is up to date")
    ap.add_argument("--check", action="store_true", help="validate the study and its decks, list the runs, stop")
    ap.add_argument("--no-plots", action="store_true", help="write the CSV only")
    a = ap.parse_args(argv)
    if a.threads < 0:
        ap.error(f"--threads {a.threads}: must be >= 0")
    if a.jobs is None:
        a.jobs = default_jobs(a.threads)
    elif a.jobs < 1:
        ap.error(f"--jobs {a.jobs}: must be >= 1 (1 runs the cases one after another)")
    return a


def build_watch(study, deck, schema):
    """The watched body, node set, node and component (Measures), and the plotted components."""
    where = study.measures
    bodies = deck.sublists("Bodies")

    def instances(b):  # a stage's body ('Instances'): its instances are the run's bodies b[k]
        return int(deck.get(f"Bodies->{b}->Instances->Count", schema) or 1)

    names = [n for b in bodies for n in ([b] if instances(b) == 1 else [f"{b}[{k}]" for k in range(instances(b))])]
    body = where.get("Body")
    if body is None:
        with_contact = [b for b in bodies if deck.get(f"Bodies->{b}->Contact node set", schema)]
        body = (with_contact or bodies or [None])[0]
        if body is None:
            raise StudyError(f"{deck.path}: the deck has no body")
        body = body if instances(body) == 1 else f"{body}[0]"
    elif body not in names:
        raise StudyError(
            f"{where['Body@']}: 'Measures->Body' = '{body}': no such body in {deck.path} "
            f"(bodies: {', '.join(names)})"
        )
    deck_body = body.split("[")[0] if body not in bodies else body  # the deck's list of an instance
    watched = split_top((deck.get(f"Bodies->{deck_body}->Watched node sets", schema) or "{}").strip()[1:-1])
    nodeset = where.get("Node set")
    if nodeset is None:
        if not watched:
            raise StudyError(
                f"{deck.path}: body '{body}' has no 'Watched node sets' (needed by the displacement "
                "measure and plot)"
            )
        nodeset = watched[0]
    elif nodeset not in watched:
        raise StudyError(
            f"{where['Node set@']}: 'Measures->Node set' = '{nodeset}' is not a watched node set of "
            f"body '{body}' in {deck.path} (watched: {', '.join(watched) or 'none'})"
        )
    node = where.get("Node", -1)
    if node < -1:
        raise StudyError(f"{where['Node@']}: 'Measures->Node' = {node}: -1 (the mean of the set) or an index >= 0")

    v0 = numbers(deck.get(f"Bodies->{deck_body}->Initial velocity", schema) or "{0,0,0}")
    comp = int(np.argmax(np.abs(v0))) if any(v0) else 0  # default: along the initial velocity
    if "Component" in where:
        if where["Component"] not in ("x", "y", "z"):
            raise StudyError(
                f"{where['Component@']}: 'Measures->Component' = '{where['Component']}' is not one " "of 'x', 'y', 'z'"
            )
        comp = "xyz".index(where["Component"])
    plot_comps = [comp]
    if "Components" in study.plots:
        plot_comps = []
        for c in study.plots["Components"]:
            if c not in ("x", "y", "z"):
                raise StudyError(
                    f"{study.plots['Components@']}: 'Plots->Components': '{c}' is not one of 'x', 'y', 'z'"
                )
            plot_comps.append("xyz".index(c))
    thr = where.get("Contact threshold", 1e-6)
    if not (0 <= thr < 1):
        raise StudyError(f"{where['Contact threshold@']}: 'Measures->Contact threshold' = {thr:g}: in [0, 1)")
    return Watch(body, nodeset, node, comp, thr), plot_comps


def validate_lists(study):
    for k in study.measures.get("Compute", []):
        if k not in MEASURES:
            raise StudyError(
                f"{study.measures['Compute@']}: 'Measures->Compute': unknown measure '{k}'" + suggest(k, MEASURES)
            )
    for k in study.plots.get("Curves", []):
        if k not in CURVES:
            raise StudyError(f"{study.plots['Curves@']}: 'Plots->Curves': unknown curve '{k}'" + suggest(k, CURVES))
    c = study.plots.get("Cost")
    if c is not None and c not in ("wall time", "loop time"):
        raise StudyError(f"{study.plots['Cost@']}: 'Plots->Cost' = '{c}' is not one of 'wall time', 'loop time'")
    tw = study.plots.get("Time window")
    if tw is not None and (len(tw) != 2 or not tw[0] < tw[1]):
        raise StudyError(f"{study.plots['Time window@']}: 'Plots->Time window' = {tw}: {{tmin, tmax}} with tmin < tmax")


def main_run(argv):
    a = parse(argv)
    if not os.path.isfile(a.input):
        raise StudyError(f"{a.input}: no such file")
    root = read_xml(a.input)
    if root.tag == "ParameterList" and root.name == "Epaphe":
        study = Study()
        study.deck_path = os.path.abspath(a.input)
    else:
        study = Study.from_file(a.input, root)
    study.apply_cli(a)
    stem = os.path.splitext(os.path.basename(a.input))[0]
    out = os.path.abspath(a.out or stem)
    study.check_structure()
    validate_lists(study)
    base = Deck(study.deck_path)
    run_exe = find_run(a.run)
    schema = Schema.of(run_exe)
    study.check_keys(base, schema)
    set_over = {k: e.values[0] for k, e in study.set.items()}
    where = study.path or a.input
    rundir = os.path.join(out, "runs")
    os.makedirs(rundir, exist_ok=True)

    entries = (
        list(study.set.values())
        + study.vary
        + (list(study.reference[1].values()) if study.reference and study.reference[0] == "run" else [])
    )

    def make(name, label, over):
        full = dict(set_over)
        full.update(over)
        full["Output->File"] = name + ".h5"
        r = Case(name, label, over, base.with_overrides(full, schema), rundir)
        r.wheres = {e.key: e.where for e in entries}
        r.time_step = float(Deck(text=r.deck_text).get("Time->Time step", schema))
        return r

    runs = [make(n, lab, over) for n, lab, over in study.variants()]
    ref_run = None
    if study.reference and study.reference[0] == "run":
        rover = {k: e.values[0] for k, e in study.reference[1].items()}
        for r in runs:
            if r.overrides == rover:
                ref_run = r
        if ref_run is None:
            label = ", ".join(f"{k.split('->')[-1]}={v}" for k, v in rover.items()) or "base deck"
            ref_run = make(
                "reference_" + slug("_".join(f"{k.split('->')[-1]}={v}" for k, v in rover.items()))[:100], label, rover
            )
            ref_run.alone = True
        else:
            ref_run.alone = False
        ref_run.is_reference = True
    everything = ([ref_run] if ref_run is not None and ref_run.alone else []) + runs
    measured_deck = Deck(text=base.with_overrides(set_over, schema))
    measured_deck.path = base.path
    w, plot_comps = build_watch(study, measured_deck, schema)
    wanted = study.measures.get("Compute") or DEFAULT_MEASURES
    exact = {}
    if study.reference and study.reference[0] == "exact":
        for r in everything:
            d = Deck(text=r.deck_text)
            d.path = f"{base.path} (run {r.name})"
            exact[r.name] = EXACT[study.reference[1]](d, schema, study.reference[2])
            if exact[r.name].body != w.body:
                raise StudyError(
                    f"{study.reference[2]}: the exact solution is for body '{exact[r.name].body}', "
                    f"the measures watch '{w.body}'"
                )
    check_decks(everything, run_exe, where, a.jobs)
    say(
        f"{PROG}: {where}: {len(runs)} run(s) of {base.path}"
        + (f" (varying {', '.join(e.key for e in study.vary)}, {study.combine.lower()})")
        + (
            f", reference {'exact ' + study.reference[1] if study.reference[0] == 'exact' else ref_run.name}"
            + (" (one more run)" if ref_run is not None and ref_run.alone else "")
            if study.reference
            else ", no reference"
        )
        + f"; output in {out}"
        + (
            ""
            if a.check
            else f"; {min(a.jobs, len(everything))} at a time, "
            + (f"{a.threads} thread(s) each" if a.threads else "each on every core")
        )
    )
    if a.check:
        for r in everything:
            say(f"  {r.name}: {r.label}" + ("  [reference]" if r.is_reference else ""))
        return 0
    t_start = time.time()
    CaseRunner(run_exe, a.threads, a.jobs, a.force).run(everything)
    for r in everything:
        if r.status == "complete":
            r.hist = read_history(r.h5, w)

    # the reference's values
    ref_values, scale_ref = None, None
    failed = [r for r in everything if r.status.startswith("failed")]
    if ref_run is not None:
        if ref_run.status != "complete":
            sys.stderr.write(
                f"{PROG}: error: the reference run {ref_run.name} did not complete ({ref_run.status}): "
                "no errors computed\n"
            )
            failed.append(ref_run)
        else:
            rh = ref_run.hist
            ref_values = raw_measures(rh, w, None)
            u = rh["u"][:, w.comp] if rh["u"] is not None else None
            scale_ref = float(np.nanmax(np.abs(u))) if u is not None else float("nan")
    for r in everything:
        if r.hist is None:
            continue
        h = r.hist
        if r.name in exact:
            ex = exact[r.name]
            tend = float(h["t"][-1])
            ref = ex.measures(tend, h["ids"], w.comp, w.node)
            m = raw_measures(h, w, ex.F)
            if h["u"] is not None:
                ue = ex.watched(h["t"], h["ids"], w.comp, w.node)
                m["displacement"] = rms_difference(h["t"], h["u"][:, w.comp], h["t"], ue)
                scale = float(np.max(np.abs(ue)))
            else:
                scale = float("nan")
            r.measures, r.errors = m, errors(m, ref, scale)
        elif ref_values is not None:
            m = raw_measures(h, w, ref_values.get("peak force"))
            if h["u"] is not None and ref_run.hist["u"] is not None:
                m["displacement"] = rms_difference(
                    h["t"], h["u"][:, w.comp], ref_run.hist["t"], ref_run.hist["u"][:, w.comp]
                )
            rv = raw_measures(ref_run.hist, w, ref_values.get("peak force"))
            r.measures, r.errors = m, errors(m, rv, scale_ref)
        else:
            r.measures = raw_measures(h, w, None)
    exact_row = None
    if exact:
        keys = {e.key() for e in exact.values()}
        if len(keys) == 1:
            r0 = (
                next(r for r in everything if r.hist is not None)
                if any(r.hist is not None for r in everything)
                else None
            )
            if r0 is not None:
                ex = exact[r0.name]
                vals = ex.measures(float(r0.hist["t"][-1]), r0.hist["ids"], w.comp, w.node)
                vals["displacement"] = 0.0
                exact_row = {"label": ex.label, "values": vals}
    csv_path = os.path.join(out, stem + ".csv")
    write_csv(csv_path, study, everything, exact_row, wanted)
    written = [csv_path]
    if not a.no_plots:
        window = study.plots.get("Time window")
        ref_plot = None
        if exact:
            first = next((r for r in runs if r.hist is not None), None)
            if first is not None:
                ref_plot = ("exact", exact[first.name])
        elif ref_run is not None and ref_run.hist is not None:
            ref_plot = ("run", ref_run)
        plot_curves(study, everything, ref_plot, w, plot_comps, out, stem, window, written)
        if study.reference and study.plots.get("Work-precision", True):
            cost = "loop_time" if study.plots.get("Cost") == "loop time" else "wall_time"
            if plot_work_precision(study, everything, cost, out, stem, written) is None:
                say(f"{PROG}: no finite positive error: no work-precision diagram")
    say(
        f"{PROG}: {len(everything)} run(s) in {time.time() - t_start:.1f} s: "
        + ", ".join(f"{n} {s}" for s, n in sorted(count_status(everything).items()))
    )
    for p in written:
        print(p)
    return 1 if failed else 0


def count_status(runs):
    out = {}
    for r in runs:
        s = r.status.split(":")[0] + (" (cached)" if r.cached else "")
        out[s] = out.get(s, 0) + 1
    return out


def main(argv=None):
    return run_main(PROG, main_run, argv)
