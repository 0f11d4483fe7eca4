"""The valid deck parameters, from `epaphe-run --print-parameters=xml` (a Teuchos XML
ParameterList: Parameter attributes name, type, value (the default), docString, validatorId; a list
named "*" stands for any name, as the bodies and surfaces; a <Validators> block gives the ranges of
numbers and the values of enumerations). Read with xml.etree: nothing is scraped."""
from __future__ import annotations

import difflib
import itertools
import math
import subprocess
import xml.etree.ElementTree as ET
from typing import ClassVar, Dict, NamedTuple, Optional, Set, Tuple

from .errors import EpapheError

ANY = "*"


class Param(NamedTuple):
    """One deck parameter of the schema."""

    path: Tuple[str, ...]  # ("Bodies", "*", "Initial velocity")
    type: str  # string, int, double, bool, Array(double), ...
    default: str  # the value epaphe-run takes when the deck does not give one (text)
    doc: str  # its docString
    minimum: Optional[float] = None  # range of a number (EnhancedNumberValidator), None: unbounded
    maximum: Optional[float] = None
    values: Optional[Tuple[str, ...]] = None  # the valid strings of an enumeration

    @property
    def key(self) -> str:
        """The deck key, "Bodies->*->Initial velocity"."""
        return "->".join(self.path)


class Schema:
    """The deck parameters, keyed by their path of list names: ("Time", "Time step"); "*" for any
    name.

    Parameters
    ----------
    run : str, optional
        An epaphe-run executable, asked with `--print-parameters=xml`.
    xml_text : str, optional
        The printed XML itself (then `run` is not asked); also `Schema.from_xml(text)`.

    Attributes
    ----------
    params : dict of tuple of str to Param
        Every parameter by its path.
    lists : set of tuple of str
        The path of every list.

    Raises
    ------
    EpapheError
        `run` cannot be run, fails, or prints no parameter.

    See Also
    --------
    Schema.of : one schema per executable, cached.
    """

    _cache: ClassVar[Dict[str, Schema]] = {}

    def __init__(self, run: Optional[str] = None, xml_text: Optional[str] = None) -> None:
        self.params: Dict[Tuple[str, ...], Param] = {}
        self.lists: Set[Tuple[str, ...]] = set()
        if xml_text is None:
            xml_text = self._ask(run)
        self._read(xml_text, run or "the XML")

    @classmethod
    def from_xml(cls, text: str) -> Schema:
        """The schema from the text `epaphe-run --print-parameters=xml` printed."""
        return cls(xml_text=text)

    @classmethod
    def of(cls, run: str) -> Schema:
        """The schema of the executable `run`, asked once per process and kept."""
        if run not in cls._cache:
            cls._cache[run] = cls(run)
        return cls._cache[run]

    @staticmethod
    def _ask(run):
        try:
            proc = subprocess.run([run, "--print-parameters=xml"], capture_output=True, text=True, timeout=60)
        except OSError as e:
            raise EpapheError(f"cannot run {run} --print-parameters=xml: {e.strerror}") from None
        if proc.returncode != 0:
            raise EpapheError(f"{run} --print-parameters=xml failed: {proc.stderr.strip()}")
        return proc.stdout

    def _read(self, text, where):
        try:
            root = ET.fromstring(text)
        except ET.ParseError as e:
            raise EpapheError(f"{where} --print-parameters=xml: not well-formed XML ({e})") from None
        validators = {}
        block = root.find("Validators")
        for v in block if block is not None else []:
            kind = v.get("type", "")
            if kind.startswith("EnhancedNumberValidator"):
                validators[v.get("validatorId")] = dict(minimum=_number(v.get("min")), maximum=_number(v.get("max")))
            elif v.findall("String"):
                validators[v.get("validatorId")] = dict(values=tuple(s.get("stringValue") for s in v.findall("String")))

        def walk(node, path):
            for c in node:
                if c.tag == "ParameterList":
                    sub = path + (c.get("name"),)
                    self.lists.add(sub)
                    walk(c, sub)
                elif c.tag == "Parameter":
                    sp = path + (c.get("name"),)
                    self.params[sp] = Param(
                        sp,
                        c.get("type", "string"),
                        c.get("value", ""),
                        c.get("docString", ""),
                        **validators.get(c.get("validatorId"), {}),
                    )

        walk(root, ())
        if not self.params:
            raise EpapheError(f"{where} --print-parameters=xml printed no parameter")

    def param(self, key: str) -> Optional[Param]:
        """The parameter of a deck key.

        Parameters
        ----------
        key : str
            A deck key, 'Bodies->Bar->Initial velocity' (names of '*' lists match any name).

        Returns
        -------
        Param or None
            None when the schema has no such key.
        """
        parts = key.split("->")
        for cand in itertools.product(*[(p, ANY) for p in parts[:-1]]):
            sp = tuple(cand) + (parts[-1],)
            if sp in self.params:
                return self.params[sp]
        return None

    def lookup(self, key: str) -> Optional[Tuple[Tuple[str, ...], str, str]]:
        """(schema path, type, default) of a deck key, or None."""
        p = self.param(key)
        return None if p is None else (p.path, p.type, p.default)

    def default(self, key: str) -> Optional[str]:
        """The default (text) of a deck key, or None when the schema has no such key."""
        p = self.param(key)
        return None if p is None else p.default

    def close(self, key: str) -> Optional[str]:
        """The nearest valid key, to suggest (the '*' of the schema filled with the key's names)."""
        parts = key.split("->")
        keys = []
        for sp in self.params:
            if len(sp) == len(parts):
                keys.append("->".join(parts[i] if s == ANY else s for i, s in enumerate(sp)))
        m = difflib.get_close_matches(key, keys, n=1, cutoff=0.6)
        return m[0] if m else None


def _number(text):
    if text is None:
        return None
    v = float(text)
    return None if math.isinf(v) else v
