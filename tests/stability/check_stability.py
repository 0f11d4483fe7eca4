#!/usr/bin/env python3
"""Hard cases of contact dynamics (label `stability`): each case runs a deck of decks/ (or a variant of
it) and asserts that the history holds no NaN/Inf, that the energy balance error stays within a stated
bound, that the largest penetration after correction (-gap of /bodies/<b>/contact/gap, the gap at the
corrected q_n) stays within a stated bound, plus what the case is about -- or that the run is refused
with a clear message when that is the right answer.

    check_stability.py --run EPAPHE_RUN --case NAME --workdir DIR     (--case list: the cases)

Every bound is derived, not drawn around a measured value (see `Bounds` below); measured figures are
printed (`measured: ...`) next to them. Any failed check raises: the script then exits with a
non-zero code (and never prints PASSED)."""
import argparse
import os
import re
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "verification"))
import epaphe_testing as et  # noqa: E402
import epaphe  # noqa: E402  (epaphe_testing put python/ on the path)

BEYOND = 1e299  # gap of a node beyond every surface is 1e300


def read(path):
    """(status, {dataset path: array} of every numeric dataset) of a run."""
    with epaphe.open(path) as run:
        return run.status, run.flat()


def bodies(data):
    return sorted({k.split("/")[1] for k in data if k.startswith("bodies/")})


def common(data, balance_bound, penetration_bound, name):
    """No NaN/Inf anywhere, energy balance and penetration within bounds; returns the measures."""
    for k, v in data.items():
        if k.startswith("checkpoint/") and k.endswith("/warm_start"):
            continue  # restart state: NaN there means "no closest point yet" (a cold start), by design
        assert np.all(np.isfinite(v)), f"{name}: {k} holds NaN or Inf"
    bal = float(np.max(np.abs(data["energy/balance_error"])))
    pen = 0.0
    for b in bodies(data):
        g = data.get(f"bodies/{b}/contact/gap")
        if g is not None:
            g = g[1:]  # record 0 is the initial state, before any correction
            inside = g[g < BEYOND]
            if inside.size:
                pen = max(pen, float(-inside.min()))
    print(
        f"measured: {name}: max |energy balance error| = {bal:.3e} (bound {balance_bound:.3e}, "
        f"{bal / balance_bound:.2g} of it), max penetration = {pen:.3e} m (bound {penetration_bound:.3e} m, "
        f"{pen / penetration_bound if penetration_bound > 0 else 0:.2g} of it)"
    )
    assert bal <= balance_bound, f"{name}: energy balance error {bal:.3e} > {balance_bound:.3e}"
    assert pen <= penetration_bound, f"{name}: penetration {pen:.3e} m > {penetration_bound:.3e} m"
    return bal, pen


def positions(data, body, nodes):
    """Positions (records x len(nodes) x 3) of body nodes, from the field frames."""
    pos = data[f"bodies/{body}/fields/position"]
    return pos[:, nodes, :]


# ---- case-specific checks ------------------------------------------------------------------------
def check_grazing(data):
    u = data["bodies/Block/nodesets/y-/displacement"]
    f = data["bodies/Block/contact/force"]
    lift = float(np.max(np.abs(u[:, :, 1])))
    print(
        f"measured: grazing: largest normal displacement of the sliding face {lift:.3e} m, "
        f"largest contact force {f.max():.3e} N"
    )
    # it rests on the plane: the corrections keep it there to the penetration bound (lagrange), and
    # nothing pushes it off
    assert (
        lift <= BOUNDS["penetration"]
    ), f"grazing: the face left the plane by {lift:.3e} m (bound {BOUNDS['penetration']:.3e})"
    ux = u[-1, :, 0]
    t = data["time"][-1]
    assert np.allclose(ux, 5.0 * t, rtol=1e-3), f"grazing: slid {ux} m, expected {5 * t} m"


def check_stick(data):
    f = data["bodies/Block/contact/force"]
    u = data["bodies/Block/nodesets/y-/displacement"]
    assert np.array_equal(data["bodies/Block/contact/nodes"], data["bodies/Block/nodesets/y-/nodes"])
    t = data["time"]
    both = (f[:-1] > 0) & (f[1:] > 0)  # node in contact at two successive records
    assert both.any(), "stick: no contact"
    step = np.linalg.norm(u[1:, :, [0, 2]] - u[:-1, :, [0, 2]], axis=2)
    slip = float(step[both].max())
    free = 0.5 * float(np.max(np.diff(t)))  # what the tangential velocity would slide in one record
    stuck = float(np.mean(step[both] < 1e-12))
    print(
        f"measured: stick: {int(both.sum())} node-records in contact, {stuck * 100:.0f} % without slip (< 1e-12 m), "
        f"largest slip between two records {slip:.3e} m (free sliding {free:.3e} m)"
    )
    assert stuck >= 0.75, f"stick: only {stuck * 100:.0f} % of the node-records in contact stuck"
    assert slip <= 0.1 * free, f"stick: the nodes slid {slip:.3e} m while in contact"


def check_seam(data):
    nodes = data["bodies/Block/contact/nodes"]
    x = positions(data, "Block", nodes)
    f = data["bodies/Block/contact/force"]
    g = data["bodies/Block/contact/gap"]
    # records with contact while the face straddles the seam or lies past it
    crossed = [k for k in range(len(f)) if f[k].max() > 0 and x[k, :, 1].max() > 1e-4]
    print(
        f"measured: seam: {len(crossed)} records in contact past the seam (y > 0), final y of the face "
        f"{x[-1, :, 1].min():.4f}..{x[-1, :, 1].max():.4f} m, radius {np.hypot(x[-1, :, 0], x[-1, :, 1]).max():.6f} m"
    )
    r = np.hypot(x[:, :, 0], x[:, :, 1])
    dev = float(np.max(np.abs(g - (0.1 - r))))  # gap = distance to the wall, across the seam too
    seam = np.abs(np.degrees(np.arctan2(x[:, :, 1], x[:, :, 0]))) < 1.0
    print(
        f"measured: seam: gap against the exact distance to the wall within {dev:.2e} m over all records, "
        f"{int(seam.sum())} node-records within 1 degree of the seam"
    )
    assert dev <= 1e-6, f"seam: gap off the distance to the wall by {dev:.2e} m"
    assert seam.any(), "seam: no node near the seam"
    assert crossed, "seam: no contact past the seam"
    assert np.all(g < BEYOND), "seam: a node was lost (beyond the surface) on a closed surface"
    assert np.hypot(x[:, :, 0], x[:, :, 1]).max() <= 0.1 + 1e-6, "seam: a node went through the wall"


def check_corner_edge(data):
    f = data["bodies/Block/contact/force"]
    touched = (f > 0).any(axis=0)
    print(f"measured: patch-corner-edge: {touched.sum()} of {touched.size} nodes took a force")
    assert touched.all(), f"patch-corner-edge: nodes {np.where(~touched)[0]} never touched the plane"


def check_open_edge(data):
    nodes = data["bodies/Block/contact/nodes"]
    x = positions(data, "Block", nodes)
    f = data["bodies/Block/contact/force"]
    g = data["bodies/Block/contact/gap"]
    edge = 0.02 + 1e-3 * 0.01 + 5e-6  # plane's edge + edge tolerance (1e-3 of a 1 cm patch) + one step
    beyond = x[:, :, 0] > edge
    corrected_beyond = int((beyond & (f > 0)).sum())
    print(
        f"measured: open-edge: {int(beyond.sum())} node-records beyond the edge, {corrected_beyond} of them "
        f"corrected; lowest node beyond the edge at y = {x[:, :, 1][beyond].min() if beyond.any() else 0:.3e} m"
    )
    assert beyond.any() and beyond[-1].all(), "open-edge: the block did not leave the plane"
    assert corrected_beyond == 0, "open-edge: nodes beyond the edge were corrected"
    assert np.all(g[beyond] > BEYOND), "open-edge: nodes beyond the edge were still projected on the plane"


def check_many_nodes(data):
    f = data["bodies/Block/contact/force"]
    touched = (f > 0).any(axis=0)
    print(f"measured: many-nodes: {touched.sum()} of {touched.size} nodes took a force")
    assert touched.size == 121 and touched.all(), "many-nodes: not every node touched the patch"


def check_two_surfaces(data):
    nodes = data["bodies/Block/contact/nodes"]
    x = positions(data, "Block", nodes)
    f = data["bodies/Block/contact/force"]
    onWall = np.abs(x[0, :, 0] - x[0, :, 0].min()) < 1e-9  # x- face
    onFloor = np.abs(x[0, :, 1] - x[0, :, 1].min()) < 1e-9  # y- face
    both = [k for k in range(len(f)) if f[k, onWall & ~onFloor].max() > 0 and f[k, onFloor & ~onWall].max() > 0]
    print(f"measured: two-surfaces: {len(both)} records with forces on the wall and the floor at once")
    assert both, "two-surfaces: never in contact with both surfaces at once"


def check_impact(data):
    f = data["bodies/Cube/contact/total_force"]
    p = data["bodies/Cube/momentum"][:, 1]
    print(
        f"measured: impact-100: largest total contact force {f.max():.3e} N, momentum y {p[0]:.3e} -> {p[-1]:.3e} kg m/s"
    )
    assert f.max() > 0 and p[-1] > p[0], "impact-100: the cube did not hit the rings"


def check_free_vibration(data):
    tot = data["energy/total"]
    strain = data["energy/strain"]
    drift = float(np.max(np.abs(tot - tot[0])) / tot[0])
    print(
        f"measured: free-vibration: {len(tot)} records over {data['time'][-1]:.3g} s, relative energy drift "
        f"{drift:.3e}, largest strain energy {strain.max() / tot[0]:.3f} of the total"
    )
    # no force does work: the drift is the balance error, under the same round-off bound
    assert drift <= BOUNDS["balance"], f"free-vibration: energy drifted by {drift:.3e} (bound {BOUNDS['balance']:.3e})"
    assert strain.max() > 0.01 * tot[0], "free-vibration: the beam does not vibrate"


def check_rubbing(data):
    p = data["bodies/Block/momentum"][:, 0]
    work = data["energy/contact_work"]
    f = data["bodies/Block/contact/force"]
    print(
        f"measured: rubbing: momentum x {p[0]:.4e} -> {p[-1]:.4e} kg m/s, contact work {work[-1]:.3e} J, "
        f"{(f.sum(axis=1) > 0).mean() * 100:.0f} % of the records in contact"
    )
    assert work[-1] < 0, "rubbing: friction dissipated nothing"
    assert p[-1] < p[0], "rubbing: friction did not slow the block"
    assert p[-1] > 0.2 * p[0], "rubbing: the block stopped: it no longer rubs"
    assert (f.sum(axis=1) > 0).mean() > 0.5, "rubbing: the block was not pressed"


# ---- bounds ---------------------------------------------------------------------------------------
# Energy balance (the largest |balance error|, relative to the initial energy E0). In exact arithmetic
# it is zero: the balance is the central difference's own energy identity, with the work of the
# contact (and friction) forces computed from the forces the correction applied. What is left is
# round-off. Each step rounds every q_{n+1} = 2 q_n - q_{n-1} + h^2 a (three operations) by at most
# 3 eps |q_n|: a velocity change of 3 eps |q_n| / h that no force accounts for, which changes the
# kinetic energy, relative to E0 = 1/2 m v0^2 (v0: the rms speed of E0), by at most
# 2 x 3 eps |q_n| / (v0 h) = 6 eps A_n, where A_n = |q_n| / (v0 h) is the cancellation factor (how many
# steps of motion the displacement holds); the accumulated work and energy sums lose eps more each:
# 8 eps A_n per step, added with the same sign over the N steps (the worst case, not a random walk).
#   drift:       a body moving at most at v0 from q_0 = 0 has |q_n| <= v0 n h, A_n <= n:
#                bound 8 eps N (N + 1) / 2;
#                (rubbing: 8.9e-4, above the deck's own stop, 'Energy balance tolerance' = 1e-4; its
#                error grows linearly, 5.5e-6 after 1e6 steps, more than a random walk would give);
#   oscillation: a body vibrating about rest, |q_n| <= X, its largest displacement (read from the
#                run's watched free end, at the records): A = X / (v0 h). Summed with the same sign
#                the bound would be 8 eps N A (1.0e-6 for the 1e7 steps of free-vibration-1e7: the
#                run's own stop, no test); but the sign of the rounding of an oscillating q changes
#                with its phase: the errors add as a random walk of blocks one period long
#                (2 pi A steps, within which they may share a sign). Bound: 10 standard deviations
#                of that walk, 10 x 8 eps A sqrt(N 2 pi A).
# Penetration after the correction (the largest -gap at the corrected q_{n+1}):
#   lagrange:    the forward-increment Lagrange correction closes the gap predicted at the foot
#                point exactly; the foot point itself is off by at most the closest-point Newton
#                tolerance in parameter units (one unit per patch), i.e. tol x the patch size in
#                length, plus the round-off of the coordinates (4 eps x the largest coordinate):
#                bound tol x patch + 4 eps L;
#   caught:      a node the active set released (or corrected against another surface) is caught
#                at the next step's prediction: it goes in by at most its speed relative to the
#                surface times h; that speed is the impact speed v0 plus at most v0 again from the
#                block's elastic rebound: bound 2 v0 h (+ the lagrange bound);
#   penalty:     the penalty springs can store at most the energy the run started with (the energy
#                balance is asserted), so a single node's spring kp d^2 / 2 <= E0: d <= sqrt(2 E0 / kp);
#                the discrete spring acts on the predicted gap, which near the stability limit
#                (omega h up to 2 / sqrt(3)) shifts its stored energy by up to 100 %: bound
#                2 sqrt(2 E0 / kp).
EPS = float(np.finfo(float).eps)
BOUNDS = {}  # the running case's bounds, for its extra check


def deck_parameters(path):
    """{"Time->Time step": "1e-7", "Surfaces->Floor->Type": "Plane", ...} of a deck."""
    return epaphe.read_deck(path).parameters()


def numbers(text):
    return [float(x) for x in text.strip().strip("{}").split(",")]


def steps(P):
    h = float(P["Time->Time step"])
    return h, int(round(float(P["Time->End time"]) / h))


def largest_patch(P):
    """The largest patch (length of one parameter unit) of the deck's rigid surfaces."""
    names = sorted({k.split("->")[1] for k in P if k.startswith("Surfaces->")})
    size = 0.0
    for n in names:
        kind = P[f"Surfaces->{n}->Type"]
        pts = numbers(P[f"Surfaces->{n}->Points"])
        if kind == "Plane":
            lengths = [np.linalg.norm(numbers(P[f"Surfaces->{n}->U"])), np.linalg.norm(numbers(P[f"Surfaces->{n}->V"]))]
        elif kind == "Cylinder arc":
            a0, a1 = numbers(P[f"Surfaces->{n}->Angles"])
            z0, z1 = numbers(P[f"Surfaces->{n}->Axial range"])
            lengths = [float(P[f"Surfaces->{n}->Radius"]) * np.radians(a1 - a0), z1 - z0]
        else:
            raise SystemExit(f"check_stability.py: no patch size for surface '{n}' of type {kind}")
        size = max(size, lengths[0] / (pts[0] - 1), lengths[1] / (pts[1] - 1))
    return size


def largest_coordinate(P):
    """An upper bound of the coordinates a contact node or surface point has (m): the largest origin or
    centre plus the largest extent (box lengths, plane vectors, diameters)."""
    origin = max(float(np.abs(numbers(v)).max()) for k, v in P.items() if k.endswith(("->Origin", "->Center")))
    extent = max(
        float(np.abs(numbers(v)).max()) if not k.endswith("->Radius") else 2 * float(v)
        for k, v in P.items()
        if k.endswith(("->Lengths", "->U", "->V", "->Radius"))
    )
    return origin + extent


def speed(P):
    """The largest initial speed of the deck's bodies (m/s)."""
    return max([float(np.linalg.norm(numbers(v))) for k, v in P.items() if k.endswith("->Initial velocity")] or [0.0])


def balance_bound(P, kind, data):
    h, N = steps(P)
    if kind == "drift":
        return 8 * EPS * N * (N + 1) / 2, f"drift: 8 eps N (N + 1) / 2, N = {N}"
    _, body, nodeset = kind
    X = float(np.abs(data[f"bodies/{body}/nodesets/{nodeset}/displacement"]).max())
    v0 = speed(P)
    A = X / (v0 * h)
    return (
        10 * 8 * EPS * A * np.sqrt(N * 2 * np.pi * A),
        f"oscillation: 10 x 8 eps A sqrt(N 2 pi A), A = X / (v0 h) = {A:.4g}, N = {N}, X = {X:.4g} m, "
        f"v0 = {v0:.4g} m/s",
    )


def penetration_bound(P, kind, data):
    tol = float(P.get("Contact->Newton tolerance", 1e-8))  # the schema's default
    patch, L = largest_patch(P), largest_coordinate(P)
    lagrange = tol * patch + 4 * EPS * L
    text = f"lagrange: tol {tol:g} x patch {patch:.4g} m + 4 eps x {L:.3g} m"
    if kind is None:
        return 0.0, "no contact"
    if kind == "lagrange":
        return lagrange, text
    if kind == "caught":
        h, _ = steps(P)
        return 2 * speed(P) * h + lagrange, f"caught: 2 v0 h, v0 = {speed(P):.4g} m/s, h = {h:g} s; + {text}"
    if kind == "penalty":
        kp = float(P["Contact->Penalty stiffness"])
        E0 = float(data["energy/total"][0])
        return 2 * np.sqrt(2 * E0 / kp), f"penalty: 2 sqrt(2 E0 / kp), E0 = {E0:.4g} J, kp = {kp:.4g} N/m"
    raise SystemExit(f"check_stability.py: unknown penetration bound {kind}")


# ---- the cases -----------------------------------------------------------------------------------
# deck, overrides, bounds (energy balance and penetration: kinds of the derivations above), extra
# check; or refuse/stop: a regex the one-line error must match (refuse: no output file at all; stop:
# the output says "stopped").
CASES = {
    "grazing": dict(deck="grazing.xml", balance="drift", penetration="lagrange", check=check_grazing),
    "impact-100": dict(
        deck="../../../inputs/cube-rings.xml",
        balance="drift",
        penetration="lagrange",
        overrides={
            "Bodies->Cube->Initial velocity": "{0, -100, 0}",
            "Time->End time": "3e-4",
            "Bodies->Cube->Reduction->Frequency check": ("0", "int"),
            "Output->Every": ("50", "int"),
        },
        check=check_impact,
    ),
    "stick": dict(deck="stick.xml", balance="drift", penetration="lagrange", check=check_stick),
    # kp is found where the deck's step is the estimated critical step, which counts each penalty
    # spring three times (the penalty on the predicted gap is stable for h^2 kp / m < 4/3, an
    # ordinary spring for < 4): at 0.3 and 0.95 of it the run is stable; above it the run is
    # refused; forced (Allow unstable time step) to 3.3 times it, it creates energy and is stopped.
    "penalty-below-limit": dict(deck="penalty.xml", balance="drift", penetration="penalty", penalty=0.3),
    "penalty-at-limit": dict(deck="penalty.xml", balance="drift", penetration="penalty", penalty=0.95),
    "penalty-above-limit": dict(
        deck="penalty.xml", penalty=1.1, refuse=r"exceeds the critical step.*smaller 'Penalty stiffness'"
    ),
    "penalty-above-limit-allowed": dict(
        deck="penalty-squeeze.xml",
        penalty=3.3,
        stop=r"energy of the bodies grew|no longer finite|energy balance error",
        overrides={"Time->Allow unstable time step": ("true", "bool")},
    ),
    "penalty-squeeze-stable": dict(deck="penalty-squeeze.xml", penalty=0.3, balance="drift", penetration="penalty"),
    "seam": dict(deck="seam.xml", balance="drift", penetration="lagrange", check=check_seam),
    "patch-corner-edge": dict(
        deck="patch-corner-edge.xml", balance="drift", penetration="lagrange", check=check_corner_edge
    ),
    "open-edge": dict(deck="open-edge.xml", balance="drift", penetration="lagrange", check=check_open_edge),
    "many-nodes": dict(deck="many-nodes.xml", balance="drift", penetration="lagrange", check=check_many_nodes),
    "two-surfaces": dict(deck="two-surfaces.xml", balance="drift", penetration="caught", check=check_two_surfaces),
    "free-vibration-1e7": dict(
        deck="free-vibration.xml",
        balance=("oscillation", "Beam", "x+"),
        penetration=None,
        overrides={"Bodies->Beam->Watched node sets": ("{x+}", "Array(string)")},
        check=check_free_vibration,
    ),
    "rubbing-1e6": dict(deck="rubbing.xml", balance="drift", penetration="lagrange", check=check_rubbing),
}


def critical_penalty(run, deck, workdir):
    """The penalty stiffness at which the deck's time step is the critical step: kp -> h_crit(kp) from
    runs of one step (h_crit ~ kp^-1/2 once the springs dominate), refined by the secant in log-log."""
    h = float(et.deck_value(deck, "Time->Time step"))
    kp, pts = 1e8, []
    for it in range(8):
        v = et.variant(
            deck,
            os.path.join(workdir, "kp.xml"),
            {
                "Contact->Penalty stiffness": (f"{kp:.17g}", "double"),
                "Contact->Method": "Penalty",
                "Time->End time": (f"{h:.17g}", "double"),
                "Time->Allow unstable time step": ("true", "bool"),
                "Output->File": "kp.h5",
            },
        )
        et.run([run, v], workdir)
        with epaphe.open(os.path.join(workdir, "kp.h5")) as f:
            hc = float(f.attrs["critical_time_step"])
        pts.append((np.log(kp), np.log(hc)))
        if abs(hc / h - 1) < 1e-6:
            break
        slope = -0.5 if len(pts) < 2 else (pts[-1][1] - pts[-2][1]) / (pts[-1][0] - pts[-2][0])
        kp = float(np.exp(pts[-1][0] + (np.log(h) - pts[-1][1]) / slope))
    return kp, hc, h


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--run", required=True)
    ap.add_argument("--case", required=True)
    ap.add_argument("--workdir", required=True)
    a = ap.parse_args()
    if a.case == "list":
        print("\n".join(CASES))
        return 0
    c = CASES[a.case]
    os.makedirs(a.workdir, exist_ok=True)
    deck = os.path.normpath(os.path.join(HERE, "decks", c["deck"]))
    overrides = dict(c.get("overrides", {}))
    out = os.path.join(a.workdir, a.case + ".h5")
    overrides["Output->File"] = out
    if "penalty" in c:
        kp, hc, h = critical_penalty(a.run, deck, a.workdir)
        print(
            f"measured: {a.case}: critical kp for h = {h:g} s is {kp:.4e} N/m (critical step there {hc:.6e} s); "
            f"running kp = {c['penalty']} x that"
        )
        overrides["Contact->Method"] = "Penalty"
        overrides["Contact->Penalty stiffness"] = (f"{c['penalty'] * kp:.17g}", "double")
    if os.path.exists(out):
        os.remove(out)
    v = et.variant(deck, os.path.join(a.workdir, a.case + ".xml"), overrides)
    start = time.time()
    proc = et.run([a.run, v], a.workdir, expect_ok=False)
    wall = time.time() - start
    err = proc.stderr.strip()
    print(f"measured: {a.case}: run {wall:.1f} s, exit {proc.returncode}")
    if "refuse" in c or "stop" in c:
        regex = c.get("refuse") or c.get("stop")
        assert proc.returncode != 0, f"{a.case}: the run was accepted:\n{proc.stdout[-2000:]}"
        assert re.search(regex, err) and len(err.splitlines()) == 1, f"{a.case}: message /{regex}/ expected, got: {err}"
        if "refuse" in c:
            assert not os.path.exists(out), f"{a.case}: refused but {out} was written"
        else:
            status, data = read(out)
            assert status.startswith("stopped:"), f"{a.case}: status {status}"
            print(f"measured: {a.case}: stopped after {len(data['time'])} records at t = {data['time'][-1]:.3e} s")
        print(f"{a.case}: {err}\nPASSED")
        return 0
    if proc.returncode != 0:
        sys.stderr.write(proc.stdout[-3000:] + err)
        raise SystemExit(f"{a.case}: run failed")
    status, data = read(out)
    assert status == "complete", f"{a.case}: status {status}"
    P = deck_parameters(v)
    balance, why_balance = balance_bound(P, c["balance"], data)
    penetration, why_penetration = penetration_bound(P, c["penetration"], data)
    print(
        f"bound: {a.case}: energy balance {balance:.3e} ({why_balance}); penetration {penetration:.3e} m "
        f"({why_penetration})"
    )
    BOUNDS.update(balance=balance, penetration=penetration)
    common(data, balance, penetration, a.case)
    if "check" in c:
        c["check"](data)
    print("PASSED")
    return 0


if __name__ == "__main__":
    sys.exit(main())
