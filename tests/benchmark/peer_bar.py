#!/usr/bin/env python3
"""Peer benchmark: V1, the elastic bar on a rigid wall, in Siconos
and in Epaphe, measured one way, in one table (the issue "a bar impact against Siconos").

V1 (tests/verification/v1_bar_on_wall.py): bar L = 0.2 m, c = 5000 m/s, at v0 = 100 m/s towards a rigid
wall 2 mm away. Exact: contact from t0 = 2.0e-5 s to t1 = 1.0e-4 s, force plateau F = 1.6e6 N, rebound
at v0. Rows, each on 1 thread:
  - Siconos 4.4 (peer_siconos_bar.siconos_bar): a 1-D bar of 100 linear elements at h = 2e-7 s and of
    200 at h = 1e-7 s (Courant number 0.5), consistent mass, Moreau-Jean theta = 0.5, LCP (Lemke),
    restitution 0; BLAS held to 1 thread (OPENBLAS_NUM_THREADS / OMP_NUM_THREADS = 1).
  - Epaphe (epaphe-run DECK --threads 1, the deck's 3-D bar of 100 x 1 x 1 hexahedra, Lagrange contact):
    Craig-Bampton with 40, 100 (the deck as it is) and 200 fixed-interface modes at h = 1e-7 s; the
    massless boundary with 50, 100 and 200 elastic modes (plus the 6 rigid-body modes) at h = 4e-7 s,
    and with 100 and 200 at 1e-7 s: its stable step is set by the last kept mode, not by the mesh,
    so it allows a larger step. The first run of each row reduces (its setup time includes the
    reduction) and writes the cache; a second run reads it.
  - Epaphe, the full model with lumped mass (1212 DOFs, no reduction) at h = dx / c = 4e-7 s, the
    Courant limit: there the central difference on a lumped 1-D chain is exact at the nodes for the
    wave (the "magic" time step), so contact starts and ends on the exact step; what remains is the
    contact face's lumped mass, stopped at impact (m_f v0^2 / 2 = 16 J of 3200).
The work-precision figure (each error against the wall time, every row) is written to
WORKDIR/peer-bar-work-precision.png (its copy in docs/figures/, shown in docs/user/models.md).

Errors, relative to the exact values, the same convention for both codes (v1_bar_on_wall.measure for
Epaphe, siconos_bar for Siconos): one record per step, at the step's end t_k+1, holding the step's
contact force (Siconos: its impulse / h);
  start   = first record with force > 1e-6 F;     end = last such record + h;
  force   = total impulse / (end - start), the mean force over the measured duration;
  rebound = linear momentum / rigid mass, averaged over t > end + 5e-6 s.
The Siconos figures first quoted in the issue (100 elements: end 0.20 %, force 0.51 %, rebound 1.03 %;
200 elements: 0.20 %, 0.32 %, 0.65 %) used another convention: the impulse labelled at the step's
start t_k, and force = total impulse / the exact duration (t1 - t0). They are not comparable with
Epaphe's figures as measured here, so this table re-measures both codes the one way above.

Every Epaphe row turns the deck's `Reduction->Frequency check` off: a diagnostic that computes the full
model's lowest 10 frequencies by Anasazi to print them beside the model's (37 ms on the lumped row, more
on the reduced ones); it changes no result, and Siconos computes none.

Times, each measured the same way for both codes:
  - "process": time.perf_counter() around the whole process that computes the row, started fresh: for
    Epaphe the epaphe-run process (its start and MPI's, deck, reduction, loop, HDF5 output of every
    step); for Siconos a python3 process running peer_siconos_bar.py for that row (Python's start,
    the imports of numpy and Siconos, assembly, TimeStepping.initialize(), the loop, the measurement).
  - "in-process": what each code's own timers give for the computation inside that process: Epaphe's
    /run attributes setup_time + loop_time (deck to model, reduction, loop with its output), Siconos'
    setup + loop (assembly and initialize(), then the stepping loop with its per-step recording).
  - "cached" (Epaphe): the process again with its reduced model read from the cache the first run wrote
    (Reduction->Cache file; a study's runs reuse one); "loop": Epaphe's loop_time.
(Before 2026-11-26 the table set Epaphe's process time beside Siconos' in-process time, which left
Python's start and imports, about 0.1-0.3 s, out of Siconos' figure only.) "dE J" is, for Epaphe, the energy after the rebound less the initial 3200 J (kinetic plus
strain, energy/total): Craig-Bampton loses its contact face's kinetic energy at impact; the massless
boundary conserves it through the contact and errs only at its start and end.

After the table, one line per Epaphe row: whether each of its four errors is at or below that of the
best Siconos row (the least sum of the four errors; ties within 1e-9 count as at), and its process and
in-process times over that row's.

Asserted (a missing Siconos is a failure, not a skip: the comparison is the test):
  - every run completed and its numbers are finite;
  - Epaphe's best row (the least sum of its four errors: today the lumped full model) is at or below
    the best Siconos row on start, end and rebound;
  - its mean force is not (the finding FORCE_FINDING, pinned): 0.2500 % against Siconos' 0.073 %. It
    is m_f / (2 m), the contact face's lumped mass m_f = m / (2 N) (N = 100 elements) arrested at
    impact: the rebound falls short by m_f / m = 0.50 % and, the duration being exact, the mean force
    by half of it. Band 0.25 +- 0.02 %: round-off does not move it (measured 0.25 % to 1e-12), a
    change of the measured duration by one step moves it by 0.5 %. Better (at or below Siconos: the
    finding is gone, assert it with the others) or worse fails;
Reported, not asserted (a benchmark reports figures; the shared machine's load moves them): Epaphe's
best row's process time against the best Siconos row's, and against the target TIME_RATIO = 0.1, the
tenth the issue asked for (docs/user/models.md). Both processes are timed TIME_REPEATS = 5 times and the
best of each taken: on the shared 2-core machine at load 4-5 one run's ratio ranges 0.07-0.17, the best of
5 0.077-0.082 (0.077 when quiet), 0.113 while a sanitizer build ran beside it. The other rows' times too.
"""
import json
import math
import os
import subprocess
import sys
import time

# One thread for Siconos' dense algebra too; set before numpy or Siconos load OpenBLAS.
for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"

import h5py  # noqa: E402

_here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(_here, "..", "verification"))
sys.path.insert(0, _here)
from epaphe_testing import parse_args, run, variant, verdict  # noqa: E402
from v1_bar_on_wall import measure  # noqa: E402

KEYS = ("start", "end", "force", "rebound")
# (elements, h): consistent mass, theta = 0.5
SICONOS = [(100, 2e-7), (200, 1e-7)]
# (name, reduction method, modes, h)
EPAPHE = [
    ("cb40_h1e-7", "Craig-Bampton", 40, 1e-7),
    ("cb100_h1e-7", "Craig-Bampton", 100, 1e-7),
    ("cb200_h1e-7", "Craig-Bampton", 200, 1e-7),
    ("ml50_h4e-7", "Massless boundary", 50, 4e-7),
    ("ml100_h1e-7", "Massless boundary", 100, 1e-7),
    ("ml100_h4e-7", "Massless boundary", 100, 4e-7),
    ("ml200_h1e-7", "Massless boundary", 200, 1e-7),
    ("ml200_h4e-7", "Massless boundary", 200, 4e-7),
    ("full_h4e-7", "Full, lumped mass", 0, 4e-7),
]
MODEL = {
    "Craig-Bampton": "Epaphe Craig-Bampton",
    "Massless boundary": "Epaphe massless boundary",
    "Full, lumped mass": "Epaphe full, lumped mass",
}
TIE = 1e-9  # errors are of order 1e-3; two codes landing on the same step differ only by round-off
FORCE_FINDING = (0.0025, 0.0002)  # Epaphe's best row's mean force error and its band (docstring)
TIME_RATIO = 0.1  # Epaphe's best row's process time over the best Siconos row's
TIME_REPEATS = 5  # processes timed for that ratio, the best of each taken
SUBPROCESS_TIMEOUT = 600  # s, for one Siconos process (the slowest, V3's 200 elements, takes 35-50 s)


def epaphe_row(a, name, method, modes, h):
    reduced = method != "Full, lumped mass"
    deck = variant(
        a.deck,
        os.path.join(a.workdir, name + ".xml"),
        dict(
            {
                "Output->File": name + ".h5",
                "Run->Progress interval": ("0", "double"),
                "Bodies->Bar->Reduction->Method": method,
                "Bodies->Bar->Reduction->Frequency check": ("0", "int"),
                "Time->Time step": (f"{h:g}", "double"),
            },
            **(
                {
                    "Bodies->Bar->Reduction->Fixed-interface modes": (str(modes), "int"),
                    "Bodies->Bar->Reduction->Cache file": (name + ".rom.h5", "string"),
                }
                if reduced
                else {}
            ),
        ),
    )
    cache = os.path.join(a.workdir, name + ".rom.h5")
    if os.path.exists(cache):
        os.remove(cache)
    path = os.path.join(a.workdir, name + ".h5")

    def times():
        with h5py.File(path, "r") as f:
            r = f["/run"].attrs
            assert int(r["threads"]) == 1, f"{name}: ran on {r['threads']} threads"
            return float(r["loop_time"]), float(r["setup_time"])

    t = time.perf_counter()
    run([a.run, deck, "--threads", "1"], a.workdir)  # exits on a failed run; reduces and writes the cache
    wall = time.perf_counter() - t
    command = [a.run, deck, "--threads", "1"]
    loop, setup = times()  # this run's, reduction included
    t = time.perf_counter()
    run([a.run, deck, "--threads", "1"], a.workdir)  # the same run, its reduced model read from the cache
    cached = time.perf_counter() - t
    m = measure(path)  # refuses a run whose status is not 'complete'
    with h5py.File(path, "r") as f:
        lag = float(f["energy/total"][-1] - f["energy/total"][0])
    return dict(
        model=MODEL[method],
        size=f"{modes} modes" if reduced else "1212 DOFs",
        h=h,
        errs=m["errs"],
        wall=wall,
        loop=loop,
        setup=setup,
        inproc=setup + loop,
        lag=lag,
        cached=cached,
        command=command,
        cache=cache,
        cwd=a.workdir,
    )


def siconos_process(script, *args):
    """A Siconos script of this folder run in a fresh python3 process, timed as a whole: its last
    line's JSON and the process's wall time (the peer benchmarks' "process" column)."""
    t = time.perf_counter()
    out = subprocess.run(
        [sys.executable, os.path.join(_here, script), *map(str, args)],
        check=True,
        capture_output=True,
        text=True,
        timeout=SUBPROCESS_TIMEOUT,
    ).stdout
    wall = time.perf_counter() - t
    return json.loads(out.strip().splitlines()[-1]), wall


def require_siconos():
    """Fails (exit 1, not a skip) with what to do when this Python cannot import Siconos: the peer
    benchmarks compare with it, so without it they have nothing to assert."""
    try:
        import siconos.kernel  # noqa: F401
    except ImportError as e:
        raise SystemExit(
            f"FAILED: the peer benchmark needs Siconos, which {sys.executable} cannot import ({e}); "
            "install it (Debian: apt-get install python3-siconos) or configure EPAPHE_PYTHON "
            "to a python3 that has it"
        )


def siconos_row(elements, h):
    """The row in a fresh python3 process (peer_siconos_bar.py ELEMENTS H), timed as a whole."""
    r, wall = siconos_process("peer_siconos_bar.py", elements, repr(h))
    return dict(
        model="Siconos Moreau-Jean 0.5",
        size=f"{elements} elements",
        h=h,
        errs=r["errs"],
        wall=wall,
        loop=r["loop_seconds"],
        setup=r["setup_seconds"],
        inproc=r["setup_seconds"] + r["loop_seconds"],
        lag=None,
        cached=None,
        script="peer_siconos_bar.py",
        args=(elements, repr(h)),
    )


def best_process(row, repeats):
    """The least of `repeats` process times of the row (its table's run and repeats - 1 more, each
    started fresh; an Epaphe row's reduction cache removed before each, so each reduces as the
    table's run did)."""
    times = [row["wall"]]
    for _ in range(repeats - 1):
        if "script" in row:
            times.append(siconos_process(row["script"], *row["args"])[1])
            continue
        if os.path.exists(row["cache"]):
            os.remove(row["cache"])
        t = time.perf_counter()
        run(row["command"], row["cwd"])
        times.append(time.perf_counter() - t)
    return min(times), times


def compare(best_epaphe, best_siconos, keys, findings, ratio, limit, tie=TIE, fmt="{:.3%}"):
    """The assertions of a peer benchmark: Epaphe's best row at or below the best Siconos row on each
    error of `keys` but those of `findings` (key: (value, band), pinned within value +- band and
    above Siconos'). Its process time over Siconos' (`ratio`, as measured) is printed against the
    target `limit`, not asserted. Returns the failures."""
    failures = []
    for k in keys:
        e, s = best_epaphe["errs"][k], best_siconos["errs"][k]
        if k in findings:
            value, band = findings[k]
            if e <= s + tie:
                failures.append(
                    f"{k}: Epaphe's {fmt.format(e)} is now at or below Siconos' {fmt.format(s)}: the "
                    f"finding is gone; assert {k} with the other errors (drop it from the findings)"
                )
            elif not abs(e - value) <= band:
                failures.append(
                    f"{k}: Epaphe's {fmt.format(e)}, the recorded finding {fmt.format(value)} +- "
                    f"{fmt.format(band)}: {'better' if e < value else 'worse'} (a regression if worse; if "
                    f"better, update the recorded value and its docstring)"
                )
            else:
                print(
                    f"  KNOWN FINDING: {k} {fmt.format(e)} above Siconos' {fmt.format(s)}, as recorded "
                    f"({fmt.format(value)} +- {fmt.format(band)})"
                )
        elif not e <= s + tie:
            failures.append(f"{k}: Epaphe's best row {fmt.format(e)}, above Siconos' best {fmt.format(s)}")
    print(
        f"process time: Epaphe's best row {ratio:.3f} of Siconos', the target {limit}: "
        + ("met" if ratio <= limit else "not met on this run (a figure, not asserted)")
    )
    return failures


def main():
    a = parse_args()
    require_siconos()
    t_script = time.perf_counter()
    siconos = [siconos_row(n, h) for n, h in SICONOS]
    epaphe = [epaphe_row(a, *c) for c in EPAPHE]
    for row in siconos + epaphe:
        numbers = [row["errs"][k] for k in KEYS] + [row["wall"], row["loop"], row["setup"], row["inproc"]]
        numbers += [] if row["lag"] is None else [row["lag"]]
        assert all(math.isfinite(x) for x in numbers), f"{row['model']} {row['size']}: not finite: {numbers}"

    print(
        "V1 bar on a rigid wall, Siconos 4.4 and Epaphe, 1 thread each; errors relative to exact "
        "(start 2.0e-5 s, end 1.0e-4 s, mean force 1.6e6 N, rebound 100 m/s),\nrecords at step end, "
        "force = impulse / measured duration"
    )
    head = (
        f"{'code / model':<26} {'size':>12} {'h s':>6} | {'start':>6} {'end':>6} {'force':>6} {'rebound':>7} | "
        f"{'process s':>9} {'cached':>6} {'in-process s':>12} {'loop s':>6} | {'dE J':>7}"
    )
    print(head)
    print("-" * len(head))
    for row in siconos + epaphe:
        e = row["errs"]
        lag = "-" if row["lag"] is None else f"{row['lag']:.2f}"
        cached = "-" if row["cached"] is None else f"{row['cached']:.3f}"
        print(
            f"{row['model']:<26} {row['size']:>12} {row['h']:6.0e} | {e['start']:6.2%} {e['end']:6.2%} "
            f"{e['force']:6.2%} {e['rebound']:7.2%} | {row['wall']:9.3f} {cached:>6} {row['inproc']:12.3f} "
            f"{row['loop']:6.3f} | {lag:>7}"
        )

    best = min(siconos, key=lambda r: sum(r["errs"].values()))
    print(
        f"\nagainst the best Siconos row ({best['size']}, h = {best['h']:.0e}, process {best['wall']:.3f} s, "
        f"in-process {best['inproc']:.3f} s):"
    )
    for row in epaphe:
        verdicts = ", ".join(
            f"{k} {'at/below' if row['errs'][k] <= best['errs'][k] + TIE else 'ABOVE'} "
            f"({row['errs'][k]:.2%} vs {best['errs'][k]:.2%})"
            for k in KEYS
        )
        print(
            f"  {row['model']} {row['size']}, h = {row['h']:.0e}: {verdicts}; "
            f"process {row['wall'] / best['wall']:.2f} x Siconos' ({row['cached'] / best['wall']:.2f} x with the reduction "
            f"cached), in-process {row['inproc'] / best['inproc']:.2f} x"
        )
    figure(siconos + epaphe, os.path.join(a.workdir, "peer-bar-work-precision.png"))

    mine = min(epaphe, key=lambda r: sum(r["errs"].values()))
    t_mine, all_mine = best_process(mine, TIME_REPEATS)
    t_best, all_best = best_process(best, TIME_REPEATS)
    ratio = t_mine / t_best
    print(
        f"\nEpaphe's best row ({mine['model']} {mine['size']}, h = {mine['h']:.0e}) against the best Siconos row, "
        f"process times, best of {TIME_REPEATS}: {t_mine:.3f} s ({', '.join(f'{x:.3f}' for x in all_mine)}) "
        f"against {t_best:.3f} s ({', '.join(f'{x:.3f}' for x in all_best)}): {ratio:.3f} (target {TIME_RATIO})"
    )
    failures = compare(mine, best, KEYS, {"force": FORCE_FINDING}, ratio, TIME_RATIO)
    print(f"script time {time.perf_counter() - t_script:.1f} s")
    return verdict(failures)


def figure(rows, path):
    """Work-precision: each of the four errors against the wall time, one marker per code and model."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(10, 7.5), sharex=True)
    style = {
        "Siconos Moreau-Jean 0.5": ("s", "tab:gray"),
        "Epaphe Craig-Bampton": ("o", "tab:blue"),
        "Epaphe massless boundary": ("^", "tab:red"),
        "Epaphe full, lumped mass": ("D", "tab:green"),
    }
    for ax, key in zip(axes.flat, KEYS):
        for model, (marker, color) in style.items():
            pts = [r for r in rows if r["model"] == model]
            ax.scatter(
                [r["wall"] for r in pts],
                [max(100 * r["errs"][key], 1e-3) for r in pts],
                marker=marker,
                color=color,
                label=model,
            )
            for r in pts:
                ax.annotate(
                    f"{r['size'].split()[0]}, {r['h']:.0e}",
                    (r["wall"], max(100 * r["errs"][key], 1e-3)),
                    fontsize=6,
                    xytext=(3, 3),
                    textcoords="offset points",
                )
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(f"{key} error (%; 0 drawn at 1e-3)")
        ax.grid(True, which="both", alpha=0.3)
    for ax in axes[1]:
        ax.set_xlabel("process wall time of the run (s), 1 thread")
    axes[0, 0].legend(fontsize=7)
    fig.suptitle("V1 bar on a rigid wall: Siconos 4.4 and Epaphe (labels: elements or modes, h)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    print(f"figure: {path}")


if __name__ == "__main__":
    sys.exit(main())
