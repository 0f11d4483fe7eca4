#!/usr/bin/env python3
"""Bodies' 'Gravity': a free body falls as z(t) = z0 + v0 t + g t^2 / 2, and the energy balance closes.

The central difference integrates a uniform acceleration exactly (its second difference of a
quadratic is exact), once q_{-1} = -h v0 + h^2/2 a0 starts it; the gravity force f = sum_d g_d M t_d
is the exact weight T^T M e_d of a body whose rigid translation is a motion of its model. So, for a
free bar with 'Full, lumped mass', 'None' (consistent mass, dense), 'Craig-Bampton' (10 modes) and
'Massless boundary' (10 elastic modes and the 6 rigid-body ones: the weight acts on the rigid modes
alone, T^T M e_d = [0, Phi^T M e_d], the boundary following), at every record:
  - every watched node's displacement is v0 t + g t^2/2 and its velocity v0 + g t, to round-off
    (1e-9 of their largest value: a few hundred steps of additions of h^2 g, each exact to 1e-16
    relative, against an O(h) error, 1e-3 here, had the start q_{-1} = -h v0 been kept);
  - the momentum is m (v0 + g t) with m the rigid mass, to round-off;
  - the external work is the weight's, m g . (u_n + u_{n+1} - u_{-1} - u_0)/2 (the scheme's mid-step
    work), and the balance error is round-off (below 1e-10; the balance is an exact identity).
And the deck is refused, with a message naming the key, where the weight M t_d would be wrong: a
clamped Craig-Bampton body and a clamped massless boundary (a rigid translation is no motion of
either model). A clamped body with lumped mass is
accepted (M t_d is then its free nodes' masses, exact) and its clamped nodes stay at rest.
Finally a restart from a checkpoint continues the run with gravity bit for bit.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from epaphe_testing import history, run, verdict  # noqa: E402

G = np.array([1.5, -2.0, -9.81])
V0 = np.array([0.3, 0.2, 4.0])
H, STEPS = 1e-6, 400
ROUNDOFF = 1e-9
# The balance is an exact identity; its round-off: the kinetic energy uses q_{n+1} - q_n, which
# keeps 1e-16 |q| / |h v| ~ 1e-13 relative (|q| up to 400 h |v|), summed over 400 steps.
BALANCE = 1e-10

DECK = """<ParameterList name="Epaphe">
  <ParameterList name="Run"><Parameter name="Progress interval" type="double" value="0"/></ParameterList>
  <ParameterList name="Bodies">
    <ParameterList name="Bar">
      <ParameterList name="Mesh">
        <Parameter name="Type" type="string" value="Box"/>
        <Parameter name="Lengths" type="Array(double)" value="{{0.2, 0.02, 0.02}}"/>
        <Parameter name="Elements" type="Array(int)" value="{{10, 1, 1}}"/>
      </ParameterList>
      <ParameterList name="Material">
        <Parameter name="Density" type="double" value="8000"/>
        <Parameter name="Young's modulus" type="double" value="2e11"/>
        <Parameter name="Poisson's ratio" type="double" value="0.3"/>
      </ParameterList>
      <Parameter name="Initial velocity" type="Array(double)" value="{{{v0}}}"/>
      <Parameter name="Gravity" type="Array(double)" value="{{{g}}}"/>
      <Parameter name="Watched node sets" type="Array(string)" value="{{x+, x-}}"/>
      {clamped}
      <ParameterList name="Reduction">
        <Parameter name="Method" type="string" value="{method}"/>
        <Parameter name="Retained node set" type="string" value="x+"/>
        <Parameter name="Fixed-interface modes" type="int" value="10"/>
        <Parameter name="Frequency check" type="int" value="0"/>
      </ParameterList>
    </ParameterList>
  </ParameterList>
  <ParameterList name="Contact"><Parameter name="Method" type="string" value="Lagrange"/></ParameterList>
  <ParameterList name="Time">
    <Parameter name="Time step" type="double" value="{h}"/>
    <Parameter name="End time" type="double" value="{end}"/>
  </ParameterList>
  <ParameterList name="Output">
    <Parameter name="File" type="string" value="{name}.h5"/>
    <Parameter name="Every" type="int" value="1"/>
  </ParameterList>
</ParameterList>
"""


def write_deck(workdir, name, method, clamped="", g=G, v0=V0, retained=True):
    text = DECK.format(
        v0=", ".join(map(repr, v0)),
        g=", ".join(map(repr, g)),
        h=H,
        end=H * STEPS,
        name=name,
        method=method,
        clamped=f'<Parameter name="Clamped node set" type="string" value="{clamped}"/>' if clamped else "",
    )
    if not retained:
        text = text.replace('<Parameter name="Retained node set" type="string" value="x+"/>', "")
    path = os.path.join(workdir, name + ".xml")
    with open(path, "w") as f:
        f.write(text)
    return path


def main():
    import argparse

    ap = argparse.ArgumentParser()
    ap.add_argument("--run", required=True)
    ap.add_argument("--workdir", required=True)
    a = ap.parse_args()
    os.makedirs(a.workdir, exist_ok=True)
    failures = []

    def check_free_fall(label, method):
        deck = write_deck(a.workdir, label, method, retained=method in ("Craig-Bampton", "Massless boundary"))
        run([a.run, deck, "--threads", "1"], a.workdir)
        hist = history(os.path.join(a.workdir, label + ".h5"))
        t = hist["time"]
        u_exact = V0[None, :] * t[:, None] + 0.5 * G[None, :] * t[:, None] ** 2
        v_exact = V0[None, :] + G[None, :] * t[:, None]
        worst_u = worst_v = 0.0
        for s in ("x+", "x-"):
            u = hist[f"bodies/Bar/nodesets/{s}/displacement"]  # records x nodes x 3
            v = hist[f"bodies/Bar/nodesets/{s}/velocity"]
            worst_u = max(worst_u, np.abs(u - u_exact[:, None, :]).max() / np.abs(u_exact).max())
            worst_v = max(worst_v, np.abs(v - v_exact[:, None, :]).max() / np.abs(v_exact).max())
        m = hist["bodies/Bar/attrs"]["rigid_mass"]
        p = hist["bodies/Bar/momentum"]
        worst_p = np.abs(p - m * v_exact).max() / (m * np.abs(v_exact).max())

        # the run's external work sums f . (q_{n+1} - q_{n-1}) / 2, which telescopes to the weight's work
        # along the mid-step displacement (u_n + u_{n+1})/2 from (u_{-1} + u_0)/2
        def u_at(s):
            return V0[None, :] * s[:, None] + 0.5 * G[None, :] * s[:, None] ** 2

        mid = 0.5 * (u_at(t) + u_at(t + H)) - 0.5 * u_at(np.array([-H]))
        work_exact = m * (mid @ G)
        ext = hist["energy/external_work"]
        worst_w = np.abs(ext - work_exact).max() / np.abs(work_exact).max()
        kin_exact = 0.5 * m * (v_exact**2).sum(axis=1)
        worst_k = np.abs(hist["energy/kinetic"] - kin_exact).max() / kin_exact.max()
        balance = np.abs(hist["energy/balance_error"]).max()
        print(
            f"{label:22s} ({method}): displacement {worst_u:.1e}, velocity {worst_v:.1e}, momentum {worst_p:.1e}, "
            f"external work {worst_w:.1e}, kinetic {worst_k:.1e} (relative to the largest value), "
            f"balance error {balance:.1e}; z moved {u_exact[-1, 2]:+.6e} m, weight's work {work_exact[-1]:.6e} J"
        )
        for what, err, tol in (
            ("displacement", worst_u, ROUNDOFF),
            ("velocity", worst_v, ROUNDOFF),
            ("momentum", worst_p, ROUNDOFF),
            ("external work", worst_w, ROUNDOFF),
            ("kinetic energy", worst_k, ROUNDOFF),
            ("energy balance", balance, BALANCE),
        ):
            if not err <= tol:
                failures.append(f"{label}: {what} differs from the free fall by {err:.2e} (relative) > {tol:g}")
        return hist

    print(f"free fall with g = {G.tolist()} m/s^2 from v0 = {V0.tolist()} m/s, h = {H} s, {STEPS} steps")
    check_free_fall("lumped", "Full, lumped mass")
    check_free_fall("consistent", "None")
    check_free_fall("craig-bampton", "Craig-Bampton")
    check_free_fall("massless", "Massless boundary")

    # Refused where M t_d is not the weight
    for label, method, clamped, expect in (
        (
            "cb-clamped",
            "Craig-Bampton",
            "x-",
            "a rigid translation along x is not a motion of its Craig-Bampton " "model",
        ),
        (
            "massless-clamped",
            "Massless boundary",
            "x-",
            "a rigid translation along x is not a motion of its " "Massless boundary model",
        ),
    ):
        deck = write_deck(a.workdir, label, method, clamped=clamped, v0=[0, 0, 0])
        proc = run([a.run, deck, "--threads", "1"], a.workdir, expect_ok=False)
        msg = proc.stderr.strip()
        ok = proc.returncode != 0 and expect in msg and "Gravity" in msg
        print(f"{label}: {'refused' if ok else 'NOT refused as expected'}: exit {proc.returncode}: {msg}")
        if not ok:
            failures.append(f"{label}: expected a refusal containing '{expect}', got exit {proc.returncode}: {msg}")

    # A clamped body with lumped mass: accepted; the clamped face stays put, the free end sags.
    deck = write_deck(a.workdir, "lumped-clamped", "Full, lumped mass", clamped="x-", v0=[0, 0, 0], retained=False)
    run([a.run, deck, "--threads", "1"], a.workdir)
    hist = history(os.path.join(a.workdir, "lumped-clamped.h5"))
    fixed = np.abs(hist["bodies/Bar/nodesets/x-/displacement"]).max()
    sag = hist["bodies/Bar/nodesets/x+/displacement"][-1, :, 2].mean()
    print(
        f"clamped, lumped mass: clamped face moved {fixed:.1e} m, free end z {sag:+.3e} m after {STEPS} steps, "
        f"balance error {np.abs(hist['energy/balance_error']).max():.1e}"
    )
    if not (fixed == 0.0 and sag < 0 and np.abs(hist["energy/balance_error"]).max() <= BALANCE):
        failures.append(
            f"clamped lumped body under gravity: clamped face moved {fixed}, free end z {sag} (expected "
            "< 0), or the balance does not close"
        )

    # Restart bit for bit: stop after 150 steps, restart, compare with the uninterrupted run.
    deck = write_deck(a.workdir, "restart", "Craig-Bampton")
    ref = os.path.join(a.workdir, "restart-ref.h5")
    run([a.run, deck, "--threads", "1", "--output", ref], a.workdir)
    cut = os.path.join(a.workdir, "restart-cut.h5")
    proc = run(
        [a.run, deck, "--threads", "1", "--output", cut, "--stop-after-steps", "150"], a.workdir, expect_ok=False
    )
    run([a.run, deck, "--threads", "1", "--output", cut, "--restart", cut], a.workdir)
    h_ref, h_cut = history(ref), history(cut)
    differing = [
        k
        for k in h_ref
        if k not in ("attrs",)
        and not k.endswith("/attrs")
        and not k.startswith("checkpoint")
        and isinstance(h_ref[k], np.ndarray)
        and not np.array_equal(h_ref[k], h_cut.get(k))
    ]
    print(
        f"restart after 150 of {STEPS} steps: exit of the stopped run {proc.returncode}; series differing from the "
        f"uninterrupted run: {differing or 'none'}"
    )
    if differing:
        failures.append(f"restart with gravity is not bit for bit: {differing}")
    return verdict(failures)


if __name__ == "__main__":
    sys.exit(main())
