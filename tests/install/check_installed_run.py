#!/usr/bin/env python3
"""The installed epaphe-run's result read with the installed Python package (install.find-package).

Usage: check_installed_run.py SITE PREFIX RESULT.h5

SITE is where the install put the package (the directory holding epaphe/), PREFIX the install
prefix, RESULT.h5 the installed epaphe-run's output of the installed inputs/bar-on-wall.xml (V1,
docs/verification.md). run_install_test.cmake runs this with PYTHONPATH=SITE alone, from a directory
without an epaphe package, so `import epaphe` can only find the installed one (checked first).

Checked on the result, through the package's reader:
  - the run completed, and ran the installed deck (its name and time step, read back from /run/deck);
  - one record per step (Output->Every 1): End time / Time step records at t_n = n h, n = 0 .. steps - 1
    (a record at t_n holds v_n = (q_n+1 - q_n-1) / 2h, so the last one is a step before the end);
  - every energy finite at every record; the kinetic energy at t = 0 is the bar's 1/2 m v0^2 =
    3,200 J (m = rho L S = 0.64 kg) within 1e-9 (a rigid translation is exact in the reduced basis:
    round-off, 3e-13 measured); the balance error within 1e-8 of the largest energy (it closes to
    round-off, 9e-13 measured: the impact's loss, 59 J or 1.8e-2, is accounted as contact work, and a
    term lost or counted twice would be of that size);
  - the contact happened as V1's exact solution says: it starts at t0 = 2.0e-5 s and ends at
    t1 = 1.0e-4 s within 1 %, and its mean force over that time (impulse / duration) is the plateau
    F = 1.6e6 N within 2 % (tests/verification/v1_bar_on_wall.py's tolerances);
  - the bar rebounds at v0 = 100 m/s within 2 % (its momentum over its rigid mass after the release).
"""
import os
import sys

T0, T1, F, V0, MASS = 2.0e-5, 1.0e-4, 1.6e6, 100.0, 8000 * 0.2 * 0.02 * 0.02
TOL_TIME, TOL_FORCE, TOL_VEL, TOL_KINETIC, TOL_BALANCE = 0.01, 0.02, 0.02, 1e-9, 1e-8


def main():
    site, prefix, result = (os.path.realpath(p) for p in sys.argv[1:4])
    import numpy as np
    import epaphe
    from epaphe.results import ENERGIES

    failures = []
    where = os.path.realpath(epaphe.__file__)
    if not where.startswith(site + os.sep):
        return fail([f"import epaphe found {where}, not the installed package under {site}"])
    print(f"import epaphe: {where} (the install prefix {prefix})")
    with epaphe.open(result) as run:
        h = float(run.deck.get("Time->Time step"))
        end = float(run.deck.get("Time->End time"))
        steps = int(run.attrs["steps"])
        t = run.time
        print(
            f"{result}: status '{run.status}', deck '{run.name}', {run.records} records from {t[0]:g} to "
            f"{t[-1]:g} s, {steps} steps of {h:g} s"
        )
        if not run.complete:
            failures.append(f"status '{run.status}', expected 'complete'")
        if run.name != "bar on a rigid wall (V1)":
            failures.append(
                f"the run's deck is named '{run.name}', not the installed bar-on-wall.xml's "
                "'bar on a rigid wall (V1)'"
            )
        if steps != round(end / h):
            failures.append(f"{steps} steps, expected End time / Time step = {end:g} / {h:g} = {round(end / h)}")
        if run.records != steps:
            failures.append(f"{run.records} records, expected one per step: {steps} (Output->Every 1)")
        if not (t[0] == 0 and abs(t[-1] - (end - h)) <= 0.5 * h and np.allclose(np.diff(t), h, rtol=1e-6)):
            failures.append(
                f"record times from {t[0]:g} to {t[-1]:g} s, spaced {np.diff(t).min():g} to "
                f"{np.diff(t).max():g} s: expected 0 to {end - h:g} s every {h:g} s"
            )
        for name in ENERGIES:
            e = getattr(run.energy, name)
            if e.shape != t.shape or not np.all(np.isfinite(e)):
                failures.append(
                    f"energy {name}: shape {e.shape} (expected {t.shape}), "
                    f"{np.count_nonzero(~np.isfinite(e))} non-finite values"
                )
        kinetic0, exact0 = float(run.energy.kinetic[0]), 0.5 * MASS * V0**2
        if not abs(kinetic0 - exact0) <= TOL_KINETIC * exact0:
            failures.append(
                f"kinetic energy {kinetic0!r} J at t = 0, expected 1/2 m v0^2 = {exact0:g} J " f"within {TOL_KINETIC:g}"
            )
        balance = float(np.abs(run.energy.balance_error).max())
        print(
            f"energy: total {run.energy.total[0]:.1f} J at the start, {run.energy.total[-1]:.1f} J at the end, "
            f"largest balance error {balance:.2e}"
        )
        if not balance <= TOL_BALANCE:
            failures.append(f"energy balance error up to {balance:.3e}, more than {TOL_BALANCE:g}")
        bar = run.bodies["Bar"]
        f = bar.contact.total_force
        on = np.nonzero(f > 1e-6 * F)[0]  # V1's threshold: round-off gives 1e-4 N one step early
        if on.size == 0:
            return fail(
                failures
                + [f"no contact force at all (largest {f.max():g} N); the bar reaches the wall " f"at {T0:g} s"]
            )
        start, stop = t[on[0]], t[on[-1]] + h
        plateau = f.sum() * h / (stop - start)
        rebound = float(-bar.momentum[t > stop + 5e-6, 0].mean() / bar.rigid_mass)
        print(
            f"contact from {start:.4e} to {stop:.4e} s (exact {T0:g}, {T1:g}), mean force {plateau:.4e} N "
            f"(exact {F:g}), rebound {rebound:.3f} m/s (exact {V0:g})"
        )
        if not abs(start - T0) <= TOL_TIME * T0:
            failures.append(f"contact starts at {start:.4e} s, not within {TOL_TIME:.0%} of {T0:g} s")
        if not abs(stop - T1) <= TOL_TIME * T1:
            failures.append(f"contact ends at {stop:.4e} s, not within {TOL_TIME:.0%} of {T1:g} s")
        if not abs(plateau - F) <= TOL_FORCE * F:
            failures.append(f"mean contact force {plateau:.4e} N, not within {TOL_FORCE:.0%} of {F:g} N")
        if not abs(rebound - V0) <= TOL_VEL * V0:  # NaN (no momentum, no mass) fails too
            failures.append(f"rebound velocity {rebound:.3f} m/s, not within {TOL_VEL:.0%} of {V0:g} m/s")
    return fail(failures)


def fail(failures):
    print("FAILED:\n  " + "\n  ".join(failures) if failures else "PASSED")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
