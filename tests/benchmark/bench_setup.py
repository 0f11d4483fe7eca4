#!/usr/bin/env python3
"""Setup benchmark of epaphe-run on imported blades (label benchmark: reports figures, asserts nothing
about time).

Two models from blade_model.py, each through ccx (*FREQUENCY, SOLVER=MATRIXSTORAGE for the matrices;
*FREQUENCY, STORAGE=YES for ccx's own eigenvalues, freq.eig):
  C3D20 SI        the reduction benchmark's blade: 100 x 30 x 1 C3D20 cells, m / Pa / kg/m^3
                  (64,500 free DOFs);
  C3D15 mm-tonne  88 x 25 x 1 cells of two C3D15 wedges, mm / MPa / t/mm^3 (60,720 free DOFs), the
                  units and element of the real blade whose frequency check took 7 min (issue 12).
Each model runs epaphe-run (OMP_NUM_THREADS=1) with Reduction->Method 'Massless boundary' and
'Craig-Bampton' (50 fixed-interface modes, the 16 TIP16 nodes retained, Frequency check 10, Cache
false, 10 steps with no contact surface) on 1 and on 2 MPI ranks (mpiexec -n N). From epaphe-run's
output: reduction ("[Blade] <method>: ... in X"), check ("[Blade] frequency check: ... in X", 0 when
the check reuses the reduction's modes) and setup ("wall time: setup X"); import = setup - reduction
- check (the import of the matrices and everything else the setup does; the output does not time the
import alone). Ratios: (setup - import) / reduction and setup / reduction. Peak memory per rank:
each rank runs epaphe-run as the child of this script (--measure), which reads getrusage
(RUSAGE_CHILDREN).ru_maxrss after it exits, i.e. the peak resident set of that rank's epaphe-run
process alone. Writes bench_setup.json. Takes about 6 min on a loaded 2-core machine (357 s measured
2026-11-24, of which ccx 42 s); --models, --methods, --ranks and --cells shorten it for trials.

Asserted (nothing about time): every run completes (exit 0, its timings printed, within --timeout);
the check's full-model frequencies (/bodies/Blade/frequencies/full in the HDF5 output, Hz) equal
ccx's own (freq.eig) to CCX_TOL; on each model and method, 2 ranks give the full and the reduced
frequencies of 1 rank to RANKS_TOL (the reasoning for both is where they are checked, in main()).
"""
import argparse
import json
import math
import os
import re
import resource
import signal
import struct
import subprocess
import sys
import time

import h5py

HERE = os.path.dirname(os.path.abspath(__file__))

CCX_TOL = 1e-6  # relative, full-model frequencies against ccx's: reasoning in main()
RANKS_TOL = 1e-8  # relative, 2 ranks against 1 rank: reasoning in main()
CHECK = 10  # Reduction->Frequency check

MODELS = [  # name, blade_model.py arguments
    ("C3D20-SI", ["--cells", "100", "30", "1", "--element", "C3D20", "--units", "m"]),
    ("C3D15-mm", ["--cells", "88", "25", "1", "--element", "C3D15", "--units", "mm"]),
]
METHODS = ["Massless boundary", "Craig-Bampton"]


def measure(argv):
    """Runs argv (one MPI rank's epaphe-run) as a child; writes its exit code, wall time and peak
    resident set (getrusage of the waited-for child, KiB on Linux) to OUT.<rank>.json."""
    out, cmd = argv[0], argv[1:]
    rank = next(
        (os.environ[v] for v in ("OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK") if v in os.environ),
        f"pid{os.getpid()}",
    )
    t0 = time.time()
    code = subprocess.call(cmd)
    wall = time.time() - t0
    with open(f"{out}.{rank}.json", "w") as f:
        json.dump(
            {
                "rank": rank,
                "exit": code,
                "wall_s": wall,
                "maxrss_mb": resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024.0,
            },
            f,
        )
    return code


def seconds(text):
    """A duration as epaphe's formatDuration prints it: '1 h 02 min', '3 min 04 s', '1.23 s', '4.5 ms', '7.0 us'."""
    text = text.strip()
    m = re.fullmatch(r"(\d+) h (\d+) min", text)
    if m:
        return 3600 * int(m.group(1)) + 60 * int(m.group(2))
    m = re.fullmatch(r"(\d+) min (\d+) s", text)
    if m:
        return 60 * int(m.group(1)) + int(m.group(2))
    m = re.fullmatch(r"([\d.eE+-]+) (s|ms|us)", text)
    if m:
        return float(m.group(1)) * {"s": 1.0, "ms": 1e-3, "us": 1e-6}[m.group(2)]
    raise ValueError(f"cannot read the duration '{text}'")


def parse(stdout, method):
    """Reduction, check and setup times from epaphe-run's output (None where a line is missing)."""
    r = {}
    m = re.search(
        r"^\[Blade\] " + re.escape(method) + r": .* in (.+?) on \d+ rank\(s\) \(factor (.+?), "
        r"constraint modes (.+?), eigenmodes (.+?)\)$",
        stdout,
        re.M,
    )
    if m:
        r.update(
            reduction_s=seconds(m.group(1)),
            factor_s=seconds(m.group(2)),
            constraint_s=seconds(m.group(3)),
            eigen_s=seconds(m.group(4)),
        )
    m = re.search(r"^\[Blade\] frequency check: (.*)$", stdout, re.M)
    if m:
        t = re.search(r" in (.+)$", m.group(1))
        r["check_s"] = seconds(t.group(1)) if t else 0.0  # "... are the reduction's own modes": no solve
        r["check_line"] = m.group(1)
    m = re.search(r"^wall time: setup (.+?), loop", stdout, re.M)
    if m:
        r["setup_s"] = seconds(m.group(1))
    m = re.search(r"^\[Blade\] full model: (\d+) nodes, (\d+) free DOFs", stdout, re.M)
    if m:
        r.update(nodes=int(m.group(1)), free_dofs=int(m.group(2)))
    m = re.search(r"^\[Blade\] full model: .*, imported in (.+)$", stdout, re.M)
    if m:  # epaphe-run times the import itself
        r["import_s"] = seconds(m.group(1))
    return r


def ccx_frequencies(model):
    """ccx's eigenvalues from freq.eig (*FREQUENCY, STORAGE=YES), as frequencies in Hz."""
    with open(os.path.join(model, "freq.eig"), "rb") as f:
        b = f.read()
    nev = struct.unpack("4i", b[:16])[3]
    return [math.sqrt(lam) / (2 * math.pi) for lam in struct.unpack(f"{nev}d", b[16 : 16 + 8 * nev])]


DECK = """<ParameterList name="Epaphe">
  <ParameterList name="Bodies">
    <ParameterList name="Blade">
      <ParameterList name="Mesh">
        <Parameter name="Type" type="string" value="CalculiX"/>
        <Parameter name="Input file" type="string" value="{model}/mat.inp"/>
      </ParameterList>
      <ParameterList name="Reduction">
        <Parameter name="Method" type="string" value="{method}"/>
        <Parameter name="Retained node set" type="string" value="TIP16"/>
        <Parameter name="Fixed-interface modes" type="int" value="{modes}"/>
        <Parameter name="Frequency check" type="int" value="{check}"/>
        <Parameter name="Cache" type="bool" value="false"/>
      </ParameterList>
    </ParameterList>
  </ParameterList>
  <ParameterList name="Time">
    <Parameter name="Time step" type="double" value="1e-8"/>
    <Parameter name="End time" type="double" value="1e-7"/>
  </ParameterList>
  <ParameterList name="Output">
    <Parameter name="File" type="string" value="{output}"/>
  </ParameterList>
</ParameterList>
"""


def main():
    if len(sys.argv) > 2 and sys.argv[1] == "--measure":
        return measure(sys.argv[2:])
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--run", required=True, help="epaphe-run")
    p.add_argument("--mpiexec", required=True)
    p.add_argument("--ccx", required=True)
    p.add_argument("--workdir", required=True)
    p.add_argument("--models", nargs="+", default=[m for m, _ in MODELS], choices=[m for m, _ in MODELS])
    p.add_argument("--methods", nargs="+", default=METHODS, choices=METHODS)
    p.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    p.add_argument("--modes", type=int, default=50)
    p.add_argument(
        "--cells",
        type=int,
        nargs=3,
        action="append",
        default=None,
        help="cells per model, in --models order (default: those of the docstring); for quick trials",
    )
    p.add_argument(
        "--timeout", type=float, default=900, help="seconds after which a run is stopped (and the test fails)"
    )
    a = p.parse_args()
    workdir = os.path.abspath(a.workdir)
    os.makedirs(workdir, exist_ok=True)
    env = dict(
        os.environ,
        OMPI_ALLOW_RUN_AS_ROOT="1",
        OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
        OMPI_MCA_rmaps_base_oversubscribe="1",
        OMP_NUM_THREADS="1",
        OMP_PROC_BIND="false",
    )
    t_start = time.time()
    results, failures = [], []
    for n, name in enumerate(a.models):
        args = dict(MODELS)[name]
        if a.cells:
            if len(a.cells) != len(a.models):
                print(
                    f"--cells given {len(a.cells)} times for {len(a.models)} model(s) ({' '.join(a.models)}): "
                    "give one --cells NX NY NZ per model, in --models order"
                )
                return 2
            args = args[:]
            args[1:4] = map(str, a.cells[n])
        model = os.path.join(workdir, name)
        t0 = time.time()
        subprocess.run(
            [
                sys.executable,
                os.path.join(HERE, "blade_model.py"),
                model,
                *args,
                "--modes",
                str(CHECK),
                "--run",
                a.ccx,
                "--freq",
                "--storage",
            ],
            check=True,
            env=env,
        )
        print(f"[bench] {name}: model generated, ccx matrices and eigenvalues in {time.time() - t0:.1f} s")
        ccx = ccx_frequencies(model)
        mine = []
        for method in a.methods:
            for np_ in a.ranks:
                tag = f"{name}.{method.split()[0].split('-')[0]}.np{np_}"  # C3D20-SI.Massless.np1
                deck = os.path.join(workdir, tag + ".xml")
                with open(deck, "w") as f:
                    f.write(DECK.format(model=name, method=method, modes=a.modes, check=CHECK, output=tag + ".h5"))
                mem = os.path.join(workdir, tag + ".mem")
                for old in os.listdir(workdir):
                    if old.startswith(tag + ".mem."):
                        os.remove(os.path.join(workdir, old))
                cmd = [
                    a.mpiexec,
                    "-n",
                    str(np_),
                    sys.executable,
                    os.path.abspath(__file__),
                    "--measure",
                    mem,
                    a.run,
                    deck,
                ]
                res = {"model": name, "method": method, "ranks": np_}
                t0 = time.time()
                # Its own session: on --timeout the whole group (mpiexec, wrappers, ranks) is stopped.
                proc = subprocess.Popen(
                    cmd,
                    env=env,
                    stdout=subprocess.PIPE,
                    stderr=subprocess.PIPE,
                    text=True,
                    cwd=workdir,
                    start_new_session=True,
                )
                try:
                    stdout, stderr = proc.communicate(timeout=a.timeout)
                    r = subprocess.CompletedProcess(cmd, proc.returncode, stdout, stderr)
                except subprocess.TimeoutExpired:
                    os.killpg(proc.pid, signal.SIGKILL)
                    proc.communicate()
                    failures.append(f"{tag}: stopped after {a.timeout:.0f} s (--timeout)")
                    results.append(dict(res, error=f"stopped after {a.timeout:.0f} s"))
                    print(f"[bench] {tag}: stopped after {a.timeout:.0f} s (--timeout)")
                    continue
                res["process_wall_s"] = time.time() - t0
                with open(os.path.join(workdir, tag + ".log"), "w") as f:
                    f.write(r.stdout + r.stderr)
                res.update(parse(r.stdout, method))
                missing = [k for k in ("reduction_s", "check_s", "setup_s") if k not in res]
                if r.returncode != 0 or missing or "status: complete" not in r.stdout:
                    why = (
                        f"exit {r.returncode}"
                        + (f", no {', '.join(missing)} in its output" if missing else "")
                        + ("" if "status: complete" in r.stdout else ", no 'status: complete'")
                    )
                    failures.append(f"{tag}: {why}: {(r.stderr or r.stdout).strip()[-400:]}")
                    results.append(dict(res, error=(r.stderr or r.stdout)[-2000:]))
                    print(f"[bench] {tag} failed ({why}):\n{r.stdout}\n{r.stderr}")
                    continue
                ranks = []
                for fn in sorted(os.listdir(workdir)):
                    if fn.startswith(tag + ".mem."):
                        with open(os.path.join(workdir, fn)) as f:
                            ranks.append(json.load(f))
                ranks.sort(key=lambda x: x["rank"])
                res["maxrss_mb"] = [x["maxrss_mb"] for x in ranks]
                if len(ranks) != np_:
                    failures.append(f"{tag}: peak memory of {len(ranks)} rank(s) read, expected {np_}")
                if "import_s" not in res:  # an epaphe-run that does not time it: what the rest leaves
                    res["import_s"] = res["setup_s"] - res["reduction_s"] - res["check_s"]
                res["after_import_over_reduction"] = (res["setup_s"] - res["import_s"]) / res["reduction_s"]
                res["setup_over_reduction"] = res["setup_s"] / res["reduction_s"]
                with h5py.File(os.path.join(workdir, tag + ".h5"), "r") as f:
                    res["full_hz"] = [float(x) for x in f["/bodies/Blade/frequencies/full"][:]]
                    res["reduced_hz"] = [float(x) for x in f["/bodies/Blade/frequencies/reduced"][:]]
                # The check's full-model frequencies against ccx's own eigenvalues (freq.eig, double
                # precision), CCX_TOL = 1e-6 relative. Both solve the same (K, M): ccx writes the
                # matrices with 14 significant digits (a relative perturbation of 5e-14 per entry),
                # ARPACK in ccx and Anasazi in Epaphe converge to residuals of 1e-10 or below, and an
                # eigenvalue's error goes as the square of its vector's: differences of 1e-9 or less
                # are expected (the deck-import test's small blade: the same 1e-6 bound on
                # eigenvalues). 1e-6 still catches a wrong mode (the nearest pair here is 28 % apart),
                # a lost mode, a wrong unit conversion or a solve stopped early.
                n_cmp = min(len(res["full_hz"]), len(ccx))
                if len(res["full_hz"]) != CHECK or len(ccx) != CHECK:
                    failures.append(
                        f"{tag}: {len(res['full_hz'])} full-model frequencies in the output, "
                        f"{len(ccx)} from ccx, expected {CHECK} of each"
                    )
                res["vs_ccx"] = max(abs(x - y) / y for x, y in zip(res["full_hz"][:n_cmp], ccx[:n_cmp]))
                if not res["vs_ccx"] <= CCX_TOL:
                    failures.append(
                        f"{tag}: full-model frequencies differ from ccx's by {res['vs_ccx']:.2e} "
                        f"(relative) > {CCX_TOL:g}"
                    )
                results.append(res)
                mine.append(res)
                print(
                    f"[bench] {tag}: {res.get('free_dofs')} free DOFs: import {res['import_s']:.2f} s, reduction "
                    f"{res['reduction_s']:.2f} s (factor {res['factor_s']:.2f}, constraint modes "
                    f"{res['constraint_s']:.2f}, eigenmodes {res['eigen_s']:.2f}), check {res['check_s']:.2f} s, "
                    f"setup {res['setup_s']:.2f} s; (setup - import) / reduction "
                    f"{res['after_import_over_reduction']:.2f}, setup / reduction {res['setup_over_reduction']:.2f}; "
                    f"peak memory per rank {', '.join(f'{x:.0f}' for x in res['maxrss_mb'])} MB; full frequencies vs "
                    f"ccx {res['vs_ccx']:.1e}; f1 {res['full_hz'][0]:.6g} Hz"
                )
        # 2 ranks against 1 (same model and method), RANKS_TOL = 1e-8 relative on the full and the
        # reduced frequencies. The same matrices, solved by MUMPS on a different distribution:
        # direct solves agree to rounding (1e-13), and the eigen solves (Anasazi, residual
        # tolerance 1e-10) may stop at different iterations, moving a frequency by at most its
        # residual's first-order effect (the reduction benchmark's blade: 1.2e-10 on 2 ranks).
        # 1e-8 leaves a factor 100 for that and catches a rank whose part of the matrix is lost or
        # counted twice (a change of percents).
        for method in a.methods:
            runs = {r["ranks"]: r for r in mine if r["method"] == method}
            if 1 not in runs:
                continue
            for np_, r in runs.items():
                if np_ == 1:
                    continue
                for key in ("full_hz", "reduced_hz"):
                    x, y = r[key], runs[1][key]
                    if len(x) != len(y):
                        failures.append(f"{name} {method}: {len(x)} {key} on {np_} ranks, {len(y)} on 1")
                        continue
                    d = max(abs(u - v) / v for u, v in zip(x, y))
                    r[key + "_vs_np1"] = d
                    print(
                        f"[bench] {name} {method} np={np_}: {key} against np=1: largest relative difference "
                        f"{d:.1e} (tolerance {RANKS_TOL:g})"
                    )
                    if not d <= RANKS_TOL:
                        failures.append(
                            f"{name} {method} np={np_}: {key} differ from 1 rank's by {d:.2e} > {RANKS_TOL:g}"
                        )
    print(
        "\n model     reduction          ranks  import  reduction  check   setup  (setup-import)/red  setup/red"
        "  peak memory per rank (MB)"
    )
    for r in results:
        if "error" in r:
            print(f" {r['model']:9s} {r['method']:18s} {r['ranks']:5d}  failed")
            continue
        print(
            f" {r['model']:9s} {r['method']:18s} {r['ranks']:5d} {r['import_s']:7.2f} {r['reduction_s']:10.2f} "
            f"{r['check_s']:6.2f} {r['setup_s']:7.2f} {r['after_import_over_reduction']:19.2f} "
            f"{r['setup_over_reduction']:10.2f}  {' / '.join(f'{x:.0f}' for x in r['maxrss_mb'])}"
        )
    total = time.time() - t_start
    print(f"[bench] total {total:.0f} s")
    with open(os.path.join(workdir, "bench_setup.json"), "w") as f:
        json.dump(
            {"runs": results, "total_s": total, "ccx_tolerance": CCX_TOL, "ranks_tolerance": RANKS_TOL}, f, indent=1
        )
    print("FAILED:\n  " + "\n  ".join(failures) if failures else "PASSED (no assertion on time)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
