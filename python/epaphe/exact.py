"""Exact solutions of the verification cases: 1-D waves in Box bars along x (docs/verification.md
V1, the bar on a rigid wall, and V2, two bars, code_aster SDNL111A), computed from a deck.

    ex = exact_solution("bar-on-wall", "inputs/bar-on-wall.xml", "build/drivers/epaphe-run")
    ex.t0, ex.t1, ex.F               # contact start and end (s), plateau force (N)
    ex.force(t), ex.gap(t)           # N, m at times t (s)
    ex.displacement(s, t)            # m, sections at distances s (m) from the contact face
"""
import math

import numpy as np

from .deck import Deck, numbers
from .errors import EpapheError
from .schema import Schema


def scene(deck, name, n_bodies, where):
    """(fail, body names, "Surfaces-><its surface>") of a deck that must hold `n_bodies` bodies and one
    surface for the exact solution `name`; fail(msg) raises why it does not apply."""

    def fail(msg):
        raise EpapheError(f"{where}: the exact solution '{name}' does not apply to {deck.path}: {msg}")

    bodies = deck.sublists("Bodies")
    surfaces = deck.sublists("Surfaces")
    if len(bodies) != n_bodies or len(surfaces) != 1:
        fail(
            f"it needs {('one body', 'two bodies')[n_bodies - 1]} and one surface (deck: {len(bodies)} bodies, "
            f"{len(surfaces)} surfaces)"
        )
    return fail, bodies, "Surfaces->" + surfaces[0]


class BoxBar:
    """A body of the deck that is a Box mesh along x: its geometry, material and velocity."""

    def __init__(self, deck, schema, name, fail):
        b = "Bodies->" + name
        self.name = name
        if deck.get(b + "->Mesh->Type", schema) != "Box":
            fail(f"the mesh of body '{name}' is not a Box")
        self.origin = numbers(deck.get(b + "->Mesh->Origin", schema))
        self.lengths = numbers(deck.get(b + "->Mesh->Lengths", schema))
        self.elements = [int(x) for x in numbers(deck.get(b + "->Mesh->Elements", schema))]
        self.rho = float(deck.get(b + "->Material->Density", schema))
        self.E = float(deck.get(b + "->Material->Young's modulus", schema))
        self.nu = float(deck.get(b + "->Material->Poisson's ratio", schema))
        self.v = numbers(deck.get(b + "->Initial velocity", schema))
        self.contact = deck.get(b + "->Contact node set", schema)
        self.clamped = deck.get(b + "->Clamped node set", schema) or ""
        self.L, self.S = self.lengths[0], self.lengths[1] * self.lengths[2]

    def face_x(self, face):
        """x of the face 'x-' or 'x+'."""
        return self.origin[0] + (self.lengths[0] if face == "x+" else 0.0)


class Exact1D:
    """A 1-D elastic bar (a Box body along x) moving at speed v0 along x (direction d = +-1) and
    meeting, after the gap U0, an obstacle that pushes back with a constant force F from t0 = U0/v0
    to t1. A section at distance s from the contact face moves at piecewise constant speeds
    (`phases`); the measures, curves and exact values of epaphe-sweep follow from these."""

    label = ""
    body = None

    def setup(self, bar, v0, d, U0, t1_after_t0, F):
        self.bar, self.v0, self.d, self.U0 = bar, v0, d, U0
        self.L, self.S, self.elements = bar.L, bar.S, bar.elements
        self.c = math.sqrt(bar.E / bar.rho)
        self.m = bar.rho * bar.L * bar.S
        self.t0 = U0 / v0
        self.t1 = self.t0 + t1_after_t0
        self.F = F
        self.breaks = [self.t0, self.t1]

    def key(self):
        return (self.U0, self.v0, self.L, self.S, self.c, self.m, self.t1, self.F)

    def force(self, t):
        t = np.asarray(t, float)
        return np.where((t >= self.t0) & (t < self.t1), self.F, 0.0)

    def momentum(self, t):
        """Along the direction of motion."""
        return self.m * self.v0 - self.F * (np.clip(t, self.t0, self.t1) - self.t0)

    def displacement(self, s, t):
        """Displacement along the direction of motion of the sections at distances s from the contact
        face: the integral of the piecewise constant speeds of `phases` (times x sections)."""
        t = np.asarray(t, float)[:, None]
        starts, speeds = self.phases(np.asarray(s, float)[None, :])
        u = np.zeros(np.broadcast_shapes(t.shape, starts[0].shape))
        for k, (b, v) in enumerate(zip(starts, speeds)):
            end = starts[k + 1] if k + 1 < len(starts) else np.inf
            u = u + v * np.clip(t - b, 0.0, end - b)
        return u

    def face(self, t):
        """Displacement along x of the contact face."""
        return self.d * self.displacement([0.0], t)[:, 0]

    def gap(self, t):
        t = np.asarray(t, float)
        free = self.U0 - self.d * self.face(t)
        return np.where((t >= self.t0) & (t < self.t1), 0.0, free)

    def node_s(self, ids):
        """Distance to the contact face of Box-mesh nodes (id = i + (nx+1)(j + (ny+1)k))."""
        nx = self.elements[0]
        x = (np.asarray(ids) % (nx + 1)) * self.L / nx
        return self.L - x if self.bar.contact == "x+" else x

    def measures(self, tend, watch_ids, comp, node):
        """Reference values over [0, tend]."""
        ref = {}
        ref["contact start"] = self.t0 if tend > self.t0 else float("nan")
        ref["contact end"] = self.t1 if tend > self.t1 else float("nan")
        dur = min(tend, self.t1) - self.t0
        ref["impulse"] = self.F * max(dur, 0.0)
        ref["plateau force"] = self.F if dur > 0 else float("nan")
        ref["peak force"] = self.F if dur > 0 else 0.0
        ref["max penetration"] = 0.0 if dur > 0 else -(self.U0 - self.v0 * tend)
        ref["rebound velocity"] = self.d * float(self.momentum(tend)) / self.m * (1 if comp == 0 else 0)
        ref["energy balance"] = 0.0
        ref["duration"] = (self.t1 - self.t0) if tend > self.t1 else float("nan")
        return ref

    def watched(self, t, ids, comp, node):
        if comp != 0:
            return np.zeros(np.asarray(t).size)
        u = self.d * self.displacement(self.node_s(ids), t)
        return u[:, node] if node >= 0 else u.mean(axis=1)


class BarOnWall(Exact1D):
    """V1: a bar (free far end) hitting the plane x = const at v0 > 0. t0 = U0/v0, t1 = t0 + 2L/c,
    plateau F = rho c S v0; a section at distance s from the contact face moves at v0 until
    t0 + s/c, rests until t0 + (2L - s)/c, then moves back at -v0."""

    label = "exact (bar on a rigid wall)"

    def __init__(self, deck, schema, where):
        fail, bodies, s = scene(deck, "bar-on-wall", 1, where)
        bar = BoxBar(deck, schema, bodies[0], fail)
        self.body = bar.name
        if deck.get(s + "->Type", schema) != "Plane":
            fail("the surface is not a Plane")
        so, su, sv = (numbers(deck.get(s + "->" + k, schema)) for k in ("Origin", "U", "V"))
        if abs(bar.nu) > 0:
            fail(f"Poisson's ratio is {bar.nu:g}, the 1-D solution needs 0")
        v = bar.v
        if not (v[0] > 0 and v[1] == 0 and v[2] == 0):
            fail(f"the initial velocity {v} is not along +x")
        if su[0] != 0 or sv[0] != 0:
            fail("the plane is not x = const")
        if bar.contact != "x+":
            fail("the contact node set is not x+")
        if deck.get("Time->Damping->Type", schema) != "None":
            fail("the run is damped")
        U0 = so[0] - bar.face_x("x+")
        if U0 < 0:
            fail(f"the bar starts through the wall (gap {U0:g} m)")
        c = math.sqrt(bar.E / bar.rho)
        self.setup(bar, v[0], 1.0, U0, 2 * bar.L / c, bar.rho * c * bar.S * v[0])

    def phases(self, s):
        return [0.0 * s, self.t0 + s / self.c, self.t0 + (2 * self.L - s) / self.c], [self.v0, 0.0, -self.v0]


class TwoBars(Exact1D):
    """V2 (code_aster SDNL111A): a bar moving at v along x hits an identical bar clamped at its far
    end, whose near face is a surface it carries. 1-D waves at c = sqrt(E/rho) (the rod theory of
    SDNL111A, whatever Poisson's ratio: the 3-D bar's lateral inertia is part of the model's error),
    T = L/c: the faces move together at v/2 until t0 + 2T, back at -v/2 until t0 + 4T, where the bars
    part with the struck bar at rest and the impacting one leaving at -v; the force is rho c S v/2
    throughout. A section of the impacting bar at distance s from its contact face moves at v until
    t0 + s/c, v/2 until t0 + (2L - s)/c, 0 until t0 + 2T + s/c, -v/2 until t0 + (4L - s)/c, then -v."""

    label = "exact (two-bar impact, 1-D waves)"

    def __init__(self, deck, schema, where):
        fail, bodies, s = scene(deck, "two-bars", 2, where)
        carrier = deck.get(s + "->Body", schema)
        if deck.get(s + "->Type", schema) != "Body face" or carrier not in bodies:
            fail("the surface is not a 'Body face' carried by one of the bodies")
        struck = BoxBar(deck, schema, carrier, fail)
        bar = BoxBar(deck, schema, next(b for b in bodies if b != carrier), fail)
        self.body = bar.name
        v = bar.v
        if not (v[0] != 0 and v[1] == 0 and v[2] == 0):
            fail(f"the initial velocity {v} of '{bar.name}' is not along x")
        if any(struck.v):
            fail(f"the struck bar '{struck.name}' moves at {struck.v}")
        d = 1.0 if v[0] > 0 else -1.0
        near, far = ("x+", "x-") if d < 0 else ("x-", "x+")
        if bar.contact != far or deck.get(s + "->Node grid", schema) != near or struck.clamped != far:
            fail(f"'{bar.name}' must touch with its face {far} the face {near} of '{struck.name}', clamped at {far}")
        if (bar.L, bar.S, bar.rho, bar.E) != (struck.L, struck.S, struck.rho, struck.E):
            fail("the two bars differ in length, section or material (the solution is for identical bars)")
        if deck.get("Time->Damping->Type", schema) != "None":
            fail("the run is damped")
        U0 = d * (struck.face_x(near) - bar.face_x(far)) + 0.0  # no -0.0
        if U0 < 0:
            fail(f"the bars overlap (gap {U0:g} m)")
        c = math.sqrt(bar.E / bar.rho)
        self.setup(bar, abs(v[0]), d, U0, 4 * bar.L / c, bar.rho * c * bar.S * abs(v[0]) / 2)
        self.T = bar.L / c
        self.breaks = [self.t0, self.t0 + 2 * self.T, self.t1]

    def phases(self, s):
        t0, c, L, v = self.t0, self.c, self.L, self.v0
        return (
            [0.0 * s, t0 + s / c, t0 + (2 * L - s) / c, t0 + 2 * L / c + s / c, t0 + (4 * L - s) / c],
            [v, v / 2, 0.0, -v / 2, -v],
        )


EXACT = {"bar-on-wall": BarOnWall, "two-bars": TwoBars}


def exact_solution(name, deck, schema, where=None):
    """The exact solution `name` ('bar-on-wall', 'two-bars') of a deck (a Deck or a deck file),
    its defaults from `schema` (a Schema, or the path of epaphe-run to ask); an EpapheError says why
    it does not apply."""
    if name not in EXACT:
        raise EpapheError(f"unknown exact solution '{name}' (known: {', '.join(EXACT)})")
    d = deck if isinstance(deck, Deck) else Deck(deck)
    s = schema if isinstance(schema, Schema) else Schema.of(schema)
    return EXACT[name](d, s, where or d.path)
