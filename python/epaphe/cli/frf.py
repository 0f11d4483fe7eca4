"""epaphe-frf: a stepped-sine sweep of a driven deck, the frequency response per drive amplitude.

    epaphe-frf DECK --load "Bodies->B->Loads->L" --frequencies 5,6.25,8 [--amplitudes 0.5,1,2]
               [--periods 400] [--tolerance EPS] [--jobs J] [--out DIR] [--run EPAPHE_RUN]

DECK has a Harmonic load (--load names it) and an enabled 'Steady state' list (docs/user/loads.md).
For each amplitude (a factor on the load's 'Force') and each frequency (Hz) a variant of the deck sets
the load's 'Frequency' and 'Force', the steady state's 'Frequency', and an 'End time' of --periods drive
periods; epaphe-run runs it until its steady state (eq. (70): the first harmonic repeats after p
periods, to --tolerance EPS of itself, else to the deck's 'Steady state->Tolerance'), which stops it.
The variants run --jobs at a time (default: the cores this process may use), each on one thread.
Written: DIR/runs/*.xml and *.h5, DIR/frf.h5 (/frequency (Hz), /amplitude (the factors), and per
amplitude i /response/<i>/{harmonic_amplitude, harmonic_phase} (frequencies x H+1: a_0 .. a_H of the
watched motion, m and rad relative to the drive F cos(omega t + phi): x ~ sum |a_k| cos(k (omega t + phi)
+ phase_k)), steady, periods, pattern, wall_time (s)) and DIR/frf.png (the first harmonic's amplitude and phase against frequency,
one curve per amplitude). Each frequency needs a whole number of steps per drive period (the deck's
'Time step'); a run that is not steady by the end is marked so (steady = 0), not dropped."""
import argparse
import os
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor

from ..deck import Deck, deck_value
from ..errors import EpapheError

PROG = "epaphe-frf"


def find_run(explicit):
    """epaphe-run: `explicit`, else the package's choice (runner.find_run)."""
    if explicit:
        return explicit
    from ..runner import find_run as find

    return find()


def numbers(text):
    """The comma-separated numbers of `text`."""
    return [float(v) for v in text.split(",") if v.strip()]


def run_case(exe, deck, cwd, timeout):
    """(exit code, wall time in s, output) of epaphe-run on `deck`, one thread, in `cwd`."""
    t0 = time.perf_counter()
    p = subprocess.run([exe, deck, "--threads", "1"], cwd=cwd, capture_output=True, text=True, timeout=timeout)
    return p.returncode, time.perf_counter() - t0, p.stdout + p.stderr


def main(argv=None):
    try:
        return run(sys.argv[1:] if argv is None else argv)
    except EpapheError as e:
        sys.exit(f"{PROG}: {e}")


def run(argv):
    import h5py
    import numpy as np

    ap = argparse.ArgumentParser(prog=PROG, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("deck")
    ap.add_argument("--load", required=True, help='the Harmonic load, "Bodies->B->Loads->L"')
    ap.add_argument("--frequencies", required=True, help="Hz, comma-separated")
    ap.add_argument("--amplitudes", default="1", help="factors on the load's Force, comma-separated")
    ap.add_argument("--periods", type=float, default=400, help="the longest run, in drive periods")
    ap.add_argument(
        "--tolerance",
        type=float,
        default=None,
        help="the steady-state criterion's tolerance eps of eq. (70) (default: the deck's 'Steady state->Tolerance')",
    )
    ap.add_argument("--jobs", type=int, default=max(1, len(os.sched_getaffinity(0))))
    ap.add_argument("--out", default=None)
    ap.add_argument("--run", default=None, help="epaphe-run (default: the build's or the one on PATH)")
    ap.add_argument("--timeout", type=float, default=3600)
    a = ap.parse_args(argv)
    exe = find_run(a.run)
    freqs, amps = numbers(a.frequencies), numbers(a.amplitudes)
    if not freqs or min(freqs) <= 0:
        raise EpapheError(f"--frequencies {a.frequencies!r}: give frequencies > 0 (Hz)")
    if a.tolerance is not None and not 0 < a.tolerance < 1:
        raise EpapheError(f"--tolerance {a.tolerance!r}: give the criterion's relative tolerance, 0 < eps < 1")
    base = os.path.abspath(a.deck)
    out = os.path.abspath(a.out or os.path.splitext(os.path.basename(base))[0] + "-frf")
    runs = os.path.join(out, "runs")
    os.makedirs(runs, exist_ok=True)
    force = [float(v) for v in deck_value(base, a.load + "->Force")]
    try:
        drive_phase = float(deck_value(base, a.load + "->Phase"))
    except (KeyError, ValueError, EpapheError):
        drive_phase = 0.0
    if str(deck_value(base, "Steady state->Enabled")).lower() != "true":
        raise EpapheError(f"{a.deck}: 'Steady state->Enabled' is not true; the sweep needs the steady-state detection")
    # the variants live in DIR/runs: the base deck's files (paths relative to its directory) made absolute
    import xml.etree.ElementTree as ET

    tree = ET.parse(base)
    for e in tree.iter("Parameter"):
        v = e.get("value", "")
        if e.get("name", "").endswith(" file") and v and not os.path.isabs(v):
            e.set("value", os.path.normpath(os.path.join(os.path.dirname(base), v)))
    base_abs = os.path.join(runs, "base.xml")
    tree.write(base_abs)
    cases = []
    for i, amp in enumerate(amps):
        for j, nu in enumerate(freqs):
            name = f"a{i}-f{j}"
            deck = os.path.join(runs, name + ".xml")
            over = {
                a.load + "->Frequency": (repr(nu), "double"),
                a.load + "->Force": ("{" + ", ".join(repr(amp * f) for f in force) + "}", "Array(double)"),
                "Steady state->Frequency": (repr(nu), "double"),
                "Time->End time": (repr(a.periods / nu), "double"),
                "Output->File": (name + ".h5", "string"),
            }
            if a.tolerance is not None:
                over["Steady state->Tolerance"] = (repr(a.tolerance), "double")
            Deck(base_abs).override(over).write(deck)
            cases.append((i, j, name, deck))
    print(f"{PROG}: {len(cases)} runs ({len(amps)} amplitude(s) x {len(freqs)} frequencies), {a.jobs} at a time")
    t0 = time.perf_counter()
    results = {}
    with ThreadPoolExecutor(max_workers=a.jobs) as pool:
        futures = {pool.submit(run_case, exe, c[3], runs, a.timeout): c for c in cases}
        for k, fut in enumerate(futures):
            i, j, name, deck = futures[fut]
            code, wall, text = fut.result()
            if code != 0:
                raise EpapheError(f"{deck}: epaphe-run failed ({code}):\n{text.strip().splitlines()[-1]}")
            results[(i, j)] = (name, wall)
    with h5py.File(os.path.join(out, "frf.h5"), "w") as f:
        f["frequency"] = np.array(freqs)
        f["amplitude"] = np.array(amps)
        f.attrs["load"] = a.load
        f.attrs["deck"] = base
        for i in range(len(amps)):
            H, P, steady, periods, pattern, wall = [], [], [], [], [], []
            for j in range(len(freqs)):
                name, w = results[(i, j)]
                with h5py.File(os.path.join(runs, name + ".h5"), "r") as r:
                    g = r["steady_state"]
                    H.append(g["amplitude"][()])
                    k = np.arange(len(g["phase"][()]))
                    # relative to the drive F cos(omega t + phi): arg a_k - k phi, in (-pi, pi]
                    P.append(np.angle(np.exp(1j * (g["phase"][()] - k * drive_phase))))
                    steady.append(int(g.attrs["steady"]))
                    periods.append(int(g.attrs["periods"]))
                    pattern.append(int(g.attrs["pattern"]))
                wall.append(w)
            g = f.create_group(f"response/{i}")
            g["harmonic_amplitude"] = np.array(H)
            g["harmonic_phase"] = np.array(P)
            g["steady"] = np.array(steady)
            g["periods"] = np.array(periods)
            g["pattern"] = np.array(pattern)
            g["wall_time"] = np.array(wall)
            for j, nu in enumerate(freqs):
                print(
                    f"  amplitude x{amps[i]:g}, {nu:g} Hz: first harmonic {H[j][1]:.6e} m, phase {P[j][1]:+.5f} rad, "
                    f"{'steady' if steady[j] else 'NOT steady'} after {periods[j]} periods (p = {pattern[j]}), "
                    f"{wall[j]:.2f} s"
                )
    total = time.perf_counter() - t0
    plot(out, freqs, amps)
    print(f"{PROG}: {len(cases)} runs in {total:.1f} s; written {os.path.join(out, 'frf.h5')} and frf.png")
    return 0


def plot(out, freqs, amps):
    """DIR/frf.png: the first harmonic's amplitude and phase against frequency, one curve per amplitude
    (a run not steady by its end: a black cross)."""
    import h5py
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    fig, (ax1, ax2) = plt.subplots(2, 1, sharex=True, figsize=(6, 6))
    with h5py.File(os.path.join(out, "frf.h5"), "r") as f:
        for i, amp in enumerate(amps):
            g = f[f"response/{i}"]
            A, P, s = g["harmonic_amplitude"][:, 1], g["harmonic_phase"][:, 1], g["steady"][()]
            line = ax1.plot(freqs, A, "o-", label=f"x{amp:g}")[0]
            ax2.plot(freqs, np.unwrap(P), "o-", color=line.get_color())
            if (s == 0).any():
                ax1.plot(np.array(freqs)[s == 0], A[s == 0], "x", color="k")
    ax1.set_ylabel("first harmonic (m)")
    ax1.legend(title="drive amplitude")
    ax2.set_ylabel("phase (rad)")
    ax2.set_xlabel("frequency (Hz)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "frf.png"), dpi=100)
    plt.close(fig)
