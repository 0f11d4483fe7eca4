#!/usr/bin/env python3
"""Issue 31, item 4: CalculiX at speed. The built-in blade of inputs/blade-casing.xml written as a
CalculiX deck (rotating_blade_ccx.py's machinery: C3D8, the same mesh and clamp), ccx run at the
sample speeds SAMPLES with the centrifugal static step (*DLOAD CENTRIF, NLGEOM, *NODE PRINT U) and a
perturbation step *FREQUENCY, SOLVER=MATRIXSTORAGE; Epaphe imports the jobs (Rotation->Imported
speeds, Imported jobs) and builds the parametric model over {first, last}. The reference at a speed is
ccx's own perturbation step there (*STEP, PERTURBATION / *FREQUENCY, the same tangent as the stored
matrices, K_u included) and ccx's static displacement.

Asserted (stated before measuring):
  * at the samples, the reduced model's first MODES frequencies equal those of a direct Craig-Bampton
    reduction of the same imported matrices (Epaphe at rest on the job's K(Omega), M) within
    AT_SAMPLE = 1e-6 relative: the interpolation is exact at the samples;
  * at the samples, the direct import's full-model frequencies ('Frequency check') equal ccx's
    perturbation frequencies within SAME = 1e-5 (the same matrices; ccx prints 7 digits);
  * at the intermediate speed MIDDLE, the parametric model's frequencies are within BETWEEN = 1e-3 of a
    direct Craig-Bampton reduction of ccx's matrices at MIDDLE, and within FREQ_TOL = 0.5 % of ccx's
    perturbation frequencies there (the reduction's own truncation included);
  * the tip's largest static displacement at MIDDLE (interpolated) within TIP_TOL = 1 % of ccx's;
  * epaphe-campbell on the imported deck: its full-model frequencies at the samples (Campbell points)
    within SAME of ccx's, its curve at MIDDLE the run's reduced model there (1e-9);
  * the cache: a second run reuses the parametric model, a changed job file rebuilds it.
Measured on this blade (10 x 7 x 1 C3D8, 16 tip nodes retained, 20 modes): at the samples 1e-11 against
the direct reduction and 2e-7 between the imported full model and ccx; at 750 rad/s 3.0e-4 (mode 2)
against the direct reduction, 0.076 % against ccx (mostly the reduction's truncation, 0.078 % at the
samples) and 0.23 % on the tip's static displacement (the NLGEOM state is not quite a quadratic in
Omega^2).
Usage: rotating_blade_ccx_import.py --run EPAPHE_RUN --campbell EPAPHE_CAMPBELL --deck inputs/blade-casing.xml
       --ccx CCX --workdir DIR
"""
import argparse
import os
import re
import shutil
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from epaphe_testing import deck_value, variant, verdict  # noqa: E402
import rotating_blade_ccx as rb  # noqa: E402

SAMPLES = (0.0, 500.0, 1000.0)  # rad/s: the imported ccx jobs
MIDDLE = 750.0  # rad/s: between samples, against ccx's direct run there
MODES = 6  # frequencies compared
CB_MODES = 20  # fixed-interface modes of the reduction
AT_SAMPLE = 1e-6
SAME = 1e-5
BETWEEN = 1e-3
FREQ_TOL = 5e-3
TIP_TOL = 1e-2


def ccx_job(a, job, model, speed, store):
    """A ccx run: static centrifugal step (NLGEOM) printing U, then a perturbation step that stores the
    matrices (store) or computes the frequencies."""
    last = "*FREQUENCY, SOLVER=MATRIXSTORAGE\n" if store else f"*FREQUENCY\n{MODES + 4}\n"
    text, d = rb.ccx(
        a,
        job,
        model
        + "*STEP, NLGEOM, INC=100\n*STATIC\n"
        + rb.centrif(speed, [0, 0, 1], [0, 0, 0])
        + "*NODE PRINT, NSET=NALL\nU\n*END STEP\n*STEP, PERTURBATION\n"
        + last
        + "*END STEP\n",
    )
    return text, d


def imported_deck(a, name, speed, matrix_job, imported, check):
    text = open(a.deck).read()
    text = re.sub(
        r'<ParameterList name="Mesh">.*?</ParameterList>',
        '<ParameterList name="Mesh"><Parameter name="Type" type="string" value="CalculiX"/>'
        '<Parameter name="Input file" type="string" value="ccx/model.inp"/>'
        f'<Parameter name="Matrix job" type="string" value="ccx/{matrix_job}"/></ParameterList>',
        text,
        count=1,
        flags=re.S,
    )
    text = re.sub(r'<ParameterList name="Material">.*?</ParameterList>', "", text, count=1, flags=re.S)
    text = re.sub(r'<Parameter name="Clamped node set"[^>]*/>', "", text, count=1)
    base = os.path.join(a.workdir, name + "-base.xml")
    open(base, "w").write(text)
    over = {
        "Bodies->Blade->Reduction->Fixed-interface modes": (str(CB_MODES), "int"),
        "Bodies->Blade->Reduction->Frequency check": (str(check), "int"),
        "Bodies->Blade->Reduction->Cache": ("false", "bool"),
        "Surfaces->Casing->Radius": (f"{a.tip_radius + 0.01:.17g}", "double"),
        "Time->End revolutions": ("0", "double"),
        "Time->End time": ("1e-6", "double"),
        "Run->Progress interval": ("0", "double"),
        "Output->File": (name + ".h5", "string"),
    }
    if imported:
        over.update(
            {
                "Bodies->Blade->Rotation->Speed": (f"{speed:.17g}", "double"),
                "Bodies->Blade->Rotation->Speed range": ("{%g, %g}" % (SAMPLES[0], SAMPLES[-1]), "Array(double)"),
                "Bodies->Blade->Rotation->Imported speeds": (
                    "{%s}" % ", ".join(f"{w:g}" for w in SAMPLES),
                    "Array(double)",
                ),
                "Bodies->Blade->Rotation->Imported jobs": (
                    "{%s}" % ", ".join(f"ccx/m{w:g}" for w in SAMPLES),
                    "Array(string)",
                ),
            }
        )
    deck = variant(base, os.path.join(a.workdir, name + ".xml"), over)
    out = rb.sh([a.run, deck], a.workdir, f"epaphe-run {name}")
    with h5py.File(os.path.join(a.workdir, name + ".h5"), "r") as f:
        red = np.array(f["/bodies/Blade/frequencies/reduced"][:MODES])
        full = np.array(f["/bodies/Blade/frequencies/full"][:MODES]) if check else np.zeros(0)
    m = re.search(r"node set 'tip': static displacement up to (\S+) m", out)
    return red, full, (float(m.group(1)) if m else None), out


def main():
    ap = argparse.ArgumentParser()
    for name in ("--run", "--campbell", "--deck", "--ccx", "--workdir"):
        ap.add_argument(name, required=True)
    a = ap.parse_args()
    for k in ("run", "campbell", "deck", "ccx", "workdir"):
        if os.sep in getattr(a, k):
            setattr(a, k, os.path.abspath(getattr(a, k)))
    shutil.rmtree(a.workdir, ignore_errors=True)
    os.makedirs(a.workdir)
    failures = []
    body = "Blade"
    mat = f"Bodies->{body}->Material->"
    material = tuple(float(deck_value(a.deck, mat + k)) for k in ("Density", "Young's modulus", "Poisson's ratio"))
    a.tip_radius = float(deck_value(a.deck, f"Bodies->{body}->Mesh->Tip radius"))
    rest = rb.run_epaphe(a, body, 0.0, np.array([0.0, 0, 1]), np.zeros(3), a.tip_radius)  # the mesh and its sets
    sets = rest["sets"]
    clamped = sorted(int(i) for i in sets[deck_value(a.deck, f"Bodies->{body}->Clamped node set")])
    model = rb.model_text(rest["coords"], rest["hexes"], clamped, material)
    for s in ("tip", "tip-le", "tip-te"):
        nodes = [int(i) + 1 for i in sets[s]]
        model += f"*NSET, NSET={s}\n" + "".join(
            ", ".join(map(str, nodes[k : k + 12])) + ",\n" for k in range(0, len(nodes), 12)
        )
    os.makedirs(os.path.join(a.workdir, "ccx"), exist_ok=True)
    open(os.path.join(a.workdir, "ccx", "model.inp"), "w").write(model)
    n = len(rest["coords"])
    tip = sets["tip"]
    ref = {}
    for w in SAMPLES + (MIDDLE,):
        ccx_job(a, f"m{w:g}", model, w, True)
        text, _ = ccx_job(a, f"f{w:g}", model, w, False)
        u = rb.displacements(text, n)
        ref[w] = dict(freqs=rb.frequencies(text)[:MODES], tip=np.linalg.norm(u[tip], axis=1).max())

    print(
        f"{'speed':>6} {'mode':>4} {'parametric Hz':>14} {'direct CB Hz':>13} {'diff':>9} {'import full':>12} "
        f"{'ccx Hz':>12} {'diff':>9}"
    )
    reduced = {}
    for w in SAMPLES + (MIDDLE,):
        par, _, grow, _ = imported_deck(a, f"par{w:g}", w, "m0", True, 0)
        direct, full, _, _ = imported_deck(a, f"direct{w:g}", w, f"m{w:g}", False, MODES)
        fc = ref[w]["freqs"]
        d_direct = np.abs(par / direct - 1)
        d_same = np.abs(full / fc - 1)
        d_ccx = np.abs(par / fc - 1)
        for m in range(MODES):
            print(
                f"{w:6g} {m + 1:4d} {par[m]:13.6f} {direct[m]:12.6f} {d_direct[m]:9.1e} {full[m]:12.6f} "
                f"{fc[m]:12.6f} "
                f"{d_same[m]:9.1e}"
            )
        if grow is None:
            tip_err = np.inf
        else:  # at rest both are 0
            tip_err = abs(grow / ref[w]["tip"] - 1) if ref[w]["tip"] > 0 else abs(grow)
        print(
            f"{w:6g} parametric vs direct CB {d_direct.max():.2e}; import full vs ccx {d_same.max():.2e}; "
            f"parametric vs ccx {100 * d_ccx.max():.4f} %; tip's largest static displacement {grow} m vs ccx "
            f"{ref[w]['tip']:.6e} m ({100 * tip_err:.4f} %)"
        )
        if w in SAMPLES and d_direct.max() > AT_SAMPLE:
            failures.append(
                f"{w:g} rad/s (a sample): parametric vs direct reduction {d_direct.max():.1e} " f"> {AT_SAMPLE:g}"
            )
        if d_same.max() > SAME:
            failures.append(f"{w:g} rad/s: imported full-model frequencies vs ccx {d_same.max():.1e} > {SAME:g}")
        if w == MIDDLE and d_direct.max() > BETWEEN:
            failures.append(
                f"{w:g} rad/s (between samples): parametric vs direct reduction {d_direct.max():.1e} " f"> {BETWEEN:g}"
            )
        if d_ccx.max() > FREQ_TOL:
            failures.append(f"{w:g} rad/s: parametric vs ccx {100 * d_ccx.max():.3f} % > {100 * FREQ_TOL:g} %")
        if tip_err > TIP_TOL:
            failures.append(
                f"{w:g} rad/s: tip static displacement {grow} m vs ccx {ref[w]['tip']:.6e} m: "
                f"{100 * tip_err:.3f} % > {100 * TIP_TOL:g} %"
            )
        reduced[w] = par
    # the Campbell diagram of the imported model: its points at the samples are ccx's frequencies
    rb.sh(
        [
            a.campbell,
            os.path.join(a.workdir, f"par{MIDDLE:g}.xml"),
            "--output",
            "campbell.h5",
            "--speeds",
            "5",
            "--count",
            str(MODES),
        ],
        a.workdir,
        "epaphe-campbell",
    )
    with h5py.File(os.path.join(a.workdir, "campbell.h5"), "r") as f:
        full_speeds, full = np.array(f["/full/speeds"]), np.array(f["/full/frequencies"])
        speeds, curves = np.array(f["/speeds"]), np.array(f["/frequencies"])
    for w, fr in zip(full_speeds, full):
        d = np.abs(fr[:MODES] / ref[float(w)]["freqs"] - 1).max()
        print(f"epaphe-campbell at {w:g} rad/s: full-model frequencies vs ccx {d:.1e}")
        if d > SAME:
            failures.append(f"epaphe-campbell at {w:g} rad/s: full-model frequencies vs ccx {d:.1e} > {SAME:g}")
    if sorted(full_speeds) != sorted(SAMPLES):
        failures.append(f"epaphe-campbell's full-model speeds {list(full_speeds)}, expected the samples {SAMPLES}")
    k = int(np.argmin(np.abs(speeds - MIDDLE)))
    d = np.abs(curves[k][:MODES] / reduced[MIDDLE] - 1).max()
    print(f"epaphe-campbell's curve at {speeds[k]:g} rad/s vs the run's reduced model: {d:.1e}")
    if abs(speeds[k] - MIDDLE) > 1e-9 or d > 1e-9:
        failures.append(f"epaphe-campbell's curve at {speeds[k]:g} rad/s differs from the run's model by {d:.1e}")
    # the cache key holds every imported job's files
    text = open(os.path.join(a.workdir, f"par{MIDDLE:g}.xml")).read()
    cached = os.path.join(a.workdir, "cached.xml")
    off, on = ('name="Cache" type="bool" value="%s"' % v for v in ("false", "true"))
    open(cached, "w").write(text.replace(off, on))
    runs = []
    for touch in (False, False, True):
        if touch:
            with open(os.path.join(a.workdir, "ccx", f"m{SAMPLES[1]:g}.dat"), "a") as f:
                f.write("\n")
        runs.append("reused from" in rb.sh([a.run, cached], a.workdir, "epaphe-run with the cache"))
    print(f"cache: built, then reused {runs[1]}, then after a changed job file reused {runs[2]}")
    if runs != [False, True, False]:
        failures.append(
            f"the cache of the imported parametric model: reused in runs {runs}, expected "
            "[False, True, False] (built, reused, rebuilt after a job file changed)"
        )
    return verdict(failures)


if __name__ == "__main__":
    sys.exit(main())
