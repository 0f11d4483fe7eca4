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
      order of each set at each speed.

The rotation speed is read from the deck stored in the file (the fastest turning surface)."""
import argparse
import os
import subprocess
import sys

import numpy as np

from ..errors import EpapheError
from ..measures import contact_events, spectrum
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
    cmd = [exe, os.path.abspath(deck), "--speeds", ",".join(f"{w:g}" for w in speeds), "--revolutions", repr(float(revs))]
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
    import matplotlib
    matplotlib.use("Agg")
    from .. import plots
    for s in sets:
        plots.draw_interaction_map(eo_grid, speeds, result[s + "/amplitude"], os.path.join(out, f"map-{s}.png"),
                                   os.path.basename(deck), s, component, dominant=result[s])
    return result


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
    a = ap.parse_args(argv)
    if a.cmd == "map":
        speeds = [float(x) for x in a.speeds.split(",")]
        speed_map(a.deck, speeds, a.revs, a.skip, a.sets.split(","), a.component, a.ranks, a.run, a.mpiexec, a.out)
    elif a.cmd == "contacts":
        res = contact_events(a.file, a.body, a.sets.split(","), a.skip, a.merge)
        rows = []
        for name, r in res.items():
            print(f"{name}: {r['mean']:.2f} contacts per revolution (revolutions {a.skip:g}+: {r['per_rev']}), "
                  f"in contact {100 * np.mean(r['fraction']):.1f} % of a revolution; event angles (deg): "
                  + ", ".join(f"{x:.0f}" for x in r["angles"][:12]) + (" ..." if len(r["angles"]) > 12 else ""))
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
        print("dominant engine orders: " + ", ".join(f"EO {eo[i]:.2f} ({freq[i]:.1f} Hz, {amp[i]:.3e} {unit})" for i in top))
        if a.png:
            import matplotlib
            matplotlib.use("Agg")
            from .. import plots
            plots.draw_spectrum(eo, amp, "|contact force| (N)" if a.component == "force" else f"|u_{a.component}| (m)",
                                f"{os.path.basename(a.file)}, node set {a.set}: spectrum after {a.skip:g} revolutions",
                                a.png, rotation_hz=freq[1] / eo[1] if eo.size > 1 and eo[1] > 0 else None)
    return 0
