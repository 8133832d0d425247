"""Mass properties of primitive shapes, solid or as thin shells, and of rigid parts put together.

Each shape is centred at its frame's origin with its axis (capsule, cylinder) along z. Sizes as MJCF gives them:
sphere ``r``; capsule ``r``, half-length ``h`` of its cylinder; cylinder ``r``, half-height ``h``; box half-sizes
``a, b, c``; ellipsoid semi-axes ``a, b, c``. Returned: the volume (solid) or area (shell), m^3 or m^2, and the
principal moments ``(3,)`` about the centre *per unit mass*, m^2: multiply by the mass.

Solids (textbook formulas): sphere ``2 r^2 / 5``; cylinder ``(3 r^2 + (2h)^2) / 12`` about x, y and ``r^2 / 2``
about z; box ``(b^2 + c^2) / 3`` ...; ellipsoid ``(b^2 + c^2) / 5`` ...; capsule: a cylinder and two hemispheres
each moved by the parallel-axis theorem from its centre of mass, ``3 r / 8`` from its flat face (a hemisphere's
moment about its centre of mass perpendicular to the axis is ``83 r^2 / 320`` per unit mass).

Shells (mass on the surface): sphere ``2 r^2 / 3``; box: its six faces as plates; cylinder: its side and two end
disks; capsule: its side and two hemispherical shells (a hemispherical shell's centre of mass is ``r / 2`` from its
flat face, its moment about a diameter through the sphere's centre ``2 r^2 / 3``). A shell ellipsoid has no closed
form: :func:`shape` says so and the reader reports the body.
"""

from __future__ import annotations

import numpy as np

SHAPES = ("sphere", "capsule", "cylinder", "box", "ellipsoid")
"""Primitive shapes relacc computes itself."""


class NoClosedForm(Exception):
    """A shape whose mass properties relacc does not compute (the reader names the body and where they came from)."""


def shape(kind: str, size, shell: bool = False) -> tuple[float, np.ndarray]:
    """``(volume or area, principal moments per unit mass (3,))`` of a primitive (module docstring).

    Raises:
        NoClosedForm: a shell ellipsoid, or a kind not in :data:`SHAPES`.
    """
    s = [float(x) for x in size]
    pi = np.pi
    if kind == "sphere":
        r = s[0]
        return (4 * pi * r * r, np.full(3, 2 * r * r / 3)) if shell else (4 / 3 * pi * r**3, np.full(3, 0.4 * r * r))
    if kind == "box":
        a, b, c = s[:3]
        if not shell:
            return 8 * a * b * c, np.array([b * b + c * c, a * a + c * c, a * a + b * b]) / 3
        return _box_shell(a, b, c)
    if kind == "cylinder":
        r, h = s[:2]
        if not shell:
            return 2 * pi * r * r * h, np.array([(3 * r * r + 4 * h * h) / 12, (3 * r * r + 4 * h * h) / 12,
                                                 r * r / 2])
        return _cylinder_shell(r, h)
    if kind == "capsule":
        return _capsule(s[0], s[1], shell)
    if kind == "ellipsoid" and not shell:
        a, b, c = s[:3]
        return 4 / 3 * pi * a * b * c, np.array([b * b + c * c, a * a + c * c, a * a + b * b]) / 5
    raise NoClosedForm(f"{'a shell ' if shell else ''}{kind}")


def _box_shell(a, b, c):
    """Six plates: the faces normal to x (area 4bc each, at +-a), to y (4ac, at +-b), to z (4ab, at +-c)."""
    faces = [(4 * b * c, 0, (b, c)), (4 * a * c, 1, (a, c)), (4 * a * b, 2, (a, b))]
    half = (a, b, c)
    area = 2 * sum(A for A, _, _ in faces)
    moments = np.zeros(3)
    for A, normal, (p, q) in faces:
        others = [k for k in range(3) if k != normal]
        m = 2 * A  # both faces
        # a plate of half-sizes p, q (along others[0], others[1]), at distance half[normal] along the normal
        moments[normal] += m * (p * p + q * q) / 3
        moments[others[0]] += m * (q * q / 3 + half[normal] ** 2)
        moments[others[1]] += m * (p * p / 3 + half[normal] ** 2)
    return area, moments / area


def _cylinder_shell(r, h):
    """Side (area 4 pi r h) and two end disks (pi r^2 each, at +-h)."""
    side, disk = 4 * np.pi * r * h, np.pi * r * r
    area = side + 2 * disk
    x = side * (r * r / 2 + (2 * h) ** 2 / 12) + 2 * disk * (r * r / 4 + h * h)
    z = side * r * r + 2 * disk * r * r / 2
    return area, np.array([x, x, z]) / area


def _capsule(r, h, shell):
    """A cylinder of half-length ``h`` and two hemispheres (solid or shells), each moved to the capsule's centre."""
    if shell:
        side, cap = 4 * np.pi * r * h, 2 * np.pi * r * r  # each hemispherical shell
        whole = side + 2 * cap
        # side about x: r^2/2 + L^2/12 per unit mass; a hemispherical shell about a diameter through its sphere's
        # centre: 2 r^2/3; its centre of mass at r/2 from that centre, which is h from the capsule's centre
        x = side * (r * r / 2 + (2 * h) ** 2 / 12) + 2 * cap * (2 * r * r / 3 - (r / 2) ** 2 + (h + r / 2) ** 2)
        z = side * r * r + 2 * cap * 2 * r * r / 3
        return whole, np.array([x, x, z]) / whole
    cyl, caps = 2 * np.pi * r * r * h, 4 / 3 * np.pi * r**3  # both hemispheres
    whole = cyl + caps
    d = h + 3 * r / 8  # each hemisphere's centre of mass from the capsule's centre
    x = cyl * (3 * r * r + 4 * h * h) / 12 + caps * (83 * r * r / 320 + d * d)
    z = cyl * r * r / 2 + caps * 2 * r * r / 5
    return whole, np.array([x, x, z]) / whole


def combine(parts) -> tuple[float, np.ndarray, np.ndarray]:
    """``(mass, centre of mass (3,), inertia about it (3, 3))`` of rigid parts ``(mass, centre (3,), inertia about its
    own centre (3, 3))``, all in one frame's components (parallel-axis theorem). No mass: ``(0, 0, 0)``."""
    parts = list(parts)
    mass = float(sum(m for m, _, _ in parts))
    if mass <= 0:
        return mass, np.zeros(3), sum((np.asarray(I, dtype=float) for _, _, I in parts), np.zeros((3, 3)))
    com = sum(m * np.asarray(c, dtype=float) for m, c, _ in parts) / mass
    inertia = np.zeros((3, 3))
    for m, c, I in parts:
        d = np.asarray(c, dtype=float) - com
        inertia += np.asarray(I, dtype=float) + m * ((d @ d) * np.eye(3) - np.outer(d, d))
    return mass, com, 0.5 * (inertia + inertia.T)
