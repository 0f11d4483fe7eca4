#!/usr/bin/env python3
"""Peer benchmark: V3, the bouncing bar of Doyen, Ern & Piperno over
10 periods, in Siconos and in Epaphe, measured one way, in one table and one work-precision figure.

V3 (tests/verification/v3_bouncing_bar.py, deck tests/verification/decks/bouncing-bar.xml): bar
L = 10 m, c = 30 m/s, dropped from h0 = 5 m onto a rigid plane under g = 10 m/s^2. Exact: period
16/3 s, two contacts of T_c = 2L/c = 2/3 s each per period (20 in 10 periods), energy conserved.
Rows, each on 1 thread:
  - Siconos 4.4 (peer_siconos_bouncing_bar.py): a 1-D bar of 100 and 200 linear elements, consistent
    mass, Moreau-Jean theta = 0.5, LCP, restitution 0, at Courant number c h / le = 0.5;
  - Epaphe, the deck's 3-D bar (500 x 1 x 1 hexahedra, nu = 0), Lagrange contact:
      full model, lumped mass, at h = 6.66e-4 s (the deck: 0.999 of its stable step dx / c) and on a
      100-element mesh at h = 3.33e-3 s (the same Courant number);
      the massless boundary with 50 and 100 elastic modes (and the 6 rigid-body modes) at the deck's
      h = 6.66e-4 s, far below its stable step;
      Craig-Bampton with 100 fixed-interface modes at h = 2e-4 s (below its stable step, set by the
      contact face's own mass).
Measured the same way for both codes, from one record per step at the step's end:
  - contacts: intervals of steps with a contact force above 1e-6 rho A c V (force-free gaps shorter
    than T_c / 10 are chatter inside one contact, as v3_bouncing_bar.py counts them); the exact count
    is 20; "T_c error" is the larger |duration - T_c| / T_c of the first period's two contacts (once
    a run has split or added contacts, later durations no longer pair with the exact ones);
  - energy: E = kinetic + strain + gravity's potential (Epaphe: energy/total - energy/external_work;
    Siconos: v^T M v / 2 + u^T K u / 2 - F^T u), "drift" its largest |E - E_0| over the run and "end"
    E_end - E_0, both over m g h0 (500 J).
Times, as benchmark.peer-bar takes them: "process" around the whole fresh process (epaphe-run; for
Siconos python3 peer_siconos_bouncing_bar.py, its start and imports included), "in-process" each
code's own timers (Epaphe's setup_time + loop_time, the reduction included: the default cache of
the reduced model is removed before each run; Siconos' setup + loop).
The figure (WORKDIR/peer-bouncing-bar-work-precision.png; its copy in docs/figures/, shown in docs/user/models.md) draws the
energy drift and the first period's contact duration error against the process time.

Asserted (a missing Siconos is a failure, not a skip: the comparison is the test), as
benchmark.peer-bar does (peer_bar.compare):
  - every run completed and its numbers are finite;
  - Epaphe's best row is at or below the best Siconos row on each of the four errors: contacts
    |count - 20| / 20, T_c error, drift and |end| (the best row of each code: the least sum of the
    four; today Epaphe's lumped full model at 500 elements, 30 contacts, 0.30 %, 4.95 %, 4.95 %,
    against Siconos' 200 elements, 45 contacts, 3.13 %, 63.2 %, 63.2 %);
Reported, not asserted: Epaphe's best row's process time against that Siconos row's, and against the
target TIME_RATIO = 0.75 (no ratio is stated for V3; one run each, measured 0.42 on a quiet machine, 0.51
at load 5 on 2 cores, each process 13-50 s long). The other rows' times too.
"""
import math
import os
import sys
import time

# One thread for Siconos' dense algebra too; set before numpy or Siconos load OpenBLAS.
for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"

import numpy as np  # noqa: E402

_here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(_here, "..", "verification"))
from epaphe_testing import history, parse_args, run, variant  # noqa: E402
from v3_bouncing_bar import intervals  # noqa: E402

sys.path.insert(0, _here)
from peer_bar import compare, require_siconos, siconos_process  # noqa: E402
from epaphe_testing import verdict  # noqa: E402

L, A, RHO, C, G, H0 = 10.0, 1.0, 1.0, 30.0, 10.0, 5.0
PERIODS = 10
V = math.sqrt(2 * G * H0)
T_C = 2 * L / C
E_REF = RHO * A * L * G * H0  # m g h0 = 500 J
F_SCALE = RHO * A * C * V  # the force of an impact at V
SICONOS = [(100, 0.5 * (L / 100) / C), (200, 0.5 * (L / 200) / C)]
# (name, method, elements, modes, h)
EPAPHE = [
    ("full500", "Full, lumped mass", 500, 0, 6.66e-4),
    ("full100", "Full, lumped mass", 100, 0, 3.33e-3),
    ("ml50", "Massless boundary", 500, 50, 6.66e-4),
    ("ml100", "Massless boundary", 500, 100, 6.66e-4),
    ("cb100", "Craig-Bampton", 500, 100, 2e-4),
]
KEYS = ("contacts", "T_c", "drift", "end")
TIME_RATIO = 0.75  # Epaphe's best row's process time over the best Siconos row's (docstring)
MODEL = {
    "Full, lumped mass": "Epaphe full, lumped mass",
    "Massless boundary": "Epaphe massless boundary",
    "Craig-Bampton": "Epaphe Craig-Bampton",
}


def measures(t, force, energy, h):
    starts, ends, chatter = intervals(t, force > 1e-6 * F_SCALE, h, T_C / 10)
    durations = (ends - starts)[:2]  # the first period's two contacts
    drift = energy - energy[0]
    m = dict(
        contacts=int(starts.size),
        chatter=int(sum(chatter)),
        worst_tc=float(np.abs(durations - T_C).max() / T_C),
        drift=float(np.abs(drift).max() / E_REF),
        end=float(drift[-1] / E_REF),
    )
    m["errs"] = {
        "contacts": abs(m["contacts"] - 2 * PERIODS) / (2 * PERIODS),
        "T_c": m["worst_tc"],
        "drift": m["drift"],
        "end": abs(m["end"]),
    }
    return m


def siconos_row(elements, h):
    r, wall = siconos_process("peer_siconos_bouncing_bar.py", elements, repr(h), PERIODS)
    m = measures(np.array(r["time"]), np.array(r["force"]), np.array(r["energy"]), h)
    return dict(
        model="Siconos Moreau-Jean 0.5",
        size=f"{elements} elements",
        h=h,
        wall=wall,
        inproc=r["setup_seconds"] + r["loop_seconds"],
        loop=r["loop_seconds"],
        **m,
    )


def epaphe_row(a, name, method, elements, modes, h):
    reduced = method != "Full, lumped mass"
    changes = {
        "Output->File": name + ".h5",
        "Run->Progress interval": ("0", "double"),
        "Bodies->Bar->Reduction->Method": method,
        "Bodies->Bar->Mesh->Elements": (f"{{{elements}, 1, 1}}", "Array(int)"),
        "Time->Time step": (f"{h:g}", "double"),
    }
    if reduced:
        changes["Bodies->Bar->Reduction->Fixed-interface modes"] = (str(modes), "int")
    deck = variant(a.deck, os.path.join(a.workdir, name + ".xml"), changes)
    cache = os.path.join(a.workdir, name + ".Bar.rom.h5")  # the default cache: each run reduces
    if os.path.exists(cache):
        os.remove(cache)
    t = time.perf_counter()
    run([a.run, deck, "--threads", "1"], a.workdir)  # exits on a failed run
    wall = time.perf_counter() - t
    hist = history(os.path.join(a.workdir, name + ".h5"))  # refuses a run whose status is not 'complete'
    r = hist["attrs"]
    assert int(r["threads"]) == 1, f"{name}: ran on {r['threads']} threads"
    energy = hist["energy/total"] - hist["energy/external_work"]
    m = measures(hist["time"], hist["bodies/Bar/contact/total_force"], energy, h)
    size = f"{modes} modes" if reduced else f"{elements} elements"
    return dict(
        model=MODEL[method],
        size=size,
        h=h,
        wall=wall,
        inproc=float(r["setup_time"]) + float(r["loop_time"]),
        loop=float(r["loop_time"]),
        **m,
    )


def figure(rows, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    style = {
        "Siconos Moreau-Jean 0.5": ("s", "tab:gray"),
        "Epaphe Craig-Bampton": ("o", "tab:blue"),
        "Epaphe massless boundary": ("^", "tab:red"),
        "Epaphe full, lumped mass": ("D", "tab:green"),
    }
    for ax, key, title in (
        (axes[0], "drift", "largest |energy drift| over 10 periods (% of m g h0)"),
        (axes[1], "worst_tc", "contact duration error, first period (%)"),
    ):
        for model, (marker, color) in style.items():
            pts = [r for r in rows if r["model"] == model]
            ax.scatter(
                [r["wall"] for r in pts],
                [max(100 * r[key], 1e-4) for r in pts],
                marker=marker,
                color=color,
                label=model,
            )
            for r in pts:
                ax.annotate(
                    f"{r['size'].split()[0]}, {r['h']:.1e}, {r['contacts']} contacts",
                    (r["wall"], max(100 * r[key], 1e-4)),
                    fontsize=6,
                    xytext=(3, 3),
                    textcoords="offset points",
                )
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(title, fontsize=9)
        ax.set_xlabel("process wall time of the run (s), 1 thread")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=7, loc="center left")
    fig.suptitle("V3 bouncing bar, 10 periods: Siconos 4.4 and Epaphe (labels: elements or modes, h, contacts of 20)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    print(f"figure: {path}")


def main():
    a = parse_args()
    require_siconos()
    t_script = time.perf_counter()
    rows = [siconos_row(*r) for r in SICONOS] + [epaphe_row(a, *r) for r in EPAPHE]
    for row in rows:
        numbers = [row[k] for k in ("worst_tc", "drift", "end", "wall", "inproc", "loop")]
        assert all(math.isfinite(x) for x in numbers), f"{row['model']} {row['size']}: not finite: {numbers}"
    print(
        f"V3 bouncing bar over {PERIODS} periods, Siconos 4.4 and Epaphe, 1 thread each: exact {2 * PERIODS} "
        f"contacts of T_c = {T_C:.4f} s, energy conserved; drift and end over m g h0 = {E_REF:g} J"
    )
    head = (
        f"{'code / model':<26} {'size':>12} {'h s':>8} | {'contacts':>8} {'chatter':>7} {'T_c error':>9} | "
        f"{'drift':>7} {'end':>8} | {'process s':>9} {'in-process s':>12} {'loop s':>7}"
    )
    print(head)
    print("-" * len(head))
    for r in rows:
        print(
            f"{r['model']:<26} {r['size']:>12} {r['h']:8.2e} | {r['contacts']:8d} {r['chatter']:7d} "
            f"{r['worst_tc']:9.2%} | {r['drift']:7.3%} {r['end']:+8.3%} | {r['wall']:9.3f} {r['inproc']:12.3f} "
            f"{r['loop']:7.3f}"
        )
    figure(rows, os.path.join(a.workdir, "peer-bouncing-bar-work-precision.png"))
    siconos = [r for r in rows if r["model"].startswith("Siconos")]
    best = min(siconos, key=lambda r: sum(r["errs"].values()))
    mine = min((r for r in rows if r not in siconos), key=lambda r: sum(r["errs"].values()))
    ratio = mine["wall"] / best["wall"]
    print(
        f"\nEpaphe's best row ({mine['model']} {mine['size']}, h = {mine['h']:.2e}: {mine['contacts']} contacts, "
        f"T_c {mine['worst_tc']:.2%}, drift {mine['drift']:.3%}, end {mine['end']:+.3%}) against the best "
        f"Siconos row ({best['size']}, h = {best['h']:.2e}: {best['contacts']} contacts, {best['worst_tc']:.2%}, "
        f"{best['drift']:.3%}, {best['end']:+.3%}); process {mine['wall']:.2f} s against {best['wall']:.2f} s: "
        f"{ratio:.3f} (target {TIME_RATIO})"
    )
    failures = compare(mine, best, KEYS, {}, ratio, TIME_RATIO, tie=0.0)
    print(f"script time {time.perf_counter() - t_script:.1f} s")
    return verdict(failures)


if __name__ == "__main__":
    sys.exit(main())
