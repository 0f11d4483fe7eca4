#!/usr/bin/env python3
"""V4 (docs/verification.md; Johnson, Contact Mechanics, ch. 11): Hertz impact of an elastic ball on a
rigid plane, at three mesh sizes. A convergence check of the contact path (rigid B-spline plane,
node projection, forward-increment Lagrange) on a curved body: not an exact FE solution, so what is
asserted is that the results converge with refinement, and that the finest mesh is within TOL of
Hertz.

Hertz, for a ball of mass m, radius R on a rigid half-space (m* = m, R* = R, 1/E* = (1 - nu^2)/E):
  delta_max = (15 m v0^2 / (16 E* sqrt(R)))^(2/5),  F_max = (4/3) E* sqrt(R) delta_max^(3/2),
  t_c = 2.94 delta_max / v0 = 2.87 (m^2 / (R E*^2 v0))^(1/5).
It holds when the strains are small (delta_max / R ~ 1 %: the contact radius a = sqrt(R delta) is
0.1 R, so the half-space idealization is fair) and the impact quasi-static (t_c several times the
wave transit 2R/c_d): both are computed from the deck and checked before anything runs.

Measured, per mesh (deck's ball, cube of n^3 hexahedra mapped onto it, graded to the lower pole):
  - F_max: the largest total contact force;
  - delta_max: Hertz's delta is the approach of distant points, i.e. of the ball's centre of mass
    (the body of Hertz's impact ODE m d^2 delta/dt^2 = -F(delta)). Its z is integrated (trapezoid)
    from the run's momentum record p_z / m, which comes from the velocity field, not from the
    contact force; delta(t) = z_cm(t_0) - z_cm(t), t_0 the first step with a contact force;
  - t_c: from the first to the last step with a contact force, plus one step.
The errors are against Hertz for the ball's exact mass. Printed beside them (not asserted): the
errors against Hertz for the mesh's own mass m_h (the faceted ball is lighter: delta and t_c scale
as m^(2/5), F_max as m^(3/5)), which separate the contact's error from the volume's.
Asserted:
  - each of the three converges with the mesh: the change between successive meshes falls (self-
    convergence). Not that the error against Hertz falls at every refinement, as docs/verification.md
    V4 first asked: the FE ball converges to its own limit, which differs from Hertz's half-space by
    O(a/R) (finding, measured: at 16^3 and 24^3 the errors are +4.2/+5.0 % on F_max, -4.0/-3.3 % on
    delta, -4.4/-3.6 % on t_c, and at v0 = 2 m/s, a/R 1.7x smaller, the offsets are about 1.7x
    smaller); once the discretization error is below that offset the error against Hertz need not
    shrink (F_max: -7.7 %, +2.3 %, +4.2 % on 8^3, 12^3, 16^3 crosses it);
  - on the finest mesh each is within TOL = 5 % of Hertz. Where 5 % comes from: the finest mesh
    (16^3, pole grading 0.15) puts about 6 element widths (0.016 R) across the contact radius a =
    0.097 R, with the contact force lumped on its nodes (the pressure sqrt(1 - r^2/a^2) is resolved
    to a few %), and its faceted ball is 1.6 % light (-0.6 % on delta and t_c, -1 % on F_max, which
    scale as m^(2/5) and m^(3/5)); Hertz itself is a limit: the
    finite ball differs from the half-space by O(a/R) = 10 % in the far-field part of the approach,
    of which a small share reaches delta (the local indentation dominates); the impact is
    quasi-static only to O((2R/c_d) / t_c)^2 = 1 %. 5 % is the sum of these orders, stated before
    the numbers were seen, not a fit to them;
  - the run's energy balance closes (|error| < 1e-6, the driver's own tolerance) and the ball
    leaves the plane (coefficient of restitution printed, > 0.8: Hertz's elastic impact returns all
    but the energy left in vibrations and the Lagrange impact loss).
"""
import math
import os
import sys
import time
import xml.etree.ElementTree as ET

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from epaphe_testing import deck_value, history, parse_args, run, variant, verdict  # noqa: E402

# elements per direction of the mapped cube, coarse to fine (V4_MESHES=16,24 for a study; 24^3 takes
# about 2 min on 1 thread, too long for the ctest)
MESHES = tuple(int(x) for x in os.environ.get("V4_MESHES", "8,12,16").split(","))
TOL = 0.05  # finest mesh against Hertz, see the docstring
BALANCE_TOL = 1e-6  # Output->Energy balance tolerance's default
STEP_FRACTION = 0.9  # time step / critical step


def hertz(deck):
    """The deck's setting and Hertz's numbers."""
    root = ET.parse(deck).getroot()
    b = "Bodies->Ball->"
    assert deck_value(root, b + "Mesh->Type") == "Sphere", "V4 needs the Sphere mesh"
    R = float(deck_value(root, b + "Mesh->Radius"))
    c = deck_value(root, b + "Mesh->Center")
    E = float(deck_value(root, b + "Material->Young's modulus"))
    nu = float(deck_value(root, b + "Material->Poisson's ratio"))
    rho = float(deck_value(root, b + "Material->Density"))
    v = deck_value(root, b + "Initial velocity")
    o, U, V = (deck_value(root, "Surfaces->Ground->" + k) for k in ("Origin", "U", "V"))
    assert v[0] == v[1] == 0 and v[2] < 0, f"initial velocity {v}: V4 drops the ball along -z"
    assert U[2] == V[2] == 0, "the plane must be horizontal (z = const)"
    s = dict(R=R, E=E, nu=nu, rho=rho, v0=-v[2], gap=(c[2] - R) - o[2], end=float(deck_value(root, "Time->End time")))
    assert s["gap"] > 0, f"the plane is {s['gap']} m from the lower pole: it must be below it"
    s["Es"] = E / (1 - nu**2)
    s["m"] = 4 / 3 * math.pi * R**3 * rho
    s["delta"] = (15 * s["m"] * s["v0"] ** 2 / (16 * s["Es"] * math.sqrt(R))) ** 0.4
    s["F"] = 4 / 3 * s["Es"] * math.sqrt(R) * s["delta"] ** 1.5
    s["t_c"] = 2.87 * (s["m"] ** 2 / (R * s["Es"] ** 2 * s["v0"])) ** 0.2
    s["a"] = math.sqrt(R * s["delta"])
    s["c_d"] = math.sqrt(E * (1 - nu) / (rho * (1 + nu) * (1 - 2 * nu)))
    s["transit"] = 2 * R / s["c_d"]
    return s


def measure(hist, s):
    t = hist["time"]
    h = float(np.diff(t).mean())
    assert np.allclose(np.diff(t), h, rtol=1e-6), "records must be every step (Output->Every = 1)"
    F = hist["bodies/Ball/contact/total_force"]
    on = np.flatnonzero(F > 0)
    assert on.size > 0, "no contact at all"
    i0, i1 = on[0], on[-1]
    gaps = int(np.count_nonzero(np.diff(on) > 1))
    m = float(hist["bodies/Ball/attrs"]["rigid_mass"])
    vz = hist["bodies/Ball/momentum"][:, 2] / m
    z = np.concatenate([[0.0], np.cumsum(0.5 * (vz[1:] + vz[:-1]) * h)])
    delta = z[i0] - z
    return dict(
        h=h,
        F=float(F.max()),
        delta=float(delta.max()),
        t_c=float(t[i1] - t[i0] + h),
        gaps=gaps,
        mass=m,
        restitution=float(vz[-1] / s["v0"]),
        pole_speed=float(-hist["bodies/Ball/nodesets/z-pole/velocity"][i0 - 1, 0, 2] / s["v0"]),
        ended=bool(i1 < t.size - 1),
        balance=float(np.abs(hist["energy/balance_error"]).max()),
    )


def main():
    a = parse_args()
    s = hertz(a.deck)
    failures = []
    print(f"V4 Hertz impact: R = {s['R']:g} m, E* = {s['Es']:.4g} Pa, m = {s['m']:.5g} kg, v0 = {s['v0']:g} m/s")
    print(
        f"Hertz: delta_max = {s['delta']:.5g} m ({s['delta'] / s['R']:.3%} of R), F_max = {s['F']:.5g} N, "
        f"t_c = {s['t_c']:.5g} s, contact radius a = {s['a']:.4g} m ({s['a'] / s['R']:.3f} R)"
    )
    print(
        f"quasi-static: wave transit 2R/c_d = {s['transit']:.4g} s (c_d = {s['c_d']:.5g} m/s), "
        f"t_c / transit = {s['t_c'] / s['transit']:.2f}"
    )
    # Hertz's assumptions, from the deck (docs/verification.md V4 compares with the quasi-static theory)
    if not 0.002 <= s["delta"] / s["R"] <= 0.02:
        failures.append(
            f"delta_max / R = {s['delta'] / s['R']:.3%}: outside [0.2 %, 2 %], Hertz's small strain "
            "and half-space assumptions do not hold; change the speed"
        )
    if not s["t_c"] >= 5 * s["transit"]:
        failures.append(
            f"t_c = {s['t_c'] / s['transit']:.2f} wave transits: below 5, the impact is not "
            "quasi-static; lower the speed or the radius"
        )
    if not s["end"] >= s["gap"] / s["v0"] + 1.1 * s["t_c"]:
        failures.append(
            f"End time {s['end']:g} s: the contact (gap {s['gap']:g} m at {s['v0']:g} m/s, then about "
            f"{s['t_c']:.3g} s) would not be over; raise it"
        )
    if failures:
        return verdict(failures)

    rows = []
    for n in MESHES:
        common = {
            "Bodies->Ball->Mesh->Elements": (f"{{{n}, {n}, {n}}}", "Array(int)"),
            "Run->Progress interval": ("0", "double"),
        }
        # 1. the critical step of this mesh (epaphe-run's estimate, written to the output)
        probe = variant(
            a.deck,
            os.path.join(a.workdir, f"probe-{n}.xml"),
            dict(
                common,
                **{
                    "Output->File": f"probe-{n}.h5",
                    "Time->Time step": ("1e-12", "double"),
                    "Time->End time": ("2e-12", "double"),
                },
            ),
        )
        run([a.run, probe, "--threads", "1"], a.workdir)
        crit = float(history(os.path.join(a.workdir, f"probe-{n}.h5"))["attrs"]["critical_time_step"])
        h = float(f"{STEP_FRACTION * crit:.3e}")
        # 2. the impact
        deck = variant(
            a.deck,
            os.path.join(a.workdir, f"hertz-{n}.xml"),
            dict(common, **{"Output->File": f"hertz-{n}.h5", "Time->Time step": (repr(h), "double")}),
        )
        wall = time.time()
        run([a.run, deck, "--threads", "1"], a.workdir)
        wall = time.time() - wall
        hist = history(os.path.join(a.workdir, f"hertz-{n}.h5"))
        r = measure(hist, s)
        r.update(
            n=n, dofs=int(hist["bodies/Ball/attrs"]["reduced_dofs"]), crit=crit, wall=wall, steps=int(hist["time"].size)
        )
        for k, power in (("F", 0.6), ("delta", 0.4), ("t_c", 0.4)):
            r["e_" + k] = (r[k] - s[k]) / s[k]
            ref = s[k] * (r["mass"] / s["m"]) ** power
            r["eh_" + k] = (r[k] - ref) / ref
        rows.append(r)
        print(
            f"  n = {n}: {r['dofs']} DOFs, h = {h:.3e} s ({STEP_FRACTION:g} of critical {crit:.4e} s), "
            f"{r['steps']} steps in {wall:.1f} s; ball mass {r['mass']:.5g} kg",
            flush=True,
        )

    print(
        " mesh | DOFs   | F_max (N)            | delta_max (m)         | t_c (s)               | "
        "errors vs Hertz(m_h): F, delta, t_c | restit. | run (s)"
    )
    for r in rows:
        print(
            f" {r['n']:2d}^3 | {r['dofs']:6d} | {r['F']:9.4g} ({r['e_F']:+7.2%}) | {r['delta']:10.5g} "
            f"({r['e_delta']:+7.2%}) | {r['t_c']:10.5g} ({r['e_t_c']:+7.2%}) | {r['eh_F']:+7.2%} "
            f"{r['eh_delta']:+7.2%} {r['eh_t_c']:+7.2%} (m_h/m - 1 = {r['mass'] / s['m'] - 1:+.2%}) "
            f"| {r['restitution']:7.4f} | {r['wall']:6.1f}"
        )
    print(f" Hertz | {'':6s} | {s['F']:9.4g}            | {s['delta']:10.5g}           | {s['t_c']:10.5g}")
    for r in rows:
        if r["gaps"]:
            print(f"  n = {r['n']}: the contact force vanished and returned {r['gaps']} time(s) inside the contact")
        if not r["ended"]:
            failures.append(f"n = {r['n']}: still in contact at the end of the run; raise End time")
        if not r["balance"] < BALANCE_TOL:
            failures.append(f"n = {r['n']}: energy balance error {r['balance']:.2e} >= {BALANCE_TOL:g}")
        if not r["restitution"] > 0.8:
            failures.append(f"n = {r['n']}: the ball leaves at {r['restitution']:.3f} v0 upwards, not above 0.8 v0")
        if not abs(r["pole_speed"] - 1) < 1e-6:
            failures.append(
                f"n = {r['n']}: the pole arrives at {r['pole_speed']:.6f} v0, not v0: the ball was "
                "not in free flight before the contact"
            )
    for k, name in (("F", "F_max"), ("delta", "delta_max"), ("t_c", "t_c")):
        errs = [abs(r["e_" + k]) for r in rows]
        steps = [abs(r1[k] - r0[k]) / s[k] for r0, r1 in zip(rows, rows[1:])]
        print(f"{name}: change between successive meshes " + ", ".join(f"{x:.2%}" for x in steps))
        for (r0, r1), d0, d1 in zip(zip(rows[1:], rows[2:]), steps, steps[1:]):
            if not d1 < d0:
                failures.append(
                    f"{name}: the change from n = {r0['n']} to n = {r1['n']} ({d1:.2%} of Hertz) is not "
                    f"below the previous one ({d0:.2%}): the mesh sequence does not converge"
                )
        if not errs[-1] <= TOL:
            failures.append(
                f"{name}: finest mesh (n = {rows[-1]['n']}) {rows[-1][k]:.5g}, Hertz {s[k]:.5g}: "
                f"error {rows[-1]['e_' + k]:+.2%} beyond {TOL:.0%}"
            )
    return verdict(failures)


if __name__ == "__main__":
    sys.exit(main())
