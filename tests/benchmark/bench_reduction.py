#!/usr/bin/env python3
"""Large-model reduction benchmark (label benchmark: reports figures, asserts nothing about time).

Generates a twisted plate of C3D20 (blade_model.py, over 60,000 DOFs by default), runs ccx
(*FREQUENCY, SOLVER=MATRIXSTORAGE), then bench_reduction imports it and reduces it by
Craig-Bampton (16 retained tip nodes, 50 fixed-interface modes) with each solver on 1 and 2 MPI
ranks, each configuration in its own process so that its peak memory is its own (Belos CG on the
thin blade: 1 rank, stopped after --timeout). Then the same on a chunky C3D20 bar of about 11,000
DOFs, where Jacobi-CG converges, to compare Belos CG with MUMPS. Prints import, factor, constraint
modes, eigen solve, total, CPU time, peak memory (getrusage maxrss); writes bench_reduction.json.
"""
import argparse
import json
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--bench", required=True)
    p.add_argument("--mpiexec", required=True)
    p.add_argument("--ccx", required=True)
    p.add_argument("--workdir", required=True)
    p.add_argument("--cells", type=int, nargs=3, default=[100, 30, 1])
    p.add_argument("--modes", type=int, default=50)
    p.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    p.add_argument("--solvers", nargs="+", default=["MUMPS", "Belos CG"])
    p.add_argument("--tolerance", default="1e-10", help="Belos CG relative residual")
    p.add_argument("--timeout", type=float, default=150, help="seconds after which a configuration is stopped")
    a = p.parse_args()
    os.makedirs(a.workdir, exist_ok=True)
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1", OMP_NUM_THREADS="1", OMP_PROC_BIND="false")
    # The blade: every solver on every rank count (Jacobi-CG on the thin plate is stopped by
    # --timeout: its condition number needs tens of thousands of iterations per solve). A chunky
    # bar of C3D20 (0.1 x 0.03 x 0.03 m, about 11,000 DOFs) where CG converges, to set Belos CG
    # against MUMPS in time and memory.
    parts = [("blade", a.cells, [0.1, 0.03, 0.003], 30.0, a.solvers, a.ranks),
             ("chunk", [20, 6, 6], [0.1, 0.03, 0.03], 0.0, a.solvers, a.ranks)]
    results = []
    for part, cells, lengths, twist, solvers, ranks in parts:
        model = os.path.join(a.workdir, part)
        t0 = time.time()
        subprocess.run([sys.executable, os.path.join(HERE, "blade_model.py"), model, "--cells", *map(str, cells),
                        "--lengths", *map(str, lengths), "--twist", str(twist), "--run", a.ccx], check=True)
        print(f"[bench] {part}: model generated and ccx run in {time.time() - t0:.1f} s")
        mine = []
        for solver in solvers:
            for np_ in ranks:
                if part == "blade" and solver != "MUMPS" and np_ > 1:
                    continue  # stopped by the timeout on 1 rank already
                cmd = [a.mpiexec, "-n", str(np_), a.bench, os.path.join(model, "mat.inp"), os.path.join(model, "mat"),
                       "TIP16", str(a.modes), solver, a.tolerance]
                t0 = time.time()
                try:
                    r = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=a.timeout)
                except subprocess.TimeoutExpired:
                    print(f"[bench] {part} {solver} on {np_} rank(s): stopped after {a.timeout:.0f} s (--timeout)")
                    results.append({"part": part, "solver": solver, "ranks": np_, "error": f"stopped after {a.timeout} s"})
                    continue
                wall = time.time() - t0
                line = next((l for l in r.stdout.splitlines() if l.startswith("BENCH ")), None)
                if r.returncode != 0 or line is None:
                    print(f"[bench] {part} {solver} on {np_} rank(s) failed ({wall:.1f} s):\n{r.stdout}\n{r.stderr}")
                    results.append({"part": part, "solver": solver, "ranks": np_, "error": (r.stderr or r.stdout)[-2000:]})
                    continue
                res = json.loads(line[6:])
                res["part"] = part
                res["process_wall_s"] = wall
                results.append(res)
                mine.append(res)
                print(f"[bench] {part} {solver:8s} np={np_}: {res['free_dofs']} free DOFs, nnz(K) {res['nnz_K']}, "
                      f"{res['retained_dofs']} retained DOFs + {res['modes']} modes: import {res['import_s']:.2f} s, "
                      f"factor {res['factor_s']:.2f} s, constraint modes {res['constraint_s']:.2f} s, "
                      f"eigen {res['eigen_s']:.2f} s, projection {res['project_s']:.2f} s, reduction {res['reduction_s']:.2f} s, "
                      f"total {res['total_s']:.2f} s (CPU {res['cpu_s_max']:.1f} s, largest rank; "
                      f"{res['eigen_solves']} shift-invert vectors in {res['eigen_operator_s']:.2f} s of the eigen solve); "
                      f"peak memory {res['maxrss_mb_max']:.0f} MB (largest rank), {res['maxrss_mb_sum']:.0f} MB (all ranks)"
                      + (f"; {res['iterations']} CG iterations" if res["iterations"] else "")
                      + "; f1..f3 = " + ", ".join(f"{f:.7g}" for f in res["f_hz"][:3]) + " Hz")
        for r in mine[1:]:
            ref = mine[0]["f_hz"]
            d = max(abs(x - y) / y for x, y in zip(r["f_hz"], ref))
            print(f"[bench] {part} {r['solver']} np={r['ranks']}: largest relative difference of the first {len(ref)} "
                  f"reduced frequencies to {mine[0]['solver']} np={mine[0]['ranks']}: {d:.2e}")
    with open(os.path.join(a.workdir, "bench_reduction.json"), "w") as f:
        json.dump(results, f, indent=1)
    print("PASSED (figures only)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
