#!/usr/bin/env python3
"""Imported models in decks (Bodies/<b>/Mesh/Type CalculiX, Matrix Market, code_aster).

A small twisted C3D20 plate (blade_model.py) goes through ccx twice: *FREQUENCY, SOLVER=MATRIXSTORAGE
(K, M, DOF map) and *FREQUENCY, STORAGE=YES (ccx's own eigenvalues, as binary doubles in freq.eig).
Checked:
  1. a CalculiX deck runs (epaphe-run), and a second run reuses the cached reduced model;
  2. a changed matrix file (M scaled by 4) recomputes it, and the frequencies halve;
  3. the full-model frequencies of the import agree with ccx's eigenvalues to 1e-6 relative: ccx's
     .eig file holds them in double precision (the .dat prints 7 digits, a rounding of up to 5e-7;
     the .dat values are checked against the .eig ones to that rounding);
  4. epaphe-modes: the error of the first frequencies falls as fixed-interface modes are added, and
     every reduced frequency is an upper bound;
  5. the same matrices as Matrix Market and code_aster files give the same reduced frequencies (1e-8);
  6. Belos CG (Jacobi) gives the MUMPS full and reduced frequencies to 1e-8 (a built-in clamped bar);
  7. deck errors name the key, the value and the file (missing file, Clamped node set on an
     import, a key of another importer).
"""
import argparse
import csv
import os
import re
import shutil
import struct
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
BLADE = os.path.join(HERE, "..", "benchmark", "blade_model.py")

DECK = """<ParameterList name="Epaphe">
  <ParameterList name="Bodies">
    <ParameterList name="Blade">
      <ParameterList name="Mesh">
{mesh}
      </ParameterList>
{extra}
      <ParameterList name="Reduction">
        <Parameter name="Retained node set" type="string" value="TIP16"/>
        <Parameter name="Fixed-interface modes" type="int" value="10"/>
        <Parameter name="Frequency check" type="int" value="10"/>
        <Parameter name="Linear solver" type="string" value="{solver}"/>
      </ParameterList>
    </ParameterList>
  </ParameterList>
  <ParameterList name="Time">
    <Parameter name="Time step" type="double" value="1e-8"/>
    <Parameter name="End time" type="double" value="1e-7"/>
    <Parameter name="Allow unstable time step" type="bool" value="true"/>
  </ParameterList>
  <ParameterList name="Output">
    <Parameter name="File" type="string" value="{output}"/>
  </ParameterList>
</ParameterList>
"""


def param(name, value):
    return f'        <Parameter name="{name}" type="string" value="{value}"/>'


def write_deck(path, mesh, output, solver="MUMPS", extra=""):
    with open(path, "w") as f:
        f.write(
            DECK.format(mesh="\n".join(param(k, v) for k, v in mesh.items()), extra=extra, output=output, solver=solver)
        )
    return path


def run(cmd, cwd, expect=0):
    r = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True)
    if r.returncode != expect:
        print(f"$ {' '.join(cmd)}\n{r.stdout}\n{r.stderr}")
        raise SystemExit(f"FAILED: exit code {r.returncode}, expected {expect}")
    return r.stdout + r.stderr


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--run", required=True)
    p.add_argument("--modes", required=True)
    p.add_argument("--ccx", required=True)
    p.add_argument("--workdir", required=True)
    a = p.parse_args()
    w = a.workdir
    shutil.rmtree(w, ignore_errors=True)
    os.makedirs(w)
    failures = []
    model = os.path.join(w, "model")
    subprocess.run(
        [
            sys.executable,
            BLADE,
            model,
            "--cells",
            "6",
            "15",
            "1",
            "--modes",
            "10",
            "--run",
            a.ccx,
            "--freq",
            "--storage",
        ],
        check=True,
    )

    # 1. a CalculiX deck runs; the second run reuses the reduced model.
    ccx = {"Type": "CalculiX", "Input file": "model/mat.inp"}
    deck = write_deck(os.path.join(w, "ccx.xml"), ccx, "ccx.h5")
    out1 = run([a.run, deck], w)
    out2 = run([a.run, deck], w)
    print(out1)
    if "reused from" in out1 or "reused from" not in out2:
        failures.append("the second run of the CalculiX deck did not reuse the cached reduced model")

    # 3. frequencies of the import against ccx's own eigenvalues.
    with open(os.path.join(model, "freq.eig"), "rb") as f:
        b = f.read()
    nev = struct.unpack("4i", b[:16])[3]
    lam_eig = struct.unpack(f"{nev}d", b[16 : 16 + 8 * nev])
    lam_dat = []
    with open(os.path.join(model, "freq.dat")) as f:
        txt = f.read()
    block = txt.split("E I G E N V A L U E   O U T P U T")[1]
    for line in block.splitlines():
        m = re.match(r"\s+(\d+)\s+(\S+)\s+\S+\s+\S+\s+\S+\s*$", line)
        if m:
            lam_dat.append(float(m.group(2)))
        elif lam_dat:
            break
    dat_vs_eig = max(abs(x - y) / y for x, y in zip(lam_dat, lam_eig))
    if len(lam_dat) != nev or dat_vs_eig > 5e-7:
        failures.append(f"freq.eig does not hold the .dat eigenvalues ({len(lam_dat)} vs {nev}, {dat_vs_eig:.1e})")
    table = os.path.join(w, "modes.csv")
    out = run([a.modes, deck, "--modes", "0,2,5,10,20", "--count", "10", "--csv", table], w)
    print(out)
    rows = read_csv(table)
    full = [float(r["full_hz"]) for r in rows if r["modes"] == "0"]
    import math

    lam = [(2 * math.pi * f) ** 2 for f in full]
    worst = max(abs(x - y) / y for x, y in zip(lam, lam_eig))
    print(
        f"full-model eigenvalues of the import against ccx's (freq.eig, double precision), {len(lam)} modes: "
        f"largest relative difference {worst:.2e} (.dat rounding: {dat_vs_eig:.1e})"
    )
    if worst > 1e-6:
        failures.append(f"imported eigenvalues differ from ccx's by {worst:.2e} > 1e-6")

    # 4. convergence with the mode count: the largest error over the first 5 frequencies falls.
    counts = sorted({int(r["modes"]) for r in rows})
    worst_by = []
    for n in counts:
        err = [float(r["relative_error"]) for r in rows if int(r["modes"]) == n]
        if min(err) < -1e-9:
            failures.append(f"{n} modes: a reduced frequency is below the full one ({min(err):.2e})")
        worst_by.append(max(err[:5]))
    print(
        "largest error of the first 5 frequencies by mode count: "
        + ", ".join(f"{n}: {e:.2e}" for n, e in zip(counts, worst_by))
    )
    if not all(worst_by[i + 1] < worst_by[i] for i in range(len(worst_by) - 1)):
        failures.append(f"the error does not fall with the mode count: {worst_by}")

    # 5. the same matrices as Matrix Market and code_aster files.
    dofs = [tuple(map(int, l.strip().split("."))) for l in open(os.path.join(model, "mat.dof")) if l.strip()]
    nodes, sets, mode = [], {}, None
    for line in open(os.path.join(model, "mesh.inp")):
        s = line.strip()
        if s.startswith("*"):
            mode = "node" if s.upper().startswith("*NODE") else None
            if s.upper().startswith("*NSET"):
                mode = s.split("=")[1].strip()
                sets[mode] = []
            continue
        if mode == "node":
            nodes.append(s)
        elif mode:
            sets[mode] += [int(x) for x in s.split(",") if x.strip()]
    n = len(dofs)
    for name in ("sti", "mas"):
        ent = [l.split() for l in open(os.path.join(model, "mat." + name)) if l.strip()]
        with open(os.path.join(w, name + ".mtx"), "w") as f:
            f.write(f"%%MatrixMarket matrix coordinate real symmetric\n{n} {n} {len(ent)}\n")
            for i, j, v in ent:  # ccx: upper triangle; Matrix Market symmetric: lower
                f.write(f"{j} {i} {v}\n")
        with open(os.path.join(w, name + ".aster"), "w") as f:
            for i, j, v in ent:
                f.write(f"{i} {j} {v}\n")
    with open(os.path.join(w, "dofs.mm"), "w") as f:
        f.writelines(f"{nd} {d}\n" for nd, d in dofs)
    with open(os.path.join(w, "dofs.aster"), "w") as f:
        f.writelines(f"N{nd} D{'XYZ'[d - 1]}\n" for nd, d in dofs)
    with open(os.path.join(w, "nodes.txt"), "w") as f:
        f.writelines(" ".join(x.strip() for x in s.split(",")) + "\n" for s in nodes)
    with open(os.path.join(w, "sets.txt"), "w") as f:
        f.write("TIP16 " + " ".join(map(str, sets["TIP16"])) + "\n")
    files = {"Mass file": "mas", "Stiffness file": "sti"}
    mm = dict(
        {"Type": "Matrix Market", "DOF file": "dofs.mm", "Node file": "nodes.txt", "Node set file": "sets.txt"},
        **{k: v + ".mtx" for k, v in files.items()},
    )
    aster = dict(
        {"Type": "code_aster", "DOF file": "dofs.aster", "Node file": "nodes.txt", "Node set file": "sets.txt"},
        **{k: v + ".aster" for k, v in files.items()},
    )
    ref = [float(r["reduced_hz"]) for r in rows if r["modes"] == "10"]
    for label, mesh, solver in (("Matrix Market", mm, "MUMPS"), ("code_aster", aster, "MUMPS")):
        tag = re.sub(r"\W+", "-", label)
        d = write_deck(os.path.join(w, tag + ".xml"), mesh, tag + ".h5", solver)
        t = os.path.join(w, tag + ".csv")
        print(run([a.modes, d, "--modes", "10", "--count", "10", "--csv", t], w))
        got = [float(r["reduced_hz"]) for r in read_csv(t)]
        diff = max(abs(x - y) / y for x, y in zip(got, ref))
        tol = 1e-8  # the fixed-interface modes converge to Anasazi's 1e-10 residual, not to round-off
        print(
            f"{label}: reduced frequencies (10 modes) against the CalculiX deck with MUMPS: largest relative "
            f"difference {diff:.2e} (tolerance {tol:g})"
        )
        if diff > tol or len(got) != len(ref):
            failures.append(f"{label}: reduced frequencies differ from the CalculiX deck's by {diff:.2e}")

    # 6. Belos CG (Jacobi) against MUMPS, on a built-in clamped bar (Jacobi-CG on the thin C3D20
    # plate needs tens of thousands of iterations per solve: see the benchmark).
    box = {"Type": "Box", "Lengths": "{0.1, 0.02, 0.02}", "Elements": "{16, 3, 3}"}
    clamp = '      <Parameter name="Clamped node set" type="string" value="x-"/>'
    got = {}
    for solver in ("MUMPS", "Belos CG"):
        tag = solver.replace(" ", "-")
        d = write_deck(os.path.join(w, f"box-{tag}.xml"), box, f"box-{tag}.h5", solver, clamp)
        with open(d) as f:
            txt = f.read().replace('value="TIP16"', 'value="x+"')
        txt = txt.replace('type="string" value="{0.1, 0.02, 0.02}"', 'type="Array(double)" value="{0.1, 0.02, 0.02}"')
        txt = txt.replace('type="string" value="{16, 3, 3}"', 'type="Array(int)" value="{16, 3, 3}"')
        with open(d, "w") as f:
            f.write(txt)
        t = os.path.join(w, f"box-{tag}.csv")
        print(run([a.modes, d, "--modes", "10", "--count", "10", "--csv", t], w))
        got[solver] = [(float(r["full_hz"]), float(r["reduced_hz"])) for r in read_csv(t)]
    diff = max(max(abs(x[0] - y[0]) / y[0], abs(x[1] - y[1]) / y[1]) for x, y in zip(got["Belos CG"], got["MUMPS"]))
    print(
        f"Belos CG against MUMPS (clamped bar, 10 modes): largest relative difference of the full and reduced "
        f"frequencies {diff:.2e} (tolerance 1e-8)"
    )
    if diff > 1e-8 or len(got["Belos CG"]) != 10:
        failures.append(f"Belos CG and MUMPS differ by {diff:.2e}")

    # 2. a changed file recomputes: M scaled by 4 halves every frequency.
    with open(os.path.join(model, "mat.mas")) as f:
        lines = f.readlines()
    with open(os.path.join(model, "mat.mas"), "w") as f:
        for l in lines:
            i, j, v = l.split()
            f.write(f"{i} {j} {4 * float(v):.17g}\n")
    out3 = run([a.run, deck], w)
    if "reused from" in out3:
        failures.append("a changed mat.mas did not recompute the reduced model")
    import h5py

    with h5py.File(os.path.join(w, "ccx.h5"), "r") as f:
        f1 = f["/bodies/Blade/frequencies/full"][0]
    if abs(f1 / full[0] - 0.5) > 1e-9:
        failures.append(f"after M x 4 the first frequency is {f1} Hz, expected {full[0] / 2}")
    else:
        print(f"mat.mas changed (M x 4): recomputed, f1 {full[0]:.6g} -> {f1:.6g} Hz")

    # 7. errors name the key, the value and the file.
    bad = [
        (
            {"Type": "CalculiX", "Input file": "model/missing.inp"},
            "",
            ["Input file", "missing.inp", "relative to the deck"],
        ),
        (
            ccx,
            '      <Parameter name="Clamped node set" type="string" value="ROOT"/>',
            ["Clamped node set", "ROOT", "carries its own boundary conditions"],
        ),
        (dict(ccx, **{"Node file": "nodes.txt"}), "", ["Node file", "nodes.txt", "not read by Mesh Type CalculiX"]),
        ({"Type": "Matrix Market", "Stiffness file": "sti.mtx"}, "", ["Mass file", "is empty", "Matrix Market"]),
        ({"Type": "CalculiX", "Input file": "model/freq.inp"}, "", ["Matrix job", "freq.sti", "MATRIXSTORAGE"]),
    ]
    for k, (mesh, extra, words) in enumerate(bad):
        d = write_deck(os.path.join(w, f"bad{k}.xml"), mesh, f"bad{k}.h5", extra=extra)
        msg = run([a.run, d], w, expect=1)
        if not all(x in msg for x in words + [f"bad{k}.xml"]):
            failures.append(f"bad deck {k}: the message lacks one of {words}: {msg.strip()}")
        else:
            print(f"bad deck {k}: {msg.strip()}")
    print("FAILED:\n  " + "\n  ".join(failures) if failures else "PASSED")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
