"""Reading an Epaphe run: the HDF5 file epaphe-run writes (layout in docs/user/output.md).

    run = epaphe.open("build/run/bar-on-wall.h5")
    run.status, run.complete                  # 'complete', True
    run.time                                  # (records,) s
    bar = run.bodies["Bar"]
    bar.nodesets["x-"].displacement           # (records, nodes, 3) m
    bar.contact.total_force                   # (records,) N
    run.energy.balance_error                  # (records,) relative
    run.deck.get("Time->Time step")           # the deck the run was made from

Record arrays hold one row per entry of /time; a file still being written (or stopped) may hold
fewer rows in some datasets: the missing rows read as NaN. Names not in the file (a body, a node
set) raise epaphe.errors.UnknownName naming the ones there are.
"""
from __future__ import annotations

import os
from collections.abc import Callable, Mapping
from functools import cached_property
from typing import Any

import h5py
import numpy as np

from .deck import Deck
from .errors import EpapheError, UnknownName

ENERGIES = ("kinetic", "strain", "total", "contact_work", "external_work", "damping", "balance_error")


def text(v):
    """An HDF5 string attribute or scalar dataset as str."""
    if isinstance(v, bytes):
        return v.decode("utf-8", "replace")
    if isinstance(v, np.ndarray) and v.shape == ():
        return text(v[()])
    return str(v)


class Names(Mapping):
    """A read-only {name: item} whose unknown names raise UnknownName naming the valid ones."""

    def __init__(self, items, what, where):
        self._items, self._what, self._where = dict(items), what, where

    def __getitem__(self, name):
        if name not in self._items:
            raise UnknownName(
                f"{self._where}: unknown {self._what} '{name}' (available: " f"{', '.join(self._items) or 'none'})"
            )
        return self._items[name]

    def __iter__(self):
        return iter(self._items)

    def __len__(self):
        return len(self._items)

    def __repr__(self):
        return f"<{self._what}s: {', '.join(self._items) or 'none'}>"


class Run:
    """One Epaphe HDF5 output, kept open (use `with epaphe.open(p) as run:` or run.close()).

    Parameters
    ----------
    path : str
        The HDF5 file epaphe-run wrote (the deck's Output->File).

    Raises
    ------
    EpapheError
        The file is missing, a directory, not HDF5, or has no /time dataset.
    """

    def __init__(self, path: str) -> None:
        self.path = path
        if not os.path.exists(path):
            raise EpapheError(f"no such file: {path}")
        if os.path.isdir(path):
            raise EpapheError(f"{path} is a directory, not an Epaphe HDF5 file")
        try:
            self.file = h5py.File(path, "r")
        except OSError as e:
            raise EpapheError(f"{path}: not an HDF5 file ({str(e).splitlines()[0]})") from None
        if "time" not in self.file or not isinstance(self.file["time"], h5py.Dataset):
            self.file.close()
            raise EpapheError(f"{path}: not an Epaphe history file (no /time dataset)")

    # ---- the run ----
    @property
    def status(self) -> str:
        """'running', 'complete', or 'stopped: <why>'; only 'complete' is a finished result."""
        return text(self.file.attrs.get("status", "unknown"))

    @property
    def complete(self) -> bool:
        """True when the run reached its end: the status is 'complete', or 'complete: ...' when a
        criterion ended it early (the deck's 'Steady state')."""
        return self.status == "complete" or self.status.startswith("complete: ")

    @property
    def name(self) -> str:
        """The deck's Run->Name ('' when absent)."""
        return text(self.file.attrs.get("name", "")).strip()

    @property
    def version(self) -> str:
        """The Epaphe version that wrote the file ('' when absent)."""
        return text(self.file.attrs.get("epaphe_version", ""))

    @cached_property
    def time(self) -> np.ndarray:
        """(records,) time of each record, s."""
        return np.asarray(self.file["time"][()], dtype=float).reshape(-1)

    @property
    def records(self) -> int:
        """The number of records (entries of /time)."""
        return self.time.size

    @cached_property
    def attrs(self) -> dict[str, Any]:
        """The /run attributes: time_step, critical_time_step (s), steps, wall_time, setup_time,
        loop_time (s), steps_per_second, threads, mpi_ranks, checkpoints, checkpoint_time (s)..."""
        return {k: v for k, v in self.file["run"].attrs.items()} if "run" in self.file else {}

    @cached_property
    def deck_text(self) -> str:
        """The deck text the run was made from (/run/deck), '' when absent."""
        return text(self.file["run/deck"][()]) if "run/deck" in self.file else ""

    @cached_property
    def deck(self) -> Deck:
        """The run's deck (/run/deck) as an epaphe.deck.Deck."""
        if not self.deck_text:
            raise EpapheError(f"{self.path}: no /run/deck (the deck text)")
        return Deck(path=f"{self.path}:/run/deck", text=self.deck_text)

    @cached_property
    def bodies(self) -> Mapping[str, Body]:
        """{name: Body}; an unknown name raises epaphe.errors.UnknownName naming the bodies."""
        names = list(self.file["bodies"].keys()) if "bodies" in self.file else []
        return Names({b: Body(self, b) for b in names}, "body", self.path)

    @cached_property
    def energy(self) -> Energy:
        """Energies of the whole system (J, per record) and the relative balance error."""
        return Energy(self)

    # ---- datasets ----
    def records_of(self, path: str) -> np.ndarray:
        """The record dataset at `path` as floats, one row per entry of /time.

        Parameters
        ----------
        path : str
            The dataset's path in the file, without the leading '/' (e.g. "bodies/Bar/contact/gap").

        Returns
        -------
        numpy.ndarray
            (records, ...) floats; rows missing from an unfinished file are NaN.
        """
        if path not in self.file:
            raise EpapheError(f"{self.path}: no dataset /{path}")
        d = np.asarray(self.file[path][()], dtype=float)
        n = self.records
        if d.shape[0] < n:
            d = np.concatenate([d, np.full((n - d.shape[0],) + d.shape[1:], np.nan)])
        return d[:n]

    def ids(self, path: str) -> np.ndarray:
        """An id dataset (nodes) as a flat array."""
        if path not in self.file:
            raise EpapheError(f"{self.path}: no dataset /{path}")
        return np.asarray(self.file[path][()]).reshape(-1)

    def flat(self, kinds: str = "fi", select: Callable[[str], bool] | None = None) -> dict[str, np.ndarray]:
        """Every numeric dataset of the file, read whole.

        Parameters
        ----------
        kinds : str
            numpy dtype kinds to read ('f': float, 'i': integer).
        select : callable, optional
            Only the paths for which select(path) is true are read.

        Returns
        -------
        dict of str to numpy.ndarray
            {dataset path: array}.
        """
        out = {}

        def visit(name, obj):
            if isinstance(obj, h5py.Dataset) and obj.dtype.kind in kinds and (select is None or select(name)):
                out[name] = obj[()]

        self.file.visititems(visit)
        return out

    def close(self) -> None:
        """Closes the file."""
        self.file.close()

    def __enter__(self) -> Run:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def __repr__(self):
        return f"<epaphe run {self.path}: {self.status}, {self.records} records, bodies {', '.join(self.bodies)}>"


class Body:
    """A body of a run: node sets, contact, momentum, frequencies and attributes."""

    def __init__(self, run: Run, name: str) -> None:
        self.run, self.name, self.prefix = run, name, f"bodies/{name}"

    @cached_property
    def attrs(self) -> dict[str, Any]:
        """reduction, reduced_dofs, rigid_mass (kg), ..."""
        return {k: v for k, v in self.run.file[self.prefix].attrs.items()}

    @property
    def rigid_mass(self) -> float:
        """kg (NaN when not stored)."""
        return float(self.attrs.get("rigid_mass", float("nan")))

    @cached_property
    def nodesets(self) -> Mapping[str, NodeSet]:
        """{name: NodeSet} of the watched node sets."""
        g = self.run.file.get(self.prefix + "/nodesets")
        names = list(g.keys()) if g is not None else []
        return Names({s: NodeSet(self, s) for s in names}, "node set", f"{self.run.path}: body '{self.name}'")

    @property
    def has_contact(self) -> bool:
        """True when the body has contact nodes (a /bodies/<b>/contact group)."""
        return f"{self.prefix}/contact/total_force" in self.run.file

    @cached_property
    def contact(self) -> Contact:
        """The body's contact nodes (Contact); an error when the body has none."""
        if not self.has_contact:
            raise EpapheError(f"{self.run.path}: body '{self.name}' has no contact data")
        return Contact(self)

    @cached_property
    def momentum(self) -> np.ndarray:
        """(records, 3) linear momentum, kg m/s."""
        return self.run.records_of(self.prefix + "/momentum")

    @cached_property
    def frequencies(self) -> dict[str, np.ndarray]:
        """{reduced, full, fixed_interface: array} natural frequencies, Hz (those stored)."""
        g = self.run.file.get(self.prefix + "/frequencies")
        return {} if g is None else {k: np.asarray(g[k][()], float) for k in g}

    def __repr__(self):
        return f"<body {self.name}: node sets {', '.join(self.nodesets) or 'none'}" + (
            ", contact>" if self.has_contact else ">"
        )


class Records:
    """A dataset of a group (NodeSet, Contact, Energy: `_run`, `prefix`), read on first use and kept:
    `displacement = Records("displacement", "(records, nodes, 3) displacement, m")`; ids=True for
    node ids (read as they are), else records (floats, one row per record)."""

    def __init__(self, name, doc, ids=False):
        self.name, self.__doc__, self.ids = name, doc, ids

    def __set_name__(self, owner, attr):
        self.attr = attr

    def __get__(self, obj, owner=None):
        if obj is None:
            return self
        if self.attr not in obj.__dict__:
            path = f"{obj.prefix}/{self.name}"
            obj.__dict__[self.attr] = obj._run.ids(path) if self.ids else obj._run.records_of(path)
        return obj.__dict__[self.attr]


class NodeSet:
    """A watched node set of a body."""

    def __init__(self, body: Body, name: str) -> None:
        self.body, self.name, self._run, self.prefix = body, name, body.run, f"{body.prefix}/nodesets/{name}"

    nodes = Records("nodes", "Node ids of the set.", ids=True)
    displacement = Records("displacement", "(records, nodes, 3) displacement, m.")
    velocity = Records("velocity", "(records, nodes, 3) velocity, m/s.")


class Contact:
    """The contact nodes of a body."""

    def __init__(self, body: Body) -> None:
        self.body, self._run, self.prefix = body, body.run, f"{body.prefix}/contact"

    nodes = Records("nodes", "Contact node ids.", ids=True)
    gap = Records(
        "gap",
        "(records, nodes) normal gap to the nearest surface, m (negative: penetration; " "1e300 beyond every surface).",
    )
    force = Records("force", "(records, nodes) normal contact force on each node, N.")

    @cached_property
    def total_force(self) -> np.ndarray:
        """(records,) total normal contact force on the body, N."""
        return self._run.records_of(self.prefix + "/total_force").reshape(self._run.records, -1)[:, 0]

    def columns(self, node_ids: list[int]) -> list[int]:
        """The columns of `force`/`gap` of the given node ids that are contact nodes.

        Parameters
        ----------
        node_ids : list of int
            Node ids of the body's mesh.

        Returns
        -------
        list of int
            The column of each id that is a contact node, in the order given (others left out).
        """
        cn = list(self.nodes)
        return [cn.index(n) for n in node_ids if n in cn]


class Energy:
    """Energies of the whole system per record; balance_error = (total + damping - contact work -
    external work - initial) / largest energy. In a run with a thermal model the balance has its heat term
    (docs/theory/heat.md, eq. 63): (total + damping + friction_heat - normal_work - counterface_work -
    external work - initial) / largest energy, and `heat` gives the friction heat's partition."""

    def __init__(self, run: Run) -> None:
        self._run, self.prefix = run, "energy"

    @property
    def has_heat(self) -> bool:
        """True when the record has the heat term (a run with a thermal model)."""
        return "energy/friction_heat" in self._run.file

    @cached_property
    def heat(self) -> dict[str, np.ndarray]:
        """{body: (records,) J} the share of the friction heat (and of a coating's plastic dissipation) each
        body with a thermal model received, and "counterface": the rest (the surfaces rubbed, and bodies
        without a thermal model); they sum to friction_heat (plus plastic_dissipation with a coating).
        Empty without a thermal model."""
        if not self.has_heat:
            return {}
        return {name: self._run.records_of(f"energy/heat/{name}") for name in self._run.file["energy/heat"]}

    kinetic = Records("kinetic", "(records,) kinetic energy, J.")
    strain = Records("strain", "(records,) strain energy, J.")
    total = Records("total", "(records,) total energy (the central difference's conserved energy), J.")
    contact_work = Records("contact_work", "(records,) work of the contact forces, J.")
    external_work = Records("external_work", "(records,) work of the external loads, J.")
    damping = Records("damping", "(records,) energy dissipated by damping, J.")
    balance_error = Records("balance_error", "(records,) relative energy balance error, -.")
    friction_heat = Records(
        "friction_heat", "(records,) heat friction made at every contact node so far, J (with a thermal model)."
    )
    normal_work = Records("normal_work", "(records,) work of the normal contact forces, J (with a thermal model).")
    counterface_work = Records(
        "counterface_work",
        "(records,) work the counterface's motion (a turning surface) did through friction, J (with a thermal model).",
    )


def open(path: str) -> Run:  # noqa: A001 (epaphe.open, as h5py.File / io.open)
    """The run in an Epaphe HDF5 file.

    Parameters
    ----------
    path : str
        The file epaphe-run wrote.

    Returns
    -------
    Run
        The run, kept open: use it in a `with` block or call close().

    Raises
    ------
    EpapheError
        Naming the file when it is missing, not HDF5, or not an Epaphe output.
    """
    return Run(path)


def history(path: str, complete: bool = True) -> dict[str, Any]:
    """Every numeric dataset of a run, read whole, and its attributes.

    Parameters
    ----------
    path : str
        The file epaphe-run wrote.
    complete : bool
        When true, a run whose status is not 'complete' is an error.

    Returns
    -------
    dict
        {dataset path: array} (the flat view), plus "attrs" (the /run attributes) and
        "bodies/<b>/attrs".
    """
    with Run(path) as run:
        if complete and not run.complete:
            raise EpapheError(f"{path}: status {run.status}")
        out: dict[str, Any] = dict(run.flat())
        out["attrs"] = dict(run.attrs)
        for name, body in run.bodies.items():
            out[f"bodies/{name}/attrs"] = dict(body.attrs)
    return out
