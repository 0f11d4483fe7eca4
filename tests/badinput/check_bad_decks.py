#!/usr/bin/env python3
"""Bad decks are refused before anything runs, each with one message naming the problem.

Every case in cases/ is a deck (`<name>.xml`) whose first line is an XML comment
`<!-- expect: REGEX -->`; epaphe-run must exit non-zero, print a message matching REGEX on
stderr, and leave no output file behind that could pass for a result. A few decks that cannot be
case files (a missing deck, a directory, an empty file) are made in the work directory.

`epaphe-run --check DECK` must refuse every case with the very message of the run (one validation,
Epaphe_SceneCheck.hpp), except the few in RUN_TIME_ONLY, whose fault only the setup can see; those
must pass --check, so that the list stays exact.
"""
import argparse
import concurrent.futures
import glob
import os
import re
import shutil
import subprocess
import sys


# Faults that need the reduced model or the contact detection, which --check does not build.
RUN_TIME_ONLY = {
    # the critical step is the reduced model's highest frequency (with the penalty springs):
    # known once the body is reduced (or its lumped mass model's eigenvalue computed)
    "unstable-time-step.xml": "critical step of the reduced model",
    "full-lumped-unstable-time-step.xml": "critical step of the lumped full model",
    "penalty-too-stiff.xml": "critical step of the reduced model with the penalty springs",
    # the closest-point projection of every contact node on the B-spline surfaces at t = 0
    "bodies-start-interpenetrating.xml": "contact detection at t = 0",
    "wall-facing-away.xml": "contact detection at t = 0",
    # the smallest patch of the B-spline surfaces, against |v0| h
    "tunnelling-initial-velocity.xml": "patch sizes of the built B-spline surfaces",
    # what the reduction of the assembled model meets
    "belos-tolerance-unreachable.xml": "the iterative solves of K_CC in the reduction",
    "dense-eigensolver-too-large.xml": "the free DOFs of the assembled model, at the dense eigensolver",
    "gravity-clamped-unreduced.xml": "the Rayleigh quotient of a rigid translation on the assembled model",
    "sphere-clamped-at-pole.xml": "the eigenvalues of the massless boundary reduction (the mechanism's zero ones)",
    "rotation-past-critical-speed.xml": "the parametric model's stiffness over its speed range",
    "import-speed-unprinted.xml": "the static displacements of a CalculiX job at speed, read with its matrices",
    # 'Time->Initial state' = Static equilibrium: the contact detection at t = 0 and the static solve (eq. 71)
    "static-preload-opens-contact.xml": "the normal forces of the static contact solve on the reduced model",
    "static-preload-nothing-touches.xml": "the gaps of the contact detection at t = 0",
    # a load on the model's coordinates: how many there are is known once the body is reduced
    "load-reduced-dof-out-of-range.xml": "how many coordinates the reduced model has",
    # Gaps of --check: faults the deck and its built-in mesh show, seen only where the run builds the model or
    # the surfaces; when --check learns them, this list says so
    "full-model-all-clamped.xml": "gap of --check: the clamped set covers the mesh; seen at the model's assembly",
    "retained-set-all-clamped.xml": "gap of --check: the retained set is all clamped; seen by the reduction",
    "surface-rotation-axis-zero.xml": "gap of --check: a surface's rotation is read where the surfaces are built",
    "output-file-empty.xml": "gap of --check: an empty 'Output->File' passes the check that its directory is writable",
    "arc-angles-coincide.xml": "gap of --check: the rigid surfaces' B-splines are built with the surfaces",
    "arc-axial-range-coincide.xml": "gap of --check: the rigid surfaces' B-splines are built with the surfaces",
    "coating-elements-one-value.xml": "gap of --check: the Coating list is read where the surfaces are built",
    "coating-elements-zero.xml": "gap of --check: the Coating list is read where the surfaces are built",
    "coating-on-body-face.xml": "gap of --check: the Coating list is read where the surfaces are built",
    "coating-on-body-face-no-elements.xml": "gap of --check: the Coating list is read where the surfaces are built",
    "coating-thickness-without-elements.xml": "gap of --check: the Coating list is read where the surfaces are built",
    "coating-too-many-elements.xml": "gap of --check: the Coating list is read where the surfaces are built",
}
# An imported model's files are read when the run builds the model (--check checks that they exist, and the
# CalculiX *INCLUDE chain): the faults of their content, and of what the deck asks of such a model (its DOFs,
# node sets and boundary conditions), show at run time.
RUN_TIME_ONLY.update(
    {
        name: "the content of an imported model's files"
        for name in [
            "import-aster-all-constrained.xml",
            "import-aster-clamped-not-id.xml",
            "import-aster-clamped-not-in-mesh.xml",
            "import-aster-lagrange-node-not-in-mesh.xml",
            "import-body-face.xml",
            "import-ccx-boundary-line-unparsable.xml",
            "import-ccx-element-line-unparsable.xml",
            "import-ccx-element-node-not-a-number.xml",
            "import-ccx-element-too-many-nodes.xml",
            "import-ccx-element-without-type.xml",
            "import-ccx-generate-line-unparsable.xml",
            "import-ccx-no-node.xml",
            "import-ccx-node-defined-twice.xml",
            "import-ccx-node-line-unparsable.xml",
            "import-ccx-nset-unknown-item.xml",
            "import-ccx-nset-without-name.xml",
            "import-contact-node-clamped.xml",
            "import-gravity-unreduced.xml",
            "import-massless-too-many-candidates.xml",
            "import-mm-field-complex.xml",
            "import-mm-header-only.xml",
            "import-mm-massless-collinear.xml",
            "import-mm-no-node.xml",
            "import-mm-node-set-not-id.xml",
            "import-mm-node-set-undefined-node.xml",
            "import-mm-node-twice.xml",
            "import-mm-size-line.xml",
            "import-mm-size-not-dofs.xml",
            "import-mm-symmetry-skew.xml",
            "import-too-many-modes.xml",
        ]
    }
)


# Decks that cannot be case files, made in the work directory: name, what is made, the message expected.
MADE_CASES = [
    ("missing.xml", None, r"deck '.*missing.xml' cannot be opened: check the path and its permissions"),
    ("directory.xml", "directory", r"deck '.*directory.xml' is a directory; give an XML file"),
    ("empty.xml", "empty file", r"deck '.*empty.xml' is empty; a deck is <ParameterList name=\"Epaphe\">"),
]

TIMEOUT = 300  # s for one run of a case: the slowest reduces a model before its refusal, in seconds


def one_case(run, workdir, path, regex):
    """Runs one bad deck, then --check on it; the report lines (a line starting FAIL is a failure)."""
    name = os.path.basename(path)
    work = os.path.join(workdir, "cases", os.path.splitext(name)[0])
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    proc = subprocess.run([run, path], cwd=work, capture_output=True, text=True, timeout=TIMEOUT)
    err = proc.stderr.strip()
    outputs = [f for f in os.listdir(work) if f.endswith(".h5") and not f.endswith(".rom.h5")]
    ok = proc.returncode != 0 and re.search(regex, err) and len(err.splitlines()) == 1 and not outputs
    lines = [f"{'ok  ' if ok else 'FAIL'} {name}: exit {proc.returncode}: {err}"]
    if not ok:
        lines.append(f"     expected a one-line message matching /{regex}/, no output file (found {outputs})")
    chk = subprocess.run([run, "--check", path], cwd=work, capture_output=True, text=True, timeout=TIMEOUT)
    if name in RUN_TIME_ONLY:
        if chk.returncode != 0:
            lines.append(
                f"FAIL {name}: listed as seen only at run time ({RUN_TIME_ONLY[name]}), but --check refuses "
                f"it now: {chk.stderr.strip()}; remove it from RUN_TIME_ONLY"
            )
    elif chk.returncode == 0 or chk.stderr.strip() != err:
        lines.append(
            f"FAIL {name}: --check exit {chk.returncode}, message\n       {chk.stderr.strip()}\n     the "
            f"run's\n       {err}"
        )
    return lines


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--run", required=True)
    ap.add_argument("--cases", required=True)
    ap.add_argument("--workdir", required=True)
    a = ap.parse_args()
    a.run, a.cases = os.path.abspath(a.run), os.path.abspath(a.cases)  # each case runs in its own directory
    os.makedirs(a.workdir, exist_ok=True)
    failed = 0
    cases = []
    for path in sorted(glob.glob(os.path.join(a.cases, "*.xml"))):
        first = open(path).readline()
        m = re.match(r"<!-- expect: (.*) -->", first.strip())
        assert m, f"{path}: first line must be <!-- expect: REGEX -->"
        cases.append((path, m.group(1)))
    made = os.path.join(a.workdir, "made")
    shutil.rmtree(made, ignore_errors=True)
    os.makedirs(made)
    for name, what, regex in MADE_CASES:
        if what == "directory":
            os.makedirs(os.path.join(made, name))
        elif what == "empty file":
            open(os.path.join(made, name), "w").close()
        cases.append((os.path.join(made, name), regex))
    # Each case in its own directory, two at a time (each run is one process on one thread).
    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        results = list(pool.map(lambda c: one_case(a.run, a.workdir, *c), cases))
    for lines in results:
        print("\n".join(lines))
        failed += any(line.startswith("FAIL") for line in lines)
    print(f"{len(cases) - failed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
