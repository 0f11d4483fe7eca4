"""Measures on runs: contact events and spectra of rotating blades (engine orders), the lobes worn
in an abradable coating, the study measures of epaphe-sweep and their errors against a reference,
work-precision series.

Units: times s, forces N, impulses N s, displacements m, velocities m/s, frequencies Hz, angles
degrees (wear_lobes: radians, as the file's /coating/<s>/angle); engine order = frequency /
rotation frequency (-)."""
import math
from collections import namedtuple

import numpy as np

from .errors import EpapheError
from .results import Run

# name in a study -> (CSV column stem, unit)
MEASURES = {
    "contact start": ("contact_start", "s"),
    "contact end": ("contact_end", "s"),
    "impulse": ("impulse", "N s"),
    "plateau force": ("plateau_force", "N"),
    "peak force": ("peak_force", "N"),
    "max penetration": ("max_penetration", "m"),
    "displacement": ("displacement_rms", "m"),
    "rebound velocity": ("rebound_velocity", "m/s"),
    "energy balance": ("energy_balance", "-"),
    "max wear": ("max_wear", "m"),
    "plastic dissipation": ("plastic_dissipation", "J"),
}
# a Lagrange peak grows as 1/h; the coating's measures exist only with a coating
DEFAULT_MEASURES = [k for k in MEASURES if k not in ("peak force", "max wear", "plastic dissipation")]
# what the error of each measure is (all are dimensionless); the legend of the work-precision diagram
ERROR_DEFINITIONS = {
    "contact start": "|t - t_ref| / contact duration",
    "contact end": "|t - t_ref| / contact duration",
    "impulse": "relative",
    "plateau force": "relative",
    "peak force": "relative",
    "max penetration": "|p - p_ref| / largest displacement",
    "displacement": "RMS difference / largest displacement",
    "rebound velocity": "relative",
    "energy balance": "largest relative balance error",
    "max wear": "relative (the deepest wear of any coating at the end)",
    "plastic dissipation": "relative (the coatings' at the end)",
}


# ---- study measures (epaphe-sweep) --------------------------------------------------------------
def raw_measures(h, w, peak_ref):
    """The study measures of a run read by study.read_history (`h`), for the watch `w`
    (study.Watch): contact start and end (s: the first record whose total force exceeds
    w.threshold x `peak_ref` (else the run's own peak), the record after the last one), impulse
    (N s), peak and plateau force (N), max penetration (m), rebound velocity (m/s, along w.comp),
    energy balance (the largest |relative balance error|), duration (s); with a coating, max wear
    (m) and plastic dissipation (J) at the end."""
    t = h["t"]
    dt = t[1] - t[0] if t.size > 1 else float("nan")
    m = {}
    f = h["force"]
    if f is not None and f.size:
        thr = w.threshold * (peak_ref if peak_ref and np.isfinite(peak_ref) and peak_ref > 0 else np.nanmax(f))
        on = np.nonzero(f > thr)[0] if thr > 0 else np.array([], int)
        m["contact start"] = t[on[0]] if on.size else float("nan")
        ended = on.size and on[-1] < t.size - 1
        m["contact end"] = t[on[-1]] + dt if ended else float("nan")
        m["impulse"] = float(np.nansum(f) * dt)
        m["peak force"] = float(np.nanmax(f))
        dur = (t[on[-1]] + dt - t[on[0]]) if on.size else float("nan")
        m["plateau force"] = m["impulse"] / dur if on.size else float("nan")
        m["duration"] = m["contact end"] - m["contact start"]
    if h["gap"] is not None and h["gap"].size:
        m["max penetration"] = -float(np.nanmin(h["gap"]))
    if h["momentum"] is not None and np.isfinite(h["mass"]) and h["mass"] > 0:
        m["rebound velocity"] = float(h["momentum"][-1, w.comp] / h["mass"])
    if h["balance"] is not None:
        m["energy balance"] = float(np.nanmax(np.abs(h["balance"])))
    if h.get("wear") is not None:
        m["max wear"] = h["wear"]
    if h.get("plastic") is not None:
        m["plastic dissipation"] = h["plastic"]
    return m


def rms_difference(t, u, tr, ur):
    """RMS of u - ur, ur interpolated on the times of u shared with tr."""
    sel = (t >= tr[0] - 1e-12 * abs(tr[-1])) & (t <= tr[-1] * (1 + 1e-12))
    if not sel.any():
        return float("nan")
    d = u[sel] - np.interp(t[sel], tr, ur)
    return float(np.sqrt(np.mean(d * d)))


def errors(m, ref, scale):
    """The errors of measures `m` against the reference's `ref`: contact times relative to the
    reference contact duration, the displacement RMS and max penetration relative to `scale` (the
    reference's largest watched displacement, m), the energy balance as it is, the rest relative."""
    e = {}
    dur = ref.get("duration", float("nan"))
    for k in MEASURES:
        v, r = m.get(k, float("nan")), ref.get(k, float("nan"))
        if k == "energy balance":
            e[k] = v
        elif k == "displacement":
            e[k] = v / scale if scale > 0 else float("nan")
        elif k in ("contact start", "contact end"):
            e[k] = abs(v - r) / (dur if np.isfinite(dur) and dur > 0 else abs(r))
        elif k == "max penetration":
            e[k] = abs(v - r) / scale if scale > 0 else float("nan")
        else:
            e[k] = abs(v - r) / abs(r) if r != 0 else float("nan")
    return e


def work_precision_series(runs, measures, cost_key):
    """[(measure, [(cost in s, error, run label)])] of the study runs (epaphe.runner.Case) that hold
    errors: one series per measure, for plots.draw_work_precision."""
    return [
        (
            k,
            [
                (float(r.hist["attrs"].get(cost_key, float("nan"))), r.errors.get(k, float("nan")), r.label)
                for r in runs
            ],
        )
        for k in measures
    ]


# ---- rotating blades (thesis section 5.2) --------------------------------------------------------
def _run(source):
    """(Run, whether to close it) of a path or a Run."""
    return (source, False) if isinstance(source, Run) else (Run(source), True)


def rotation_speed(run):
    """The rotation speed of the run, rad/s: the fastest turning surface of its deck."""
    omega = 0.0
    for p in run.deck.root.iter("Parameter"):
        if p.get("name") == "Rotation speed":
            omega = max(omega, abs(float(p.get("value"))))
    if omega == 0.0:
        raise EpapheError("no surface turns in this run (no 'Rotation speed')")
    return omega


def contact_events(source, body="Blade", sets=("tip-le", "tip-te"), skip=3.0, merge=0.15):
    """Contact events per revolution of each node set of `body` in a run (a path or a Run): an event
    starts when one of the set's nodes starts carrying a contact force; one starting less than
    `merge` of a revolution after the previous start is the same contact. Per revolution after the
    first `skip`: {set: dict(per_rev=[counts], angles=[deg, the casing angle of each event],
    fraction=[share of the revolution in contact], mean=mean count)}."""
    out = {}
    run, own = _run(source)
    try:
        omega = rotation_speed(run)
        t = run.time
        b = run.bodies[body]
        force = b.contact.force
        period = 2 * math.pi / omega
        for s in sets:
            cols = b.contact.columns(b.nodesets[s].nodes)
            if not cols:
                raise EpapheError(f"node set '{s}' has no contact node")
            on = (force[:, cols] > 0).any(axis=1)
            starts = np.flatnonzero(on[1:] & ~on[:-1]) + 1
            merged = []
            for i in starts:
                if merged and t[i] - t[merged[-1]] < merge * period:
                    continue
                merged.append(i)
            rev = np.floor(t / period).astype(int)
            nrev = int(math.floor(t[-1] / period + 1e-9))
            counts, fractions = [], []
            for r in range(int(math.ceil(skip)), nrev):
                counts.append(sum(1 for i in merged if rev[i] == r))
                sel = rev == r
                fractions.append(float(on[sel].mean()) if sel.any() else 0.0)
            angles = [math.degrees((omega * t[i]) % (2 * math.pi)) for i in merged if rev[i] >= skip]
            out[s] = dict(
                per_rev=counts,
                fraction=fractions,
                angles=angles,
                mean=float(np.mean(counts)) if counts else float("nan"),
            )
    finally:
        if own:
            run.close()
    return out


def spectrum(source, body="Blade", nodeset="tip-le", component="x", skip=3.0):
    """(engine orders, frequencies in Hz, amplitudes) of a node set's mean displacement along
    `component` (x, y or z; amplitude in m), or with component="force" of the total contact force
    on the set's contact nodes (N): FFT with a Hann window over the whole revolutions after the
    first `skip` (whole engine orders fall on bins, 1 / revolutions of an order apart)."""
    run, own = _run(source)
    try:
        omega = rotation_speed(run)
        t = run.time
        b = run.bodies[body]
        ns = b.nodesets[nodeset]
        if component == "force":
            cols = b.contact.columns(ns.nodes)
            if not cols:
                raise EpapheError(f"node set '{nodeset}' has no contact node")
            u = b.contact.force[:, cols].sum(axis=1)
        else:
            u = ns.displacement[:, :, "xyz".index(component)].mean(axis=1)
    finally:
        if own:
            run.close()
    period = 2 * math.pi / omega
    return sine_spectrum(t, u, period, skip, getattr(source, "path", source))


def sine_spectrum(t, u, period, skip=0.0, where="the signal"):
    """(orders, frequencies in Hz, amplitudes in u's unit) of u(t) sampled at a constant step, over
    the whole periods after `skip` periods: Hann window, amplitude-corrected (a sine of amplitude A
    on a bin reads A); orders = frequency x period."""
    dt = t[1] - t[0]
    revs = math.floor((t[-1] + dt - skip * period) / period + 1e-6)
    if revs < 1:
        raise EpapheError(f"{where} holds {t[-1] / period:.2f} revolutions, fewer than --skip {skip:g} + 1")
    sel = (t >= skip * period - 1e-9 * period) & (t < (skip + revs) * period - 0.5 * dt)
    t, u = t[sel], u[sel] - u[sel].mean()
    dt = t[1] - t[0]
    w = np.hanning(len(u))
    amp = np.abs(np.fft.rfft(u * w)) * 2 / w.sum()
    freq = np.fft.rfftfreq(len(u), dt)
    eo = freq * period
    return eo, freq, amp


def engine_order_lines(eo, amp, revolutions, low=0.5, top=40):
    """Reads an engine-order spectrum (epaphe-rotor spectrum over `revolutions` whole revolutions:
    bins 1/revolutions of an order apart, so neighbouring whole orders are `revolutions` bins apart;
    Hann window: a line spreads over its bin and one bin either side). Above EO `low` (the mean and
    slow drift sit below) returns dict(
      peak   the EO of the largest bin, order: the nearest whole order, off: |peak - order| in bins;
      lines  {k: the amplitude on the bin of whole order k} for k = 1..top;
      even_fraction  the share of the spectral energy within one bin of even whole orders;
      off_line_ratio the largest bin / the largest bin farther than one bin from every even order)."""
    sel = eo > low
    eo, amp = eo[sel], amp[sel]
    k = int(np.argmax(amp))
    order = int(round(eo[k]))
    bins = eo * revolutions
    lines = {}
    for o in range(1, top + 1):
        on = np.abs(bins - o * revolutions) <= 0.5
        lines[o] = float(amp[on].max()) if on.any() else 0.0
    even = np.abs(bins - 2 * np.round(eo / 2) * revolutions) <= 1.01
    off = amp[~even]
    return dict(
        peak=float(eo[k]),
        order=order,
        off=abs(eo[k] - order) * revolutions,
        lines=lines,
        even_fraction=float((amp[even] ** 2).sum() / (amp**2).sum()),
        off_line_ratio=float(amp[k] / off.max()) if off.size else float("inf"),
    )


# ---- abradable coating: wear lobes ----------------------------------------------------------------
WearLobes = namedtuple(
    "WearLobes", "profile dominant_order harmonic_angles lobe_count lobe_angles max_wear " "contrast"
)
WearLobes.__doc__ = """The lobes worn in a coating (wear_lobes): profile (n_u,) m, dominant_order (0 when the
profile has no harmonic), harmonic_angles (rad, sorted), lobe_count, lobe_angles (rad, sorted),
max_wear (m), contrast (the dominant harmonic's amplitude over the mean wear, 2 |W_n| / W_0; 0
without one)."""


def wear_lobes(angle, wear_2d, where="the wear map"):
    """The lobes worn in a coating, from the centre angles of its element columns `angle` (n_u,
    rad, uniformly spaced around the casing axis, increasing modulo 2 pi: /coating/<s>/angle) and
    the wear depth of its elements at one instant `wear_2d` (n_u, n_v) m (/coating/<s>/wear[last]).
    The C++ summary of epaphe-run uses the same definition:

      * profile: w_i = max over the axial rows j of wear_2d[i, j], i = 0..n_u-1;
      * dominant harmonic: the order n in 1..floor(n_u / 2) maximizing |W_n|,
        W_n = sum_i w_i exp(-2 pi I n i / n_u) (ties: the smallest n; an |W_n| within a relative 1e-9
        of the largest is a tie, so that round-off does not choose); its angles, where that harmonic
        peaks: theta_j = (angle[0] - arg(W_n) / n + 2 pi j / n) mod 2 pi, j = 0..n-1, sorted. A
        profile without harmonic content (every |W_n| below 1e-12 n_u max(w): no wear, or the same
        wear all round), where arg(W_n) means nothing, has dominant_order 0 and no harmonic angles;
      * lobes: the circular runs of consecutive columns with w_i > 0.5 max(w) (none if max(w) == 0;
        a run wrapping from the last column to the first is one run; every column above: one run);
        each lobe's angle is angle[i] of the column of largest w_i in its run (ties: the first
        column of the run, in increasing i from the run's start); lobe_angles sorted;
      * contrast: 2 |W_n| / W_0 of the dominant order n, the amplitude of its cosine over the mean
        wear (a pattern of n lobes cut between unworn columns: about 1; a uniform groove: 0).

    Returns a WearLobes(profile, dominant_order, harmonic_angles, lobe_count, lobe_angles, max_wear,
    contrast)
    (angles in rad, in [0, 2 pi); profile and max_wear in m). EpapheError (naming `where`) for
    shapes that disagree, non-finite wear or columns that are not uniformly spaced."""
    angle = np.asarray(angle, dtype=float).reshape(-1)
    wear = np.asarray(wear_2d, dtype=float)
    n_u = angle.size
    if wear.ndim != 2 or wear.shape[0] != n_u or n_u < 1 or wear.shape[1] < 1:
        raise EpapheError(
            f"{where}: wear of shape {wear.shape} for {n_u} column angles; expected "
            f"({n_u}, n_v) (element columns around the casing x rows along its axis)"
        )
    if not np.all(np.isfinite(wear)) or not np.all(np.isfinite(angle)):
        raise EpapheError(f"{where}: non-finite wear or angles (a record not written yet?)")
    if n_u > 1:
        # the definition numbers the columns around the circle: the steps must all be 2 pi / n_u
        step = np.mod(np.diff(angle), 2 * math.pi)
        if np.max(np.abs(step - 2 * math.pi / n_u)) > 1e-6 * 2 * math.pi / n_u:
            raise EpapheError(
                f"{where}: the {n_u} column angles are not uniformly spaced by 360/{n_u} deg "
                f"in increasing order (steps {np.degrees(step.min()):.6g} to "
                f"{np.degrees(step.max()):.6g} deg)"
            )
    w = wear.max(axis=1)
    top = float(w.max())

    # dominant harmonic (numpy's FFT is exactly sum_i w_i exp(-2 pi I n i / n_u))
    order, harmonic, contrast = 0, np.empty(0), 0.0
    if n_u >= 2:
        spec = np.fft.fft(w)
        mag = np.abs(spec[1 : n_u // 2 + 1])
        big = float(mag.max())
        if big > 1e-12 * n_u * abs(top):
            order = int(np.flatnonzero(mag >= big * (1 - 1e-9))[0]) + 1
            phase = float(np.angle(spec[order]))
            harmonic = np.sort(np.mod(angle[0] - phase / order + 2 * math.pi * np.arange(order) / order, 2 * math.pi))
            contrast = 2 * float(np.abs(spec[order])) / float(np.abs(spec[0]))

    # lobes: circular runs of columns above half the largest wear
    lobes = []
    if top > 0:
        above = w > 0.5 * top
        if above.all():
            lobes.append(int(np.argmax(w)))
        else:
            first = int(np.argmin(above))  # a column below: no run crosses its start
            i = 0
            while i < n_u:
                if not above[(first + i) % n_u]:
                    i += 1
                    continue
                run = []
                while i < n_u and above[(first + i) % n_u]:
                    run.append((first + i) % n_u)
                    i += 1
                lobes.append(run[int(np.argmax(w[run]))])
    lobe_angles = np.sort(np.mod(angle[lobes], 2 * math.pi)) if lobes else np.empty(0)
    return WearLobes(
        profile=w,
        dominant_order=order,
        harmonic_angles=harmonic,
        lobe_count=len(lobes),
        lobe_angles=lobe_angles,
        max_wear=top,
        contrast=contrast,
    )
