"""Decks: read (with line numbers), get values (with the schema's defaults), override keys
"Time->Time step" (creating missing lists and parameters), write.

    d = read_deck("inputs/bar-on-wall.xml")
    d.get("Time->Time step")                      # '1e-7' (text, as in the deck)
    d.line("Time->Time step")                     # 45
    d.override({"Time->End time": "1e-4", "Output->File": ("short.h5", "string")}).write("short.xml")
"""
from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Mapping
from typing import TYPE_CHECKING, Optional, Tuple, Union
from xml.parsers import expat

from .errors import EpapheError, UnknownName

if TYPE_CHECKING:
    from .schema import Schema

#: An override's value: the text (or a number, written with str()), or (value, type).
Value = Union[str, float, int, Tuple[Union[str, float, int], str]]


# ---- XML with line numbers ----------------------------------------------------------------------
class XNode:
    def __init__(self, tag, attrs, line):
        self.tag, self.attrs, self.line, self.children = tag, attrs, line, []

    @property
    def name(self):
        return self.attrs.get("name")


def read_xml(path):
    """The XML file at `path` as a tree of XNode (tag, attrs, line, children)."""
    try:
        with open(path, "rb") as fh:
            data = fh.read()
    except OSError as e:
        raise EpapheError(f"{path}: cannot be read ({e.strerror})") from None
    parser = expat.ParserCreate()
    stack, root = [], []

    def start(tag, attrs):
        n = XNode(tag, attrs, parser.CurrentLineNumber)
        (stack[-1].children if stack else root).append(n)
        stack.append(n)

    parser.StartElementHandler = start
    parser.EndElementHandler = lambda tag: stack.pop()
    try:
        parser.Parse(data, True)
    except expat.ExpatError as e:
        raise EpapheError(f"{path}:{e.lineno}: not well-formed XML: {expat.ErrorString(e.code)}") from None
    return root[0]


# ---- values -------------------------------------------------------------------------------------
def split_top(text, sep=","):
    """Splits on `sep` outside braces: '{0, -10, 0}, {0, -50, 0}' -> two items."""
    out, depth, cur = [], 0, ""
    for ch in text:
        if ch == "{":
            depth += 1
        elif ch == "}":
            depth -= 1
        if ch == sep and depth == 0:
            out.append(cur.strip())
            cur = ""
        else:
            cur += ch
    if cur.strip():
        out.append(cur.strip())
    return out


def numbers(text):
    """'{0.2, 0.02, 0.02}' or '0.2' -> [floats]."""
    t = text.strip()
    if t.startswith("{") and t.endswith("}"):
        t = t[1:-1]
    return [float(x) for x in t.split(",") if x.strip()]


def deck_child(node, tag, name):
    """The child <tag name="name"> of an XML deck node, matched by attribute, not by an XPath predicate
    (names hold quotes: "Young's modulus"); None when absent."""
    return next((c for c in node.findall(tag) if c.get("name") == name), None)


# ---- decks --------------------------------------------------------------------------------------
class Deck:
    """A deck as an ElementTree (`root`), its parameters read through the schema's defaults.

    Parameters
    ----------
    path : str, optional
        The deck file to read, or, with `text`, where the text came from (for messages).
    text : str, optional
        The deck's XML text (then `path` is not read).

    Attributes
    ----------
    root : xml.etree.ElementTree.Element
        The deck's root <ParameterList>.
    lines : dict of str to int
        {key: line} of every list and parameter, when the deck was read from a file.

    Raises
    ------
    EpapheError
        The file cannot be read or is not well-formed XML.
    """

    def __init__(self, path: Optional[str] = None, text: Optional[str] = None) -> None:
        self.path = path
        self.lines: dict[str, int] = {}
        if path is None and text is None:
            raise EpapheError("Deck: give a path or a text")
        try:
            self.root = ET.fromstring(text) if text is not None else ET.parse(str(path)).getroot()
        except ET.ParseError as e:
            raise EpapheError(f"{path}: not well-formed XML ({e})") from None
        except OSError as e:
            raise EpapheError(f"{path}: cannot be read ({e.strerror})") from None
        if text is None:

            def walk(node, prefix):
                for c in node.children:
                    key = prefix + [c.name or ""]
                    self.lines["->".join(key)] = c.line
                    walk(c, key)

            walk(read_xml(path), [])

    def line(self, key: str) -> Optional[int]:
        """The line of the parameter or list `key` in the file read, or None."""
        return self.lines.get(key)

    def node(self, path: str) -> Optional[ET.Element]:
        """The <ParameterList> at 'Bodies->Bar' ('' for the root), or None."""
        node = self.root
        for name in [p for p in path.split("->") if p]:
            node = deck_child(node, "ParameterList", name)
            if node is None:
                return None
        return node

    def sublists(self, path: str) -> list[str]:
        """The names of the lists in the list `path`: deck.sublists("Bodies") -> ["Bar"]."""
        node = self.node(path)
        return [] if node is None else [c.get("name", "") for c in node.findall("./ParameterList")]

    def parameters(self) -> dict[str, str]:
        """{"Time->Time step": "1e-7", "Surfaces->Wall->Type": "Plane", ...}: every parameter the deck
        gives, as text, in document order."""
        out = {}

        def walk(node, prefix):
            for c in node:
                name = c.get("name")
                if c.tag == "ParameterList":
                    walk(c, prefix + [name])
                elif c.tag == "Parameter":
                    out["->".join(prefix + [name])] = c.get("value")

        walk(self.root, [])
        return out

    def has(self, key: str) -> bool:
        """True when the deck gives parameter `key` ("Time->Time step")."""
        *lists, name = key.split("->")
        node = self.node("->".join(lists))
        return node is not None and deck_child(node, "Parameter", name) is not None

    def get(self, key: str, schema: Optional[Schema] = None, default: Optional[str] = None) -> Optional[str]:
        """The text of a parameter.

        Parameters
        ----------
        key : str
            The parameter's path, "Time->Time step".
        schema : Schema, optional
            Gives the default when the deck has no such parameter.
        default : str, optional
            Returned when neither the deck nor the schema has a value.

        Returns
        -------
        str or None
            The value as written in the deck, else the schema's default, else `default`.
        """
        *lists, name = key.split("->")
        node = self.node("->".join(lists))
        p = None if node is None else deck_child(node, "Parameter", name)
        if p is not None:
            return p.get("value")
        found = schema.default(key) if schema is not None else None
        return found if found is not None else default

    def override(self, overrides: Mapping[str, Value], schema: Optional[Schema] = None) -> Deck:
        """A new Deck with overrides applied (this one is unchanged).

        Parameters
        ----------
        overrides : mapping of str to value
            {key: value}; a value may be (value, type). Missing lists and parameters are created.
        schema : Schema, optional
            Gives a parameter's type when `overrides` does not: else the deck's, else string.

        Returns
        -------
        Deck
            The new deck.
        """
        d = Deck.__new__(Deck)
        d.path, d.lines = self.path, dict(self.lines)
        d.root = ET.fromstring(ET.tostring(self.root))
        for key, value in overrides.items():
            ptype = None
            if isinstance(value, tuple):
                value, ptype = value
            *lists, name = key.split("->")
            node = d.root
            for sub_name in lists:
                sub = deck_child(node, "ParameterList", sub_name)
                if sub is None:
                    sub = ET.SubElement(node, "ParameterList", name=sub_name)
                node = sub
            p = deck_child(node, "Parameter", name)
            if p is None:
                p = ET.SubElement(node, "Parameter", name=name)
            if ptype is None and schema is not None:
                found = schema.param(key)
                ptype = found.type if found is not None else None
            p.set("type", ptype or p.get("type", "string"))
            p.set("value", str(value))
        return d

    def text(self) -> str:
        """The deck as XML text."""
        return ET.tostring(self.root, encoding="unicode") + "\n"

    def with_overrides(self, overrides: Mapping[str, Value], schema: Optional[Schema] = None) -> str:
        """The deck text with {key: value} applied (see override)."""
        return self.override(overrides, schema).text()

    def write(self, path: str) -> str:
        """Writes the deck to `path`; returns `path`."""
        with open(path, "w", encoding="utf-8") as fh:
            fh.write(self.text())
        return path


def read_deck(path: str) -> Deck:
    """The deck file at `path`, with the line of every list and parameter.

    Parameters
    ----------
    path : str
        A deck (XML ParameterList) file.

    Returns
    -------
    Deck
        The deck; `Deck.line(key)` gives a key's line.
    """
    return Deck(path)


def deck_value(root: Union[str, Deck, ET.Element], path: str) -> Union[str, list[float]]:
    """The value of a deck parameter.

    Parameters
    ----------
    root : str, Deck or xml.etree.ElementTree.Element
        A deck file, a Deck, or a deck's XML root.
    path : str
        The parameter's path, "Bodies->Bar->Mesh->Lengths".

    Returns
    -------
    str or list of float
        A list of floats for an array "{...}", else the text.

    Raises
    ------
    UnknownName
        No such list or parameter, naming the ones there are.
    """
    if isinstance(root, str):
        root = Deck(root)
    node = root.root if isinstance(root, Deck) else root
    *lists, name = path.split("->")
    for sub_name in lists:
        nxt = deck_child(node, "ParameterList", sub_name)
        if nxt is None:
            raise UnknownName(
                f"deck: no list '{sub_name}' on the way to '{path}' (lists there: "
                + (", ".join(c.get("name", "") for c in node.findall("ParameterList")) or "none")
                + ")"
            )
        node = nxt
    p = deck_child(node, "Parameter", name)
    if p is None:
        raise UnknownName(
            f"deck: no parameter '{path}' (parameters there: "
            + (", ".join(c.get("name", "") for c in node.findall("Parameter")) or "none")
            + ")"
        )
    v = p.get("value", "")
    return [float(x) for x in v.strip("{}").split(",")] if v.startswith("{") else v


def variant(base_deck: str, out_path: str, overrides: Mapping[str, Value], schema: Optional[Schema] = None) -> str:
    """Writes a copy of a deck file with overrides.

    Parameters
    ----------
    base_deck : str
        The deck file to copy.
    out_path : str
        Where to write the new deck.
    overrides : mapping of str to value
        {"Time->Time step": "5e-8", ...}; a value may be (value, type) (see Deck.override).
    schema : Schema, optional
        Gives the types of parameters the base deck lacks.

    Returns
    -------
    str
        `out_path`.
    """
    return Deck(base_deck).override(overrides, schema).write(out_path)
