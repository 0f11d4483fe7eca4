"""epaphe-rotor: rotating-blade analysis of an Epaphe history (thesis section 5.2).

  epaphe-rotor contacts RUN.h5 [--body B] [--sets tip-le,tip-te] [--skip REVS] [--csv F]
      Contact events per revolution for each watched node set: an event starts when one of the
      set's nodes starts carrying a contact force; an event starting less than --merge (default 0.15)
      of a revolution after the previous one's start is the same contact (a bounce on one lobe);
      per revolution after the first REVS (the transient): the count, the angular positions of the
      events (casing angle, degrees, in the casing's frame) and the fraction of the revolution in
      contact.
  epaphe-rotor spectrum RUN.h5 [--body B] [--set tip-le] [--component x|y|z|force] [--skip REVS] [--png F]
      FFT (Hann window) of the mean displacement of a node set (or, with --component force, of the
      total contact force on its contact nodes) over the whole revolutions after the transient, with
      the engine order axis (frequency / rotation frequency; bins 1 / revolutions apart); prints the
      dominant engine orders.

  epaphe-rotor map DECK.xml --speeds W1,W2,... [--revs R] [--skip REVS] [--sets tip-le,tip-te]
                   [--component x] [--ranks P] [--mpiexec M] [--run EPAPHE_RUN] [--out DIR]
      Speed sweep: runs the deck at each rotation speed (rad/s; every turning surface of the deck
      gets that speed, its sign kept) for R revolutions with `epaphe-run --speeds`, the speeds dealt
      to P MPI ranks (mpiexec -n P; each rank runs its speeds alone), and writes the interaction
      map (thesis figures 5.12-5.15): per node set, the spectrum amplitude against engine order and
      speed, to DIR/map.h5 (/speeds, /engine_orders, /<set>/amplitude [speeds x orders]) and
      DIR/map-<set>.png (engine order (-) across, rotation speed (rad/s) up, the amplitude (m) in a
      log colour scale, the dominant order at each speed circled), and prints the dominant engine
      order of each set at each speed. A deck with an abradable coating also gets the wear map over
      speed: per speed the final wear profile around the casing, its lobes and dominant harmonic
      (as `wear` below), in DIR/map.h5 (/wear/{angle, profile [speeds x columns], dominant_order,
      lobes, max_wear, contrast}) and DIR/map-wear.png (angle across, speed up, wear depth as colour, the
      dominant harmonic at the right), printed per speed.

  epaphe-rotor campbell DECK.xml [--body B] [--orders 1-12] [--speeds N] [--count K] [--out DIR]
                   [--campbell EPAPHE_CAMPBELL]
      Campbell diagram of a rotating body with 'Rotation->Speed range': epaphe-campbell builds its
      parametric model and tabulates its frequencies over the range beside the full model's at the
      sample speeds and half-way between (DIR/campbell.h5); this command adds the engine-order lines
      f = k Omega / 2 pi (k in --orders, "1-12" or "1,2,6"), lists every crossing (speed, order, mode,
      frequency) and writes them to DIR/campbell.h5 (/crossings: speed, order, mode, frequency per
      row) and DIR/campbell.png (speed (rad/s) across, frequency (Hz) up).

  epaphe-rotor wear RUN.h5 [--surface S] [--png F] [--csv F]
      Wear of the abradable coating of surface S (by default the only coated surface of the run) at
      the last record of /coating/<S>/wear: the largest wear depth (um); the lobes, runs of element
      columns around the casing worn deeper than half the largest wear (their count and angles,
      degrees in the casing's frame); the dominant harmonic of the circumferential profile (its
      order and the angles where it peaks); the plastic dissipation at the end (J). The profile is
      the deepest wear of each column over the axial rows (definitions: epaphe.measures.wear_lobes,
      the same as epaphe-run's summary). --png: the wear map of the unrolled casing (angle across,
      axial position up, wear as colour) over the profile with the lobes marked; --csv: the
      profile (angle_deg, wear_m: one row per column, in the file's order).

  epaphe-rotor nodal-diameters RUN.h5 [--body B] [--set tip-le] [--component x] [--skip S]
                   [--casing ROM.h5] [--png F]
      A bladed stage (a body with 'Instances', docs/user/stage.md): the mean displacement of node
      set --set on every instance B[k], after the first S seconds, split into nodal diameters (the
      spatial DFT over the instances; the RMS of each printed) and into forward and backward
      travelling waves over frequency (the largest printed). --casing: the reduced model of the
      casing (its cache file): its modes' nodal diameters, and the speeds where the modal-interaction
      condition of Legrand et al. (2009) holds, Omega_n = (omega_b + omega_c,n) / n with the blade's
      frequencies of the run. --png: the travelling-wave spectrum (frequency across, nodal diameter up,
      forward above the axis and backward below, amplitude as colour).

The rotation speed is read from the deck stored in the file (the fastest turning surface); a file
whose status is not "complete" is read with a warning (its last record is not the end of the run)."""
import argparse
import os
import subprocess
import sys

import numpy as np

from ..errors import EpapheError
from ..measures import contact_events, spectrum, wear_lobes
from ..results import Names, Run
from ..runner import find_run

PROG = "epaphe-rotor"


def speed_map(deck, speeds, revs, skip, sets, component, ranks, run_exe, mpiexec, out):
    """Runs `deck` at every speed with `epaphe-run --speeds`, which deals the speeds to `ranks` MPI
    ranks (mpiexec -n ranks; each rank runs its speeds alone), then builds the map from speed-<W>.h5:
    {set: [dominant engine order per speed], set + "/amplitude": (speeds x orders)}, written to
    out/map.h5 and out/map-<set>.png."""
    import shutil

    import h5py

    os.makedirs(out, exist_ok=True)
    exe = find_run(run_exe)
    cmd = [
        exe,
        os.path.abspath(deck),
        "--speeds",
        ",".join(f"{w:g}" for w in speeds),
        "--revolutions",
        repr(float(revs)),
    ]
    if ranks > 1:
        launcher = mpiexec or shutil.which("mpiexec") or shutil.which("mpirun")
        if not launcher:
            raise EpapheError("--ranks %d needs mpiexec (give --mpiexec PATH)" % ranks)
        cmd = [launcher, "-n", str(ranks)] + cmd
    env = dict(os.environ)
    # Open MPI as root and on fewer cores than ranks (a laptop, a CI container).
    env.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
    env.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
    env.setdefault("OMPI_MCA_rmaps_base_oversubscribe", "1")
    print(f"epaphe-rotor: {len(speeds)} speeds on {ranks} MPI rank(s): {' '.join(cmd)}", flush=True)
    p = subprocess.run(cmd, cwd=out, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    sys.stdout.write(p.stdout)
    if p.returncode != 0:
        raise EpapheError(f"the speed sweep failed (exit {p.returncode}):\n{p.stderr.strip()}")
    runs = [(w, os.path.join(out, f"speed-{w:g}.h5")) for w in speeds]
    result = {}
    eo_grid = None
    for s in sets:
        rows = []
        for w, h5 in runs:
            eo, freq, amp = spectrum(h5, "Blade", s, component, skip)
            if eo_grid is None:
                eo_grid = np.linspace(0, min(40.0, eo[-1]), 801)
            rows.append(np.interp(eo_grid, eo, amp))
            k = int(np.argmax(amp[eo > 0.5])) + int(np.argmax(eo > 0.5))
            print(f"{s} at {w:g} rad/s: dominant engine order {eo[k]:.2f} ({freq[k]:.1f} Hz)")
            result.setdefault(s, []).append(eo[k])
        result[s + "/amplitude"] = np.array(rows)
    with h5py.File(os.path.join(out, "map.h5"), "w") as f:
        f["speeds"] = np.array(speeds, dtype=float)
        f["engine_orders"] = eo_grid
        for s in sets:
            f[f"{s}/amplitude"] = result[s + "/amplitude"]
            f[f"{s}/dominant_engine_order"] = np.array(result[s])
    wear_map = speed_wear_map(runs)  # None without a coating
    if wear_map is not None:
        result["wear"] = wear_map
        with h5py.File(os.path.join(out, "map.h5"), "a") as f:
            for k in ("angle", "profile", "dominant_order", "lobes", "max_wear", "contrast"):
                f[f"wear/{k}"] = wear_map[k]
            f["wear"].attrs["surface"] = wear_map["surface"]
    import matplotlib

    matplotlib.use("Agg")
    from .. import plots

    for s in sets:
        plots.draw_interaction_map(
            eo_grid,
            speeds,
            result[s + "/amplitude"],
            os.path.join(out, f"map-{s}.png"),
            os.path.basename(deck),
            s,
            component,
            dominant=result[s],
        )
    if wear_map is not None:
        plots.draw_wear_speed_map(
            wear_map["angle"],
            speeds,
            wear_map["profile"],
            wear_map["dominant_order"],
            os.path.join(out, "map-wear.png"),
            os.path.basename(deck),
            wear_map["surface"],
        )
    return result


def speed_wear_map(runs):
    """The final wear of each run of a speed sweep [(speed, file)] with a coating: dict(surface, angle
    (n_u,) rad, profile (speeds x n_u) m -- the deepest wear of each column --, dominant_order,
    lobes, max_wear, contrast (per speed), as epaphe.measures.wear_lobes defines them); None when the runs have
    no coating. Prints one line per speed."""
    rows, orders, counts, deepest, contrasts, angle, surface = [], [], [], [], [], None, None
    for w, h5 in runs:
        with Run(h5) as run:
            if run.file.get("coating") is None:
                return None
            coat = read_coating(run, surface)
        surface, angle = coat["surface"], coat["angle"]
        lobes = wear_lobes(coat["angle"], coat["wear"], where=h5)
        rows.append(lobes.profile)
        orders.append(lobes.dominant_order)
        counts.append(lobes.lobe_count)
        deepest.append(lobes.max_wear)
        contrasts.append(lobes.contrast)
        print(
            f"wear at {w:g} rad/s: {lobes.lobe_count} lobe(s), dominant harmonic {lobes.dominant_order} "
            f"(amplitude {lobes.contrast:.2f} of the mean wear), max wear {lobes.max_wear * 1e6:.3g} um"
        )
    return dict(
        surface=surface,
        angle=angle,
        profile=np.array(rows),
        dominant_order=np.array(orders),
        lobes=np.array(counts),
        max_wear=np.array(deepest),
        contrast=np.array(contrasts),
    )


# ---- abradable coating: wear lobes ----------------------------------------------------------------
def read_coating(run, surface=None):
    """The coating of `surface` in a run (the only coated surface when None), at its last wear
    record: dict(surface, attrs {thickness, youngs_modulus, yield_stress, hardening_modulus,
    elements}, angle (n_u,) rad, axial (n_v,) m, time (s, of the last record), records, wear (n_u, n_v)
    m). EpapheError naming the file when it has no coating, when several surfaces are coated and
    `surface` is None, when `surface` is not coated, or when the datasets disagree in shape."""
    path = run.path
    g = run.file.get("coating")
    names = list(g.keys()) if g is not None else []
    if not names:
        raise EpapheError(
            f"{path} has no coating ({'an empty' if g is not None else 'no'} /coating group): "
            "its deck puts no abradable coating on any surface"
        )
    if surface is None:
        if len(names) > 1:
            raise EpapheError(
                f"{path} has {len(names)} coated surfaces ({', '.join(names)}): choose one " "with --surface"
            )
        surface = names[0]
    c = Names({n: g[n] for n in names}, "coated surface", path)[surface]
    where = f"{path}: /coating/{surface}"
    for d in ("angle", "axial", "time", "wear"):
        if d not in c:
            raise EpapheError(f"{where}: no dataset '{d}' (an incomplete coating group)")
    angle = np.asarray(c["angle"][()], dtype=float).reshape(-1)
    axial = np.asarray(c["axial"][()], dtype=float).reshape(-1)
    time = np.asarray(c["time"][()], dtype=float).reshape(-1)
    wear = c["wear"]
    shape = (time.size, angle.size, axial.size)
    if wear.ndim != 3 or wear.shape[1:] != shape[1:] or wear.shape[0] < 1 or wear.shape[0] > time.size:
        raise EpapheError(f"{where}/wear: shape {wear.shape}, expected {shape} (time x angle x axial)")
    elements = c.attrs.get("elements")
    if elements is not None and tuple(np.asarray(elements).reshape(-1)) != shape[1:]:
        raise EpapheError(
            f"{where}: attribute elements = {list(np.asarray(elements).reshape(-1))} but "
            f"{angle.size} angles and {axial.size} axial positions"
        )
    last = wear.shape[0] - 1  # a run still being written may have fewer wear rows than times
    return dict(
        surface=surface,
        attrs={k: v for k, v in c.attrs.items()},
        angle=angle,
        axial=axial,
        time=float(time[last]),
        records=last + 1,
        wear=np.asarray(wear[last], dtype=float),
    )


def draw_wear(coat, lobes, title, path):
    """The wear of a coating (read_coating) and its lobes (measures.wear_lobes): on top the map of the
    unrolled casing (angle, deg, across; axial position, mm, up; wear, um, as colour, with a colour
    bar), below the circumferential profile (um) with half its maximum (the lobe threshold) dashed,
    the lobes (triangles) and the peaks of the dominant harmonic (ticks). Written to `path`."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    deg = np.degrees(np.mod(coat["angle"], 2 * np.pi))
    cols = np.argsort(deg)  # columns in increasing angle (the file may start anywhere)
    rows = np.argsort(coat["axial"])
    um = 1e6 * coat["wear"][cols][:, rows]
    prof = 1e6 * lobes.profile[cols]
    fig, (ax, bx) = plt.subplots(
        2, 1, figsize=(8, 6.4), sharex=True, layout="constrained", gridspec_kw=dict(height_ratios=(3, 2))
    )
    mesh = ax.pcolormesh(
        deg[cols],
        1e3 * coat["axial"][rows],
        um.T,
        shading="nearest",
        cmap="viridis",
        vmin=0.0,
        vmax=max(float(um.max()), 1e-12),
    )
    fig.colorbar(mesh, ax=[ax], label="wear depth (\u00b5m)", pad=0.02)
    ax.set_ylabel("axial position (mm)")
    ax.set_title(title, fontsize=10)
    bx.plot(deg[cols], prof, "-", lw=1.2, label="profile: deepest wear of each column")
    if lobes.max_wear > 0:
        bx.axhline(0.5e6 * lobes.max_wear, color="0.5", ls="--", lw=0.8, label="half the largest wear")
    if lobes.lobe_count:
        la = np.degrees(lobes.lobe_angles)
        at = [prof[int(np.argmin(np.abs(deg[cols] - a)))] for a in la]
        bx.plot(la, at, "v", color="C3", ms=7, ls="none", label=f"{lobes.lobe_count} lobe(s)")
        for a in la:
            ax.axvline(a, color="C3", lw=0.6, ls=":")
    if lobes.dominant_order:
        bx.plot(
            np.degrees(lobes.harmonic_angles),
            np.zeros(lobes.dominant_order),
            "|",
            color="C1",
            ms=12,
            mew=1.5,
            ls="none",
            label=f"peaks of harmonic {lobes.dominant_order}",
        )
    bx.set_xlim(0, 360)
    bx.set_ylim(
        min(0.0, float(prof.min())) - 0.05 * max(float(prof.max()), 1e-12), 1.45 * max(float(prof.max()), 1e-12)
    )  # room for the markers and legend
    bx.set_xticks(np.arange(0, 361, 45))
    bx.set_xlabel("angle about the casing axis (deg, casing frame)")
    bx.set_ylabel("wear (\u00b5m)")
    bx.grid(True, alpha=0.3)
    bx.legend(fontsize=7, loc="upper center", ncol=2)
    fig.colorbar(mesh, ax=[bx], pad=0.02).ax.set_visible(False)  # the same width as the map above
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return fig


def wear(path, surface=None, png=None, csv=None):
    """epaphe-rotor wear: prints the wear summary of a coated surface of the run at `path` and writes
    the figure `png` and the profile `csv` when given; returns (read_coating dict, WearLobes)."""
    with Run(path) as run:
        if not run.complete:
            sys.stderr.write(
                f"{PROG}: warning: {path}: status '{run.status}', not 'complete': the wear is "
                "the last record's, not the end of a run\n"
            )
        coat = read_coating(run, surface)
        plastic = None
        if "energy/plastic_dissipation" in run.file:
            e = np.asarray(run.file["energy/plastic_dissipation"][()], dtype=float).reshape(-1)
            e = e[np.isfinite(e)]
            plastic = float(e[-1]) if e.size else None
    s = coat["surface"]
    lobes = wear_lobes(coat["angle"], coat["wear"], f"{path}: /coating/{s}")
    n_u, n_v = coat["wear"].shape
    thick = coat["attrs"].get("thickness")
    thick = f" {1e3 * float(thick):.4g} mm thick," if thick is not None else ""

    def degs(a):
        return ", ".join(f"{x:.1f}" for x in np.degrees(a))

    print(
        f"{s}: coating{thick} {n_u} x {n_v} elements (around x along the axis); wear at "
        f"t = {coat['time']:.6g} s (record {coat['records']})"
    )
    print(f"max wear: {1e6 * lobes.max_wear:.4g} um")
    print(
        f"lobes: {lobes.lobe_count}"
        + (f" at {degs(lobes.lobe_angles)} deg" if lobes.lobe_count else "")
        + " (runs of columns worn deeper than half the max wear)"
    )
    if lobes.dominant_order:
        print(
            f"dominant harmonic: order {lobes.dominant_order} (amplitude {lobes.contrast:.2f} of the mean wear), "
            f"peaks at {degs(lobes.harmonic_angles)} deg"
        )
    else:
        print("dominant harmonic: none (no wear, or the same wear all round)")
    print(
        "plastic dissipation at the end: "
        + (f"{plastic:.6g} J" if plastic is not None else "not in the file (no /energy/plastic_dissipation)")
    )
    if csv:
        with open(csv, "w") as f:
            f.write("angle_deg,wear_m\n")
            for a, w in zip(np.degrees(coat["angle"]), lobes.profile):
                f.write(f"{float(a)!r},{float(w)!r}\n")
    if png:
        draw_wear(
            coat,
            lobes,
            f"{os.path.basename(path)}, coating of {s}: {lobes.lobe_count} lobe(s), "
            f"max {1e6 * lobes.max_wear:.3g} \u00b5m",
            png,
        )
    return coat, lobes


def parse_orders(text):
    """Engine orders from "1-12" or "1,2,6" (positive integers)."""
    try:
        if "-" in text:
            lo, hi = (int(x) for x in text.split("-"))
            orders = list(range(lo, hi + 1))
        else:
            orders = [int(x) for x in text.split(",")]
    except ValueError:
        raise EpapheError(f"--orders {text}: give a range 1-12 or a list 1,2,6 of engine orders")
    if not orders or min(orders) < 1:
        raise EpapheError(f"--orders {text}: engine orders are integers >= 1")
    return orders


def campbell(deck, body, orders, points, count, out, exe=None):
    """Runs epaphe-campbell on `deck`, then draws the diagram and lists the crossings."""
    import h5py
    import matplotlib

    matplotlib.use("Agg")
    from .. import campbell as cb

    os.makedirs(out, exist_ok=True)
    if exe is None:
        exe = os.path.join(os.path.dirname(find_run(None)), "epaphe-campbell")
    if not (os.path.isfile(exe) and os.access(exe, os.X_OK)):
        raise EpapheError(f"epaphe-campbell not found at {exe}: give it with --campbell")
    h5 = os.path.join(out, "campbell.h5")
    cmd = [exe, os.path.abspath(deck), "--output", h5, "--speeds", str(points)]
    if body:
        cmd += ["--body", body]
    if count:
        cmd += ["--count", str(count)]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=7200)
    sys.stdout.write(proc.stdout)
    if proc.returncode != 0:
        raise EpapheError(f"epaphe-campbell failed (exit {proc.returncode}): {proc.stderr.strip()}")
    with h5py.File(h5, "r") as f:
        table = {
            "speeds": f["speeds"][()],
            "frequencies": f["frequencies"][()],
            "full_speeds": f["full/speeds"][()],
            "full_frequencies": f["full/frequencies"][()],
        }
        name = f.attrs["body"]
        name = name.decode() if isinstance(name, bytes) else str(name)
    rows = cb.crossings(table["speeds"], table["frequencies"], orders)
    with h5py.File(h5, "a") as f:
        if "crossings" in f:
            del f["crossings"]
        d = f.create_dataset("crossings", data=np.array(rows, dtype=float).reshape(-1, 4))
        d.attrs["columns"] = "speed_rad_s,engine_order,mode,frequency_hz"
    print(
        f"\n{len(rows)} crossings of modes 1-{table['frequencies'].shape[1]} with engine orders "
        f"{orders[0]}-{orders[-1]}:"
    )
    for w, k, mode, fr in rows:
        print(f"  {w:10.2f} rad/s ({w * 30 / np.pi:8.1f} rpm)  EO {k:2d}  mode {mode:2d}  {fr:9.2f} Hz")
    png = os.path.join(out, "campbell.png")
    cb.draw(table, orders, f"{os.path.basename(deck)}, body {name}: Campbell diagram", png)
    print(f"written {h5} and {png}")
    return rows


def nodal_diameters(path, body, node_set, component, skip, casing=None, png=None):
    """epaphe-rotor nodal-diameters (see the module's help); returns (content, waves, criterion rows)."""
    import h5py

    from .. import stage

    names = stage.instances(path, body)
    comp = "xyz".index(component)
    u = stage.instance_histories(path, body, f"nodesets/{node_set}/displacement")  # [k, t, node, 3]
    x = u[..., comp].mean(axis=2) if u.ndim == 4 else u[:, :, comp::3].mean(axis=2)
    with h5py.File(path, "r") as f:
        t = f["time"][()]
        blade_hz = f[f"bodies/{names[0]}/frequencies/reduced"][()]
    keep = t >= skip
    if keep.sum() < 8:
        raise EpapheError(
            f"{path}: {keep.sum()} records after --skip {skip} s; skip less (the run ends at {t[-1]:g} s)"
        )
    x, t = x[:, keep], t[keep]
    dt = float(np.mean(np.diff(t)))
    content = stage.nodal_diameter_content(x)
    print(
        f"{len(names)} instances of '{body}', node set {node_set}, u_{component} after {skip:g} s: RMS per nodal diameter:"
    )
    for n, v in enumerate(content):
        print(f"  ND {n:2d}: {v:.3e} m")
    w = stage.travelling_waves(x, dt)
    for kind in ("forward", "backward"):
        a = w[kind][:, 1:]
        n, j = np.unravel_index(np.argmax(a), a.shape)
        print(f"largest {kind} wave: ND {n}, {w['frequency'][j + 1]:.1f} Hz, amplitude {a[n, j]:.3e} m")
    rows = []
    if casing:
        fc, u, coords = stage.model_modes(casing, 20)
        modes = []
        for k in range(len(fc)):
            n, share = stage.nodal_diameter_of(u[k], coords)
            modes.append((float(fc[k]), n))
            print(f"casing mode {k + 1}: {fc[k]:.1f} Hz, ND {n} ({100 * share:.0f} % of its radial motion)")
        # every casing diameter n: N blades sample its wave at their N positions, where it is their
        # wave of n mod N diameters (stage.interaction_speeds); a casing's pair of modes with one
        # nodal diameter (its two orientations) gives one row
        rows = sorted(set(stage.interaction_speeds([float(f) for f in blade_hz[:3]], modes)))
        rows = [
            r
            for i, r in enumerate(rows)
            if i == 0 or abs(r[0] - rows[i - 1][0]) > 1e-6 * r[0] or r[1] != rows[i - 1][1]
        ]
        print("modal interaction (Legrand et al. 2009), Omega_n = (omega_b + omega_c,n) / n:")
        for W, n, fb, fcn in rows:
            print(f"  ND {n:2d}: {W:9.1f} rad/s (blade {fb:.1f} Hz, casing {fcn:.1f} Hz)")
    if png:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        N = len(names)
        img = np.vstack([w["backward"][::-1], w["forward"][1:]])
        fig, ax = plt.subplots(figsize=(7, 4.5))
        f = w["frequency"]
        m = ax.imshow(
            np.log10(np.maximum(img, img.max() * 1e-6)),
            aspect="auto",
            origin="lower",
            extent=[f[0], f[-1], -(N - 1) - 0.5, (N - 1) + 0.5],
            cmap="viridis",
        )
        ax.set_xlabel("frequency (Hz)")
        ax.set_ylabel("nodal diameter (-): forward > 0, backward < 0")
        ax.set_title(f"{os.path.basename(path)}: travelling waves of {body}, u_{component} at {node_set}")
        fig.colorbar(m, ax=ax, label="log10 amplitude (m)")
        fig.savefig(png, dpi=110)
        plt.close(fig)
        print(f"written {png}")
    return content, w, rows


def main(argv=None):
    try:
        return run(sys.argv[1:] if argv is None else argv)
    except EpapheError as e:
        sys.exit(f"{PROG}: {e}")


def run(argv):
    ap = argparse.ArgumentParser(prog=PROG, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    c = sub.add_parser("contacts")
    c.add_argument("file")
    c.add_argument("--body", default="Blade")
    c.add_argument("--sets", default="tip-le,tip-te")
    c.add_argument("--skip", type=float, default=3.0)
    c.add_argument("--merge", type=float, default=0.15)
    c.add_argument("--csv")
    s = sub.add_parser("spectrum")
    s.add_argument("file")
    s.add_argument("--body", default="Blade")
    s.add_argument("--set", default="tip-le")
    s.add_argument("--component", default="x", choices=["x", "y", "z", "force"])
    s.add_argument("--skip", type=float, default=3.0)
    s.add_argument("--png")
    m = sub.add_parser("map")
    m.add_argument("deck")
    m.add_argument("--speeds", required=True)
    m.add_argument("--revs", type=float, default=8)
    m.add_argument("--skip", type=float, default=3.0)
    m.add_argument("--sets", default="tip-le,tip-te")
    m.add_argument("--component", default="x", choices=["x", "y", "z"])
    m.add_argument("--ranks", type=int, default=1)
    m.add_argument("--mpiexec")
    m.add_argument("--run")
    m.add_argument("--out", default="speed-map")
    cb = sub.add_parser("campbell")
    cb.add_argument("deck")
    cb.add_argument("--body")
    cb.add_argument("--orders", default="1-12")
    cb.add_argument("--speeds", type=int, default=41)
    cb.add_argument("--count", type=int)
    cb.add_argument("--out", default="campbell")
    cb.add_argument("--campbell", help="the epaphe-campbell executable (default: beside epaphe-run)")
    w = sub.add_parser("wear")
    w.add_argument("file")
    w.add_argument("--surface")
    w.add_argument("--png")
    w.add_argument("--csv")
    nd = sub.add_parser("nodal-diameters")
    nd.add_argument("file")
    nd.add_argument("--body", default="Blade")
    nd.add_argument("--set", default="tip-le")
    nd.add_argument("--component", default="x", choices=["x", "y", "z"])
    nd.add_argument("--skip", type=float, default=0.0)
    nd.add_argument("--casing")
    nd.add_argument("--png")
    a = ap.parse_args(argv)
    if a.cmd == "nodal-diameters":
        nodal_diameters(a.file, a.body, a.set, a.component, a.skip, a.casing, a.png)
    elif a.cmd == "campbell":
        campbell(a.deck, a.body, parse_orders(a.orders), a.speeds, a.count, a.out, a.campbell)
    elif a.cmd == "wear":
        wear(a.file, a.surface, a.png, a.csv)
    elif a.cmd == "map":
        speeds = [float(x) for x in a.speeds.split(",")]
        speed_map(a.deck, speeds, a.revs, a.skip, a.sets.split(","), a.component, a.ranks, a.run, a.mpiexec, a.out)
    elif a.cmd == "contacts":
        res = contact_events(a.file, a.body, a.sets.split(","), a.skip, a.merge)
        rows = []
        for name, r in res.items():
            print(
                f"{name}: {r['mean']:.2f} contacts per revolution (revolutions {a.skip:g}+: {r['per_rev']}), "
                f"in contact {100 * np.mean(r['fraction']):.1f} % of a revolution; event angles (deg): "
                + ", ".join(f"{x:.0f}" for x in r["angles"][:12])
                + (" ..." if len(r["angles"]) > 12 else "")
            )
            rows.append((name, r["mean"], float(np.mean(r["fraction"]))))
        if a.csv:
            with open(a.csv, "w") as f:
                f.write("node_set,contacts_per_revolution,fraction_in_contact\n")
                for row in rows:
                    f.write("%s,%.6g,%.6g\n" % row)
    else:
        eo, freq, amp = spectrum(a.file, a.body, a.set, a.component, a.skip)
        top = np.argsort(amp)[::-1][:5]
        unit = "N" if a.component == "force" else "m"
        print(
            "dominant engine orders: "
            + ", ".join(f"EO {eo[i]:.2f} ({freq[i]:.1f} Hz, {amp[i]:.3e} {unit})" for i in top)
        )
        if a.png:
            import matplotlib

            matplotlib.use("Agg")
            from .. import plots

            plots.draw_spectrum(
                eo,
                amp,
                "|contact force| (N)" if a.component == "force" else f"|u_{a.component}| (m)",
                f"{os.path.basename(a.file)}, node set {a.set}: spectrum after {a.skip:g} revolutions",
                a.png,
                rotation_hz=freq[1] / eo[1] if eo.size > 1 and eo[1] > 0 else None,
            )
    return 0
