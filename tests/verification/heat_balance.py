#!/usr/bin/env python3
"""Heat from rubbing, end to end (docs/user/heat.md): inputs/blade-casing-heat.xml for 10 revolutions,
run four times: with the thermal model and its thermal growth (the deck), with the thermal model alone ('Expansion
coefficient' 0), without it ('Conductivity' 0), and with the full thermal model and no growth.

Asserted, from the output files:
  - the partition is the effusivities' e_b / (e_b + e_c), computed here from the deck's values;
  - friction made heat (> 0), and the heat the blade received is the partition times it, to 1e-10 of
    it, at every record (every joule of the frictional heat entered the thermal model, sub-cycling
    included);
  - the tip warmed: its hottest contact node is above the reference temperature at the end, no
    contact node is below it at any record by more than 1 % of the rise (heat only enters: the lumped
    capacity keeps the full model from undershooting, this bounds the reduced basis'), the body's
    hottest node is warmer at the last record than at the first, and below titanium's melting point
    (1668 degrees C: a rub the tip survives);
  - epaphe.history() reads the thermal series as written;
  - the thermal model alone does not act on the mechanics: the contact force history is that of the run
    without it, bit for bit;
  - the reduction (42 vectors) against the full thermal model (every mode, 'Thermal->Modes' 100000) on the
    scene's own heat inputs: the contact nodes' temperatures within 1 % of the peak rise at every record;
  - the temperature field for ParaView ('Output->Fields every'): a frame's T at every node, the last one's
    hottest the last record's max_temperature exactly, and the XDMF file names it;
  - thermal growth: the tip's contact nodes move outwards (their mean radial growth at the end is > 0,
    the root being clamped), the run's contact force history differs from the one without growth, and
    every run's mechanical energy balance closes (the run's own monitor fails it otherwise);
  - the energy record's heat term (docs/theory/heat.md, eq. 63), read with epaphe.open(), in the runs with
    and without growth: the balance total + damping + friction heat - normal work - counterface work -
    external work - initial, recomputed here from the record, closes within 1e-6 of the largest energy at
    every record (and is the monitor's balance_error to 1e-9), while the same balance without the friction
    heat is off by more than the run's tolerance (1e-2): the heat term is what closes it; the record's
    friction heat is the thermal record's at the end, and its partition (heat/Blade, heat/counterface) is
    p and 1 - p of it to 1e-10;
  - a coating's plastic dissipation as a heat source (eq. 64), on a fifth run over 3 revolutions with
    blade-coating.xml's coating in front of the casing: the heat the blade received is the partition times
    the frictional work plus the coating's dissipation, to 1e-10 of the work, at every record; the thermal
    record's coating heat is the coating's plastic dissipation (/energy/plastic_dissipation) at the end to
    1e-10, and it is large enough for the check to see it left out (p times it above 1e-10 of the work); the
    energy record's shares sum to friction heat + plastic dissipation.
Figures printed: frictional power and heat, heat received, peak tip temperature rise, the tip's growth, the
smallest clearance with and without growth, and the thermal update's cost per mechanical step against the
rest of the step (a benchmark figure, not asserted). --figure PNG draws tip temperature, clearance and
contact force against time, with and without the thermal coupling."""
import argparse
import math
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from epaphe_testing import history, run, variant, verdict  # noqa: E402

import epaphe  # noqa: E402  (on the path epaphe_testing sets)

ap = argparse.ArgumentParser()
ap.add_argument("--run", required=True)
ap.add_argument("--deck", required=True)
ap.add_argument("--workdir", required=True)
ap.add_argument("--revolutions", default="10")
ap.add_argument("--figure", help="a PNG of tip temperature, clearance and contact force against time")
a = ap.parse_args()
os.makedirs(a.workdir, exist_ok=True)
common = {
    "Time->End revolutions": (a.revolutions, "double"),
    "Bodies->Blade->Reduction->Cache": ("false", "bool"),
    "Run->Progress interval": ("0", "double"),
}
cases = {
    "growth": {"Output->Fields every": ("10000", "int")},
    "heat": {"Bodies->Blade->Thermal->Expansion coefficient": ("0", "double")},
    "cold": {"Bodies->Blade->Thermal->Conductivity": ("0", "double")},
    # the reference of the reduction: every mode of the blade's thermal model (its 160 free nodes), the
    # same heat inputs (no growth: the mechanics are the heat run's, bit for bit)
    "full": {
        "Bodies->Blade->Thermal->Expansion coefficient": ("0", "double"),
        "Bodies->Blade->Thermal->Modes": ("100000", "int"),
    },
    # the coating of blade-coating.xml, its front where the rigid casing was (the casing moved out by it)
    "coating": {
        "Time->End revolutions": ("3", "double"),
        "Surfaces->Casing->Radius": ("0.3002", "double"),
        "Surfaces->Casing->Coating->Thickness": ("2e-4", "double"),
        "Surfaces->Casing->Coating->Young's modulus": ("2e9", "double"),
        "Surfaces->Casing->Coating->Yield stress": ("5e6", "double"),
        "Surfaces->Casing->Coating->Hardening modulus": ("2e8", "double"),
        "Surfaces->Casing->Coating->Elements": ("{360, 6}", "Array(int)"),
    },
}
for name, over in cases.items():
    deck = variant(
        a.deck, os.path.join(a.workdir, name + ".xml"), {**common, **over, "Output->File": (name + ".h5", "string")}
    )
    p = run([a.run, deck, "--threads", "1"], a.workdir)
    if name == "growth":
        print("\n".join(x for x in p.stdout.splitlines() if "thermal" in x))

failures = []
k, c, rho, ec = 7.0, 560.0, 4430.0, 13000.0  # the deck's blade and casing
eb = math.sqrt(k * rho * c)
files = {name: h5py.File(os.path.join(a.workdir, name + ".h5"), "r") for name in cases}
f = files["heat"]
t = f["thermal/Blade"]
p = t.attrs["partition"]
if not abs(p - eb / (eb + ec)) <= 1e-12:
    failures.append(f"partition {p} is not e_b / (e_b + e_c) = {eb / (eb + ec)}")
time, made, heat = t["time"][:], t["friction_heat"][:], t["heat"][:]
T, Tmax = t["temperature"][:], t["max_temperature"][:]
Tref = t.attrs["reference_temperature"]
rise = Tmax.max() - Tref
print(
    f"frictional heat {made[-1]:.6g} J (mean power {made[-1] / time[-1] / 1e3:.4g} kW), received by the blade "
    f"{heat[-1]:.6g} J (partition {p:.4f}); hottest tip node {T[-1].max() - Tref:.4g} K above the reference at the "
    f"end, hottest node {rise:.4g} K; lowest contact node {T.min() - Tref:.3g} K ({(T.min() - Tref) / rise:.2%} of "
    f"the rise)"
)
if not made[-1] > 0:
    failures.append("friction made no heat: the blade does not rub")
gap = np.abs(heat - p * made).max()
print(f"heat balance: |heat received - p friction heat| at most {gap / made[-1]:.2e} of the frictional heat")
if not gap <= 1e-10 * made[-1]:
    failures.append(f"heat received differs from partition x frictional heat by {gap / made[-1]:.3g} of it")
if not T[-1].max() > Tref:
    failures.append("the tip did not warm")
if not T.min() >= Tref - 0.01 * rise:
    failures.append(f"a contact node fell below the reference temperature by {Tref - T.min():.4g} K (rise {rise:.4g})")
if not Tmax[-1] > Tmax[0]:
    failures.append("the hottest node did not warm over the run")
if not Tmax.max() < 1668.0:
    failures.append(f"the hottest node reached {Tmax.max():.5g} degrees C, above titanium's melting point")
force = {name: g["bodies/Blade/contact/total_force"][:] for name, g in files.items()}
if not np.array_equal(force["heat"], force["cold"]):
    failures.append("the thermal model without thermal growth changed the contact force history")
if not np.array_equal(history(os.path.join(a.workdir, "heat.h5"))["thermal/Blade/heat"], heat):
    failures.append("epaphe.history() does not read /thermal/Blade/heat as written")

# the reduction's error against the full thermal model on the scene's own heat inputs
full = files["full"]["thermal/Blade"]
Tf = full["temperature"][:]
red_error = np.abs(T - Tf).max()
print(
    f"reduction: {t.attrs['modes']} vectors against the full model's {full.attrs['modes']}: worst contact-node "
    f"error {red_error:.3g} K over the run, {red_error / (Tf.max() - Tref):.2%} of the full model's peak rise "
    f"{Tf.max() - Tref:.4g} K; hottest node {abs(Tmax.max() - full['max_temperature'][:].max()):.3g} K apart"
)
if not np.array_equal(force["full"], force["heat"]):
    failures.append("the full thermal model's run changed the contact forces: the comparison is not on the same inputs")
if not red_error <= 0.01 * (Tf.max() - Tref):  # measured 0.23 %
    failures.append(f"the reduced thermal model is {red_error:.3g} K off the full one, above 1 % of the rise")

# thermal growth: the tip's contact nodes' radial displacement (engine axis z)
g = files["growth"]
u = g["thermal/Blade/growth"][:].reshape(len(g["thermal/Blade/time"]), -1, 3)
Tg, Tg_max = g["thermal/Blade/temperature"][:], g["thermal/Blade/max_temperature"][:]
# the blade stands along +y about the engine axis z: its tip nodes' radial direction is +y to within
# the chord's half-angle (6 degrees)
radial = u[-1, :, 1]
print(
    f"thermal growth of the tip at the end: radial (y) mean {radial.mean() * 1e6:.4g} um, largest "
    f"{radial.max() * 1e6:.4g} um; tip {Tg[-1].max() - Tref:.4g} K"
)
if not radial.mean() > 0:
    failures.append(f"the heated tip did not grow outwards: mean radial growth {radial.mean():.3g} m")
if np.array_equal(force["growth"], force["heat"]):
    failures.append("thermal growth left the contact force history unchanged: it does not reach the contact")
# the temperature field for ParaView: each frame's T at every node, its last frame the last thermal record's
field = g["bodies/Blade/fields/temperature"][:]
print(
    f"temperature field: {field.shape[0]} frames of {field.shape[1]} nodes, last frame's hottest {field[-1].max():.6g}"
)
if not (field.shape[1] == g["bodies/Blade/mesh/coordinates"].shape[0] and field[-1].max() == Tg_max[-1]):
    failures.append(
        f"the temperature field's last frame (hottest {field[-1].max()}) is not the last record ({Tg_max[-1]})"
    )
with open(os.path.join(a.workdir, "growth.xmf"), encoding="utf-8") as xmf:
    if 'Attribute Name="temperature"' not in xmf.read():
        failures.append("growth.xmf does not describe the temperature field")
clearance = {name: h["bodies/Blade/contact/gap"][:].min(axis=1) for name, h in files.items()}
print(
    "smallest clearance over the run: "
    + ", ".join(f"{name} {clearance[name].min() * 1e6:.4g} um" for name in ("growth", "heat"))
    + "; frictional heat "
    + ", ".join(f"{name} {h['thermal/Blade/friction_heat'][-1]:.5g} J" for name, h in files.items() if name != "cold")
)

# the energy record's heat term (eq. 63): the balance closes with it, and not without it
for name in ("growth", "heat"):
    with epaphe.open(os.path.join(a.workdir, name + ".h5")) as r:
        e = r.energy
        if not e.has_heat:
            failures.append(f"{name}: the energy record has no heat term")
            continue
        E, D, Q, Wn, Ws, Wx = e.total, e.damping, e.friction_heat, e.normal_work, e.counterface_work, e.external_work
        # the blade starts at rest, out of contact: its initial energy is the first record's balance
        E0 = E[0] + D[0] + Q[0] - Wn[0] - Ws[0] - Wx[0]
        scale = max(np.abs(E).max(), abs(E0))
        with_heat = np.abs(E + D + Q - Wn - Ws - Wx - E0).max() / scale
        without = np.abs(E + D - Wn - Ws - Wx - E0).max() / scale
        monitor = np.abs(e.balance_error).max()
        shares = e.heat
        pn = r.file["thermal/Blade"].attrs["partition"]
        split = max(np.abs(shares["Blade"] - pn * Q).max(), np.abs(shares["counterface"] - (1 - pn) * Q).max())
        thermal = r.file["thermal/Blade/friction_heat"][-1]
        print(
            f"{name}: energy balance with its heat term {with_heat:.2e} of the largest energy ({scale:.4g} J; the "
            f"monitor's {monitor:.2e}), without it {without:.3g}; friction heat {Q[-1]:.6g} J = counterface work "
            f"{Ws[-1]:.6g} J + normal work {Wn[-1]:.4g} J - contact work {e.contact_work[-1]:.4g} J; "
            f"partition error {split / Q[-1]:.1e}, against the thermal record {abs(Q[-1] - thermal) / Q[-1]:.1e}"
        )
        if not with_heat <= 1e-6:  # measured 1.2e-9
            failures.append(f"{name}: the energy balance with its heat term is off by {with_heat:.3g}")
        if not monitor <= 1e-6:
            failures.append(f"{name}: the monitor's balance error reached {monitor:.3g}")
        if not without > 1e-2:  # the run's 'Energy balance tolerance'
            failures.append(f"{name}: the balance closes without its heat term ({without:.3g}): the term is not tested")
        if not (split <= 1e-10 * Q[-1] and abs(Q[-1] - thermal) <= 1e-10 * Q[-1]):
            failures.append(f"{name}: the heat's partition in the energy record is off by {split:.3g} J")

# the coating's plastic dissipation as a heat source (eq. 64)
c = files["coating"]
ct = c["thermal/Blade"]
made_c, plastic_c, heat_c = ct["friction_heat"][:], ct["coating_heat"][:], ct["heat"][:]
work = made_c[-1] + plastic_c[-1]
gap_c = np.abs(heat_c - p * (made_c + plastic_c)).max()
dissipated = c["energy/plastic_dissipation"][-1]
shares = c["energy/heat/Blade"][-1] + c["energy/heat/counterface"][-1]
print(
    f"coating: frictional heat {made_c[-1]:.6g} J, coating dissipation {plastic_c[-1]:.4g} J (the coating's own "
    f"{dissipated:.4g} J, {abs(plastic_c[-1] - dissipated) / dissipated:.1e} apart), received {heat_c[-1]:.6g} J: "
    f"|heat - p (friction + coating)| at most {gap_c / work:.2e} of the work, p x coating {p * plastic_c[-1] / work:.2e} "
    f"of it; energy record's shares {abs(shares - c['energy/friction_heat'][-1] - dissipated) / work:.1e} off"
)
if not gap_c <= 1e-10 * work:
    failures.append(f"coating: the heat received is off p (friction + coating) by {gap_c / work:.3g} of the work")
if not (plastic_c[-1] > 0 and abs(plastic_c[-1] - dissipated) <= 1e-10 * dissipated):
    failures.append(f"coating: coating heat {plastic_c[-1]:.6g} J is not the coating's dissipation {dissipated:.6g} J")
if not p * plastic_c[-1] > 1e-8 * work:
    failures.append("coating: the coating's dissipation is too small for the heat balance to see it")
if not abs(shares - c["energy/friction_heat"][-1] - dissipated) <= 1e-10 * work:
    failures.append("coating: the energy record's heat shares do not sum to friction heat + plastic dissipation")

# the thermal update's cost per mechanical step (a figure: benchmarks report, tests do not time)
steps = float(f["/run"].attrs["steps"])
cost = {kk: 1e6 * v / steps for kk, v in f["/run/cost"].attrs.items()}
thermal = cost.get("thermal", 0.0)
rest = sum(v for kk, v in cost.items() if kk != "thermal")
print(
    f"thermal update {thermal:.3g} us per mechanical step, the rest of the step {rest:.3g} us: "
    f"{100 * thermal / rest:.2f} % (" + ", ".join(f"{kk} {v:.3g}" for kk, v in sorted(cost.items())) + ")"
)

if a.figure:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(3, 1, figsize=(8, 8), sharex=True)
    for name, style in (("growth", "-"), ("heat", "--")):
        h = files[name]
        label = "with thermal growth" if name == "growth" else "without (heat only)"
        tt = h["thermal/Blade/time"][:]
        ax[0].plot(1e3 * tt, h["thermal/Blade/temperature"][:].max(axis=1) - Tref, style, label=label)
        tm = h["time"][:]
        ax[1].plot(1e3 * tm, 1e6 * clearance[name], style, label=label)
        ax[2].plot(1e3 * tm, force[name], style, label=label)
    # the clearance the growth closes: the tip's largest radial (y) growth, against the rubs' depth
    ug = g["thermal/Blade/growth"][:].reshape(len(g["thermal/Blade/time"]), -1, 3)[:, :, 1].max(axis=1)
    ax[1].plot(1e3 * g["thermal/Blade/time"][:], 1e6 * ug, ":", color="k", label="tip's thermal growth (largest)")
    ax[1].set_ylim(-4, 6)  # the rubs (negative: the tip's penetration under the penalty), not the open clearance
    ax[1].legend(loc="upper left", fontsize="small")
    ax[0].set_ylabel("hottest tip node, T - T_ref (K)")
    ax[1].set_ylabel("smallest tip clearance (um)")
    ax[2].set_ylabel("total contact force (N)")
    ax[2].set_xlabel("time (ms)")
    ax[0].legend()
    fig.tight_layout()
    fig.savefig(a.figure, dpi=100)
    print(f"figure: {a.figure}")
for h in files.values():
    h.close()
sys.exit(verdict(failures))
