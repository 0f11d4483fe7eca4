#!/usr/bin/env python3
"""V3 (docs/verification.md): the bouncing bar of Doyen, Ern & Piperno, SIAM J. Sci. Comput. 33
(2011) 223-249, Section 3, over 10 periods.

Exact solution (d'Alembert on the 1-D bar, c = sqrt(E/rho)), from the deck's numbers: the bar falls
rigidly for T_fall = V/g, V = sqrt(2 g h0); on impact a compression wave crosses the bar and back,
and the contact force E A (V/c + g s/c^2) (s = c (t - t_impact)) stays compressive until s = 2L,
where it would jump to tension (V > 2 g L / c): the first contact lasts T_c = 2L/c. The bar leaves
with its centre of mass at +V, compressed to twice its static state, and flies for 2V/g; when that
is a whole number of wave periods 2L/c, it lands in the time-reversed state of its release, so the
second contact lasts T_c too and ends with a rigid, stress-free bar at +V, which rises to its
starting height in T_fall. Period 2 T_fall + 2 T_c + 2V/g (16/3 s for L = 10, E = 900, rho = 1,
g = 10, h0 = 5).

Measured, against the exact values: the initial fall T_fall, the duration of every contact (2 per
period, 20 in all) against T_c, every flight between two contacts against 2V/g (the flight with a
wave, and the rigid flight down and up again, T_fall + T_fall), and the number of contacts. A contact
interval runs from the first to the last step with a contact force; steps without force inside it,
separated by less than T_c/10 (the exact solution has no flight shorter than T_fall), are chatter
and are counted and reported, not hidden.

The reference, every duration within 1 % over the 10 periods and exactly 2 contacts per period
(docs/verification.md V3), is NOT met today. The finding (docs/verification.md V3, issue 16's
massless contact boundary): the lumped contact face's mass arrested at each impact detunes the second
contact of each period, +1.3 % in period 2, +9.6 % in period 7; periods 1 to 8 keep 2 contacts each
(FINDING below: their 32 signed duration errors), and from period 9 the motion is no longer periodic:
30 contacts instead of 20. Bands, all stated with the numbers below:
  - a duration is counted in steps of h (one step is 0.10 % of T_c, 0.033 % of a 2 s flight);
    MARGIN = 3 steps. Perturbing the run by far more than round-off (the plane moved by 1e-10 m,
    the density by 1e-12 relative) moves none of the 32 durations by a step; changing h by 1e-6
    relative moves period 7's second contact by 5 steps (+0.5 %). The detuning grows by 0.7 to
    3.7 % a period from period 2 on: a change of the contact's physics leaves the band.
  - from period 9 (the contacts after the first 16), the durations no longer pair with the exact
    ones: every contact no longer than the finding's longest (period 7's second, +9.59 %) plus
    MARGIN, every flight no longer than the exact rigid flight 2 T_fall within 1 % (the recorded ones
    are all shorter: the bar has lost energy);
  - the number of contacts: 30 +- 4 (CONTACTS_BAND): the round-off perturbations above leave 30, the
    1e-6 change of h gives 33, the reference 20;
  - the energy the contact took over the 8 regular periods (to the end of the 16th contact): 5.505 J
    +- 5 % (LOSS_BAND): the round-off perturbations move it by 0.07 %, the 1e-6 change of h by 2.6 %.

Two registrations (tests/CMakeLists.txt):
  - verification.v3-bouncing-bar (default suite): every period's durations no worse than the finding,
    each within max(1 %, |recorded error| + MARGIN), so the durations recorded within 1 % less the
    margin are held to 1 %; from period 9 the bounds above; at most 30 + 4 contacts; every energy
    check below;
  - verification.v3-ten-periods (--expect-finding, label finding): the finding pinned from both
    sides: each of the 32 durations of periods 1 to 8 within MARGIN of its recorded error, the
    contacts within 30 +- 4, the contact's loss over periods 1 to 8 within 5.505 J +- 5 %, and every
    check of the default test. It fails when the finding gets worse (a regression) or better (update the
    recorded signature here and in docs/verification.md); once every duration is within 1 % with
    20 contacts it says to drop --expect-finding and hold the default test to 1 %.

Energy (E_ref = m g h0 = m V^2/2, the bar's energy at impact):
  - the run's energy balance closes to round-off with gravity's work (|balance error| <= 1e-9:
    an exact identity of the scheme summed over ~8e4 steps);
  - the forward-increment Lagrange contact never adds energy: each step's contact work is
    -lambda g_{n-1}/2 <= 0 (lambda >= 0, the node ends on the plane from a gap >= 0), so the
    contact work never rises (by more than 1e-9 E_ref of round-off);
  - the drift of the physical energy E = kinetic + strain - (work of gravity) over the 10 periods
    is reported and bounded. Derivation, for a contact face of lumped mass m_f = rho A dx / 2
    arriving at speed V_i: the step that finds the predicted gap g* = g_n - V' h < 0 (V' the
    predicted speed) applies lambda_n = m_f (V' h - g_n) / h^2, the next holds the face with
    lambda_{n+1} = m_f (g_n / h^2 + a'), a' = g + F_s'/m_f, F_s' = k (V' h - g_n) the spring
    k = E A / dx compressed in between; their work -(lambda_n (g_n + v h) + lambda_{n+1} g_n) / 2
    sums to -(m_f/2) [V' v + (a + a') g_n], v = V' - a h the speed before the step. With
    0 <= g_n < V' h and k h^2 / m_f = 2 alpha^2 (alpha = c h / dx), the loss of one impact lies
    between (m_f/2) v V' and B(V') = (m_f/2) (1 + alpha^2/2) V'^2 + m_f g V' h. The first impact of
    a period arrives at V_1 = V; the second at most at V_2 = V + 2 g L / c (the free end's speed
    when the compression front of the flight reaches it). Bound: |drift| <= sum over the 20
    impacts of B(V_i). The first impact, on a stress-free bar, is checked on its own within
    [(m_f/2)(V - 2 g h)^2, B(V + g h)].
"""
import math
import os
import sys
import time
import xml.etree.ElementTree as ET

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from epaphe_testing import deck_value, history, parse_args, run, variant, verdict  # noqa: E402

TOL = 0.01  # docs/verification.md V3: contact durations within 1 % over 10 periods
BALANCE_TOL = 1e-9  # round-off of the balance identity
ROUNDOFF = 1e-9  # contact work never rises by more than this (relative to E_ref)
# The finding, as recorded (docs/verification.md V3): the signed errors (%) of the 8 regular periods'
# durations: fall (period 1) or rigid flight, contact 1, wave flight, contact 2
FINDING = (
    (-0.033, +0.200, -0.167, +0.300),
    (-0.200, +0.200, -0.500, +1.299),
    (-0.533, +0.200, -0.699, +1.998),
    (-0.833, +0.200, -0.999, +2.897),
    (-1.199, +0.200, -1.365, +3.896),
    (-1.765, +0.200, -2.031, +5.894),
    (-3.064, +0.200, -3.263, +9.590),
    (-6.394, +0.200, -6.594, +0.200),
)
MARGIN_STEPS = 3  # the band on each duration, in steps of h (derivation in the docstring)
FINDING_CONTACTS, CONTACTS_BAND = 30, 4
FINDING_LOSS, LOSS_BAND = 5.505, 0.05  # J the contact took over the 8 regular periods, relative band


def setting(deck, lumped=True):
    """The V3 setting from the deck, and its exact solution (with `lumped`, the deck must reduce the
    bar as the lumped full model, which the energy bound below is derived for)."""
    root = ET.parse(deck).getroot()
    b = "Bodies->Bar->"
    Lx, Ly, Lz = deck_value(root, b + "Mesh->Lengths")
    nx = int(deck_value(root, b + "Mesh->Elements")[0])
    x0 = deck_value(root, b + "Mesh->Origin")[0]
    E = float(deck_value(root, b + "Material->Young's modulus"))
    rho = float(deck_value(root, b + "Material->Density"))
    grav = deck_value(root, b + "Gravity")
    method = deck_value(root, b + "Reduction->Method")
    plane = deck_value(root, "Surfaces->Ground->Origin")[0]
    h = float(deck_value(root, "Time->Time step"))
    end = float(deck_value(root, "Time->End time"))
    assert grav[1] == grav[2] == 0 and grav[0] < 0, f"gravity {grav}: V3 drops the bar along -x"
    assert (
        method == "Full, lumped mass" or not lumped
    ), f"the energy bound is derived for a lumped contact face, not '{method}'"
    s = dict(L=Lx, A=Ly * Lz, dx=Lx / nx, E=E, rho=rho, g=-grav[0], h0=x0 - plane, h=h, end=end)
    s["c"] = math.sqrt(E / rho)
    s["V"] = math.sqrt(2 * s["g"] * s["h0"])
    s["T_fall"] = s["V"] / s["g"]
    s["T_c"] = 2 * s["L"] / s["c"]
    s["T_flight"] = 2 * s["V"] / s["g"]
    s["period"] = 2 * s["T_fall"] + 2 * s["T_c"] + s["T_flight"]
    s["periods"] = int(round(end / s["period"]))
    s["m_f"] = rho * s["A"] * s["dx"] / 2
    s["alpha"] = s["c"] * h / s["dx"]
    s["E_ref"] = rho * s["A"] * s["L"] * s["g"] * s["h0"]
    # the exact solution above holds when the contact force jumps to tension at s = 2L (V > 2gL/c)
    # and the flight is a whole number of wave periods 2L/c
    assert s["V"] > 2 * s["g"] * s["L"] / s["c"], "V <= 2gL/c: the first contact would not end at 2L/c"
    waves = s["T_flight"] / s["T_c"]
    assert abs(waves - round(waves)) < 1e-9, f"flight 2V/g = {waves} wave periods, not a whole number"
    assert abs(end - s["periods"] * s["period"]) < 0.01 * s["T_fall"], f"end time {end}: not a whole number of periods"
    return s


def intervals(t, force, h, merge_below):
    """Contact intervals [start, end) from the force history, gaps shorter than merge_below merged
    (returned with the number of force-free steps inside each)."""
    on = np.flatnonzero(force)
    assert on.size > 0, "no contact at all"
    groups = np.split(on, np.flatnonzero(np.diff(on) * h > merge_below) + 1)
    starts = np.array([t[g[0]] for g in groups])
    ends = np.array([t[g[-1]] + h for g in groups])
    chatter = [int(g[-1] - g[0] + 1 - g.size) for g in groups]
    return starts, ends, chatter


def main():
    expect_finding = "--expect-finding" in sys.argv  # (this script's option; the rest is parse_args')
    if expect_finding:
        sys.argv.remove("--expect-finding")
    a = parse_args()
    s = setting(a.deck)
    failures = []  # the default test's checks: energy, and durations no worse than the finding
    misses = []  # the reference: every duration within 1 %, 2 contacts a period
    moved = []  # the finding's signature out of its band, either way (--expect-finding)
    deck = variant(
        a.deck,
        os.path.join(a.workdir, "bouncing-bar.xml"),
        {"Output->File": "bouncing-bar.h5", "Run->Progress interval": ("0", "double")},
    )
    wall = time.time()
    run([a.run, deck, "--threads", "1"], a.workdir)
    wall = time.time() - wall
    hist = history(os.path.join(a.workdir, "bouncing-bar.h5"))
    t = hist["time"]
    h = s["h"]
    assert np.allclose(np.diff(t), h), "records must be every step (Output->Every = 1)"
    crit = hist["attrs"]["critical_time_step"]
    print(
        f"V3 bouncing bar: L = {s['L']}, c = {s['c']:g}, g = {s['g']}, h0 = {s['h0']}: V = {s['V']:g}, "
        f"T_fall = {s['T_fall']:g}, T_c = {s['T_c']:.6f}, flight 2V/g = {s['T_flight']:g}, period "
        f"{s['period']:.6f}, {s['periods']} periods"
    )
    print(
        f"mesh dx = {s['dx']:g} (contact face mass m_f = {s['m_f']:g} of {s['rho'] * s['A'] * s['L']:g}), "
        f"h = {h:g} s (critical {crit:.6g} s printed by epaphe-run; c h / dx = {s['alpha']:.4f}), "
        f"{t.size} steps in {wall:.1f} s on 1 thread"
    )

    # ---- contact and flight durations ------------------------------------------------------------
    force = hist["bodies/Bar/contact/total_force"]
    f_scale = s["rho"] * s["A"] * s["c"] * s["V"]  # rho A c V, the force of an impact at V
    starts, ends, chatter = intervals(t, force > 1e-6 * f_scale, h, s["T_c"] / 10)
    contact = ends - starts
    flights = np.concatenate([[starts[0]], starts[1:] - ends[:-1], [s["end"] - ends[-1]]])
    n_expected = 2 * s["periods"]
    regular = len(FINDING)  # periods recorded with 2 contacts each
    print(
        f"{contact.size} contacts (expected {n_expected}, recorded {FINDING_CONTACTS} +- {CONTACTS_BAND}); "
        f"steps without force inside them (chatter): {sum(chatter)}"
    )
    print(
        f"durations against the exact ones; [recorded error, band: max({TOL:.0%}, |recorded| + "
        f"{MARGIN_STEPS} steps)]"
    )
    print(
        " period | fall/rigid flight                      | contact 1                              | "
        "wave flight                            | contact 2"
    )
    worst = {"contact": (0.0,), "flight": (0.0,)}  # (|error|, error, period)

    def rel(x, ref):
        return (x - ref) / ref

    def cell(x, ref, rec=None, band=None):
        if x is None:
            return " " * 38
        return f"{x:9.5f} ({rel(x, ref):+7.3%})" + (f" [{rec:+7.3%}, {band:6.3%}]" if rec is not None else " " * 18)

    for p in range(s["periods"]):
        i1, i2 = 2 * p, 2 * p + 1
        fall_ref = s["T_fall"] if p == 0 else 2 * s["T_fall"]
        fall = flights[i1] if i1 < flights.size else None
        c1 = contact[i1] if i1 < contact.size else None
        wave = flights[i2] if i2 < flights.size and i2 < contact.size else None
        c2 = contact[i2] if i2 < contact.size else None
        row = []
        for k, (what, x, ref) in enumerate(
            (
                ("flight", fall, fall_ref),
                ("contact", c1, s["T_c"]),
                ("flight", wave, s["T_flight"]),
                ("contact", c2, s["T_c"]),
            )
        ):
            if p >= regular:  # not periodic any more: printed, bounded below
                row.append(cell(x, ref))
                continue
            rec = FINDING[p][k] / 100
            margin = MARGIN_STEPS * h / ref
            band = max(TOL, abs(rec) + margin)
            row.append(cell(x, ref, rec, band))
            name = f"period {p + 1}: {what} {k // 2 + 1}"
            if x is None:
                failures.append(
                    f"{name} missing: {contact.size} contacts, the finding has 2 in each of periods 1 " f"to {regular}"
                )
                continue
            err = rel(x, ref)
            worst[what] = max(worst[what], (abs(err), err, p + 1))
            if not abs(err) <= TOL:
                misses.append(f"{name} of {x:.5f} s, exact {ref:.5f} s ({err:+.2%}, tolerance {TOL:.0%})")
            if not abs(err) <= band:
                failures.append(
                    f"{name} of {x:.5f} s, exact {ref:.5f} s: {err:+.3%}, worse than the recorded finding "
                    f"({rec:+.3%}) by more than {MARGIN_STEPS} steps (band {band:.3%})"
                )
            if not abs(err - rec) <= margin + 5e-6:  # (+ the recorded figures' last digit)
                moved.append(
                    f"{name}: {err:+.3%}, recorded {rec:+.3%}: {'better' if abs(err) < abs(rec) else 'worse'} "
                    f"by more than {MARGIN_STEPS} steps ({margin:.3%})"
                )
        print(f" {p + 1:6d} | " + " | ".join(row))
    print(f"last rigid flight, cut by the end of the run: {flights[-1]:.5f} s (exact {s['T_fall']:g})")
    recorded_worst = {
        "flight": max(abs(r[k]) for r in FINDING for k in (0, 2)) / 100,
        "contact": max(abs(r[k]) for r in FINDING for k in (1, 3)) / 100,
    }
    for what, w in worst.items():
        if len(w) > 1:
            print(
                f"worst {what} over periods 1 to {regular}: {w[1]:+.3%} in period {w[2]} (recorded: "
                f"{recorded_worst[what]:.3%})"
            )
    # from period 9 (the contacts after the regular periods'): no pairing with the exact durations; bounded
    # by the finding's longest contact and the exact rigid flight
    later = slice(2 * regular, None)
    longest = s["T_c"] * (1 + max(max(r[1], r[3]) for r in FINDING) / 100) + MARGIN_STEPS * h
    longest_flight = 2 * s["T_fall"] * (1 + TOL)
    late_c, late_f = contact[later], flights[2 * regular : -1]
    print(
        f"from period {regular + 1}: {late_c.size} contacts, longest {late_c.max(initial=0):.5f} s "
        f"(bound {longest:.5f} s: the finding's longest + {MARGIN_STEPS} steps), longest flight "
        f"{late_f.max(initial=0):.5f} s (bound {longest_flight:.5f} s: 2 T_fall + {TOL:.0%})"
    )
    for i in np.flatnonzero(late_c > longest):
        failures.append(
            f"contact {2 * regular + i + 1} (from {starts[2 * regular + i]:.4f} s) lasts "
            f"{late_c[i]:.5f} s, longer than the finding's longest contact + {MARGIN_STEPS} steps "
            f"({longest:.5f} s)"
        )
    for i in np.flatnonzero(late_f > longest_flight):
        failures.append(
            f"the flight before contact {2 * regular + i + 1} lasts {late_f[i]:.5f} s, longer than the "
            f"exact rigid flight 2 T_fall + {TOL:.0%} ({longest_flight:.5f} s)"
        )
    if contact.size != n_expected:
        misses.append(f"{contact.size} contacts in {s['periods']} periods, {n_expected} expected")
    if not contact.size <= FINDING_CONTACTS + CONTACTS_BAND:
        failures.append(f"{contact.size} contacts, more than the recorded {FINDING_CONTACTS} + {CONTACTS_BAND}")
    if not abs(contact.size - FINDING_CONTACTS) <= CONTACTS_BAND:
        moved.append(
            f"{contact.size} contacts, recorded {FINDING_CONTACTS} +- {CONTACTS_BAND}: "
            f"{'better' if contact.size < FINDING_CONTACTS else 'worse'} (exact {n_expected})"
        )

    # ---- energy ----------------------------------------------------------------------------------
    E_ref = s["E_ref"]
    total, ext, work = hist["energy/total"], hist["energy/external_work"], hist["energy/contact_work"]
    physical = total - ext  # kinetic + strain + potential of gravity, from its start
    drift = physical - physical[0]
    balance = np.abs(hist["energy/balance_error"]).max()
    rise = np.diff(work).max()
    bound_impact = lambda v: 0.5 * s["m_f"] * (1 + s["alpha"] ** 2 / 2) * v**2 + s["m_f"] * s["g"] * v * h  # noqa
    V1, V2 = s["V"], s["V"] + 2 * s["g"] * s["L"] / s["c"]
    bound = s["periods"] * (bound_impact(V1) + bound_impact(V2))
    first = -(work[np.searchsorted(t, ends[0])] - work[0])
    lo, hi = 0.5 * s["m_f"] * (s["V"] - 2 * s["g"] * h) ** 2, bound_impact(s["V"] + s["g"] * h)
    per_period = [
        -(work[np.searchsorted(t, ends[min(2 * p + 1, ends.size - 1)])] - work[0]) for p in range(s["periods"])
    ]
    print(
        f"energy: E_ref = m g h0 = {E_ref:g} J; drift after {s['periods']} periods {drift[-1]:+.4f} J "
        f"({drift[-1] / E_ref:+.3%} of E_ref), largest rise {drift.max():+.2e} J; contact work {work[-1]:+.4f} J; "
        f"balance error {balance:.1e}"
    )
    print("  cumulative loss at the end of contacts 2, 4, 6, ... (J): " + ", ".join(f"{x:.4f}" for x in per_period))
    print(
        f"  bound sum_i B(V_i) = {s['periods']} x (B({V1:g}) + B({V2:.4g})) = {bound:.4f} J "
        f"({bound / E_ref:.3%} of E_ref); first impact lost {first:.5f} J, derived within [{lo:.5f}, {hi:.5f}] J"
    )
    if not balance <= BALANCE_TOL:
        failures.append(f"energy balance error {balance:.2e} > {BALANCE_TOL:g}: gravity's work is not accounted for")
    if not rise <= ROUNDOFF * E_ref:
        failures.append(f"the contact work rose by {rise:.3e} J in a step: the Lagrange contact added energy")
    if not drift.max() <= ROUNDOFF * E_ref:
        failures.append(f"the physical energy rose {drift.max():.3e} J above its start")
    if not abs(drift[-1]) <= bound:
        failures.append(f"energy drift {drift[-1]:.4f} J exceeds the derived bound {bound:.4f} J")
    if not lo <= first <= hi:
        failures.append(f"first impact lost {first:.5f} J, outside the derived [{lo:.5f}, {hi:.5f}] J")
    if ends.size >= 2 * regular:
        loss = -(work[np.searchsorted(t, ends[2 * regular - 1])] - work[0])
        print(
            f"  the contact took {loss:.4f} J over the {regular} regular periods (recorded {FINDING_LOSS} J "
            f"+- {LOSS_BAND:.0%})"
        )
        if not abs(loss - FINDING_LOSS) <= LOSS_BAND * FINDING_LOSS:
            moved.append(
                f"the contact took {loss:.4f} J over periods 1 to {regular}, recorded {FINDING_LOSS} J "
                f"+- {LOSS_BAND:.0%}: {'better' if loss < FINDING_LOSS else 'worse'}"
            )
    print(
        f"the reference (every duration within {TOL:.0%}, {n_expected} contacts): "
        + (f"not met, {len(misses)} misses (the finding; listed with --expect-finding)" if misses else "met")
    )
    if not expect_finding:
        return verdict(failures)
    if not misses:
        failures.append(
            f"every duration is now within {TOL:.0%} over the {s['periods']} periods, {n_expected} "
            "contacts: the finding is gone; hold the default test's durations to 1 % (drop FINDING) "
            "and this registration's --expect-finding (docs/verification.md V3)"
        )
    for m in moved:
        failures.append(
            f"the finding moved: {m} (a regression if worse; if better, update FINDING in this script "
            "and docs/verification.md V3)"
        )
    if misses and not moved:
        print(
            "KNOWN FINDING (docs/verification.md V3, issue 16), still as recorded: the reference misses\n  "
            + "\n  ".join(misses)
        )
    return verdict(failures)


if __name__ == "__main__":
    sys.exit(main())
