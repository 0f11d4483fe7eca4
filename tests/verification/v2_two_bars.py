#!/usr/bin/env python3
"""V2 (docs/verification.md; code_aster SDNL111A): two identical bars, the impacting one at 1 m/s
against one clamped at its far end; a flexible body against a surface carried by another flexible
body, both corrected together (thesis eq. 2.33).

Exact solution (1-D waves, c = sqrt(E / rho), T = L / c): the contact faces move together at
-v/2 until 2T, come back at +v/2 until 4T, where the bars part; the impacting bar then leaves at
+v. So the displacement of the contact face of the impacting bar is
    u = -v t / 2 (t <= 2T),  -v T + v (t - 2T) / 2 (2T <= t <= 4T),  v (t - 4T) (t >= 4T).
docs/verification.md's table is this curve with c = 5000 m/s (T = 0.2 ms); with the deck's steel
(E = 2e11, rho = 7800) c = 5063.7 m/s, so its "exact" column is off by up to 5 % at 1 ms (at 4T
the bars part 1.3 % earlier). We check every row against the exact curve at the model's own c,
with code_aster's tolerance of that row (relative, or 1e-5 m absolute at 0.8 ms), and that our
error is below code_aster's own at every row. The table names the node "of the struck bar": its values
after the bars part (+2e-4 m at 1 ms, moving at +1 m/s) are the impacting bar's; before, the two
faces coincide, which we check as well (the gap closes to round-off under Lagrange).

Modes: code_aster uses 40 modes. At 40 fixed-interface modes per bar (run here) every row is within
code_aster's tolerance (asserted), but our error is not below code_aster's at 0.4 ms (1.85 % against
0.64 %) and 0.8 ms (4.6e-6 m against 2.1e-6 m): 40 modes of a 3-D bar include its bending and
torsion modes, which the axial impact does not excite. Measured (20 / 40 / 60 / 100 modes): rows
outside code_aster's tolerance at 20 modes (0.2, 0.4, 1.0 ms); not below code_aster's error at 0.4
and 0.8 ms with 40 and 60 modes; every row within tolerance and below code_aster's error at the
deck's 100, where "closer than code_aster" is asserted. The rest is checked on the deck (100 modes)."""
import sys
import xml.etree.ElementTree as ET

import numpy as np

import epaphe_testing as et

a = et.parse_args()
ex = et.exact_solution("two-bars", a.deck, a.run)  # epaphe-sweep's, from the deck (E, rho, L, v)
c, T, v = ex.c, ex.T, ex.v0


def exact(t):
    return ex.face(np.atleast_1d(t))[0]


rows = [  # t (ms), table exact, code_aster, tolerance (relative, or absolute when exact is 0)
    (0.2, -1.0e-4, -1.0078e-4, 0.01),
    (0.4, -2.0e-4, -1.9373e-4, 0.035),
    (0.6, -1.0e-4, -9.558e-5, 0.05),
    (0.8, 0.0, 7.97e-6, 1e-5),
    (1.0, 2.0e-4, 2.0616e-4, 0.035),
]

failures = []


def table(deck, name, closer):
    """Runs `deck`, prints the table's rows against the exact curve and code_aster, appends a failure
    for every row outside code_aster's tolerance and, if `closer`, for every row where our error is
    not below code_aster's. Returns the history and the impacting bar's face displacement."""
    et.run([a.run, deck, "--output", name + ".h5"], a.workdir)
    h = et.history(f"{a.workdir}/{name}.h5")
    t = h["time"]
    u_imp = h["bodies/Free bar/nodesets/x-/displacement"][:, :, 0].mean(axis=1)
    modes = (
        ET.parse(deck)
        .getroot()
        .find(
            "./ParameterList[@name='Bodies']/ParameterList[@name='Free bar']/"
            "ParameterList[@name='Reduction']/Parameter[@name='Fixed-interface modes']"
        )
    )
    print(f"{name}: {modes.get('value')} fixed-interface modes per bar")
    print(" t (ms)   exact(c)     ours        error    tol    code_aster  its error   table exact")
    for tm, tab, aster, tol in rows:
        ts = tm * 1e-3
        i = int(np.argmin(abs(t - ts)))
        assert abs(t[i] - ts) < 1e-9, f"no record at {tm} ms"
        ue = float(exact(ts))
        ours = float(u_imp[i])
        if tab == 0.0:
            err, err_aster, ok = abs(ours - ue), abs(aster - ue), abs(ours - ue) <= tol
            fmt = f"{err:9.2e} m"
        else:
            err, err_aster = abs(ours - ue) / abs(ue), abs(aster - ue) / abs(ue)
            ok = err <= tol
            fmt = f"{100 * err:7.3f} % "
        print(
            f" {tm:5.2f}  {ue: .4e}  {ours: .4e}  {fmt} {tol:6g}  {aster: .4e}  "
            f"{(f'{err_aster:9.2e} m' if tab == 0.0 else f'{100 * err_aster:7.3f} % ')}  {tab: .1e}"
            f"{'' if err < err_aster else '  (not below code_aster)'}"
        )
        if not ok:
            failures.append(f"{name}, t = {tm} ms: {ours:.5e} against exact {ue:.5e} (tolerance {tol})")
        if closer and err >= err_aster:
            failures.append(f"{name}, t = {tm} ms: our error {err:.3e} is not below code_aster's {err_aster:.3e}")
    return h, u_imp


print(f"c = {c:.1f} m/s, T = L/c = {T * 1e3:.5f} ms")
# code_aster's own number of modes, 40 per bar: every row within its tolerance. Closer than
# code_aster at 40 modes is not met (measured: 0.4 ms 1.85 % against its 0.64 %, 0.8 ms 4.6e-6 m
# against 2.1e-6 m; our 40 modes of a 3-D bar include its bending and torsion modes, code_aster's
# are a 1-D bar's): it is asserted at the deck's 100 modes, and reported at 40 (issue 13).
table(
    et.variant(
        a.deck,
        f"{a.workdir}/two-bars-40.xml",
        {f"Bodies->{b}->Reduction->Fixed-interface modes": ("40", "int") for b in ("Struck bar", "Free bar")},
    ),
    "two-bars-40",
    closer=False,
)
h, u_imp = table(a.deck, "two-bars", closer=True)
t = h["time"]
u_struck = h["bodies/Struck bar/nodesets/x+/displacement"][:, :, 0].mean(axis=1)
gap = h["bodies/Free bar/contact/gap"]
force = h["bodies/Free bar/contact/total_force"]

# The two faces coincide while in contact (Lagrange closes the gap), and part at 4T.
contact = force > 1e-6 * force.max()
last = t[contact][-1]
print(f"contact from {t[contact][0] * 1e3:.4f} ms to {last * 1e3:.4f} ms (exact 0 to 4T = {4 * T * 1e3:.4f} ms)")
if abs(last - 4 * T) > 0.02 * 4 * T:
    failures.append(f"the bars part at {last * 1e3:.4f} ms, exact 4T = {4 * T * 1e3:.4f} ms (2 % allowed)")
pen = -gap[contact].min()
print(
    f"largest penetration while in contact {pen:.2e} m; faces' difference "
    f"{abs(u_imp[contact] - u_struck[contact]).max():.2e} m"
)
if pen > 1e-9:
    failures.append(f"penetration {pen:.2e} m > 1e-9 m under Lagrange")
# Momentum: the impacting bar leaves at +v (the clamped bar reflects the whole wave); energy.
m = h["bodies/Free bar/attrs"]["rigid_mass"]
vout = h["bodies/Free bar/momentum"][-1, 0] / m
print(f"impacting bar leaves at {vout:.4f} m/s (exact {v}); energy balance {abs(h['energy/balance_error']).max():.1e}")
if abs(vout - v) > 0.01 * v:
    failures.append(
        f"rebound velocity {vout:.4f} m/s, exact {v} (1 % allowed: the forward increment arrests "
        "the faces' effective mass at impact, 0.7 % with the deck's 100 modes)"
    )
if abs(h["energy/balance_error"]).max() > 1e-8:
    failures.append("energy balance error above 1e-8")
sys.exit(et.verdict(failures))
