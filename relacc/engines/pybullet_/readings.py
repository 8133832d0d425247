"""How PyBullet's URDF importer reads a file, as changes to relacc's reading (imports no engine).

Measured on pybullet 3.2.7 (``tests/test_pybullet.py`` holds each rule to PyBullet itself) and read in its importer
(``BulletURDFImporter::getMassAndInertia2``, ``convertURDFToCollisionShape``):

* **A link without ``<inertial>``** gets 1 kg, its inertial frame the link's own: with ``URDF_USE_INERTIA_FROM_FILE``
  an inertia ``diag(1, 1, 1)`` kg m^2; without it, the inertia of its collision shapes (below). The URDF
  specification makes such a link massless.
* **Without ``URDF_USE_INERTIA_FROM_FILE``** (``loadURDF``'s default) every link's inertia is Bullet's of its
  collision shapes, for the link's mass, about the ``<inertial>``'s origin and in its axes. One shape placed exactly at
  the inertial frame is taken alone (:data:`ALONE`): a box's own inertia (``btBoxShape``), a ball's ``0.4 m r^2``, a
  capsule's the solid box around it, a cylinder's the solid box around it grown by 3 mm a side, an OBJ or STL mesh's
  the solid box around its vertices grown by 3 mm a side (the capsule's, the cylinder's and the STL mesh's with
  Bullet's literal ``0.08333333`` for 1/12). Otherwise (several shapes, one shape elsewhere) the solid box
  around the compound's bounding box in the inertial frame: each child's box (``|R| h`` about its centre; a ball's
  ``r`` whatever its turn) grown by its margin (:data:`MARGINS`: an OBJ mesh 3 mm, an STL mesh or a cylinder 2 mm, a
  box, ball or capsule none) and the whole by the compound's 1 mm a side; no collision shape: a 2 mm box. Another
  mesh format is not reproduced (the change refuses it and the difference stays unexplained).
* **With ``URDF_USE_INERTIA_FROM_FILE``**, an inertia whose principal moments break the triangle inequality (or
  are negative) is set to zero ("Bad inertia tensor properties"); others are kept, diagonalized.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from relacc.engines.base import KnownBehaviour
from relacc.engines.known import with_bodies
from relacc.errors import ModelError

FLAG = "URDF_USE_INERTIA_FROM_FILE"

MARGINS = {"box": 0.0, "sphere": 0.0, "capsule": 0.0, "cylinder": 0.002, ".stl": 0.002, ".obj": 0.003}
"""m a side: how far Bullet's box around a collision shape reaches beyond the shape (a mesh's by its file's format:
the box around its vertices); measured on pybullet 3.2.7, each to the printed digits of ``getDynamicsInfo``."""

ALWAYS_COMPOUND: tuple[str, ...] = ()
"""Shapes the importer puts in a compound even alone at the inertial frame (none found)."""

ALONE = {"box": (0.0, None), "capsule": (0.0, 0.08333333), "cylinder": (0.003, 0.08333333), ".obj": (0.003, None),
         ".stl": (0.003, 0.08333333)}
"""A shape alone at the inertial frame: ``(m a side its box reaches beyond the shape, Bullet's literal factor for
1/12 or None)`` (``btBoxShape``, ``btCapsuleShape``, ``btCylinderShapeZ``, ``btConvexHullShape``; measured)."""
COMPOUND_MARGIN = 0.001
"""m a side: a compound shape's margin, added to its children's boxes (measured: ``gUrdfDefaultCollisionMargin``)."""


def _geometry(reading) -> dict:
    return reading.facts.get("geometry", {}) if reading.format == "urdf" else {}


def _box(mass: float, edges, twelfth: float | None = None) -> np.ndarray:
    """``(3, 3)`` the inertia of a solid box of ``mass`` and ``edges (3,)`` about its centre, its axes (``mass / 12``
    times the squares, or ``twelfth`` times the mass where Bullet writes the factor as a literal)."""
    a, b, c = (float(x) ** 2 for x in edges)
    scaled = mass / 12.0 if twelfth is None else mass * twelfth
    return scaled * np.diag([b + c, a + c, a + b])


def _kind(shape) -> str:
    """A shape's kind for :data:`MARGINS`: its element's name, a mesh's file suffix.

    Raises:
        ModelError: a mesh not found, or of a format whose box Bullet's importer was not measured on.
    """
    if shape.kind != "mesh":
        return shape.kind
    if shape.mesh is None:
        raise ModelError(f"{shape.place}: the mesh file is not found")
    suffix = shape.mesh.suffix.lower()
    if suffix not in MARGINS:
        raise ModelError(f"{shape.place}: a {suffix} mesh, whose box in Bullet's importer relacc has not measured")
    return suffix


def _hull_box(shape) -> tuple[np.ndarray, np.ndarray]:
    """``(centre (3,), half extents (3,))`` of a mesh's vertices' box in its own frame, scaled.

    Raises:
        ModelError: the mesh is not found or not read (binary STL, OBJ).
    """
    from relacc.reading.mesh import load

    _kind(shape)
    vertices, _ = load(shape.mesh, shape.place)
    v = vertices * np.asarray(shape.scale, dtype=float)
    lo, hi = v.min(axis=0), v.max(axis=0)
    return (lo + hi) / 2.0, (hi - lo) / 2.0


def _child_box(shape) -> tuple[np.ndarray, np.ndarray]:
    """``(centre (3,), half extents (3,))`` of a shape's own box with its margin, in the shape's frame."""
    if shape.kind == "box":
        return np.zeros(3), np.asarray(shape.size, dtype=float) / 2.0
    if shape.kind == "sphere":
        return np.zeros(3), np.full(3, shape.size[0])
    if shape.kind == "capsule":
        r, length = shape.size
        return np.zeros(3), np.array([r, r, length / 2.0 + r])
    if shape.kind == "cylinder":
        r, length = shape.size
        return np.zeros(3), np.array([r, r, length / 2.0]) + MARGINS["cylinder"]
    centre, half = _hull_box(shape)
    return centre, half + MARGINS[_kind(shape)]


def collision_inertia(mass: float, g) -> np.ndarray:
    """``(3, 3)`` Bullet's inertia of a link's collision shapes (module docstring), about its inertial frame's
    origin, in that frame's axes; ``g``: the link's :class:`relacc.reading.urdf.LinkGeometry`."""
    shapes = g.shapes
    if len(shapes) == 1 and _kind(shapes[0]) not in ALWAYS_COMPOUND and np.array_equal(shapes[0].xyz, g.xyz) \
            and tuple(shapes[0].rpy) == tuple(g.rpy):
        s = shapes[0]
        if s.kind == "sphere":
            return 0.4 * mass * s.size[0] ** 2 * np.eye(3)
        pad, twelfth = ALONE[_kind(s)]
        centre, half = _child_box(s)
        half = half - MARGINS[_kind(s)] + pad
        return _box(mass, 2.0 * half, twelfth)
    lo, hi = np.zeros(3), np.zeros(3)
    if shapes:
        lows, highs = [], []
        for s in shapes:
            centre, half = _child_box(s)
            R = g.R.T @ s.R  # the shape's axes in the inertial frame
            c = g.R.T @ (s.xyz - g.xyz) + R @ centre
            reach = half if s.kind == "sphere" else np.abs(R) @ half  # a ball's box does not turn
            lows.append(c - reach)
            highs.append(c + reach)
        lo, hi = np.min(lows, axis=0), np.max(highs, axis=0)
    return _box(mass, hi - lo + 2.0 * COMPOUND_MARGIN)


def _without_inertial(reading) -> bool:
    return any(not g.inertial for name, g in _geometry(reading).items() if _moves(reading, name))


def _moves(reading, name: str) -> bool:
    """Whether a link is a body of relacc's tree that moves (not the root, welded to the world)."""
    tree = reading.tree
    if name not in tree.body_names:
        return False
    b = tree.body(name)
    while b >= 0:
        if tree.bodies[b].joints:
            return True
        b = tree.bodies[b].parent
    return False


def _in_link_frame(g, inertia) -> np.ndarray:
    """An inertia in its inertial frame's axes turned into the link's."""
    return g.R @ inertia @ g.R.T


def _as_default_loading(reading):
    """Every moving link's inertia Bullet's of its collision shapes; a link without ``<inertial>``: 1 kg at its
    origin."""
    geometry = _geometry(reading)

    def change(body):
        g = geometry.get(body.name)
        if g is None or not _moves(reading, body.name):
            return None
        mass = body.mass if g.inertial else 1.0
        com = body.com if g.inertial else np.zeros(3)
        return replace(body, mass=mass, com=com, inertia=_in_link_frame(g, collision_inertia(mass, g)))

    return with_bodies(reading, change)


def _one_kilogram(reading):
    """A link without ``<inertial>``: 1 kg and ``diag(1, 1, 1)`` kg m^2 at its origin (with the flag)."""
    geometry = _geometry(reading)
    return with_bodies(reading, lambda b: replace(b, mass=1.0, com=np.zeros(3), inertia=np.eye(3))
                       if b.name in geometry and not geometry[b.name].inertial and _moves(reading, b.name) else None)


def _bad(inertia: np.ndarray) -> bool:
    """Bullet's test of a file inertia's principal moments (negative, or one above the sum of the others)."""
    x, y, z = np.linalg.eigvalsh(inertia)
    return min(x, y, z) < 0 or x > y + z or y > x + z or z > x + y


def _has_bad(reading) -> bool:
    geometry = _geometry(reading)
    return any(_bad(b.inertia) for b in reading.tree.bodies if b.name in geometry and geometry[b.name].inertial
               and _moves(reading, b.name))


def _zero_bad(reading):
    geometry = _geometry(reading)
    return with_bodies(reading, lambda b: replace(b, inertia=np.zeros((3, 3)))
                       if b.name in geometry and geometry[b.name].inertial and _moves(reading, b.name)
                       and _bad(b.inertia) else None)


FILE_READINGS = (
    KnownBehaviour(
        "collision_inertia",
        "PyBullet's loadURDF without flags (its default) does not read a link's inertia from the file: Bullet "
        "computes it from the link's collision shapes (a box around them, or one shape's own; a link without "
        f"collision shapes a 2 mm box), keeping the mass and the inertial frame, and gives a link without <inertial> "
        f"1 kg; load with flags=pybullet.{FLAG} to use the file's inertias",
        lambda r: bool(_geometry(r)),
        _as_default_loading,
    ),
)
"""PyBullet's known readings as users load a URDF (``loadURDF`` without flags)."""

FILE_READINGS_FROM_FILE = (
    KnownBehaviour(
        "no_inertial_one_kilogram",
        f"PyBullet (with {FLAG} too) gives a link without <inertial> 1 kg and an inertia diag(1, 1, 1) kg m^2 at the "
        "link's origin (\"No inertial data for link\"); the URDF specification makes it massless: give such a link "
        "an <inertial> with its real mass",
        _without_inertial,
        _one_kilogram,
    ),
    KnownBehaviour(
        "bad_inertia_zeroed",
        f"PyBullet with {FLAG} sets to zero an inertia whose principal moments break the triangle inequality (\"Bad "
        "inertia tensor properties\"): a tensor no rigid body has",
        _has_bad,
        _zero_bad,
    ),
)
"""PyBullet's known readings with ``URDF_USE_INERTIA_FROM_FILE``."""

ENGINE_READINGS: tuple = ()
"""No known difference in PyBullet's algorithms."""
