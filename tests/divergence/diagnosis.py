#!/usr/bin/env python3
"""A run whose energy grows without bound says why (docs/user/divergence.md), on two decks changed as
a user would:

- inputs/rotor37-massless.xml with 'Friction coefficient' 0.5 (the casing turns): the contact work
  feeds the blade and the same run at h/2 diverges too, so the stop says "physical instability of
  the model" and advises no smaller step;
- inputs/bar-on-wall.xml at a step just above its critical step ('Allow unstable time step'): no
  force's work feeds it and the run at h/2 does not diverge, so the stop says "numerical
  instability" and gives h/2.

    diagnosis.py --run EPAPHE_RUN --inputs INPUTS_DIR --workdir DIR"""
import argparse
import os
import re
import subprocess
import sys


def deck(src, dst, replacements):
    text = open(src).read()
    for old, new in replacements:
        assert old in text, f"{src}: '{old}' not found"
        text = text.replace(old, new)
    open(dst, "w").write(text)


def stop_message(run, path, workdir):
    p = subprocess.run([run, path], capture_output=True, text=True, cwd=workdir)
    sys.stdout.write(p.stdout + p.stderr)
    return p.returncode, p.stdout + p.stderr


def main():
    a = argparse.ArgumentParser()
    a.add_argument("--run", required=True)
    a.add_argument("--inputs", required=True)
    a.add_argument("--workdir", required=True)
    o = a.parse_args()
    os.makedirs(o.workdir, exist_ok=True)
    failures = []

    rotor = os.path.join(o.workdir, "rotor37-mu05.xml")
    deck(
        os.path.join(o.inputs, "rotor37-massless.xml"),
        rotor,
        [
            (
                'name="Friction coefficient" type="double" value="0.15"',
                'name="Friction coefficient" type="double" value="0.5"',
            ),
            (
                '<Parameter name="End revolutions" type="double" value="50"/>',
                '<Parameter name="End revolutions" type="double" value="0"/>'
                '<Parameter name="End time" type="double" value="3e-3"/>',
            ),
            ('value="rotor37-massless.h5"', 'value="rotor37-mu05.h5"'),
        ],
    )
    code, m = stop_message(o.run, rotor, o.workdir)
    if code == 0:
        failures.append("rotor 37 at mu = 0.5 completed; it should stop")
    for text in [
        "while pressed on surface 'Casing'",
        "Diagnosis: the bodies' energy (kinetic + strain) grows without bound",
        "It came from contact work",
        "At h/2 = 2.3375e-06 s it diverges too",
        "a physical instability of the model",
    ]:
        if text not in m:
            failures.append(f"rotor 37 at mu = 0.5: '{text}' not in the stop")
    for text in ["tunnelling", "smaller 'Time->Time step'", "numerical instability"]:
        if text in m:
            failures.append(f"rotor 37 at mu = 0.5: '{text}' in the stop")
    efold = re.search(r"e-folding time ([0-9.e+-]+) s", m)
    if not efold or not 0 < float(efold.group(1)) < 1e-3:
        failures.append("rotor 37 at mu = 0.5: no e-folding time below the stop time")

    bar = os.path.join(o.workdir, "bar-unstable.xml")
    # the bar's critical step is 1.35261e-06 s: 1.42e-06 is 5 % above it
    deck(
        os.path.join(o.inputs, "bar-on-wall.xml"),
        bar,
        [
            ('name="Time step" type="double" value="1e-7"', 'name="Time step" type="double" value="1.42e-6"'),
            (
                '<Parameter name="End time" type="double" value="2e-4"/>',
                '<Parameter name="End time" type="double" value="2e-4"/>'
                '<Parameter name="Allow unstable time step" type="bool" value="true"/>',
            ),
            ('value="bar-on-wall.h5"', 'value="bar-unstable.h5"'),
        ],
    )
    code, m = stop_message(o.run, bar, o.workdir)
    if code == 0:
        failures.append("the bar at an unstable step completed; it should stop")
    for text in [
        "grows without bound",
        "It came from the integrator",
        "without diverging",
        "a numerical instability. Use 'Time->Time step' <= 7.1e-07 s",
    ]:
        if text not in m:
            failures.append(f"unstable bar: '{text}' not in the stop")
    if "physical instability" in m:
        failures.append("unstable bar: called a physical instability")

    print("FAILED:\n  " + "\n  ".join(failures) if failures else "2 passed, 0 failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
