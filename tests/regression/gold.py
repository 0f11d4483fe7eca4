#!/usr/bin/env python3
"""Regression gold files: every deck of inputs/ against a small, down-sampled history of its own.

Usage:
    gold.py --run EPAPHE_RUN --inputs DIR --gold DIR --workdir DIR [--deck NAME ...] [--threads N]
            [--regenerate]

For each deck inputs/<deck>.xml (a glob: a new deck is covered at once, and fails until it has a
gold file), runs epaphe-run on a variant of the deck cut to a horizon that holds its first contacts
(HORIZON below; 1 thread, no reduced-model cache, so that the reduction itself is checked too),
reduces the history it writes to at most MAX_RECORDS records per dataset and compares it with
<gold>/<deck>.h5. What is compared (all from the HDF5 output, see docs/user/output.md):

- /time, /energy/*, /bodies/<b>/momentum: sampled at the last record of each of MAX_RECORDS windows
  of equal length (the last record of the run included; fewer windows on a deck with many datasets,
  so that a gold file holds about BUDGET values, < 100 kB);
- /bodies/<b>/nodesets/<set>/{displacement, velocity}: three nodes of the set (first, middle, last)
  sampled, and the norm over all the set's nodes and components, sampled;
- /bodies/<b>/contact/{gap, force}: per window the smallest gap and the largest force over all
  contact nodes and over every record of the window (a contact event shorter than a window is
  still seen), and the three nodes with the largest peak force in the gold run, sampled;
  /bodies/<b>/contact/total_force: sampled, its largest value and its sum per window;
- /bodies/<b>/frequencies/*: all of them (a modes-only deck such as ring-modes.xml is checked there);
- /thermal/<b> (decks with a thermal model): time, max_temperature, friction_heat, heat, coating_heat
  sampled; temperature (records x contact nodes) per window its largest value over the nodes and the
  records of the window, and the three contact nodes hottest in the gold run, sampled; growth (records x
  3 contact nodes) the norm over the nodes, sampled, and the same three nodes' growth; rates (the
  reduced thermal model's decay rates) all of them;
- the run summary's contact line (first and last contact, max force, impulse: over every step).

A value x passes against its gold value g when |x - g| <= ATOL * scale + RTOL * |g|, scale being
the largest |g| of the gold dataset (not below the kind's FLOOR). On failure the deck, dataset,
record (and its time), both values and the excess are printed.

The gold files store the deck's overrides, its SHA-256, the epaphe git commit (and whether the tree
was modified) they were made with, the epaphe version, and these tolerances.

--regenerate (or the environment variable EPAPHE_REGENERATE_GOLD=1, e.g.
`EPAPHE_REGENERATE_GOLD=1 ctest --test-dir build -R regression.gold`) rewrites the gold files and
compares nothing: do it only after a change of results you meant and have checked. The test never
regenerates by itself: a deck without a gold file fails.

--threads N (default 1) runs on N threads against the same 1-thread gold files and tolerances, which
are set above what 1 and 2 threads differ by (regression.gold-2threads runs every deck so). That
difference comes from the reduction alone: its eigensolver's iterates sum in another order on 2
threads and its modes agree to its tolerance (the recovery to 2e-10 of its largest entry on
cube-rings), while the explicit step on 2 threads, from the same reduced model, gives the 1-thread
history bit for bit, energies and momenta included (faults.restart-2threads checks that).
"""
import argparse
import datetime
import glob
import hashlib
import json
import os
import re
import resource
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "verification"))
from epaphe_testing import variant  # noqa: E402
import epaphe  # noqa: E402  (epaphe_testing put python/ on the path)

MAX_RECORDS = 200  # records kept per dataset (windows of the run) at most ...
BUDGET = 10000  # ... and fewer on a deck with many datasets: about this many values in all (< 100 kB)
NODES_KEPT = 3  # nodes of a node set kept individually (first, middle, last)

# ---- tolerances ------------------------------------------------------------------------------------
# The run is deterministic on 1 thread: the same binary gives the same bits (faults.restart checks it;
# two 1-thread runs here agree to 0). What the tolerances must absorb is a change of summation order
# that changes no physics: another thread count, BLAS, compiler. Measured: every deck on 2 threads
# against its 1-thread gold file (gold.py --threads 2, 11 decks), the largest
# |x - g| / scale over all datasets of a kind and all decks, in the comment of each kind (and where).
# Each tolerance is that times 77-170 (never above 1e-6 of the scale), while a small change of physics
# is far larger (measured): the cube's density +1 % (cube-rings) moves its displacements by
# 2e-3 of their scale (5e4 x the bound), mu 0.15 -> 0.1515 (rotor37-massless) the tip by 8e-2 (2e6 x),
# the blade's modal damping 0.5 -> 0.505 % (blade-casing) the tip by 6e-4 (1e4 x) and the damping
# energy by 1.4e5 x its bound; a time step +1 % changes the number of records, which fails at once.
# kind: (ATOL as a fraction of the dataset's scale, RTOL of the value)
TOLERANCES = {
    "time": (1e-12, 1e-12),  # t_k = k h; measured 0
    "energy": (3e-8, 3e-8),  # J; measured 2.9e-10 (rotor37-casing)
    "balance": (1e-8, 0.0),  # balance_error (already relative, compared absolutely): 9.6e-11 (cube-rings)
    "momentum": (3e-7, 3e-7),  # kg m/s; measured 3.0e-9 (two-bars, the free bar)
    "displacement": (3e-8, 3e-8),  # m; measured 2.3e-10 (blade-casing, leading edge)
    "velocity": (3e-7, 3e-7),  # m/s; measured 3.0e-9 (two-bars)
    "gap": (3e-8, 3e-8),  # m; measured 2.4e-10 (two-bars; see FLOORS)
    "force": (1e-6, 1e-6),  # N; jumps with the active set; measured 1.3e-8 (blade-casing, one node)
    "frequency": (1e-8, 1e-8),  # Hz; measured 5.9e-11 (two-bars), rigid-body modes set to 0 (below)
    "summary": (1e-6, 1e-6),  # printed with 7 digits (5e-7 of rounding); measured 0
    # /thermal (blade-casing-heat): the heat follows the contact forces, the temperature and the growth the
    # heat; the same bounds as the energies and displacements (measured in the comments)
    "temperature": (3e-8, 3e-8),  # K; measured 4.8e-11 (blade-casing-heat, the hottest tip nodes)
    "heat": (3e-8, 3e-8),  # J; measured 1.1e-10 (blade-casing-heat)
    "growth": (3e-8, 3e-8),  # m; measured 3.2e-10 (blade-casing-heat)
    "rate": (1e-8, 1e-8),  # 1/s, the thermal model's decay rates; measured 0 (a dense LAPACK solve)
}
# the smallest scale of a dataset: a dataset whose values all stay below it is compared in absolute
# terms, atol x floor. Gap: nodes in contact throughout (two-bars) have gaps of the Lagrange solve's
# round-off, 1e-16 m, differing by 2e-16 m between thread counts: a micron is the floor (3e-14 m of
# tolerance there, far below the 1e-12 m penetrations docs/user/rotation.md quotes as physics).
FLOORS = {
    "time": 1e-12,
    "energy": 1e-12,
    "balance": 1.0,
    "momentum": 1e-12,
    "displacement": 1e-12,
    "velocity": 1e-9,
    "gap": 1e-6,
    "force": 1e-6,
    "frequency": 1e-6,
    "summary": 1e-12,
    "temperature": 1e-6,
    "heat": 1e-12,
    "growth": 1e-12,
    "rate": 1e-12,
}

# ---- horizons: each deck cut to what holds its first contacts, so that the whole test takes about
# a minute on 1 thread. A deck not listed keeps its own End time, capped at DEFAULT_MAX_STEPS steps
# (a deck that ends in revolutions must be listed); a deck with surfaces must then still see a
# contact, or the test asks for a horizon here.
HORIZON = {
    # V1: contact from 2e-5 to 1e-4 s and the rebound: the whole deck (2000 steps)
    "bar-on-wall": {},
    # the friction-damped cantilever: in contact from t = 0 (a static start), 1 drive period at 50 Hz
    "beam-friction": {"Time->End time": ("0.02", "double")},
    # the oblique contact: stuck, sliding from 1.24 ms, lifted off at 10 ms: the whole deck
    "oblique-contact": {},
    # V2: contact from t = 0 for 2L/c = 4e-4 s, then the bars part
    "two-bars": {"Time->End time": ("6e-4", "double")},
    # cube at 50 m/s: first contact at 6e-5 s, through both rings' contacts
    "cube-rings": {"Time->End time": ("1e-3", "double")},
    "cube-flexible-rings": {"Time->End time": ("4e-4", "double")},
    # thesis chapter 4 at E = 2.1 GPa (h = 1e-6 s): the first contacts last about 1.8 ms
    "cube-rings-thesis": {"Time->End time": ("4e-3", "double")},
    "cube-flexible-rings-thesis": {"Time->End time": ("2e-3", "double")},
    # blade: the leading edge touches twice per revolution, the trailing edge six times
    "blade-casing": {"Time->End revolutions": ("0.5", "double")},
    "blade-coating": {"Time->End revolutions": ("0.5", "double")},
    "blade-coating-sweep": {"Time->End revolutions": ("1", "double")},
    "blade-flexible-casing": {"Time->End revolutions": ("0.25", "double")},
    # rotor 37: the blade starts between the lobes, meets the first after a quarter revolution
    "rotor37-casing": {"Time->End revolutions": ("0.5", "double")},
    "rotor37-massless": {"Time->End revolutions": ("3", "double")},
    # the 8-blade stage: its first revolution, before the modal interaction grows (10x a revolution)
    "stage-flexible-casing": {"Time->End revolutions": ("1", "double")},
    # at 1000 rad/s: one revolution holds the pattern every later one repeats (seven contacts, from
    # 0.086 rev); the deck's 20 revolutions (1.26e6 steps) let round-off grow past the 2-rank bound
    "blade-casing-at-speed": {"Time->End revolutions": ("1", "double")},
    # heat from rubbing: first contact at 1.4 ms; two revolutions (126k steps, 1256 thermal steps) heat
    # the tip and grow it towards the casing (the energy record's heat term is compared with the energies)
    "blade-casing-heat": {"Time->End revolutions": ("2", "double")},
    # run-up: the ramp (720 to 800 rad/s) cut to 1.8 ms, its stiffness refreshed about every 400 steps
    "blade-casing-run-up": {
        "Time->End time": ("2e-3", "double"),
        "Bodies->Blade->Rotation->Speed law->Start time": ("1e-4", "double"),
        "Bodies->Blade->Rotation->Speed law->End time": ("1.9e-3", "double"),
    },
    # modes only: the deck's own few free steps
    "ring-modes": {},
}
DEFAULT_MAX_STEPS = 10000
# a run that does not end within this is killed and fails its deck (a hang must not block the suite):
# the slowest deck takes 6 s, 70 s on 2 threads that spin on a loaded 2-core machine (OMP_WAIT_POLICY)
RUN_TIMEOUT = 300

# datasets that are not results (costs, counters of iterations, checkpoints, field frames, meshes)
IGNORE = re.compile(r"(^checkpoint|^fields|/fields/|/mesh/|^surfaces/|cost|iterations|wall|seconds|projected)")
SUMMARY = re.compile(r"contact: first (\S+) s, last (\S+) s, max force (\S+) N, impulse (\S+) N s")


def kind_of(path):
    leaf = path.rsplit("/", 1)[-1]
    if path == "time":
        return "time"
    if path.startswith("thermal/"):
        leaf = leaf.split(":")[0]  # thermal/<b>/temperature:nodes and the like: the dataset's kind
        if leaf == "time":
            return "time"
        if leaf in ("temperature", "max_temperature"):
            return "temperature"
        if leaf in ("friction_heat", "coating_heat", "heat"):
            return "heat"
        return {"growth": "growth", "rates": "rate"}.get(leaf)  # nodes: the contact nodes' numbers, not a result
    if path.startswith("energy/"):
        return "balance" if leaf == "balance_error" else "energy"
    if path.startswith("summary/"):
        return "summary"
    if "/frequencies/" in path:
        return "frequency"
    if leaf == "momentum":
        return "momentum"
    if "/nodesets/" in path:
        return "displacement" if "/displacement" in path else "velocity"
    if "/contact/" in path:
        return "gap" if "/gap" in path else "force"
    return None


def windows(n, r):
    """MAX_RECORDS windows of records 0..n-1: (sample index = last record of each window, slices)."""
    chunks = [c for c in np.array_split(np.arange(n), min(n, r)) if c.size]
    return np.array([c[-1] for c in chunks]), [slice(c[0], c[-1] + 1) for c in chunks]


def columns(name, shape):
    """How many values per record a raw dataset keeps once reduced."""
    if "/frequencies/" in name:
        return 0
    if "/nodesets/" in name:
        return NODES_KEPT * 3 + 1
    if name.endswith(("/contact/gap", "/contact/force")):
        return 1 + NODES_KEPT
    if name.endswith("total_force"):
        return 3
    if name.startswith("thermal/") and name.endswith(("/temperature", "/growth")):
        return 1 + NODES_KEPT * (3 if name.endswith("growth") else 1)
    if name.endswith("/rates"):
        return 0
    return int(np.prod(shape[1:]))


def reduce_history(h5path, stdout, selection=None, records=None):
    """The compared datasets of one run: {name: array}, and the node selection {name: columns} (taken
    from `selection`, the gold file's, when given, so that the same nodes are compared), over
    `records` windows (the gold file's; else MAX_RECORDS, or fewer to hold BUDGET values)."""
    out, chosen = {}, {}
    with epaphe.open(h5path) as run:
        if not run.complete:
            raise RuntimeError(f"{h5path}: status '{run.status}', not complete")
        n = run.records
        raw = run.flat("f", select=lambda name: not IGNORE.search(name) and kind_of(name) is not None)
        if records is None:
            per_record = sum(columns(k, a.shape) for k, a in raw.items())
            records = max(50, min(MAX_RECORDS, BUDGET // max(per_record, 1)))
        idx, wins = windows(n, records)
        # a thermal body's records (thermal/<b>/time) start after the first step: windows of their own
        own = {}
        for name, a in raw.items():
            if name.startswith("thermal/") and name.endswith("/time"):
                own[name[: -len("time")]] = windows(a.shape[0], records)
        for name, a in sorted(raw.items()):
            group = name[: name.rfind("/") + 1] if name.startswith("thermal/") else None
            n_rec, (idx_g, wins_g) = (raw[group + "time"].shape[0], own[group]) if group in own else (n, (idx, wins))
            if name.startswith("thermal/") and name.endswith("/rates"):
                out[name] = a  # not a history: every rate
            elif "/frequencies/" in name:
                # rigid-body modes (below 1e-4 of the largest, the driver's own criterion) are zero up to
                # round-off, sqrt(eps) f_max = 1.5e-8 f_max (1.2e-8 f_max measured between 1 and 2 threads)
                out[name] = np.where(a < 1e-4 * (a.max() if a.size else 0.0), 0.0, a)
            elif a.ndim >= 1 and a.shape[0] != n_rec:
                raise RuntimeError(
                    f"{h5path}: {name} has {a.shape[0]} records, "
                    + (f"{group}time {n_rec}" if group in own else f"/time {n}")
                )
            elif "/nodesets/" in name:  # records x nodes x 3
                cols = selection.get(name) if selection else None
                if cols is None:
                    cols = sorted(set(np.linspace(0, a.shape[1] - 1, NODES_KEPT).round().astype(int).tolist()))
                chosen[name] = np.asarray(cols)
                out[name + ":nodes"] = a[idx][:, chosen[name], :]
                out[name + ":norm"] = np.sqrt(np.sum(a[idx] ** 2, axis=(1, 2)))
            elif name.startswith("thermal/") and name.endswith("/growth"):  # records x 3 contact nodes
                out[name + ":norm"] = np.sqrt(np.sum(a[idx_g] ** 2, axis=1))
            elif name.startswith("thermal/") and name.endswith("/temperature"):  # records x contact nodes
                out[name + ":window_max"] = np.array([a[w].max() for w in wins_g])
            elif name.startswith("thermal/"):  # records
                out[name] = a[idx_g]
            elif name.endswith("/contact/gap") or name.endswith("/contact/force"):  # records x nodes
                out[name + (":window_min" if name.endswith("gap") else ":window_max")] = np.array(
                    [a[w].min() if name.endswith("gap") else a[w].max() for w in wins]
                )
            else:  # records (x 3)
                out[name] = a[idx]
                if name.endswith("total_force"):
                    out[name + ":window_max"] = np.array([a[w].max() for w in wins])
                    out[name + ":window_sum"] = np.array([a[w].sum() for w in wins])
        # the contact nodes compared one by one: those with the largest peak force (the gold run's)
        for name in [k for k in raw if k.endswith("/contact/force")]:
            key = name[: -len("force")]
            cols = selection.get(key + "nodes") if selection else None
            if cols is None:
                peak = raw[name].max(axis=0)
                cols = sorted(np.argsort(-peak, kind="stable")[:NODES_KEPT].tolist())
            chosen[key + "nodes"] = np.asarray(cols)
            out[key + "force:nodes"] = raw[name][idx][:, chosen[key + "nodes"]]
            out[key + "gap:nodes"] = raw[key + "gap"][idx][:, chosen[key + "nodes"]]
        # the thermal bodies' contact nodes compared one by one: the hottest in the gold run
        for name in [k for k in raw if k.startswith("thermal/") and k.endswith("/temperature")]:
            key = name[: -len("temperature")]
            cols = selection.get(key + "nodes") if selection else None
            if cols is None:
                cols = sorted(np.argsort(-raw[name].max(axis=0), kind="stable")[:NODES_KEPT].tolist())
            chosen[key + "nodes"] = np.asarray(cols)
            idx_g = own[key][0]
            out[name + ":nodes"] = raw[name][idx_g][:, chosen[key + "nodes"]]
            if key + "growth" in raw:
                g = raw[key + "growth"].reshape(raw[key + "growth"].shape[0], -1, 3)
                out[key + "growth:nodes"] = g[idx_g][:, chosen[key + "nodes"], :]
    m = SUMMARY.findall(stdout)
    for i, (first, last, fmax, impulse) in enumerate(m):
        for k, v in (("first_contact", first), ("last_contact", last), ("max_force", fmax), ("impulse", impulse)):
            out[f"summary/{i}/{k}"] = np.array([float(v)])
    return out, chosen, n, idx


def git_commit(source):
    try:
        head = subprocess.run(
            ["git", "-C", source, "rev-parse", "HEAD"], capture_output=True, text=True, check=True, timeout=60
        ).stdout.strip()
        dirty = subprocess.run(
            ["git", "-C", source, "status", "--porcelain", "--untracked-files=no"],
            capture_output=True,
            text=True,
            check=True,
            timeout=60,
        ).stdout.strip()
        return head, bool(dirty)
    except (OSError, subprocess.CalledProcessError, subprocess.TimeoutExpired):
        return "unknown", True


def body_names(deck):
    bodies = ET.parse(deck).getroot().find("./ParameterList[@name='Bodies']")
    return [b.get("name") for b in bodies.findall("./ParameterList")] if bodies is not None else []


def has_surfaces(deck):
    s = ET.parse(deck).getroot().find("./ParameterList[@name='Surfaces']")
    return s is not None and len(s.findall("./ParameterList")) > 0


def overrides_for(name, deck):
    """The deck variant's overrides: the horizon, 1 output file, no reduced-model cache, quiet."""
    over = {"Output->File": f"{name}.h5", "Run->Progress interval": ("0", "double")}
    if name in HORIZON:
        over.update(HORIZON[name])
    else:
        time_list = ET.parse(deck).getroot().find("./ParameterList[@name='Time']")
        get = {p.get("name"): p.get("value") for p in time_list.findall("./Parameter")} if time_list is not None else {}
        h = float(get.get("Time step", "1e-7"))
        if "End time" in get and float(get["End time"]) > DEFAULT_MAX_STEPS * h:
            over["Time->End time"] = (f"{DEFAULT_MAX_STEPS * h:.6g}", "double")
        if "End revolutions" in get:
            raise SystemExit(
                f"FAILED: {name}: its deck ends after 'End revolutions' = {get['End revolutions']}, which "
                f"DEFAULT_MAX_STEPS cannot cap without the speed: give it a horizon in HORIZON "
                f"({os.path.abspath(__file__)})"
            )
    for b in body_names(deck):
        over[f"Bodies->{b}->Reduction->Cache"] = ("false", "bool")
    return over


def run_deck(run, deck, name, workdir, threads):
    over = overrides_for(name, deck)
    path = variant(deck, os.path.join(workdir, f"{name}.xml"), over)
    out = os.path.join(workdir, f"{name}.h5")
    if os.path.exists(out):
        os.remove(out)
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), OMP_PROC_BIND="false", OPENBLAS_NUM_THREADS="1")
    t0, c0 = time.monotonic(), resource.getrusage(resource.RUSAGE_CHILDREN)
    try:
        proc = subprocess.run(
            [run, path, "--threads", str(threads)],
            cwd=workdir,
            capture_output=True,
            text=True,
            env=env,
            timeout=RUN_TIMEOUT,
        )
    except subprocess.TimeoutExpired:
        raise RuntimeError(
            f"epaphe-run on {path} did not end within {RUN_TIMEOUT} s (killed): a hang, or a "
            f"deck far slower than its horizon allows (see HORIZON)"
        )
    except OSError as e:
        raise RuntimeError(f"cannot start {run} ({e}): build it first (cmake --build build)")
    c1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    seconds = (time.monotonic() - t0, c1.ru_utime + c1.ru_stime - c0.ru_utime - c0.ru_stime)
    if proc.returncode != 0:
        raise RuntimeError(f"epaphe-run failed on {path} (exit {proc.returncode}):\n{proc.stdout}{proc.stderr}")
    return out, proc.stdout, over, seconds


def sha256(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def scale_of(kind, g):
    return max(float(np.max(np.abs(g))) if g.size else 0.0, FLOORS[kind])


def write_gold(gold_path, deck, name, data, chosen, n, idx, over, stdout, source):
    commit, dirty = git_commit(source)
    os.makedirs(os.path.dirname(gold_path), exist_ok=True)
    tmp = gold_path + ".tmp"
    with h5py.File(tmp, "w", libver="latest") as g:
        g.attrs["deck"] = f"inputs/{name}.xml"
        g.attrs["deck_sha256"] = sha256(deck)
        g.attrs["overrides"] = json.dumps({k: (v if isinstance(v, str) else list(v)) for k, v in over.items()})
        g.attrs["epaphe_commit"] = commit
        g.attrs["epaphe_tree_modified"] = dirty
        g.attrs["created_utc"] = datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")
        g.attrs["threads"] = 1
        g.attrs["records"] = n
        g.attrs["max_records"] = MAX_RECORDS
        g.attrs["tolerances"] = json.dumps(TOLERANCES)
        g.attrs["floors"] = json.dumps(FLOORS)
        g.attrs["tolerance_rule"] = "|x - g| <= atol * scale + rtol * |g|, scale = max(max |g| of the dataset, floor)"
        # one packed, compressed array and a JSON index: a dataset per entry would cost 2-4 kB of HDF5
        # metadata each (167 kB for the bar's 31 entries, measured)
        index, offset = [], 0
        for k, v in data.items():
            kind = kind_of(k)
            index.append(
                {"name": k, "kind": kind, "shape": list(v.shape), "offset": offset, "scale": scale_of(kind, v)}
            )
            offset += v.size
        values = np.concatenate([np.ravel(v).astype(np.float64) for v in data.values()])
        g.create_dataset(
            "values",
            data=values,
            compression="gzip",
            compression_opts=9,
            shuffle=True,
            chunks=(min(values.size, 1 << 16),),
        )
        g.attrs["index"] = json.dumps(index)
        g.attrs["record_indices"] = json.dumps([int(i) for i in idx])
        g.attrs["selection"] = json.dumps({k: [int(c) for c in v] for k, v in chosen.items()})
    os.replace(tmp, gold_path)


def read_gold(gold_path):
    with h5py.File(gold_path, "r") as g:
        attrs = dict(g.attrs)
        values = g["values"][()]
    data = {
        e["name"]: values[e["offset"] : e["offset"] + int(np.prod(e["shape"]))].reshape(e["shape"])
        for e in json.loads(attrs["index"])
    }
    sel = {k: np.asarray(v) for k, v in json.loads(attrs["selection"]).items()}
    return attrs, data, sel, np.asarray(json.loads(attrs["record_indices"]))


def compare(name, gold, new, times):
    """Failure lines, and per kind the largest |x - g| / scale and the largest share of the bound."""
    failures, worst = [], {}
    for k in sorted(set(gold) | set(new)):
        if k not in new:
            failures.append(f"{name}: dataset {k} is in the gold file but not in the run's output")
            continue
        if k not in gold:
            failures.append(f"{name}: dataset {k} is in the run's output but not in the gold file")
            continue
        g, x = np.asarray(gold[k], float), np.asarray(new[k], float)
        if g.shape != x.shape:
            failures.append(f"{name}: {k} has shape {x.shape}, the gold file {g.shape}")
            continue
        kind = kind_of(k)
        atol, rtol = TOLERANCES[kind]
        scale = scale_of(kind, g)
        err = np.abs(x - g)
        err[~np.isfinite(x)] = np.inf
        bound = atol * scale + rtol * np.abs(g)
        share = err / np.maximum(bound, 1e-300)
        i = np.unravel_index(int(np.argmax(share)), share.shape) if share.size else None
        w = worst.setdefault(kind, [0.0, 0.0, ""])
        if share.size and float(np.max(err)) / scale > w[0]:
            w[0] = float(np.max(err)) / scale
        if share.size and float(share[i]) > w[1]:
            w[1], w[2] = float(share[i]), k
        if share.size and share[i] > 1.0:
            rec = int(i[0])
            if k.startswith("summary/"):
                where = "run summary"
            elif "/frequencies/" in k:
                where = f"frequency {rec + 1}"
            else:
                where = f"record {rec} of {len(times)} (t = {times[rec]:.6e} s)" + (
                    f", entry {tuple(int(j) for j in i[1:])}" if len(i) > 1 else ""
                )
            nbad = int(np.sum(share > 1.0))
            failures.append(
                f"{name}: {k} [{kind}]: {where}: {x[i]:.9e} against gold {g[i]:.9e}, "
                f"|diff| {err[i]:.3e} > bound {bound[i]:.3e} (atol {atol:g} x scale {scale:.3e} + "
                f"rtol {rtol:g} x |gold|), {share[i]:.3g} x the bound; {nbad} of {share.size} entries out"
            )
    return failures, worst


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--run", required=True, help="build/drivers/epaphe-run")
    ap.add_argument("--inputs", required=True, help="the decks' directory (inputs/)")
    ap.add_argument("--gold", required=True, help="the gold files' directory (tests/regression/gold)")
    ap.add_argument("--workdir", required=True)
    ap.add_argument("--deck", action="append", help="only this deck (name without .xml; repeatable)")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--regenerate", action="store_true", help="rewrite the gold files (also EPAPHE_REGENERATE_GOLD=1)")
    a = ap.parse_args()
    a.run = os.path.abspath(a.run)
    regenerate = a.regenerate or os.environ.get("EPAPHE_REGENERATE_GOLD", "") not in ("", "0")
    os.makedirs(a.workdir, exist_ok=True)
    source = os.path.dirname(os.path.abspath(a.inputs))
    decks = sorted(glob.glob(os.path.join(a.inputs, "*.xml")))
    names = [os.path.splitext(os.path.basename(d))[0] for d in decks]
    if a.deck:
        unknown = sorted(set(a.deck) - set(names))
        if unknown:
            print(f"FAILED: --deck {', '.join(unknown)}: no such deck in {a.inputs} (decks: {', '.join(names)})")
            return 1
        decks = [d for d, n in zip(decks, names) if n in a.deck]
        names = [n for n in names if n in a.deck]
    if not decks:
        print(f"FAILED: no deck in {a.inputs}")
        return 1
    if regenerate:
        bar = "!" * 100
        print(
            f"{bar}\n!!! REGENERATING the gold files of {len(decks)} deck(s) in {a.gold}: NOTHING IS COMPARED.\n"
            f"!!! Do this only for a change of results you meant; check the new files in with a reason.\n{bar}"
        )
        if a.threads != 1:
            print("FAILED: gold files are made on 1 thread (--threads 1)")
            return 1
    failures, total0 = [], time.monotonic()
    for deck, name in zip(decks, names):
        gold_path = os.path.join(a.gold, f"{name}.h5")
        if not regenerate and not os.path.exists(gold_path):
            failures.append(
                f"{name}: no gold file {gold_path}. If inputs/{name}.xml is a new deck, check its "
                f"horizon (HORIZON in {os.path.abspath(__file__)}) and create it with: "
                f"{sys.executable} {os.path.abspath(__file__)} --run {a.run} --inputs {a.inputs} "
                f"--gold {a.gold} --workdir {a.workdir} --deck {name} --regenerate"
            )
            print(f"{name}: no gold file: FAIL")
            continue
        try:
            out, stdout, over, seconds = run_deck(a.run, deck, name, a.workdir, a.threads)
            if regenerate:
                data, chosen, n, idx = reduce_history(out, stdout)
            else:
                gattrs, gold, sel, gidx = read_gold(gold_path)
                data, chosen, n, idx = reduce_history(out, stdout, sel, len(gidx))
        except RuntimeError as e:
            failures.append(f"{name}: {e}")
            print(f"{name}: FAIL (the run)")
            continue
        if has_surfaces(deck) and not SUMMARY.search(stdout):
            failures.append(
                f"{name}: no contact within the horizon {over}: lengthen it in HORIZON "
                f"({os.path.abspath(__file__)}) so that the regression covers the scene's contacts"
            )
        if regenerate:
            write_gold(gold_path, deck, name, data, chosen, n, idx, over, stdout, source)
            print(
                f"{name}: REGENERATED {gold_path} ({os.path.getsize(gold_path) / 1024:.1f} kB, {n} records -> "
                f"{len(idx)}, {len(data)} datasets; run {seconds[0]:.1f} s, CPU {seconds[1]:.1f} s)"
            )
            continue
        with epaphe.open(out) as run:
            times = run.time[idx]
        fails, worst = [], {}
        if n != gattrs["records"] or not np.array_equal(idx, gidx):
            fails.append(
                f"{name}: the run wrote {n} records, the gold run {gattrs['records']} (the deck's time step, "
                f"end or output interval changed?)"
            )
        else:
            fails, worst = compare(name, gold, data, times)
        if fails and gattrs.get("deck_sha256") != sha256(deck):
            fails.append(
                f"{name}: note: inputs/{name}.xml changed since its gold file was made "
                f"(commit {gattrs.get('epaphe_commit')}); if its results were meant to change, regenerate"
            )
        if fails and json.loads(gattrs["overrides"]) != json.loads(
            json.dumps({k: (v if isinstance(v, str) else list(v)) for k, v in over.items()})
        ):
            fails.append(
                f"{name}: note: the horizon changed since the gold file was made: "
                f"gold {gattrs['overrides']}, now {over}"
            )
        if len(fails) > 12:  # the first datasets out, the notes, and how many more
            notes = [f for f in fails if ": note: " in f]
            rest = [f for f in fails if ": note: " not in f]
            fails = rest[:10] + [f"{name}: ... and {len(rest) - 10} more datasets out of tolerance"] + notes
        failures += fails
        report = ", ".join(f"{k} {w[0]:.1e} ({w[1]:.2g} of bound)" for k, w in sorted(worst.items()))
        print(
            f"{name}: {'FAIL' if fails else 'ok'} in {seconds[0]:.1f} s (CPU {seconds[1]:.1f} s); largest |diff|/scale per kind: {report}"
        )
    print(f"total {time.monotonic() - total0:.1f} s")
    if regenerate:
        print("REGENERATED (nothing compared)" if not failures else "FAILED:\n  " + "\n  ".join(failures))
        return 1 if failures else 0
    print("FAILED:\n  " + "\n  ".join(failures) if failures else "PASSED")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
