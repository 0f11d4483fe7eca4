#!/usr/bin/env python3
"""Whole runs on 2 MPI ranks against 1: the reduced models and every record of the history.

Usage:
    ranks.py --run EPAPHE_RUN --mpiexec MPIEXEC --inputs DIR --workdir DIR
             [--deck NAME ...] [--exclude NAME ...] [--ranks P]

On P MPI ranks (default 2) the reduction is distributed: Tpetra maps split the full model, MUMPS
factors it in parallel, Anasazi finds the fixed-interface (or normal) modes on distributed vectors;
rank 0 then runs the explicit loop alone on the reduced model it gathered. Each deck (--deck, else
every deck of --inputs but those of --exclude) runs as regression.gold runs it (gold.py's horizon,
HORIZON), 1 thread per rank, once on 1 rank and once on P ranks, each reduction made afresh (its
cache file deleted before the run, then written by the run so that it can be read here). Compared:

- the reduced model of every body: K, M, the recovery R and the kept modes' frequencies, and for a
  massless boundary G, Phi_b and Phi^T M e_d, as max |x_P - x_1| / max |x_1| per matrix, once the
  P-rank modes are expressed in the 1-rank basis: an eigenvector's sign is arbitrary, and so is the
  basis of a repeated eigenvalue's space (the square bars' bending pairs), so per cluster of modes
  whose frequencies lie within CLUSTER of each other the orthogonal map that best carries the P-rank
  shapes onto the 1-rank ones is applied (Procrustes on R's columns; for a lone mode its sign). The
  highest cluster is left out of the matrices (its frequencies are compared): the truncation can
  split a repeated eigenvalue, keeping one vector of its pair, and then which one is arbitrary
  (two-bars: the 100th mode, 37076 Hz, is half of a bending pair, and 1 and 2 ranks keep vectors
  0.43 of the largest entry apart; the casing of blade-flexible-casing, its 10th mode, 2.7e-7). The
  largest difference over matrices and bodies must stay within MODEL_TOL;
- the whole history, every record of every dataset that is a result (what gold.py compares before
  its down-sampling: /time, energies, momenta, node sets, contact gaps and forces, frequencies) and
  the run summary's contact line, the same number of records: |x_P - x_1| <= atol x scale +
  rtol x |x_1| with gold.py's tolerances of the dataset's kind (TOLERANCES, FLOORS), the scale the
  dataset's largest |x_1|. Why those, below (HISTORY).

Measured (every deck of inputs/ but blade-casing-at-speed, 2 ranks against 1, once the modes are
aligned): the reduced models differ by at most 1.2e-10 of their largest entry (the recovery of
blade-flexible-casing's casing; K 2.1e-11, the massless boundary's, M 2.5e-12, the frequencies
4e-13), the histories by at most 1.6e-8 of their scale (two-bars' end velocity; blade-casing's contact
force 1.5e-8), 0.05 of gold.py's bound at most. blade-casing-at-speed (a parametric model, whose
basis is not compared) differs by 2.1e-8 to 6.9e-8 of its contact force's scale over its horizon
of one revolution, 0.06 of the bound at most; the difference grows with the number of contacts
(to 1.1e-6 to 1.4e-6 over the deck's 20 revolutions, past the bound: round-off, not a defect,
which is why every deck is compared over its gold horizon and not its full length). Two runs
on 2 ranks are not bit for bit the same either (their reduced models 1e-14 apart, measured on
blade-casing; on 1 rank, 0), so their differences from 1 rank vary a little from run to run.
"""
import argparse
import glob
import os
import re
import subprocess
import sys
import time

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import gold  # noqa: E402  (the horizons, what a result is, its kind, floor and tolerance)
from epaphe_testing import variant  # noqa: E402  (gold put tests/verification on the path)

# ---- tolerances ------------------------------------------------------------------------------------
# The reduced model on P ranks is not the 1-rank one up to round-off: Anasazi's Krylov-Schur iterates
# differ from the first inner product on (another summation order over the ranks' pieces; so on 2
# threads), and it stops once every Ritz pair's relative residual is below 1e-10
# (CraigBamptonOptions::eigenTolerance): its vectors are that converged, not more. The eigenvalues are
# then exact to round-off (their error goes as the residual squared: measured 5e-14), the
# eigenvectors to about the residual over the relative gap to the nearest frequency outside their
# cluster: 1e-10 / CLUSTER = 1e-7 at most. That is MODEL_TOL. The same difference, and only it,
# separates 1 and 2 threads (measured on cube-rings: the 2-thread reduction's recovery 2.1e-10 from
# the 1-thread one; the loop on 2 threads from the 1-thread reduced model gives the 1-thread history
# bit for bit but for the energies' and momenta's order of summation, faults.restart-2threads).
CLUSTER = 1e-3
MODEL_TOL = 1e-7
# ...but for a body whose modes the bound above does not hold for, measured: stage-flexible-casing's
# casing, a shell 3 mm thick at 0.3 m radius whose 28 modes are 14 double pairs 1-7 % apart: once
# aligned per pair, its modes on 2 ranks differ by 1.2e-7 to 4.2e-7 of the recovery's largest entry
# (its static columns by 7.6e-8), where residual / gap would give 1e-8 (the shell's conditioning);
# the histories differ by 0.004 of gold.py's bound at most
MODEL_TOL_OF = {("stage-flexible-casing", "Casing"): 1e-6}
# HISTORY: the run responds to that model difference as it does on 2 threads, which gold.py's
# tolerances were set on (77-170 times the 1- against 2-thread differences): the same per kind.
# Measured per kind, 2 ranks against 1 over every deck but blade-casing-at-speed (largest |diff| /
# scale; gold.py's atol): displacement 4.9e-10 (3e-8), velocity 1.6e-8 (3e-7), momentum 2.1e-9 (3e-7),
# gap 9.7e-10 (3e-8), force 1.5e-8 (1e-6), energy 1.4e-9 (3e-8), balance 1.2e-10 (1e-8), frequency
# 1.2e-10 (1e-8), time and the summary's contact line 0.
RUN_TIMEOUT = 240  # s per run; the slowest (cube-flexible-rings on 2 ranks) takes 10-20 s on a loaded machine


def run(cmd, cwd, env):
    try:
        p = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, env=env, timeout=RUN_TIMEOUT)
    except subprocess.TimeoutExpired:
        raise RuntimeError(f"no exit within {RUN_TIMEOUT} s (killed): {' '.join(cmd)} (in {cwd})")
    if p.returncode != 0:
        raise RuntimeError(
            f"exit code {p.returncode}: {' '.join(cmd)} (in {cwd})\n" f"{p.stdout[-3000:]}{p.stderr[-3000:]}"
        )
    return p


def run_deck(a, deck, name, ranks):
    """One run of the deck on `ranks` ranks, its reductions made afresh: (output, stdout, {body: cache file}, s)."""
    tag = f"{name}.np{ranks}"
    over = gold.overrides_for(name, deck)
    over["Output->File"] = (f"{tag}.h5", "string")
    caches = {}
    for b in gold.body_names(deck):
        caches[b] = os.path.join(a.workdir, f"{tag}.{re.sub(r'[^A-Za-z0-9]+', '_', b)}.rom.h5")
        over[f"Bodies->{b}->Reduction->Cache"] = ("true", "bool")
        over[f"Bodies->{b}->Reduction->Cache file"] = (caches[b], "string")
    path = variant(deck, os.path.join(a.workdir, f"{tag}.xml"), over)
    out = os.path.join(a.workdir, f"{tag}.h5")
    for f in [out] + list(caches.values()):
        if os.path.exists(f):
            os.remove(f)
    env = dict(os.environ, OMP_NUM_THREADS="1", OMP_PROC_BIND="false", OPENBLAS_NUM_THREADS="1")
    launcher = [a.mpiexec, "-n", str(ranks)] if ranks > 1 else []
    t0 = time.monotonic()
    p = run(launcher + [a.run, path, "--threads", "1"], a.workdir, env)
    return out, p.stdout, caches, time.monotonic() - t0


def read_model(path):
    with h5py.File(path, "r") as f:
        m = {
            k: f[k][()]
            for k in (
                "K",
                "M",
                "recovery",
                "boundaryModes",
                "residualFlexibility",
                "modalTranslation",
                "modeFrequencies",
                "staticDisplacement",
            )
            if k in f
        }
        m["size"], m["modes"] = int(f.attrs["size"]), int(f.attrs["modes"])
    return m


def clusters(freqs):
    """Runs of modes (in their stored, ascending order) each within CLUSTER of the next."""
    out, start = [], 0
    for j in range(1, len(freqs) + 1):
        if j == len(freqs) or abs(freqs[j] - freqs[j - 1]) > CLUSTER * max(abs(freqs[j]), 1e-300):
            out.append(list(range(start, j)))
            start = j
    return out


def model_difference(m1, m2):
    """{matrix: max |x2 - x1| / max |x1|} once m2's modes are expressed in m1's basis: q2 = T q1,
    T = diag(I, Q), Q per cluster of modes the orthogonal map that best carries m2's mode shapes
    (R's columns) onto m1's; the highest cluster's rows and columns left out (see the docstring)."""
    n, nm = m1["size"], m1["modes"]
    if (m2["size"], m2["modes"]) != (n, nm) or m1["modeFrequencies"].shape != m2["modeFrequencies"].shape:
        return {"size": np.inf}
    nb = n - nm
    r1, r2 = m1["recovery"].reshape(-1, n), m2["recovery"].reshape(-1, n)
    if len(m1["modeFrequencies"]) != nm:
        # not a basis of eigenvectors (a parametric model's, made of several reductions): MODEL_TOL's
        # reasoning does not hold, and only what is basis-free is compared here (its history below)
        return {
            k: (
                float(np.max(np.abs(m2[k] - m1[k])) / max(float(np.max(np.abs(m1[k]))), 1e-300))
                if m2.get(k, np.empty(0)).shape == m1[k].shape
                else np.inf
            )
            if m1[k].size
            else 0.0
            for k in ("modeFrequencies", "staticDisplacement")
            if k in m1
        }
    groups = clusters(m1["modeFrequencies"])
    Q = np.eye(nm)
    for c in filter(None, groups):
        u, _, vt = np.linalg.svd(r2[:, [nb + j for j in c]].T @ r1[:, [nb + j for j in c]])
        Q[np.ix_(c, c)] = u @ vt
    T = np.eye(n)
    T[nb:, nb:] = Q
    keep_modes = [j for c in groups[:-1] for j in c]
    keep = list(range(nb)) + [nb + j for j in keep_modes]
    K2, M2 = m2["K"].reshape(n, n), m2["M"].reshape(n, n)  # symmetric: the storage order does not matter
    aligned = {
        "K": (T.T @ K2 @ T)[np.ix_(keep, keep)],
        "M": (T.T @ M2 @ T)[np.ix_(keep, keep)],
        "recovery": (r2 @ T)[:, keep],
    }
    ref = {
        "K": m1["K"].reshape(n, n)[np.ix_(keep, keep)],
        "M": m1["M"].reshape(n, n)[np.ix_(keep, keep)],
        "recovery": r1[:, keep],
    }
    if m1.get("boundaryModes", np.empty(0)).size:  # Phi_b (nb x nm) and Phi^T M e_d (nm x 3), column-major
        aligned["boundaryModes"] = (Q.T @ m2["boundaryModes"].reshape(nm, nb))[keep_modes]
        ref["boundaryModes"] = m1["boundaryModes"].reshape(nm, nb)[keep_modes]
        aligned["modalTranslation"] = (m2["modalTranslation"].reshape(3, nm) @ Q)[:, keep_modes]
        ref["modalTranslation"] = m1["modalTranslation"].reshape(3, nm)[:, keep_modes]
        aligned["residualFlexibility"] = m2["residualFlexibility"]
        ref["residualFlexibility"] = m1["residualFlexibility"]
    for k in ("modeFrequencies", "staticDisplacement"):  # basis-free
        if k in m1:
            aligned[k], ref[k] = m2.get(k, np.full(1, np.inf)), m1[k]
    return {
        k: (
            float(np.max(np.abs(aligned[k] - x1)) / max(float(np.max(np.abs(x1))), 1e-300))
            if aligned[k].shape == x1.shape
            else np.inf
        )
        if x1.size
        else 0.0
        for k, x1 in ref.items()
    }


def results(path, stdout):
    """Every dataset of the history that is a result, whole, and the summary's contact line."""
    out = {}
    with h5py.File(path, "r") as f:
        status = f.attrs["status"]
        status = status.decode() if isinstance(status, bytes) else str(status)
        if status != "complete":
            raise RuntimeError(f"{path}: status '{status}', not complete")

        def visit(name, obj):
            if (
                isinstance(obj, h5py.Dataset)
                and obj.dtype.kind == "f"
                and not gold.IGNORE.search(name)
                and gold.kind_of(name) is not None
            ):
                out[name] = obj[()]

        f.visititems(visit)
    for i, fields in enumerate(gold.SUMMARY.findall(stdout)):
        for k, v in zip(("first_contact", "last_contact", "max_force", "impulse"), fields):
            out[f"summary/{i}/{k}"] = np.array([float(v)])
    return out


def compare_histories(name, h1, h2, ranks, worst):
    """Failure lines; `worst` {kind: [largest |diff| / scale, its share of the bound, dataset]} updated."""
    failures = []
    if sorted(h1) != sorted(h2):
        failures.append(
            f"{name}: datasets differ: only on 1 rank {sorted(set(h1) - set(h2))}, only on {ranks} "
            f"ranks {sorted(set(h2) - set(h1))}"
        )
    times = np.asarray(h1.get("time", []))
    for k in sorted(set(h1) & set(h2)):
        x1, x2 = np.asarray(h1[k], float), np.asarray(h2[k], float)
        if x1.shape != x2.shape:
            failures.append(
                f"{name}: {k}: shape {x2.shape} on {ranks} ranks, {x1.shape} on 1 (records: "
                f"{len(h2.get('time', []))} and {len(times)})"
            )
            continue
        if not x1.size:
            continue
        kind = gold.kind_of(k)
        if kind == "frequency":  # rigid-body modes: zero up to round-off (gold.py's criterion)
            x1 = np.where(x1 < 1e-4 * x1.max(), 0.0, x1)
            x2 = np.where(x2 < 1e-4 * x2.max(), 0.0, x2)
        atol, rtol = gold.TOLERANCES[kind]
        scale = gold.scale_of(kind, x1)
        err = np.abs(x2 - x1)
        err[~np.isfinite(x2)] = np.inf
        bound = atol * scale + rtol * np.abs(x1)
        share = err / np.maximum(bound, 1e-300)
        i = np.unravel_index(int(np.argmax(share)), share.shape)
        w = worst.setdefault(kind, [0.0, 0.0, ""])
        w[0] = max(w[0], float(np.max(err)) / scale)
        if share[i] > w[1]:
            w[1], w[2] = float(share[i]), f"{name}: {k}"
        if share[i] > 1.0:
            at = (
                f"record {i[0]} (t = {times[i[0]]:.6e} s)"
                if kind not in ("summary", "frequency") and len(times) == x1.shape[0]
                else f"entry {i[0]}"
            )
            entry = f", entry {tuple(int(j) for j in i[1:])}" if len(i) > 1 else ""
            failures.append(
                f"{name}: {k} [{kind}]: {at}{entry}: "
                f"{x2[i]:.9e} on {ranks} ranks against {x1[i]:.9e} on 1, |diff| {err[i]:.3e} > bound "
                f"{bound[i]:.3e} (atol {atol:g} x scale {scale:.3e} + rtol {rtol:g} x |x_1|), "
                f"{share[i]:.3g} x the bound; {int(np.sum(share > 1.0))} of {share.size} entries out"
            )
    return failures


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--run", required=True, help="build/drivers/epaphe-run")
    ap.add_argument("--mpiexec", required=True)
    ap.add_argument("--inputs", required=True, help="the decks' directory (inputs/)")
    ap.add_argument("--workdir", required=True)
    ap.add_argument("--deck", action="append", help="only this deck (name without .xml; repeatable)")
    ap.add_argument("--exclude", action="append", default=[], help="every deck but this one (repeatable)")
    ap.add_argument("--ranks", type=int, default=2)
    a = ap.parse_args()
    a.run, a.workdir = os.path.abspath(a.run), os.path.abspath(a.workdir)
    os.makedirs(a.workdir, exist_ok=True)
    decks = {os.path.splitext(os.path.basename(d))[0]: d for d in glob.glob(os.path.join(a.inputs, "*.xml"))}
    unknown = sorted((set(a.deck or []) | set(a.exclude)) - set(decks))
    if unknown:
        print(f"FAILED: {', '.join(unknown)}: no such deck in {a.inputs} (decks: {', '.join(sorted(decks))})")
        return 1
    names = a.deck or sorted(set(decks) - set(a.exclude))
    failures, worst, worst_model, total0 = [], {}, [0.0, ""], time.monotonic()
    for name in names:
        try:
            o1, s1, c1, t1 = run_deck(a, decks[name], name, 1)
            o2, s2, c2, t2 = run_deck(a, decks[name], name, a.ranks)
            h1, h2 = results(o1, s1), results(o2, s2)
        except RuntimeError as e:
            failures.append(f"{name}: {e}")
            print(f"{name}: FAIL (the run)")
            continue
        fails = []
        for b in c1:
            if not (os.path.exists(c1[b]) and os.path.exists(c2[b])):
                continue  # nothing reduced (full model, lumped mass): no cache written
            d = model_difference(read_model(c1[b]), read_model(c2[b]))
            k = max(d, key=d.get)
            print(
                f"{name}: body '{b}': reduced model, {a.ranks} ranks against 1, max |diff| / max |x|: "
                + ", ".join(f"{m} {v:.1e}" for m, v in d.items())
                + ("" if "K" in d else " (its basis is not one of eigenvectors: K, M and R not compared)")
            )
            if d[k] > worst_model[0]:
                worst_model[:] = [d[k], f"{name}: '{b}' {k}"]
            tol = MODEL_TOL_OF.get((name, b), MODEL_TOL)
            if not d[k] <= tol:
                fails.append(
                    f"{name}: body '{b}': the reduced model on {a.ranks} ranks differs from the 1-rank one by "
                    f"{d[k]:.3g} of its largest entry in {k} (> its bound {tol:g}, MODEL_TOL or MODEL_TOL_OF; "
                    f"modes aligned per cluster of frequencies within {CLUSTER:g})"
                )
        deck_worst = {}
        fails += compare_histories(name, h1, h2, a.ranks, deck_worst)
        for kind, w in deck_worst.items():
            g = worst.setdefault(kind, [0.0, 0.0, ""])
            g[0] = max(g[0], w[0])
            if w[1] >= g[1]:
                g[1], g[2] = w[1], w[2]
        failures += fails
        report = ", ".join(f"{k} {w[0]:.1e} ({w[1]:.2g} of bound)" for k, w in sorted(deck_worst.items()))
        print(
            f"{name}: {'FAIL' if fails else 'ok'}: 1 rank {t1:.1f} s, {a.ranks} ranks {t2:.1f} s, "
            f"{len(h1.get('time', []))} records; largest |diff|/scale per kind: {report}"
        )
    print(
        f"largest reduced-model difference {worst_model[0]:.2e} ({worst_model[1]}); per kind, largest |diff|/scale "
        f"and largest share of the bound: "
        + ", ".join(f"{k} {w[0]:.1e}, {w[1]:.2g} ({w[2]})" for k, w in sorted(worst.items()))
    )
    print(f"total {time.monotonic() - total0:.1f} s")
    print("FAILED:\n  " + "\n  ".join(failures) if failures else "PASSED")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
