#!/usr/bin/env python3
"""Hard cases of contact dynamics (label `stability`): each case runs a deck of decks/ (or a variant of
it) and asserts that the history holds no NaN/Inf, that the energy balance error stays within a stated
bound, that the largest penetration after correction (-gap of /bodies/<b>/contact/gap, the gap at the
corrected q_n) stays within a stated bound, plus what the case is about -- or that the run is refused
with a clear message when that is the right answer.

    check_stability.py --run EPAPHE_RUN --case NAME --workdir DIR     (--case list: the cases)

Measured figures are printed (`measured: ...`) so that the bounds can be revisited."""
import argparse
import os
import re
import sys
import time

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "verification"))
import epaphe_testing as et  # noqa: E402

BEYOND = 1e299  # gap of a node beyond every surface is 1e300


def read(path):
    with h5py.File(path, "r") as f:
        status = f.attrs["status"]
        status = status.decode() if isinstance(status, bytes) else status
        data = {}
        f.visititems(lambda n, o: data.__setitem__(n, o[()]) if isinstance(o, h5py.Dataset) and o.dtype.kind in "fi" else None)
    return status, data


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
    print(f"measured: {name}: max |energy balance error| = {bal:.3e} (bound {balance_bound:g}), "
          f"max penetration = {pen:.3e} m (bound {penetration_bound:g})")
    assert bal <= balance_bound, f"{name}: energy balance error {bal:.3e} > {balance_bound:g}"
    assert pen <= penetration_bound, f"{name}: penetration {pen:.3e} m > {penetration_bound:g}"
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
    print(f"measured: grazing: largest normal displacement of the sliding face {lift:.3e} m, "
          f"largest contact force {f.max():.3e} N")
    assert lift <= 1e-9, f"grazing: the face left the plane by {lift:.3e} m (bound 1e-9)"
    ux = u[-1, :, 0]
    t = data["time"][-1]
    assert np.allclose(ux, 5.0 * t, rtol=1e-3), f"grazing: slid {ux} m, expected {5 * t} m"


def check_stick(data):
    f = data["bodies/Block/contact/force"]
    u = data["bodies/Block/nodesets/y-/displacement"]
    assert np.array_equal(data["bodies/Block/contact/nodes"], data["bodies/Block/nodesets/y-/nodes"])
    t = data["time"]
    both = (f[:-1] > 0) & (f[1:] > 0)       # node in contact at two successive records
    assert both.any(), "stick: no contact"
    step = np.linalg.norm(u[1:, :, [0, 2]] - u[:-1, :, [0, 2]], axis=2)
    slip = float(step[both].max())
    free = 0.5 * float(np.max(np.diff(t)))  # what the tangential velocity would slide in one record
    stuck = float(np.mean(step[both] < 1e-12))
    print(f"measured: stick: {int(both.sum())} node-records in contact, {stuck * 100:.0f} % without slip (< 1e-12 m), "
          f"largest slip between two records {slip:.3e} m (free sliding {free:.3e} m)")
    assert stuck >= 0.75, f"stick: only {stuck * 100:.0f} % of the node-records in contact stuck"
    assert slip <= 0.1 * free, f"stick: the nodes slid {slip:.3e} m while in contact"


def check_seam(data):
    nodes = data["bodies/Block/contact/nodes"]
    x = positions(data, "Block", nodes)
    f = data["bodies/Block/contact/force"]
    g = data["bodies/Block/contact/gap"]
    # records with contact while the face straddles the seam or lies past it
    crossed = [k for k in range(len(f)) if f[k].max() > 0 and x[k, :, 1].max() > 1e-4]
    print(f"measured: seam: {len(crossed)} records in contact past the seam (y > 0), final y of the face "
          f"{x[-1, :, 1].min():.4f}..{x[-1, :, 1].max():.4f} m, radius {np.hypot(x[-1, :, 0], x[-1, :, 1]).max():.6f} m")
    r = np.hypot(x[:, :, 0], x[:, :, 1])
    dev = float(np.max(np.abs(g - (0.1 - r))))   # gap = distance to the wall, across the seam too
    seam = np.abs(np.degrees(np.arctan2(x[:, :, 1], x[:, :, 0]))) < 1.0
    print(f"measured: seam: gap against the exact distance to the wall within {dev:.2e} m over all records, "
          f"{int(seam.sum())} node-records within 1 degree of the seam")
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
    print(f"measured: open-edge: {int(beyond.sum())} node-records beyond the edge, {corrected_beyond} of them "
          f"corrected; lowest node beyond the edge at y = {x[:, :, 1][beyond].min() if beyond.any() else 0:.3e} m")
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
    onWall = np.abs(x[0, :, 0] - x[0, :, 0].min()) < 1e-9    # x- face
    onFloor = np.abs(x[0, :, 1] - x[0, :, 1].min()) < 1e-9   # y- face
    both = [k for k in range(len(f)) if f[k, onWall & ~onFloor].max() > 0 and f[k, onFloor & ~onWall].max() > 0]
    print(f"measured: two-surfaces: {len(both)} records with forces on the wall and the floor at once")
    assert both, "two-surfaces: never in contact with both surfaces at once"


def check_impact(data):
    f = data["bodies/Cube/contact/total_force"]
    p = data["bodies/Cube/momentum"][:, 1]
    print(f"measured: impact-100: largest total contact force {f.max():.3e} N, momentum y {p[0]:.3e} -> {p[-1]:.3e} kg m/s")
    assert f.max() > 0 and p[-1] > p[0], "impact-100: the cube did not hit the rings"


def check_free_vibration(data):
    tot = data["energy/total"]
    strain = data["energy/strain"]
    drift = float(np.max(np.abs(tot - tot[0])) / tot[0])
    print(f"measured: free-vibration: {len(tot)} records over {data['time'][-1]:.3g} s, relative energy drift "
          f"{drift:.3e}, largest strain energy {strain.max() / tot[0]:.3f} of the total")
    assert drift <= 1e-9, f"free-vibration: energy drifted by {drift:.3e} (bound 1e-9)"
    assert strain.max() > 0.01 * tot[0], "free-vibration: the beam does not vibrate"


def check_rubbing(data):
    p = data["bodies/Block/momentum"][:, 0]
    work = data["energy/contact_work"]
    f = data["bodies/Block/contact/force"]
    print(f"measured: rubbing: momentum x {p[0]:.4e} -> {p[-1]:.4e} kg m/s, contact work {work[-1]:.3e} J, "
          f"{(f.sum(axis=1) > 0).mean() * 100:.0f} % of the records in contact")
    assert work[-1] < 0, "rubbing: friction dissipated nothing"
    assert p[-1] < p[0], "rubbing: friction did not slow the block"
    assert p[-1] > 0.2 * p[0], "rubbing: the block stopped: it no longer rubs"
    assert (f.sum(axis=1) > 0).mean() > 0.5, "rubbing: the block was not pressed"


# ---- the cases -----------------------------------------------------------------------------------
# deck, overrides, bounds (energy balance, penetration in m), extra check; or refuse/stop: a regex
# the one-line error must match (refuse: no output file at all; stop: the output says "stopped").
# Bounds: about 100 x what was measured (see `measured:`), except penetrations that are physical:
# many-nodes (121 nodes, some released and caught again: 9.6e-9 m = 0.1 v h), two-surfaces (a node on
# the block's edge touches both planes but is corrected against one: 6e-7 m, under 2 v h = 1e-6 m)
# and penalty (lambda / kp).
CASES = {
    "grazing": dict(deck="grazing.xml", balance=1e-8, penetration=1e-12, check=check_grazing),
    "impact-100": dict(deck="../../../inputs/cube-rings.xml", balance=1e-10, penetration=1e-8,
                       overrides={"Bodies->Cube->Initial velocity": "{0, -100, 0}", "Time->End time": "3e-4",
                                  "Bodies->Cube->Reduction->Frequency check": ("0", "int"),
                                  "Output->Every": ("50", "int")}, check=check_impact),
    "stick": dict(deck="stick.xml", balance=1e-10, penetration=1e-12, check=check_stick),
    # kp is found where the deck's step is the estimated critical step, which counts each penalty
    # spring three times (the penalty on the predicted gap is stable for h^2 kp / m < 4/3, an
    # ordinary spring for < 4): at 0.3 and 0.95 of it the run is stable; above it the run is
    # refused; forced (Allow unstable time step) to 3.3 times it, it creates energy and is stopped.
    "penalty-below-limit": dict(deck="penalty.xml", balance=1e-10, penetration=4e-5, penalty=0.3),  # ~ F / kp
    "penalty-at-limit": dict(deck="penalty.xml", balance=1e-10, penetration=1e-5, penalty=0.95),
    "penalty-above-limit": dict(deck="penalty.xml", penalty=1.1, refuse=r"exceeds the critical step.*smaller 'Penalty stiffness'"),
    "penalty-above-limit-allowed": dict(deck="penalty-squeeze.xml", penalty=3.3,
                                        stop=r"energy of the bodies grew|no longer finite|energy balance error",
                                        overrides={"Time->Allow unstable time step": ("true", "bool")}),
    "penalty-squeeze-stable": dict(deck="penalty-squeeze.xml", penalty=0.3, balance=1e-6, penetration=1e-8),
    "seam": dict(deck="seam.xml", balance=1e-7, penetration=1e-9, check=check_seam),
    "patch-corner-edge": dict(deck="patch-corner-edge.xml", balance=1e-10, penetration=1e-12, check=check_corner_edge),
    "open-edge": dict(deck="open-edge.xml", balance=1e-8, penetration=1e-12, check=check_open_edge),
    "many-nodes": dict(deck="many-nodes.xml", balance=1e-10, penetration=2e-8, check=check_many_nodes),
    "two-surfaces": dict(deck="two-surfaces.xml", balance=1e-10, penetration=1e-6, check=check_two_surfaces),
    "free-vibration-1e7": dict(deck="free-vibration.xml", balance=1e-9, penetration=0, check=check_free_vibration),
    "rubbing-1e6": dict(deck="rubbing.xml", balance=2e-5, penetration=1e-12, check=check_rubbing),
}


def critical_penalty(run, deck, workdir):
    """The penalty stiffness at which the deck's time step is the critical step: kp -> h_crit(kp) from
    runs of one step (h_crit ~ kp^-1/2 once the springs dominate), refined by the secant in log-log."""
    h = float(re.search(r'name="Time step" type="double" value="([^"]+)"', open(deck).read()).group(1))
    kp, pts = 1e8, []
    for it in range(8):
        v = et.variant(deck, os.path.join(workdir, "kp.xml"), {"Contact->Penalty stiffness": (f"{kp:.17g}", "double"),
                                                               "Contact->Method": "Penalty", "Time->End time": (f"{h:.17g}", "double"),
                                                               "Time->Allow unstable time step": ("true", "bool"),
                                                               "Output->File": "kp.h5"})
        et.run([run, v], workdir)
        with h5py.File(os.path.join(workdir, "kp.h5"), "r") as f:
            hc = float(f["/run"].attrs["critical_time_step"])
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
        print(f"measured: {a.case}: critical kp for h = {h:g} s is {kp:.4e} N/m (critical step there {hc:.6e} s); "
              f"running kp = {c['penalty']} x that")
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
    common(data, c["balance"], c["penetration"], a.case)
    if "check" in c:
        c["check"](data)
    print("PASSED")
    return 0


if __name__ == "__main__":
    sys.exit(main())
