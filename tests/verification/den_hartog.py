#!/usr/bin/env python3
"""Forced response with friction against Den Hartog's exact steady state, and the linear limit against
the scheme's exact frequency response (docs/theory/forced-response.md, eqs. (68)-(70)).

The model: one node of mass m (an imported Matrix Market model, 'Reduction->Method' 'None') on springs
k in x, y and z, resting on a rigid plane y = 0 (normal +y) and pressed onto it by a Constant load
-N along y; a Harmonic load F_0 cos(omega t) along x drives it. Lagrange contact with Coulomb friction
mu: the plane holds the node with the normal force N, and friction mu N opposes its sliding along x:
Den Hartog's oscillator m x'' + k x + mu N sgn(x') = F_0 cos(omega t).

1. Den Hartog (Trans. ASME 53, APM-53-9, 1931), eq. (68): at r = omega / omega_n in R_DH, with
   mu N / F_0 = 0.25 (the drive F_0 sin(omega t) at r = 0.8: from zero force, on a body at rest),
   each run goes to its steady state (eq. (70): the first harmonic of x over one drive period repeats
   to STEADY = 1e-6 of itself after p <= 10 periods, over the last p + 4 periods: with friction the
   stops fall on the step grid and the discrete motion may repeat only after a few periods); then the
   peak amplitude X (the largest x of each period, refined by a parabola through the three samples
   around it) and the lag phi of the peak +X behind the force's (omega t_peak + phase mod 2 pi),
   averaged over the last p periods, are compared with (68): within TOL_DH = 1 % (the issue's
   figure) for X, and within 1 % of pi for phi (phi itself is near 0 below resonance, where a relative
   error means nothing); measured: X within 8.1e-4, phi within 1.7e-4 of pi. The step (omega_n h =
   3e-3) resolves the peak to (omega h)^2 / 8 ~ 1e-6 and its time to h / 2 after the parabola: what
   is left is the scheme's own error at the stops, O(omega h). That each r is in the non-sticking
   regime (the velocity of the exact solution keeps its sign over the half period, and at a stop the
   drive and the spring overcome friction at once) is checked on the exact solution first, so the test
   cannot drift into a regime (68) does not describe.
2. Linear limit, eq. (69): mu = 0 and no contact node (the contact open), Rayleigh damping alpha M
   (5 % of critical at omega_n): the first harmonic of x, by the DFT over the last drive period of
   an integer number of steps (steady over p = 1 period), equals the scheme's exact frequency response
   Q = F_0 / (k - (4/h^2) sin^2(omega h/2) m + i (sin(omega h)/h) alpha m) within TOL_LIN = 1e-6 in
   modulus and argument (the criterion's STEADY: the runs last until exp(-zeta omega_n t) ~ 1e-11;
   measured 1.8e-11 and less); the continuous frequency response differs by O((omega h)^2), printed
   (1.8e-5 at 20 Hz).

    den_hartog.py --run EPAPHE_RUN --workdir DIR
"""
import argparse
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from epaphe_testing import POINT_MASS_MESH, history, run, verdict, write_point_mass  # noqa: E402

M = 1.0
FN = 10.0  # Hz, natural frequency along x
K = M * (2 * math.pi * FN) ** 2
F0 = 10.0  # N
RATIO = 0.25  # mu N / F_0
MU = 0.5
N = RATIO * F0 / MU  # N, the normal load
H = 5e-5  # s: omega_n h = 3.1e-3
R_DH = [0.625, 0.8, 1.25, 1.6, 2.0]  # each drive period a whole number of steps H
# The drive's phase: at r = 0.8, F_0 sin(omega t), a force that starts from 0 on a body at rest whose
# contact holds the preload: the energy balance then starts from no energy at all (its reference is the
# loads' scale, Epaphe_EnergyMonitor.cpp)
PHASE = {0.8: -math.pi / 2}
TOL_DH = 0.01
STEADY = 1e-6  # eq. (70): the first harmonic repeats to this, relative, over a pattern of p drive periods
P_MAX = 10  # the longest pattern looked for
W = 4  # the pattern holds over the last p + W periods
ZETA = 0.05
ALPHA = 2 * ZETA * 2 * math.pi * FN
H_LIN = 1e-4
NU_LIN = [5.0, 8.0, 10.0, 12.5, 20.0]
TOL_LIN = 1e-6  # = STEADY: what the criterion leaves of the transient


def write_model(workdir):
    """The node's model files (Matrix Market import)."""
    write_point_mass(workdir, [(i, i, K) for i in (1, 2, 3)], M)


def write_deck(path, nu, end, out, friction, h, phase=0.0):
    contact = '<Parameter name="Contact node set" type="string" value="MASS"/>' if friction else ""
    damping = (
        ""
        if friction
        else f"""<ParameterList name="Damping"><Parameter name="Type" type="string" value="Rayleigh"/>
      <Parameter name="Alpha" type="double" value="{ALPHA:.17g}"/></ParameterList>"""
    )
    with open(path, "w") as f:
        f.write(
            f"""<ParameterList name="Epaphe">
  <ParameterList name="Run"><Parameter name="Name" type="string" value="Den Hartog oscillator at {nu:.6g} Hz"/>
    <Parameter name="Progress interval" type="double" value="0"/>
    <Parameter name="Divergence step check" type="bool" value="false"/>
  </ParameterList>
  <ParameterList name="Bodies">
    <ParameterList name="Mass">
      {POINT_MASS_MESH}
      {contact}
      <Parameter name="Watched node sets" type="Array(string)" value="{{MASS}}"/>
      <ParameterList name="Loads">
        <ParameterList name="Drive">
          <Parameter name="Node set" type="string" value="MASS"/>
          <Parameter name="Force" type="Array(double)" value="{{{F0}, 0, 0}}"/>
          <Parameter name="Time function" type="string" value="Harmonic"/>
          <Parameter name="Frequency" type="double" value="{nu:.17g}"/>
          <Parameter name="Phase" type="double" value="{phase:.17g}"/>
        </ParameterList>
        <ParameterList name="Preload">
          <Parameter name="Node set" type="string" value="MASS"/>
          <Parameter name="Force" type="Array(double)" value="{{0, {-N if friction else 0.0}, 0}}"/>
        </ParameterList>
      </ParameterList>
    </ParameterList>
  </ParameterList>
  <ParameterList name="Surfaces">
    <ParameterList name="Floor">
      <Parameter name="Type" type="string" value="Plane"/>
      <Parameter name="Origin" type="Array(double)" value="{{-1, 0, 1}}"/>
      <Parameter name="U" type="Array(double)" value="{{2, 0, 0}}"/>
      <Parameter name="V" type="Array(double)" value="{{0, 0, -2}}"/>
    </ParameterList>
  </ParameterList>
  <ParameterList name="Contact">
    <Parameter name="Method" type="string" value="Lagrange"/>
    <Parameter name="Friction coefficient" type="double" value="{MU if friction else 0.0}"/>
  </ParameterList>
  <ParameterList name="Time">
    <Parameter name="Time step" type="double" value="{h}"/>
    <Parameter name="End time" type="double" value="{end:.17g}"/>
    {damping}
  </ParameterList>
  <ParameterList name="Output">
    <Parameter name="File" type="string" value="{out}"/>
    <Parameter name="Every" type="int" value="1"/>
  </ParameterList>
</ParameterList>
"""
        )


def den_hartog(r):
    """(X, phi, sticks) of eq. (68): the peak amplitude (m), the lag of the peak behind the force's
    (rad, in [0, 2 pi)), and whether the exact solution's velocity changes sign within a half period."""
    xst = F0 / K
    theta = math.pi / r
    V = 1.0 / (1.0 - r * r)
    U = math.tan(theta / 2) / r
    X = xst * math.sqrt(V * V - (RATIO * U) ** 2)
    s = V * xst
    sn = RATIO * xst * U / s  # sin psi = (mu N / k) tan(theta/2) / (r s)
    cs = -X / s
    psi = math.atan2(sn, cs)
    # the half period from the stop at -X: x = -a + a cos(w_n t) + r s sn sin(w_n t) + s cos(w t + psi)
    wn = 2 * math.pi * FN
    w = r * wn
    a = RATIO * xst
    t = np.linspace(0, math.pi / w, 2001)[1:-1]
    v = -a * wn * np.sin(wn * t) + r * s * sn * wn * np.cos(wn * t) - s * w * np.sin(w * t + psi)
    # and it leaves the stop at once: at -X the drive and the spring beat friction, F_0 cos psi + k X > mu N
    restarts = F0 * math.cos(psi) + K * X > RATIO * F0
    return X, (math.pi + psi) % (2 * math.pi), bool((v < 0).any()) or not restarts


def den_hartog_first_harmonic(r, samples=20000):
    """The complex first harmonic a_1 of (68)'s exact periodic motion (x ~ Re(a_1 e^{i omega t}), t the
    force's time): the half period from the stop at -X in closed form, the other half its negative,
    by the rectangle rule over `samples` points of a period (exact to round-off for a smooth periodic
    integrand; x has kinks at the stops: error O(1/samples^2))."""
    xst = F0 / K
    V = 1.0 / (1.0 - r * r)
    U = math.tan(math.pi / r / 2) / r
    X = xst * math.sqrt(V * V - (RATIO * U) ** 2)
    s = V * xst
    sn = RATIO * xst * U / s
    psi = math.atan2(sn, -X / s)
    wn = 2 * math.pi * FN
    w = r * wn
    a = RATIO * xst
    tt = (np.arange(samples) + 0.5) * (2 * math.pi / w) / samples
    half = tt < math.pi / w
    tp = np.where(half, tt, tt - math.pi / w)
    x = -a + a * np.cos(wn * tp) + r * s * sn * np.sin(wn * tp) + s * np.cos(w * tp + psi)
    x = np.where(half, x, -x)
    return np.exp(-1j * psi) * 2.0 * np.mean(x * np.exp(-1j * w * tt))


def first_harmonics(t, x, omega, steps_per_period):
    """The complex first harmonic (x ~ Re(a e^{i omega t})) of each whole period, from the end backwards."""
    out = []
    n = len(x)
    k = n
    while k - steps_per_period >= 0:
        sl = slice(k - steps_per_period, k)
        out.append(2.0 / steps_per_period * np.sum(x[sl] * np.exp(-1j * omega * t[sl])))
        k -= steps_per_period
    return out


def peak(t, x):
    """The largest x and its time, refined by the parabola through the three samples around it."""
    i = int(np.argmax(x))
    i = min(max(i, 1), len(x) - 2)
    y0, y1, y2 = x[i - 1], x[i], x[i + 1]
    den = y0 - 2 * y1 + y2
    d = 0.5 * (y0 - y2) / den if den != 0 else 0.0
    return y1 - 0.25 * (y0 - y2) * d, t[i] + d * (t[1] - t[0])


def run_case(exe, workdir, name, nu, friction, h, periods, phase=0.0):
    deck = os.path.join(workdir, name + ".xml")
    write_deck(deck, nu, periods / nu, name + ".h5", friction, h, phase)
    run([exe, deck, "--threads", "1"], workdir)
    hist = history(os.path.join(workdir, name + ".h5"))
    return hist["time"], hist["bodies/Mass/nodesets/MASS/displacement"][:, 0, :]


def steady(harmonics):
    """Eq. (70): (criterion, p). The response is steady when its first harmonic over one drive period,
    a_j (j periods before the end), repeats after p periods: max_{j < p + W} |a_j - a_{j+p}| <= STEADY |a_0|
    for some p <= P_MAX. A linear response repeats every period (p = 1); with friction the stops fall on
    the step grid, so the discrete motion may repeat only after a few periods (p = 5 at r = 0.625 and
    1.25 here, each period's harmonic then differing from the next by up to 3e-3). Returns the smallest
    p's criterion (the least over p when none is below STEADY)."""
    a = np.array(harmonics)
    best = (float("inf"), 1)
    for p in range(1, P_MAX + 1):
        n = p + W
        if n + p > len(a):
            break
        c = float(np.abs(a[:n] - a[p : n + p]).max() / abs(a[0]))
        if c <= STEADY:
            return c, p
        best = min(best, (c, p))
    return best


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--run", required=True)
    ap.add_argument("--workdir", required=True)
    ap.add_argument("--periods", type=int, default=150)
    a = ap.parse_args()
    os.makedirs(a.workdir, exist_ok=True)
    write_model(a.workdir)
    failures = []
    wn = 2 * math.pi * FN

    print(f"Den Hartog: m = {M} kg, k = {K:.6g} N/m (f_n = {FN} Hz), F_0 = {F0} N, mu N / F_0 = {RATIO}, h = {H} s")
    for r in R_DH:
        X, phi, sticks = den_hartog(r)
        if sticks:
            failures.append(f"r = {r}: the exact solution stops within a half period (outside (68)'s regime)")
            continue
        nu = r * FN
        omega = 2 * math.pi * nu
        phase = PHASE.get(r, 0.0)
        t, u = run_case(a.run, a.workdir, f"den-hartog-r{r:g}", nu, True, H, a.periods, phase)
        x = u[:, 0]
        spp = int(round(1.0 / (nu * H)))
        harm = first_harmonics(t, x, omega, spp)
        crit, p = steady(harm)
        jitter = float(np.abs(np.diff(harm[: p + 1])).max() / abs(harm[0]))
        peaks, lags = [], []
        for j in range(p):  # the peak and its lag in each period of the last pattern, averaged
            sl = slice(len(x) - (j + 1) * spp, len(x) - j * spp)
            Xj, tp = peak(t[sl], x[sl])
            peaks.append(Xj)
            lags.append((omega * tp + phase - phi + math.pi) % (2 * math.pi) - math.pi)
        Xm, dphi = float(np.mean(peaks)), float(np.mean(lags))
        phim = phi + dphi
        eX = abs(Xm - X) / X
        ey = float(np.abs(u[:, 1]).max())
        print(
            f"r = {r:4.2f}: X = {Xm:.6e} m against {X:.6e} ({eX:.2e}); lag {phim:.5f} rad against {phi:.5f} "
            f"({dphi:+.2e} rad, {abs(dphi) / math.pi:.2e} of pi); steady to {crit:.1e} over {p} period(s) (from one to the next {jitter:.1e}); "
            f"|y| <= {ey:.1e} m"
        )
        if not crit <= STEADY:
            failures.append(f"r = {r}: not steady after {a.periods} periods (first harmonic changes by {crit:.2e})")
        if not eX <= TOL_DH:
            failures.append(f"r = {r}: amplitude {Xm:.6e} m against Den Hartog's {X:.6e} m ({eX:.2%})")
        if not abs(dphi) <= TOL_DH * math.pi:
            failures.append(f"r = {r}: phase lag {phim:.5f} rad against Den Hartog's {phi:.5f} rad ({dphi:+.3e})")

    print(f"linear limit: mu = 0, no contact node, Rayleigh alpha = {ALPHA:.6g} /s ({ZETA:.0%} at f_n), h = {H_LIN} s")
    for nu in NU_LIN:
        omega = 2 * math.pi * nu
        spp = int(round(1.0 / (nu * H_LIN)))
        assert abs(spp * nu * H_LIN - 1) < 1e-12
        periods = max(10, int(math.ceil(25.0 / (ZETA * wn) * nu)))  # exp(-zeta w_n t) ~ 1e-11
        t, u = run_case(a.run, a.workdir, f"linear-{nu:g}hz", nu, False, H_LIN, periods)
        harm = first_harmonics(t, u[:, 0], omega, spp)
        h = H_LIN
        exact = F0 / (K - 4 / h**2 * math.sin(omega * h / 2) ** 2 * M + 1j * math.sin(omega * h) / h * ALPHA * M)
        cont = F0 / (K - omega**2 * M + 1j * omega * ALPHA * M)
        # x ~ Re(Q e^{i w t}): the DFT above gives Q's conjugate convention; compare |Q| and the lag
        em = abs(abs(harm[0]) - abs(exact)) / abs(exact)
        ea = abs(np.angle(harm[0] / exact))
        ec = abs(abs(cont) - abs(exact)) / abs(exact)
        crit, p = steady(harm)
        print(
            f"{nu:5.1f} Hz: |Q| = {abs(harm[0]):.9e} m against (69) {abs(exact):.9e} ({em:.1e}), phase {ea:.1e} rad; "
            f"steady to {crit:.1e} over {p} period(s); the continuous response differs by {ec:.1e}"
        )
        if not (crit <= STEADY and p == 1):
            failures.append(f"{nu} Hz: not steady over one period (the first harmonic changes by {crit:.2e})")
        if not (em <= TOL_LIN and ea <= TOL_LIN):
            failures.append(f"{nu} Hz: first harmonic {harm[0]:.6e} against the scheme's exact {exact:.6e}")
    sys.exit(verdict(failures))


if __name__ == "__main__":
    main()
