#!/usr/bin/env python3
"""The abradable coating (docs/user/coatings.md; Legrand, Batailly & Pierre 2012) in whole runs.

1. Energy: the bar of bar-on-wall.xml at 10 m/s (32 J) into the wall coated with 2 mm of an
   elastic-plastic coating that stops it (yield 100 MPa, E = 10 GPa, H = 1 GPa, 1 cm^2 elements),
   Lagrange and penalty: after the bar has left the wall, the energy the bodies lost equals the
   coating's plastic dissipation to 1 % of the initial energy (measured 0.30 % at h = 1e-7 s with
   either law, the step's error: Lagrange at h/2 must at least halve it, 1.8x asserted, measured
   0.30 -> 0.15 -> 0.077 % at h, h/2, h/4), the energy balance error is at most 1e-8, and the four
   face nodes' elements wore alike (1e-9).
   An infinite yield stress (1e300) with penalty is the elastic run: the penalty law of the
   element's stiffness A E / t on the bare wall at the coating's front, to 1e-8 (measured 4.5e-10: the
   round-off of A (E delta / t) against (A E / t) delta, grown over the impact; force, momentum,
   energies), with no wear.
2. A coating of zero thickness reproduces the rigid casing run: blade-coating.xml at thickness 0
   against blade-casing.xml (the same casing), one revolution: every history equal to 1e-12 of its
   scale.
3. The wear follows the casing: blade-coating.xml (2 revolutions): on the first and last axial rows
   of elements, the dominant harmonic of the wear around the casing (epaphe-rotor's and the
   summary's definition) is the clearance law's there, 2 at the leading edge's end and 6 at the
   trailing edge's, peaking where the law brings the casing in (0 and 180 degrees; multiples of 60)
   within 8 degrees (the tip's response lags the lobe it rides: up to 3 degrees measured on
   2026-11-25); the run summary prints the lobes. (The count of lobes deeper than half the deepest
   is printed, not asserted: after 2 revolutions one of the 6 is shallower.)
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python")))
from epaphe_testing import COATED_BAR, history, parse_args, run, variant, verdict  # noqa: E402
from epaphe.measures import wear_lobes  # noqa: E402

a = parse_args("--bar-deck", "--rigid-deck")
failures = []

# ---- 1. energy on the bar ----------------------------------------------------------------------
coat = COATED_BAR
for method in ("Lagrange", "Penalty"):
    extra = {"Contact->Method": (method, "string")}
    if method == "Penalty":
        extra["Contact->Penalty stiffness"] = ("1e7", "double")
    name = f"bar-{method.lower()}"
    deck = variant(
        a.bar_deck,
        os.path.join(a.workdir, name + ".xml"),
        dict(coat, **extra, **{"Output->File": (name + ".h5", "string")}),
    )
    proc = run([a.run, deck], a.workdir)
    h = history(os.path.join(a.workdir, name + ".h5"))
    f = h["bodies/Bar/contact/total_force"]
    last = np.nonzero(f > 0)[0].max()
    e0, e1 = h["energy/total"][0], h["energy/total"][-1]
    plastic, elastic = h["energy/plastic_dissipation"][-1], h["energy/coating_elastic"][-1]
    lost = e0 - e1
    wear = h["coating/Wall/wear"][-1]
    worn = np.sort(wear[wear > 0])
    bal = np.abs(h["energy/balance_error"]).max()
    print(
        f"{method}: contact until t = {h['time'][last] * 1e3:.3f} ms of {h['time'][-1] * 1e3:.1f}; "
        f"energy {e0:.4f} -> {e1:.4f} J, lost {lost:.4f} J; plastic dissipation {plastic:.4f} J, "
        f"elastic left {elastic:.3g} J; lost - dissipated = {lost - plastic:.4f} J ({(lost - plastic) / e0 * 100:.3f} %); "
        f"wear of the {worn.size} worn elements {worn.min() * 1e6:.3f}-{worn.max() * 1e6:.3f} um; balance {bal:.2e}"
    )
    if not last < len(f) - 10:
        failures.append(f"{method}: the bar is still on the wall at the end")
    if not plastic > 0.1 * e0:
        failures.append(f"{method}: the coating dissipated only {plastic:.4g} J of {e0:.4g}")
    if not abs(lost - plastic - elastic) <= 1e-2 * e0:
        failures.append(
            f"{method}: energy lost {lost:.5g} J against the coating's {plastic + elastic:.5g} J, more than "
            f"1 % of {e0:.4g} J apart"
        )
    if method == "Lagrange":  # the difference is the step's: first order in h (the contact work's trapezoid)
        half = variant(
            deck,
            os.path.join(a.workdir, name + "-half.xml"),
            {"Time->Time step": ("5e-8", "double"), "Output->File": (name + "-half.h5", "string")},
        )
        run([a.run, half], a.workdir)
        hh = history(os.path.join(a.workdir, name + "-half.h5"))
        diff2 = hh["energy/total"][0] - hh["energy/total"][-1] - hh["energy/plastic_dissipation"][-1]
        print(
            f"  at h/2: lost - dissipated = {diff2:.4f} J ({diff2 / e0 * 100:.3f} %), "
            f"{(lost - plastic) / diff2:.2f} times less than at h"
        )
        if not (lost - plastic) / diff2 >= 1.8:
            failures.append(
                f"{method}: lost - dissipated {lost - plastic:.4g} J at h, {diff2:.4g} J at h/2: not first "
                "order in h"
            )
    if not bal <= 1e-8:
        failures.append(f"{method}: energy balance error {bal:.3g} > 1e-8")
    if not (worn.size == 4 and worn.max() - worn.min() <= 1e-9 * worn.max()):
        failures.append(f"{method}: {worn.size} elements worn (4 expected, alike): {worn}")
    if "coating 'Wall'" not in proc.stdout:
        failures.append(f"{method}: the summary has no coating line")

# ---- 1b. an infinite yield stress: the elastic run (penalty of the element's stiffness) ---------
# penalty, sigma_Y = 1e300, E = 1e9: the coating is a spring A E / t = 1e-4 x 1e9 / 2e-3 = 5e7 N/m per
# node at its front (x = 0.202; it stops the bar within 0.6 mm of its 2), the penalty law of that
# stiffness on a bare wall there
elastic = variant(
    a.bar_deck,
    os.path.join(a.workdir, "bar-elastic.xml"),
    dict(
        coat,
        **{
            "Surfaces->Wall->Coating->Yield stress": ("1e300", "double"),
            "Surfaces->Wall->Coating->Young's modulus": ("1e9", "double"),
            "Contact->Method": ("Penalty", "string"),
            "Contact->Penalty stiffness": ("1e7", "double"),
            "Output->File": ("bar-elastic.h5", "string"),
        },
    ),
)
spring = variant(
    a.bar_deck,
    os.path.join(a.workdir, "bar-spring.xml"),
    {k: v for k, v in coat.items() if not k.startswith("Surfaces")}
    | {
        "Contact->Method": ("Penalty", "string"),
        "Contact->Penalty stiffness": ("5e7", "double"),
        "Output->File": ("bar-spring.h5", "string"),
    },
)
for d in (elastic, spring):
    run([a.run, d], a.workdir)
he, hs = history(os.path.join(a.workdir, "bar-elastic.h5")), history(os.path.join(a.workdir, "bar-spring.h5"))
worst = max(
    np.abs(he[k] - hs[k]).max() / max(np.abs(hs[k]).max(), 1e-300)
    for k in ("bodies/Bar/contact/force", "bodies/Bar/momentum", "energy/kinetic", "energy/contact_work")
)
print(
    f"infinite yield against a penalty spring of the element's stiffness: largest difference {worst:.2e} of scale; "
    f"wear {he['coating/Wall/wear'].max():.3g} m, peak force {hs['bodies/Bar/contact/total_force'].max():.4g} N"
)
if not (worst <= 1e-8 and he["coating/Wall/wear"].max() == 0.0 and hs["bodies/Bar/contact/total_force"].max() > 0):
    failures.append(f"infinite yield: {worst:.3g} from the elastic (penalty 5e7 N/m) run, or wear, or no contact")

# ---- 2. zero thickness = the rigid casing ------------------------------------------------------
one = {
    "Time->End revolutions": ("1", "double"),
    "Output->Every": ("20", "int"),
    "Bodies->Blade->Reduction->Cache file": ("blade.rom.h5", "string"),
}
rigid = variant(
    a.rigid_deck, os.path.join(a.workdir, "rigid.xml"), dict(one, **{"Output->File": ("rigid.h5", "string")})
)
thin = variant(
    a.deck,
    os.path.join(a.workdir, "thin.xml"),
    dict(
        one,
        **{
            "Output->File": ("thin.h5", "string"),
            "Surfaces->Casing->Radius": ("0.3", "double"),
            "Surfaces->Casing->Coating->Thickness": ("0", "double"),
        },
    ),
)
for d in (rigid, thin):
    run([a.run, d], a.workdir)
hr, ht = history(os.path.join(a.workdir, "rigid.h5")), history(os.path.join(a.workdir, "thin.h5"))
compared = 0
for key, x in hr.items():
    if not isinstance(x, np.ndarray) or key.startswith(("checkpoint", "run")) or x.dtype.kind != "f":
        continue
    y = ht.get(key)
    if y is None or y.shape != x.shape:
        failures.append(f"zero thickness: {key} missing or of another shape")
        continue
    scale = max(np.abs(x).max(), 1e-300)
    d = np.abs(x - y).max()
    compared += 1
    if not d <= 1e-12 * scale:
        failures.append(f"zero thickness: {key} differs from the rigid casing run by {d:.3g} (scale {scale:.3g})")
print(
    f"zero thickness against the rigid casing: {compared} histories compared, "
    f"peak contact force {hr['bodies/Blade/contact/total_force'].max():.4g} N"
)
if compared < 10:
    failures.append(f"zero thickness: only {compared} histories compared")

# ---- 3. the wear follows the casing's lobes ----------------------------------------------------
two = variant(
    a.deck,
    os.path.join(a.workdir, "coated.xml"),
    dict(one, **{"Time->End revolutions": ("2", "double"), "Output->File": ("coated.h5", "string")}),
)
proc = run([a.run, two], a.workdir)
h = history(os.path.join(a.workdir, "coated.h5"))
angle, wear = h["coating/Casing/angle"], h["coating/Casing/wear"][-1]
for row, order in ((0, 2), (wear.shape[1] - 1, 6)):
    lobes = wear_lobes(angle, wear[:, row : row + 1])
    peaks = np.degrees(lobes.harmonic_angles)
    expected = np.arange(order) * 360.0 / order
    miss = max((min(abs((x - e + 180) % 360 - 180) for x in peaks) for e in expected), default=360.0)
    print(
        f"row {row} (axial {h['coating/Casing/axial'][row] * 1e3:.0f} mm): {lobes.lobe_count} lobes at "
        f"{', '.join(f'{x:.1f}' for x in np.degrees(lobes.lobe_angles))} deg, dominant harmonic {lobes.dominant_order} "
        f"peaking at {', '.join(f'{x:.1f}' for x in peaks)} deg, max wear {lobes.max_wear * 1e6:.2f} um; farthest "
        f"from the clearance law's {order} lobes: {miss:.1f} deg"
    )
    if lobes.dominant_order != order or miss > 8.0:
        failures.append(
            f"row {row}: dominant wear harmonic {lobes.dominant_order} peaking at {peaks} deg; expected "
            f"{order} at {expected} deg"
        )
if "wear lobe(s)" not in proc.stdout:
    failures.append("blade-coating: the summary has no lobes line")
sys.exit(verdict(failures))
