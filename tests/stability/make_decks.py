#!/usr/bin/env python3
"""Writes the decks of the stability suite into decks/ (run again after editing this file).

Small models throughout (a 1- or 2-element block, the dense full model or Craig-Bampton with few
modes, no frequency check) so that the whole suite runs in a few minutes."""
import os
import xml.etree.ElementTree as ET

HERE = os.path.dirname(os.path.abspath(__file__))


def P(name, typ, value):
    return f'<Parameter name="{name}" type="{typ}" value="{value}"/>'


def L(name, *items, indent=1):
    pad = "  " * indent
    body = "\n".join(pad + "  " + i.replace("\n", "\n  ") for i in items)
    return f'<ParameterList name="{name}">\n{body}\n{pad}</ParameterList>'


def vec(v):
    return "{" + ", ".join(f"{x:.12g}" if isinstance(x, float) else str(x) for x in v) + "}"


def body(
    name, origin, lengths, elements, velocity, contact="", watched=(), clamped="", method="None", modes=4, retained=""
):
    red = [P("Method", "string", method), P("Frequency check", "int", 0)]
    if method == "Craig-Bampton":
        red.append(P("Fixed-interface modes", "int", modes))
    if retained:
        red.append(P("Retained node set", "string", retained))
    items = [
        L(
            "Mesh",
            P("Type", "string", "Box"),
            P("Origin", "Array(double)", vec(origin)),
            P("Lengths", "Array(double)", vec(lengths)),
            P("Elements", "Array(int)", vec(elements)),
        ),
        L(
            "Material",
            P("Density", "double", 7800),
            P("Young's modulus", "double", 2.1e11),
            P("Poisson's ratio", "double", 0.3),
        ),
        P("Initial velocity", "Array(double)", vec(velocity)),
    ]
    if contact:
        items.append(P("Contact node set", "string", contact))
    if watched:
        items.append(P("Watched node sets", "Array(string)", vec(watched)))
    if clamped:
        items.append(P("Clamped node set", "string", clamped))
    items.append(L("Reduction", *red))
    return L(name, *items)


def plane(name, origin, U, V, points=(5, 5), flip=False):
    items = [
        P("Type", "string", "Plane"),
        P("Origin", "Array(double)", vec(origin)),
        P("U", "Array(double)", vec(U)),
        P("V", "Array(double)", vec(V)),
        P("Points", "Array(int)", vec(points)),
    ]
    if flip:
        items.append(P("Flip normal", "bool", "true"))
    return L(name, *items)


def deck(path, comment, bodies, surfaces, h, end, every, contact=(), output=None, time_extra=(), out_extra=()):
    name = os.path.splitext(os.path.basename(path))[0]
    items = [L("Run", P("Name", "string", name)), L("Bodies", *bodies)]
    if surfaces:
        items.append(L("Surfaces", *surfaces))
    items.append(L("Contact", P("Method", "string", "Lagrange"), *contact))
    items.append(L("Time", P("Time step", "double", h), P("End time", "double", end), *time_extra))
    items.append(L("Output", P("File", "string", output or name + ".h5"), P("Every", "int", every), *out_extra))
    root = ET.fromstring(L("Epaphe", *items, indent=0))
    ET.indent(root)
    text = f"<!-- {comment} -->\n" + ET.tostring(root, encoding="unicode") + "\n"
    with open(os.path.join(HERE, "decks", path), "w") as f:
        f.write(text)


# plane y = 0 seen from above: U along z, V along x (U x V = +y)
def floor(name, x0, x1, z0, z1, points=(5, 5)):
    return plane(name, (x0, 0.0, z0), (0, 0, z1 - z0), (x1 - x0, 0, 0), points)


BLOCK = dict(lengths=(0.02, 0.01, 0.02), elements=(2, 1, 2))

deck(
    "grazing.xml",
    "Grazing contact: a block resting at zero gap on the plane y = 0 slides along it at 5 m/s "
    "(velocity tangent to the plane); no correction should be needed beyond round-off",
    [body("Block", (0.0, 0.0, -0.01), velocity=(5.0, 0, 0), contact="y-", watched=("y-",), **BLOCK)],
    [floor("Floor", -0.05, 0.1, -0.05, 0.05)],
    2e-7,
    4e-3,
    100,
)

deck(
    "stick.xml",
    "Coulomb mu = 0.8, stick: a block hits the plane y = 0 at 1 m/s with a tangential 0.5 m/s "
    "(ratio 0.5 < mu): the contact nodes stick while in contact",
    [body("Block", (0.0, 1e-5, -0.01), velocity=(0.5, -1.0, 0), contact="y-", watched=("y-",), **BLOCK)],
    [floor("Floor", -0.05, 0.1, -0.05, 0.05)],
    1e-7,
    1e-4,
    10,
    contact=[P("Friction coefficient", "double", 0.8)],
)

deck(
    "penalty.xml",
    "Penalty contact: a block hits the plane y = 0 at 10 m/s; the check varies kp around the critical " "step's limit",
    [body("Block", (0.0, 1e-5, -0.01), velocity=(0, -10.0, 0), contact="y-", **BLOCK)],
    [floor("Floor", -0.05, 0.05, -0.05, 0.05)],
    1e-7,
    1e-4,
    10,
    contact=[P("Penalty stiffness", "double", 1e8)],
)

# Full 360-degree cylinder (closed by the deck: its last grid row repeats the first), radius 0.1 m,
# axis z, seam at angle 0 (the +x direction). A 4 mm block inside it, its x+ face 0.1 mm from the
# wall (contact side: towards the axis, 'Flip normal'), just below the seam (y in [-0.004, 0]),
# moving at (1, 10, 0) m/s: its leading nodes reach the wall just past the seam, and it then slides
# along the curved wall, pressed against it (the wall turns it), its trailing nodes crossing the seam.
deck(
    "seam.xml",
    "A node crossing the seam of a closed surface: a block inside a full rigid cylinder (radius 0.1 m, "
    "angles 0..360 degrees, seam at +x) slides along the wall across the seam at 10 m/s",
    [
        body(
            "Block",
            (0.0959, -0.004, -0.002),
            (0.004, 0.004, 0.004),
            (1, 1, 1),
            (1.0, 10.0, 0),
            contact="x+",
            watched=("x+",),
        )
    ],
    [
        L(
            "Cylinder",
            P("Type", "string", "Cylinder arc"),
            P("Center", "Array(double)", "{0, 0, 0}"),
            P("Radius", "double", 0.1),
            P("Angles", "Array(double)", "{0, 360}"),
            P("Axial range", "Array(double)", "{-0.01, 0.01}"),
            P("Points", "Array(int)", "{37, 4}"),
            P("Flip normal", "bool", "true"),
        )
    ],
    1e-7,
    8e-4,
    20,
    out_extra=[P("Fields every", "int", 20)],
)

# Plane y = 0 with 4 x 4 points over x, z in [-0.03, 0.03]: grid lines at -0.03, -0.01, 0.01, 0.03.
# The block's y- nodes (x, z in {-0.01, 0, 0.01}) fall on patch corners (+-0.01, +-0.01) and on
# patch edges (x or z = +-0.01, the other 0).
deck(
    "patch-corner-edge.xml",
    "Nodes hitting patch corners and patch edges: the contact nodes of a block land exactly on the grid "
    "points and grid lines of a 4 x 4 plane at 10 m/s",
    [body("Block", (-0.01, 1e-5, -0.01), (0.02, 0.01, 0.02), (2, 1, 2), (0, -10.0, 0), contact="y-")],
    [floor("Floor", -0.03, 0.03, -0.03, 0.03, points=(4, 4))],
    1e-7,
    1e-4,
    10,
)

# Plane y = 0 ends at x = 0.02; the block (x in [0, 0.02]) slides +x at 20 m/s with a small downward
# velocity: its nodes leave the plane one column after the other and must then be left alone.
deck(
    "open-edge.xml",
    "Nodes leaving the edge of an open surface: a block sliding at 20 m/s (and 0.5 m/s towards the plane) "
    "off the edge x = 0.02 of a plane; beyond the edge a node is not corrected",
    [body("Block", (0.0, 0.0, -0.01), velocity=(20.0, -0.5, 0), contact="y-", watched=("y-",), **BLOCK)],
    [floor("Floor", -0.02, 0.02, -0.02, 0.02)],
    1e-7,
    1.5e-3,
    50,
    out_extra=[P("Fields every", "int", 50)],
)

deck(
    "many-nodes.xml",
    "Many nodes on one patch: the 121 bottom nodes of a 10 x 10 block fall at 5 m/s on one patch of a " "4 x 4 plane",
    [
        body(
            "Block",
            (-0.005, 1e-5, -0.005),
            (0.01, 0.002, 0.01),
            (10, 1, 10),
            (0, -5.0, 0),
            contact="y-",
            method="Craig-Bampton",
            modes=4,
        )
    ],
    [floor("Floor", -0.015, 0.015, -0.015, 0.015, points=(4, 4))],
    2e-8,
    2e-5,
    10,
)

# Two planes: y = 0 (floor) and x = 0 (wall, U along y, V along z: U x V = +x). The block's corner
# edge at x = y = 0 hits both at once.
deck(
    "two-surfaces.xml",
    "Simultaneous contact on two surfaces: a block moving at (-5, -5, 0) m/s hits the floor y = 0 and "
    "the wall x = 0 at the same instant",
    [body("Block", (1e-5, 1e-5, -0.01), velocity=(-5.0, -5.0, 0), contact="x-, y-", **BLOCK)],
    [floor("Floor", -0.05, 0.05, -0.05, 0.05), plane("Wall", (0.0, -0.05, -0.05), (0, 0.1, 0), (0, 0, 0.1))],
    1e-7,
    1e-4,
    10,
    out_extra=[P("Fields every", "int", 10)],
)

deck(
    "free-vibration.xml",
    "10^7 steps of free vibration: a one-element cantilever (clamped x-, the dense full model) "
    "released with a uniform velocity; the energy must not drift",
    [body("Beam", (0.0, 0.0, 0.0), (0.02, 0.01, 0.01), (1, 1, 1), (0, 1.0, 0), clamped="x-")],
    [],
    1e-7,
    1.0,
    100000,
)

# Rubbing: a one-element block squeezed between the floor y = 0 and a ceiling y = 0.01 (it starts
# 2e-10 m into each), sliding at 2 m/s with mu = 0.05: it slows down (about 11 m/s^2) but slides
# all along.
deck(
    "rubbing.xml",
    "10^6 steps of rubbing: a one-element block squeezed between two planes slides with friction mu = 0.05",
    [body("Block", (0.0, -2e-10, -0.005), (0.01, 0.01 + 4e-10, 0.01), (1, 1, 1), (2.0, 0, 0), contact="y-, y+")],
    [floor("Floor", -0.02, 0.4, -0.02, 0.02), plane("Ceiling", (-0.02, 0.01, -0.02), (0.42, 0, 0), (0, 0, 0.04))],
    1e-7,
    0.1,
    10000,
    contact=[P("Friction coefficient", "double", 0.05)],
    # the balance error of sliding friction grows by about 2.6e-12 per step (1.1e-6 after 4.3e5 steps)
    out_extra=[P("Energy balance tolerance", "double", 1e-4)],
)

# The same squeeze with penalty contact and no friction: the contact never opens, so a penalty
# stiffness above the stability limit makes the central difference blow up.
deck(
    "penalty-squeeze.xml",
    "Penalty contact held closed: a one-element block squeezed between two planes; the check varies kp "
    "around the critical step's limit",
    [body("Block", (0.0, -1e-9, -0.005), (0.01, 0.01 + 2e-9, 0.01), (1, 1, 1), (0, 0, 0), contact="y-, y+")],
    [floor("Floor", -0.02, 0.04, -0.02, 0.02), plane("Ceiling", (-0.02, 0.01, -0.02), (0.06, 0, 0), (0, 0, 0.04))],
    1e-7,
    2e-4,
    10,
    contact=[P("Penalty stiffness", "double", 1e8)],
)
