#!/usr/bin/env python3
"""V7 (thesis chapter 5), the thesis-like scene inputs/blade-casing.xml: a blade clamped at its root
in a rigid casing turning at 1000 rad/s, whose clearance has 2 lobes at the leading edge's end and 6
at the trailing edge's. Asserted, over revolutions 3 to 20 (after the transient): exactly 2 contacts
per revolution (re-contacts within 0.15 revolution of a contact start are the same contact:
bounces on one lobe, which spans 60 degrees at the leading edge) at the tip's leading edge and 6 at its trailing edge (epaphe-rotor contacts),
at the same casing angles every revolution (within 5 degrees); energy balance below 1e-8; the tip
never penetrates the casing by more than 1e-9 m. Also prints the dominant engine orders of the tip's
motion (epaphe-rotor spectrum)."""
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from epaphe_testing import history, load_script, parse_args, run, variant, verdict  # noqa: E402

a = parse_args("--rotor", "--rotor37")
deck = variant(a.deck, os.path.join(a.workdir, "blade.xml"), {"Run->Progress interval": ("0", "double")})
out = run([a.run, deck], a.workdir)
print("\n".join(l for l in out.stdout.splitlines() if "steps/s" in l or "per-step" in l or "contact:" in l))
h5 = os.path.join(a.workdir, "blade-casing.h5")
rotor = load_script(a.rotor, "epaphe_rotor")
failures = []
res = rotor.contact_events(h5, "Blade", ["tip-le", "tip-te"], skip=3)
for name, expected in (("tip-le", 2), ("tip-te", 6)):
    r = res[name]
    print(f"{name}: contacts per revolution {r['per_rev']} (expected {expected}), "
          f"in contact {100 * np.mean(r['fraction']):.1f} % of a revolution")
    if r["per_rev"] != [expected] * len(r["per_rev"]) or len(r["per_rev"]) < 15:
        failures.append(f"{name}: {r['per_rev']} contacts per revolution, expected {expected} in each of 17")
    ang = np.array(r["angles"]).reshape(-1, expected) if len(r["angles"]) % expected == 0 else None
    if ang is not None:
        spread = np.abs((ang - ang[0] + 180) % 360 - 180).max()
        print(f"{name}: event angles {np.round(ang[0]).tolist()} deg, spread over revolutions {spread:.2f} deg")
        if spread > 5:
            failures.append(f"{name}: event angles move by {spread:.1f} degrees between revolutions")
    eo, freq, amp = rotor.spectrum(h5, "Blade", name, "x", skip=3)
    top = np.argsort(amp)[::-1][:3]
    print(f"{name}: dominant engine orders (x) " + ", ".join(f"{eo[i]:.2f}" for i in top))
h = history(h5)
bal = np.abs(h["energy/balance_error"]).max()
pen = max(0.0, -h["bodies/Blade/contact/gap"].min())
print(f"energy balance {bal:.1e}; largest penetration {pen:.1e} m")
if bal > 1e-8:
    failures.append(f"energy balance {bal:.2e} > 1e-8")
if pen > 1e-9:
    failures.append(f"penetration {pen:.2e} m > 1e-9 m")
# The rotor 37 casing law with friction (inputs/rotor37-casing.xml), 5 of its 50 revolutions: it
# stays finite and balanced, and the leading edge touches the two lobes once each per revolution.
deck = variant(a.rotor37, os.path.join(a.workdir, "rotor37.xml"), {"Run->Progress interval": ("0", "double"),
                                                                    "Time->End revolutions": ("5", "double")})
out = run([a.run, deck], a.workdir)
print("\n".join(l for l in out.stdout.splitlines() if "steps/s" in l or "contact:" in l))
h5 = os.path.join(a.workdir, "rotor37-casing.h5")
r = rotor.contact_events(h5, "Blade", ["tip-le"], skip=1)["tip-le"]
h = history(h5)
bal = np.abs(h["energy/balance_error"]).max()
print(f"rotor 37 law, mu = 0.15: tip-le contacts per revolution {r['per_rev']}, energy balance {bal:.1e}")
if r["per_rev"] != [2] * len(r["per_rev"]) or not r["per_rev"]:
    failures.append(f"rotor 37: {r['per_rev']} leading-edge contacts per revolution, expected 2")
if not bal <= 1e-8:
    failures.append(f"rotor 37: energy balance {bal:.2e}")
sys.exit(verdict(failures))
