#!/usr/bin/env python3
"""Benchmark (reports, never asserts timings): which model of the cube between the rigid rings
(inputs/cube-rings.xml, 50 m/s, Lagrange, the side and bottom faces retained as the deck has them)
is cheaper, the dense Craig-Bampton model or the full sparse model with lumped mass?

Usage: bench_lumped.py --run EPAPHE_RUN --deck DECK --workdir DIR [--end 1e-3] [--no-fine]

Runs, on 1 thread and at the deck's time step:
  cb      the deck as it is: Craig-Bampton, 20 modes (dense reduced model);
  full    Reduction Method 'Full, lumped mass' (K sparse, M diagonal, diagonal contact flexibility);
  ref     Reduction Method 'None': the full model with its consistent mass, dense (what both
          approximate on this mesh: no modes left out, no lumping);
  cb12, full12   (unless --no-fine) the same two on a 12 x 12 x 12 mesh: a larger retained interface
          (1443 retained DOFs), and finer references.
  cb-big, full-big   cb and full again at 0.75 of their own critical step (the largest step each
          model allows): the time a millisecond of the scene takes with each, and its accuracy.
Each is run twice: once for timing (a record every 1000 steps; steps/s and the per-step cost split
from /run/cost), once for accuracy (a record every 10 steps). Printed: DOFs, critical step, setup
time (with the reduction: no cache is reused), steps/s, loop time, cost split, contact start/end/impulse, and the RMS difference of the watched node
(bottom face, x = -0.025, z = 0) between the models, relative to the largest displacement of it.

Asserted (accuracy only; the times are reported), each of cb, full, cb-big and full-big against ref,
and full12 against cb12:
  - first and last contact within 2 % of ref's contact duration, plus the record interval of the
    coarser run (contact is seen only at records: every 10 steps, 1e-6 s at h = 1e-7 s, 1e-5 s at
    full-big's step, 5.5 % of the duration), and the impulse within 2 %: verification.v6-full-lumped's
    tolerances for the same two models (tests/verification/v6_full_lumped.py);
  - the watched node's RMS difference within RMS_TOL = 0.2 % of ref's largest displacement: 3 times
    the largest measured (0.064 %, Craig-Bampton against ref; the others 0.04-0.054 %), and 16 times
    below what refining the mesh to 12^3 moves it (3.2 %)."""
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "verification"))
from epaphe_testing import parse_args, run, variant, verdict  # noqa: E402

FULL = {"Bodies->Cube->Reduction->Method": "Full, lumped mass"}
FINE = {"Bodies->Cube->Mesh->Elements": ("{12, 12, 12}", "Array(int)")}
CONTACT_TOL = 0.02  # contact start/end (of ref's duration) and impulse: verification.v6-full-lumped's
RMS_TOL = 0.002  # watched node's RMS difference, of ref's largest displacement (docstring)
CONFIGS = {
    "cb": {},
    "full": FULL,
    "ref": {"Bodies->Cube->Reduction->Method": "None"},
    "cb12": FINE,
    "full12": {**FULL, **FINE},
}


def text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def watched_node(elements):
    """Node id of (x = -0.025, y = bottom, z = 0) in the structured box (i fastest, then j, then k)."""
    n = elements + 1
    return 0 + n * (0 + n * (elements // 2))


def main():
    import argparse

    extra = argparse.ArgumentParser(add_help=False)
    extra.add_argument("--end", default="1e-3")
    extra.add_argument("--no-fine", action="store_true")
    opts, rest = extra.parse_known_args()
    sys.argv = [sys.argv[0]] + rest
    a = parse_args()
    names = [n for n in CONFIGS if not (n.endswith("12") and opts.no_fine)]
    for old in os.listdir(a.workdir):  # the setup times include the reductions
        if old.endswith(".rom.h5"):
            os.remove(os.path.join(a.workdir, old))
    figures, curves = {}, {}
    for name in names + ["cb-big", "full-big"]:
        if name.endswith("-big"):  # at 0.75 of the model's own critical step
            base = name[:-4]
            CONFIGS[name] = {**CONFIGS[base], "Time->Time step": (f"{0.75 * figures[base]['critical']:.4e}", "double")}
            names.append(name)
        for purpose, every in (("timing", 1000), ("accuracy", 10)):
            tag = f"cube-{name}-{purpose}"
            deck = variant(
                a.deck,
                os.path.join(a.workdir, tag + ".xml"),
                {
                    **CONFIGS[name],
                    "Output->File": tag + ".h5",
                    "Output->Every": (str(every), "int"),
                    "Time->End time": (opts.end, "double"),
                    "Run->Progress interval": ("0", "double"),
                    "Bodies->Cube->Reduction->Cache file": f"cube-{name.replace('-big', '')}.rom.h5",
                },
            )
            run([a.run, deck, "--threads", "1"], a.workdir)
            with h5py.File(os.path.join(a.workdir, tag + ".h5"), "r") as f:
                if purpose == "timing":
                    r = f["/run"].attrs
                    steps = r["steps"]
                    figures[name] = dict(
                        dofs=int(f["/bodies/Cube"].attrs["reduced_dofs"]),
                        method=text(f["/bodies/Cube"].attrs["reduction"]),
                        critical=r["critical_time_step"],
                        h=r["time_step"],
                        rate=r["steps_per_second"],
                        setup=r["setup_time"],
                        loop=r["loop_time"],
                        cost={k: 1e6 * v / steps for k, v in f["/run/cost"].attrs.items()},
                    )
                    continue
                elements = 12 if name.endswith("12") else 6
                nodes = list(f["/bodies/Cube/nodesets/all/nodes"][()])
                k = nodes.index(watched_node(elements))
                t = f["/time"][()]
                force = f["/bodies/Cube/contact/total_force"][()]
                on = np.nonzero(force > 1e-6 * force.max())[0]
                curves[name] = dict(
                    t=t,
                    u=f["/bodies/Cube/nodesets/all/displacement"][:, k, :],
                    start=t[on[0]],
                    end=t[on[-1]],
                    impulse=force.sum() * (t[1] - t[0]),
                )
    print(f"cube between two rigid rings at 50 m/s, end {opts.end} s, 1 thread")
    for name in names:
        g, c = figures[name], curves[name]
        split = ", ".join(f"{k} {v:.1f} us" for k, v in sorted(g["cost"].items()))
        print(
            f"{name:8s} {g['method']:17s} {g['dofs']:5d} DOFs, h = {g['h']:.3e} s: critical step {g['critical']:.3e} s, "
            f"setup {g['setup']:.2f} s, {g['rate']:.0f} steps/s, loop {g['loop']:.2f} s; per step: {split}"
        )
        print(f"      contact {c['start']:.4e} .. {c['end']:.4e} s, impulse {c['impulse']:.5e} N s")
    ref = curves["ref"]
    scale = np.abs(ref["u"]).max()

    def rms(x, y):
        """RMS over y's records of |u_x - u_y|, x interpolated linearly on y's times."""
        keep = y["t"] <= x["t"][-1]
        ux = np.stack([np.interp(y["t"][keep], x["t"], x["u"][:, c]) for c in range(3)], axis=1)
        return np.sqrt(np.mean(np.sum((ux - y["u"][keep]) ** 2, axis=1)))

    pairs = [("full", "cb"), ("cb", "ref"), ("full", "ref"), ("cb-big", "ref"), ("full-big", "ref")]
    if "full12" in names:
        pairs += [("full12", "cb12")] + [(x, y) for y in ("cb12", "full12") for x in ("cb", "full", "ref")]
    for x, y in pairs:
        d = rms(curves[x], curves[y])
        print(
            f"watched node displacement, RMS {x} - {y}: {d:.3e} m ({d / scale:.2%} of the reference's largest "
            f"{scale:.3e} m)"
        )
    for x, y in (("full", "cb"), ("full12", "cb12"), ("full-big", "cb-big")):
        if x in figures:
            print(
                f"{x} against {y}: {figures[x]['rate'] / figures[y]['rate']:.2f} x the steps/s, "
                f"{figures[y]['loop'] / figures[x]['loop']:.2f} x faster over {opts.end} s"
            )

    failures = []
    checked = [(x, "ref") for x in ("cb", "full", "cb-big", "full-big")]
    checked += [("full12", "cb12")] if "full12" in names else []
    print(
        f"accuracy asserted: contact start and end within {CONTACT_TOL:.2%} of the reference's duration + the "
        f"record interval, impulse within {CONTACT_TOL:.2%}, RMS within {RMS_TOL:.2%} of {scale:.3e} m"
    )
    for x, y in checked:
        cx, cy = curves[x], curves[y]
        duration = cy["end"] - cy["start"]
        interval = max(cx["t"][1] - cx["t"][0], cy["t"][1] - cy["t"][0])
        for key in ("start", "end"):
            d = abs(cx[key] - cy[key])
            print(
                f"  {x} - {y}: contact {key} differs by {d:.3e} s ({d / duration:.2%} of {duration:.3e} s; "
                f"record interval {interval:.1e} s)"
            )
            if not d <= CONTACT_TOL * duration + interval:
                failures.append(
                    f"{x} against {y}: contact {key} {cx[key]:.4e} s against {cy[key]:.4e} s, off by "
                    f"{d / duration:.2%} of the duration, more than {CONTACT_TOL:.2%} + one record "
                    f"interval ({interval:.1e} s)"
                )
        d = abs(cx["impulse"] - cy["impulse"]) / cy["impulse"]
        print(f"  {x} - {y}: impulse differs by {d:.3%}")
        if not d <= CONTACT_TOL:
            failures.append(
                f"{x} against {y}: impulse {cx['impulse']:.5e} N s against {cy['impulse']:.5e} N s, "
                f"{d:.2%} apart, more than {CONTACT_TOL:.2%}"
            )
        d = rms(cx, cy) / scale
        if not d <= RMS_TOL:
            failures.append(
                f"{x} against {y}: the watched node's RMS difference is {d:.3%} of the largest "
                f"displacement, more than {RMS_TOL:.2%}"
            )
    return verdict(failures)


if __name__ == "__main__":
    sys.exit(main())
