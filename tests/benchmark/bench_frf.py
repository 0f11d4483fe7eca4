#!/usr/bin/env python3
"""Benchmark: stepped-sine sweeps of the friction-damped cantilever (inputs/beam-friction.xml) with
epaphe-frf on 2 jobs, their wall time and what the steady-state detection saves, and the cost against
the accuracy of the frequency-response peak. Reports figures; asserts nothing about time.

1. The 40-frequency sweep, 35 to 80 Hz (FREQS40: each a whole number of the deck's steps of 2.5 us),
   `--jobs 2`, each run from the preloaded static start to its steady state (eq. (70)) or --periods:
     strict  the deck's criterion, eps = 1e-6, at most 400 periods (the sweep of docs/user/loads.md);
     fast    eps = 1e-4 (`--tolerance 1e-4`), at most 200 periods.
   Reported: each sweep's wall time, the sum of its runs' times, the periods run against the 400 of a
   sweep without the detection (the steps it saved), the runs not steady by their end, and the fast
   sweep's largest difference to the strict one (first harmonic, relative to the strict curve's
   peak) and its peak's (FRF peak: the vertex of the parabola through the largest sample and its
   neighbours).
2. Cost against accuracy: the peak from the three frequencies around it (PEAK3, 0.29 Hz apart), at
   time steps h = 2.5e-6 (the deck's, 86 % of the critical step: 6,400 steps per period at the peak),
   h/2 and h/4, eps = 1e-6; the error of the peak's amplitude and frequency against the h/4 run's
   (the explicit step cannot be longer: the central difference is stable up to 2.9e-6 s). Reported
   with each level's summed run time; drawn against the steps per period into
   WORKDIR/frf-cost-accuracy.png (tools/make-performance copies it to docs/figures/).
Written: WORKDIR/bench_frf.json (read by tools/make-performance, section `frf`).

    bench_frf.py --run EPAPHE_RUN --frf EPAPHE_FRF --deck inputs/beam-friction.xml --workdir DIR
"""
import json
import os
import platform
import subprocess
import sys
import time

import h5py
import numpy as np

_here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(_here, "..", "verification"))
from epaphe_testing import parse_args, variant  # noqa: E402
from peer_beam_friction import peak  # noqa: E402

H = 2.5e-6
FREQS40 = [1.0 / (n * H) for n in np.unique(np.round(1.0 / (np.linspace(35.0, 80.0, 40) * H)).astype(int))[::-1]]
PEAK3 = [1.0 / (n * H) for n in (6450, 6420, 6390)]
SWEEPS = [("strict", None, 400), ("fast", 1e-4, 200)]
LEVELS = [1, 2, 4]  # h / level
LOAD = "Bodies->Beam->Loads->Drive"


def machine():
    model = platform.processor() or "unknown CPU"
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                if line.startswith("model name"):
                    model = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return f"{model}, {len(os.sched_getaffinity(0))} CPUs"


def sweep(a, deck, out, freqs, tolerance, periods):
    cmd = [sys.executable, a.frf, deck, "--load", LOAD, "--frequencies", ",".join(repr(f) for f in freqs)]
    cmd += ["--jobs", "2", "--periods", str(periods), "--out", out, "--run", os.path.abspath(a.run)]
    if tolerance is not None:
        cmd += ["--tolerance", repr(tolerance)]
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=7200)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        sys.stderr.write(p.stdout[-3000:] + p.stderr[-3000:])
        raise SystemExit(f"epaphe-frf failed ({p.returncode}): {' '.join(cmd)}")
    with h5py.File(os.path.join(out, "frf.h5"), "r") as f:
        g = f["response/0"]
        return dict(
            wall=wall,
            amplitude=g["harmonic_amplitude"][:, 1].tolist(),
            steady=g["steady"][()].tolist(),
            periods=g["periods"][()].tolist(),
            run_seconds=g["wall_time"][()].tolist(),
        )


def figure(levels, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4.2))
    pts = [lv for lv in levels if lv["level"] != LEVELS[-1]]
    x = [lv["steps_per_period"] for lv in pts]
    ax.loglog(x, [max(abs(lv["amplitude_error"]), 1e-9) for lv in pts], "o-", label="peak amplitude")
    ax.loglog(x, [max(abs(lv["frequency_error"]), 1e-9) for lv in pts], "s-", label="peak frequency")
    for lv in pts:
        ax.annotate(
            f"{lv['run_seconds']:.0f} s",
            (lv["steps_per_period"], abs(lv["amplitude_error"])),
            fontsize=8,
            xytext=(4, 4),
            textcoords="offset points",
        )
    ax.set_xlabel("steps per drive period at the peak")
    ax.set_ylabel(f"relative error against {levels[-1]['steps_per_period']:,} steps per period")
    ax.set_title(
        "friction-damped cantilever: FRF peak against the time step\n(labels: the 3 runs' summed time)", fontsize=9
    )
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main():
    a = parse_args("--frf")
    t_all = time.perf_counter()
    res = dict(machine=machine(), frequencies=FREQS40, sweeps={}, levels=[])
    for name, tol, periods in SWEEPS:
        s = sweep(a, a.deck, os.path.join(a.workdir, name), FREQS40, tol, periods)
        s.update(tolerance=tol if tol is not None else 1e-6, max_periods=periods)
        s["saved"] = 1 - sum(p * f0 for p, f0 in zip(s["periods"], [1 / f for f in FREQS40])) / sum(
            400 / f for f in FREQS40
        )
        res["sweeps"][name] = s
        print(
            f"{name}: {len(FREQS40)} frequencies, eps = {s['tolerance']:g}, at most {periods} periods: {s['wall']:.1f} s "
            f"wall on 2 jobs ({sum(s['run_seconds']):.1f} s of runs), {sum(s['steady'])} steady, "
            f"{np.mean(s['periods']):.0f} periods a run on average, {s['saved']:.0%} of the steps of 400 periods "
            "each saved"
        )
    strict, fast = (np.array(res["sweeps"][n]["amplitude"]) for n in ("strict", "fast"))
    ps, pf = peak(FREQS40, strict), peak(FREQS40, fast)
    res["fast_vs_strict"] = dict(
        largest=float(np.max(np.abs(fast - strict)) / strict.max()),
        peak_frequency=float(pf[0] / ps[0] - 1),
        peak_amplitude=float(pf[1] / ps[1] - 1),
    )
    print(
        "fast against strict: largest difference {largest:.2e} of the peak; peak frequency {peak_frequency:+.2e}, "
        "amplitude {peak_amplitude:+.2e}".format(**res["fast_vs_strict"])
    )
    for level in LEVELS:
        h = H / level
        deck = variant(a.deck, os.path.join(a.workdir, f"h{level}.xml"), {"Time->Time step": (repr(h), "double")})
        s = sweep(a, deck, os.path.join(a.workdir, f"h{level}"), PEAK3, None, 400)
        pk = peak(PEAK3, s["amplitude"])
        res["levels"].append(
            dict(
                level=level,
                time_step=h,
                steps_per_period=round(1 / (pk[0] * h)),
                peak_frequency=pk[0],
                peak_amplitude=pk[1],
                run_seconds=sum(s["run_seconds"]),
                wall=s["wall"],
                steady=s["steady"],
            )
        )
    ref = res["levels"][-1]
    print(
        f"\n{'h s':>9} {'steps/period':>12} {'peak Hz':>10} {'peak m':>12} {'freq error':>10} {'ampl error':>10} "
        f"{'runs s':>7}"
    )
    for lv in res["levels"]:
        lv["frequency_error"] = lv["peak_frequency"] / ref["peak_frequency"] - 1
        lv["amplitude_error"] = lv["peak_amplitude"] / ref["peak_amplitude"] - 1
        print(
            f"{lv['time_step']:9.3e} {lv['steps_per_period']:12,} {lv['peak_frequency']:10.4f} "
            f"{lv['peak_amplitude']:12.6e} {lv['frequency_error']:+10.2e} {lv['amplitude_error']:+10.2e} "
            f"{lv['run_seconds']:7.1f}"
        )
    figure(res["levels"], os.path.join(a.workdir, "frf-cost-accuracy.png"))
    res["total_seconds"] = time.perf_counter() - t_all
    with open(os.path.join(a.workdir, "bench_frf.json"), "w") as fh:
        json.dump(res, fh, indent=1)
    print(
        f"written {os.path.join(a.workdir, 'bench_frf.json')} and frf-cost-accuracy.png; "
        f"{res['total_seconds']:.0f} s in all"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
