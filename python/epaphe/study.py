"""Studies of epaphe-sweep: the study file (inputs/studies/*.xml, format in docs/user/studies.md)
read with line numbers and validated, its variants, the watched quantities of each run, the CSV.
Errors are StudyError: one line naming the file, line, key and value."""
import csv
import difflib
import itertools
import math
import os
import re

import numpy as np

from .deck import numbers, split_top
from .errors import EpapheError
from .exact import EXACT
from .measures import MEASURES
from .results import Run

CURVES = ("force", "gap", "displacement")
KEEP = "-"  # a varied value that keeps the base deck's
COSTS = (
    ("wall_time", "wall_time_s"),
    ("setup_time", "setup_time_s"),
    ("loop_time", "loop_time_s"),
    ("steps", "steps"),
    ("steps_per_second", "steps_per_second"),
    ("threads", "threads"),
)


class StudyError(EpapheError):
    """A user error: one line on stderr, exit status 1."""


def suggest(word, choices):
    m = difflib.get_close_matches(word, list(choices), n=1, cutoff=0.6)
    return f"; did you mean '{m[0]}'?" if m else f" (valid: {', '.join(choices)})"


def slug(text):
    s = re.sub(r"[^A-Za-z0-9+.=-]+", "_", text).strip("_")
    return s or "run"


# ---- the study ----------------------------------------------------------------------------------
class Entry:
    """A deck override named in the study: key, values (with legend labels), where it was."""

    def __init__(self, key, values, labels, where):
        self.key, self.values, self.labels, self.where = key, values, labels, where


class Study:
    TOP_PARAMS = {"Name": "string", "Deck": "string", "Combine": "string"}
    TOP_LISTS = ("Set", "Vary", "Reference", "Measures", "Plots")
    MEASURE_PARAMS = {
        "Compute": "Array(string)",
        "Body": "string",
        "Node set": "string",
        "Node": "int",
        "Component": "string",
        "Contact threshold": "double",
    }
    PLOT_PARAMS = {
        "Curves": "Array(string)",
        "Components": "Array(string)",
        "Work-precision": "bool",
        "Cost": "string",
        "Time window": "Array(double)",
    }

    def __init__(self):
        self.path = None
        self.name = ""
        self.deck_path = None
        self.combine = "Zip"
        self.set = {}  # key -> Entry (one value)
        self.vary = []  # [Entry]
        self.reference = None  # None | ("exact", name, where) | ("run", {key: value}, where)
        self.measures = {}
        self.plots = {}

    # -- reading --
    @classmethod
    def from_file(cls, path, root):
        s = cls()
        s.path = path
        if root.tag != "ParameterList" or root.name != "Study":
            raise StudyError(
                f'{path}:{root.line}: a study is <ParameterList name="Study">, not '
                f'<{root.tag} name="{root.name}"> (see inputs/studies/)'
            )
        params, lists = s._members(root, "Study", cls.TOP_PARAMS, cls.TOP_LISTS)
        if "Name" in params:
            s.name = params["Name"].attrs["value"]
        if "Deck" not in params:
            raise StudyError(
                f"{path}:{root.line}: 'Study' has no 'Deck' parameter (the base deck, " "relative to the study file)"
            )
        d = params["Deck"]
        s.deck_path = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(path)), d.attrs["value"]))
        if not os.path.isfile(s.deck_path):
            raise StudyError(f"{path}:{d.line}: 'Deck' = '{d.attrs['value']}': no such file " f"({s.deck_path})")
        if "Combine" in params:
            c = params["Combine"]
            s.combine = s._choice(c, "Study->Combine", ("Zip", "Product"))
        for n in lists["Set"].children if "Set" in lists else []:
            s._need_param(n, "Set")
            s.set[n.name] = Entry(n.name, [n.attrs["value"]], [None], f"{path}:{n.line}")
        for n in lists["Vary"].children if "Vary" in lists else []:
            s.vary.append(s._vary_entry(n))
        if "Reference" in lists:
            s.reference = s._reference(lists["Reference"])
        if "Measures" in lists:
            s.measures = s._typed(lists["Measures"], "Measures", cls.MEASURE_PARAMS)
        if "Plots" in lists:
            s.plots = s._typed(lists["Plots"], "Plots", cls.PLOT_PARAMS)
        return s

    def _members(self, node, where, params, lists):
        ps, ls = {}, {}
        for n in node.children:
            if n.tag == "Parameter":
                self._need_param(n, where)
                if n.name not in params:
                    if n.name in lists:
                        raise StudyError(
                            f"{self.path}:{n.line}: '{where}->{n.name}' must be a "
                            f'<ParameterList name="{n.name}">, not a parameter'
                        )
                    raise StudyError(
                        f"{self.path}:{n.line}: unknown parameter '{n.name}' in '{where}'"
                        + suggest(n.name, list(params) + list(lists))
                    )
                ps[n.name] = n
            elif n.tag == "ParameterList":
                if n.name not in lists:
                    if n.name in params:
                        raise StudyError(f"{self.path}:{n.line}: '{where}->{n.name}' is a parameter, " "not a list")
                    raise StudyError(
                        f"{self.path}:{n.line}: unknown list '{n.name}' in '{where}'"
                        + suggest(str(n.name), list(lists) + list(params))
                    )
                ls[n.name] = n
            else:
                raise StudyError(
                    f"{self.path}:{n.line}: unexpected <{n.tag}> in '{where}' " "(only <Parameter> and <ParameterList>)"
                )
        return ps, ls

    def _need_param(self, n, where):
        if n.tag != "Parameter":
            raise StudyError(
                f"{self.path}:{n.line}: '{where}' holds <Parameter name=... type=... value=...> "
                f'entries, not <{n.tag} name="{n.name}">'
            )
        for a in ("name", "type", "value"):
            if a not in n.attrs:
                raise StudyError(f"{self.path}:{n.line}: <Parameter> in '{where}' without a '{a}' attribute")

    def _choice(self, n, key, choices):
        v = n.attrs["value"]
        if v not in choices:
            raise StudyError(
                f"{self.path}:{n.line}: '{key}' = '{v}' is not one of " + ", ".join(f"'{c}'" for c in choices)
            )
        return v

    def _typed(self, node, where, spec):
        ps, _ = self._members(node, where, spec, ())
        out = {}
        for name, n in ps.items():
            want, v = spec[name], n.attrs["value"]
            if n.attrs["type"] != want:
                raise StudyError(
                    f"{self.path}:{n.line}: '{where}->{name}' has type {n.attrs['type']}, " f"expected {want}"
                )
            try:
                if want == "int":
                    out[name] = int(v)
                elif want == "double":
                    out[name] = float(v)
                    if not math.isfinite(out[name]):
                        raise ValueError
                elif want == "bool":
                    if v.lower() not in ("true", "false", "1", "0"):
                        raise ValueError
                    out[name] = v.lower() in ("true", "1")
                elif want == "Array(double)":
                    out[name] = numbers(v)
                elif want == "Array(string)":
                    out[name] = [x for x in split_top(v.strip()[1:-1] if v.strip().startswith("{") else v)]
                else:
                    out[name] = v
            except ValueError:
                raise StudyError(f"{self.path}:{n.line}: '{where}->{name}' = '{v}' is not a valid {want}") from None
            out[name + "@"] = f"{self.path}:{n.line}"
        return out

    def _vary_entry(self, n):
        where = f"{self.path}:{n.line}"
        if n.tag == "Parameter":
            self._need_param(n, "Vary")
            v = n.attrs["value"].strip()
            if n.attrs["type"].startswith("Array("):
                if not (v.startswith("{") and v.endswith("}")):
                    raise StudyError(f"{where}: 'Vary->{n.name}' = '{v}': an array is {{v1, v2, ...}}")
                values = split_top(v[1:-1])
            else:
                values = [v]
            if not values:
                raise StudyError(f"{where}: 'Vary->{n.name}' has no value")
            return Entry(n.name, values, [None] * len(values), where)
        if n.tag == "ParameterList":
            values, labels = [], []
            for c in n.children:
                self._need_param(c, f"Vary->{n.name}")
                labels.append(c.name)
                values.append(c.attrs["value"].strip())
            if not values:
                raise StudyError(f"{where}: 'Vary->{n.name}' has no value")
            return Entry(n.name, values, labels, where)
        raise StudyError(f"{where}: unexpected <{n.tag}> in 'Vary'")

    def _reference(self, node):
        ps, ls = self._members(node, "Reference", {"Exact": "string"}, ("Run",))
        if ("Exact" in ps) == ("Run" in ls):
            raise StudyError(
                f"{self.path}:{node.line}: 'Reference' holds either <Parameter name=\"Exact\"> "
                'or <ParameterList name="Run"> (the overrides naming the reference run), one of them'
            )
        if "Exact" in ps:
            n = ps["Exact"]
            return ("exact", self._choice(n, "Reference->Exact", EXACT), f"{self.path}:{n.line}")
        over = {}
        for c in ls["Run"].children:
            self._need_param(c, "Reference->Run")
            over[c.name] = Entry(c.name, [c.attrs["value"]], [None], f"{self.path}:{c.line}")
        return ("run", over, f"{self.path}:{ls['Run'].line}")

    # -- the command line --
    def apply_cli(self, a):
        for text in a.set:
            key, val = cli_pair(text, "--set")
            self.set[key] = Entry(key, [val], [None], f"--set '{text}'")
        for text in a.vary:
            key, val = cli_pair(text, "--vary")
            values = split_top(val)
            if not values:
                raise StudyError(f"--vary '{text}': no value")
            self.vary = [e for e in self.vary if e.key != key] + [
                Entry(key, values, [None] * len(values), f"--vary '{text}'")
            ]
        if a.product:
            self.combine = "Product"
        if a.zip:
            self.combine = "Zip"
        if a.reference is not None:
            r = a.reference
            if r.lower() == "none":
                self.reference = None
            elif r.lower().startswith("exact:"):
                name = r.split(":", 1)[1]
                if name not in EXACT:
                    raise StudyError(f"--reference '{r}': unknown exact solution '{name}' (known: {', '.join(EXACT)})")
                self.reference = ("exact", name, f"--reference '{r}'")
            else:
                over = {}
                for part in [p for p in r.split(";") if p.strip()]:
                    key, val = cli_pair(part.strip(), "--reference")
                    over[key] = Entry(key, [val], [None], f"--reference '{r}'")
                self.reference = ("run", over, f"--reference '{r}'")

    # -- checks against the deck and its schema --
    def check_structure(self):
        """What needs neither the deck nor epaphe-run."""
        if not self.vary:
            raise StudyError(f"{self.path or self.deck_path}: nothing to vary (a 'Vary' list in the study, or --vary)")
        if self.combine == "Zip":
            lengths = {e.key: len(e.values) for e in self.vary}
            if len(set(lengths.values())) > 1:
                raise StudyError(
                    f"{self.path or 'command line'}: 'Combine' is Zip but the varied lists differ in "
                    "length ("
                    + ", ".join(f"'{k}': {n}" for k, n in lengths.items())
                    + "); give lists of one length, or set Combine to Product"
                )
        keys = [e.key for e in self.vary]
        dup = {k for k in keys if keys.count(k) > 1}
        if dup:
            raise StudyError(f"{self.path}: 'Vary' names '{dup.pop()}' twice")

    def check_keys(self, deck, schema):
        """Every deck key exists (schema, and the deck's body and surface names); values parse."""
        entries = list(self.set.values()) + self.vary
        if self.reference and self.reference[0] == "run":
            entries += list(self.reference[1].values())
        for e in entries:
            self._check_key(e, deck, schema)

    def _check_key(self, e, deck, schema):
        found = schema.lookup(e.key)
        if found is None:
            near = schema.close(e.key)
            raise StudyError(
                f"{e.where}: unknown deck parameter '{e.key}'"
                + (
                    f"; did you mean '{near}'?"
                    if near
                    else " (a path of lists ending with a parameter, as in 'Time->Time step'; "
                    "see epaphe-run --print-parameters)"
                )
            )
        sp, ptype, _ = found
        parts = e.key.split("->")
        for i, s in enumerate(sp[:-1]):
            if s == "*":
                where_list = "->".join(parts[:i])
                names = deck.sublists(where_list)
                if parts[i] not in names:
                    raise StudyError(
                        f"{e.where}: '{e.key}': the deck {deck.path} has no '{parts[i]}' in "
                        f"'{where_list}' (it has: {', '.join(names) or 'none'})"
                    )
        for v in e.values:
            if v == KEEP:
                continue
            try:
                if ptype == "double" and not math.isfinite(float(v)):
                    raise ValueError
                if ptype == "int":
                    int(v)
                if ptype.startswith("Array(") and not (v.startswith("{") and v.endswith("}")):
                    raise ValueError
                if ptype in ("Array(double)", "Array(int)"):
                    [int(x) if ptype == "Array(int)" else float(x) for x in v[1:-1].split(",") if x.strip()]
                if ptype == "bool" and v.lower() not in ("true", "false", "1", "0"):
                    raise ValueError
            except ValueError:
                raise StudyError(f"{e.where}: '{e.key}' = '{v}' is not a valid {ptype}") from None

    # -- the runs --
    def variants(self):
        """[(name, label, {key: value} of the varied keys)], in study order."""
        if self.combine == "Zip":
            combos = [[(e, i) for e in self.vary] for i in range(len(self.vary[0].values))]
        else:
            combos = [list(c) for c in itertools.product(*[[(e, i) for i in range(len(e.values))] for e in self.vary])]
        out, names = [], set()
        for combo in combos:
            over, labels, parts = {}, [], []
            for e, i in combo:
                v = e.values[i]
                leaf = e.key.split("->")[-1]
                if e.labels[i] is not None:
                    lab = e.labels[i]
                elif v == KEEP:
                    lab = None
                else:
                    lab = f"{leaf}={v}"
                if lab and lab not in labels:
                    labels.append(lab)
                if v != KEEP:
                    over[e.key] = v
                parts.append(f"{leaf}={'base' if v == KEEP else v}")
            if all(e.labels[i] is not None for e, i in combo):  # labelled values name the run
                name = slug(re.sub(r"\s*=\s*", "=", "_".join(labels)))[:120]
            else:
                name = slug("_".join(parts))[:120]
            base, k = name, 2
            while name in names:
                name, k = f"{base}-{k}", k + 1
            names.add(name)
            out.append((name, ", ".join(labels) or "base deck", over))
        return out


def cli_pair(text, opt):
    if "=" not in text:
        raise StudyError(f"{opt} '{text}': expected KEY=VALUE, as in \"Time->Time step=4e-7,2e-7\"")
    key, val = text.split("=", 1)
    return key.strip(), val.strip()


# ---- the watched quantities of a run ------------------------------------------------------------
class Watch:
    """What the measures look at: body, node set, node (-1: the set's mean), component (0, 1, 2),
    contact threshold (a fraction of the reference's peak force)."""

    def __init__(self, body, nodeset, node, comp, threshold):
        self.body, self.nodeset, self.node, self.comp, self.threshold = body, nodeset, node, comp, threshold


def read_history(path, w):
    """What the measures of the watch `w` need from the run at `path`: t (s), force (total contact
    force, N), gap (records x contact nodes, m), u (watched displacement, records x 3, m), ids (the
    node set's ids), momentum (kg m/s), mass (kg), balance (relative), attrs (/run), status."""
    h = {}
    with Run(path) as run:
        h["status"] = run.status
        h["t"] = run.time
        body = run.bodies[w.body] if w.body in run.bodies else None
        c = body.contact if body is not None and body.has_contact else None
        h["force"] = c.total_force if c is not None else None
        h["gap"] = c.gap if c is not None else None
        ns = body.nodesets[w.nodeset] if body is not None and w.nodeset in body.nodesets else None
        if ns is not None:
            d = ns.displacement
            h["ids"] = ns.nodes
            if w.node >= d.shape[1]:
                raise StudyError(
                    f"{path}: 'Measures->Node' {w.node} out of range: node set '{w.nodeset}' has " f"{d.shape[1]} nodes"
                )
            h["u"] = d[:, w.node, :] if w.node >= 0 else d.mean(axis=1)
        else:
            h["u"], h["ids"] = None, None
        h["momentum"] = body.momentum if body is not None and f"{body.prefix}/momentum" in run.file else None
        h["mass"] = body.rigid_mass if body is not None else float("nan")
        h["balance"] = run.energy.balance_error if "energy/balance_error" in run.file else None
        coating = run.file.get("coating")
        h["wear"] = (
            max(float(np.max(g["wear"][-1])) for g in coating.values() if "wear" in g and len(g["wear"]))
            if coating is not None and len(coating)
            else None
        )
        h["plastic"] = (
            float(run.file["energy/plastic_dissipation"][-1])
            if "energy/plastic_dissipation" in run.file and len(run.file["energy/plastic_dissipation"])
            else None
        )
        h["attrs"] = dict(run.attrs)
    return h


# ---- CSV ----------------------------------------------------------------------------------------
def fmt(v):
    if v is None:
        return ""
    if isinstance(v, (float, np.floating)):
        return "" if not np.isfinite(v) else repr(float(v))
    if isinstance(v, (np.integer,)):
        return str(int(v))
    return str(v)


def write_csv(path, study, runs, exact_row, wanted):
    keys = [e.key for e in study.vary]
    head = ["run", "label"] + keys + ["status", "reference", "time_step_s"]
    for k in wanted:
        col, unit = MEASURES[k]
        head += [f"{col}_{unit_tag(unit)}", f"{col}_error"]
    head += [c for _, c in COSTS] + ["file"]
    rows = []
    if exact_row is not None:
        row = ["exact", exact_row["label"]] + [""] * len(keys) + ["exact", "", ""]
        for k in wanted:
            row += [fmt(exact_row["values"].get(k, float("nan"))), ""]
        row += [""] * len(COSTS) + [""]
        rows.append(row)
    for r in runs:
        vals = [r.overrides.get(k, KEEP) for k in keys]
        a = r.hist["attrs"] if r.hist else {}
        row = [r.name, r.label] + vals + [r.status, "yes" if r.is_reference else "", fmt(r.time_step)]
        for k in wanted:
            row += [fmt(r.measures.get(k)), fmt(r.errors.get(k))]
        row += [fmt(a.get(c)) for c, _ in COSTS] + [os.path.relpath(r.h5, os.path.dirname(path)) if r.hist else ""]
        rows.append(row)
    with open(path, "w", newline="") as fh:
        wr = csv.writer(fh)
        wr.writerow(head)
        wr.writerows(rows)


def unit_tag(unit):
    return {"s": "s", "N s": "Ns", "N": "N", "m": "m", "m/s": "m_per_s", "-": "rel", "J": "J"}[unit]
