"""Engines' known readings of a file as changes to relacc's own reading: the helpers each engine's ``readings``
module builds its ``FILE_READINGS`` from (:class:`relacc.engines.base.KnownBehaviour` whose ``applies(reading)`` and
``change(reading) -> Reading`` take :class:`relacc.reading.Reading`). Most read the file again the engine's way
(:data:`relacc.reading.mjcf.VARIANTS`, :func:`reread`): they need no engine, MuJoCo included, to read the file.
Imports no engine."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from relacc.core.tolerances import EPS
from relacc.core.tree.model import Tree
from relacc.engines.base import KnownBehaviour


def with_bodies(reading, change):
    """``reading`` with each body replaced by ``change(body)`` (None keeps it)."""
    bodies = tuple(change(b) or b for b in reading.tree.bodies)
    t = reading.tree
    return replace(reading, tree=Tree(t.name, bodies, gravity=t.gravity, points=t.points, source=t.source))


def massless_with_inertia(reading) -> bool:
    return any(b.mass == 0 and np.any(b.inertia != 0) for b in reading.tree.bodies)


def drop_massless_inertia(reading):
    return with_bodies(reading, lambda b: replace(b, inertia=np.zeros((3, 3))) if b.mass == 0 else None)


WATER = 1000.0
"""kg/m^3: the density of the solid sphere Drake's URDF parser puts in place of an inertia it cannot take."""


def water_sphere(mass: float) -> np.ndarray:
    """``(3, 3)`` kg m^2: the inertia about its centre of a solid sphere of water of ``mass`` kg, ``0.4 m r^2`` with
    ``r = (3 m / (4 pi 1000))^(1/3)``: what Drake's URDF parser gives a link whose inertia is not physical (measured on
    Drake 1.51: the 25 such bodies of a public URDF dataset to 1.2e-15, and a massless link given 1 kg)."""
    r = (3.0 * mass / (4.0 * np.pi * WATER)) ** (1.0 / 3.0)
    return 0.4 * mass * r * r * np.eye(3)


def massless_get_a_kilogram(reading):
    return with_bodies(reading, lambda b: replace(b, mass=1.0, inertia=water_sphere(1.0))
                       if b.mass == 0 and np.any(b.inertia != 0) else None)


def drake_invalid(inertia: np.ndarray) -> bool:
    """Whether Drake's ``RotationalInertia::CouldBePhysicallyValid()`` refuses an inertia ``(3, 3)`` (kg m^2): its
    principal moments ``p0 <= p1 <= p2`` with ``p0 < -e`` or ``p0 + p1 + e < p2``, ``e = 16 eps max(1, trace / 2)``,
    an absolute floor of 3.6e-15 kg m^2 below 2 kg m^2 (measured on Drake 1.51: products of inertia alone of 1.7e-15
    kept, of 2.1e-15 replaced by a water sphere; iCub's head, whose only product is 2.4e-35, is a point mass to Drake
    and not physical to relacc's own check)."""
    p = np.linalg.eigvalsh(0.5 * (inertia + inertia.T))
    e = 16 * EPS * max(1.0, 0.5 * float(np.trace(inertia)))
    return bool(p[0] < -e or p[0] + p[1] + e < p[2])


def unphysical_inertia(reading) -> bool:
    return reading.format == "urdf" and any(b.mass > 0 and drake_invalid(b.inertia) for b in reading.tree.bodies)


def water_spheres(reading):
    return with_bodies(reading, lambda b: replace(b, inertia=water_sphere(b.mass))
                       if b.mass > 0 and drake_invalid(b.inertia) else None)


def urdf_inertial_turned(reading) -> bool:
    """A URDF whose inertials are turned (``rpy``): what MuJoCo up to 3.13 misreads (google-deepmind/mujoco#3559;
    measured on the releases 3.3.1 to 4.0.0: wrong up to 3.13.0, right from 3.14.0)."""
    return reading.format == "urdf" and bool(reading.turned_inertials)


def unturned_inertials(reading):
    """Each turned inertial as if its ``rpy`` were zero: the inertia as written, in the link's axes."""
    return with_bodies(
        reading,
        lambda b: replace(b, inertia=reading.turned_inertials[b.name]) if b.name in reading.turned_inertials else None,
    )


def reread(*variant):
    """The change that reads the file again the engine's way (:data:`relacc.reading.mjcf.VARIANTS`), on top of the
    variants the reading already follows."""

    def change(reading):
        from relacc.reading import read

        return read(reading.source, variant=reading.variant | frozenset(variant))

    return change


def mjcf(reading) -> bool:
    return reading.format == "mjcf"


def mjcf_reading(key: str, text: str, fact: str, variant: str) -> KnownBehaviour:
    """An engine's MJCF parser reading the file its own way (``text``, the sentence a cause quotes): it applies where
    the reading's ``facts[fact]`` is set, and is reproduced by reading the file again with ``variant``."""
    return KnownBehaviour(key, text, lambda r: mjcf(r) and bool(r.facts.get(fact)), reread(variant))


def settotalmass_ignored(engine: str, said: str = "") -> KnownBehaviour:
    """``engine`` ignoring ``<compiler settotalmass>`` (Pinocchio's and Drake's; ``said``: what it says of it, as
    ``" (it warns so)"``)."""
    return mjcf_reading("settotalmass", f"{engine} ignores <compiler settotalmass>{said}, which makes MuJoCo scale "
                        "every mass", "settotalmass", "settotalmass_ignored")


def element_skipped(engine: str, element: str, fact: str, what: str) -> KnownBehaviour:
    """``engine``'s MJCF parser skipping every ``<element>`` (counted in the reading's ``facts[fact]``; ``what``: what
    is then absent, and what it says), read again with the variant ``<element>_skipped``."""
    return mjcf_reading(element, f"{engine}'s MJCF parser skips {'an' if element[0] in 'aeiou' else 'a'} <{element}> "
                        f"({what})", fact, f"{element}_skipped")


def inertiagrouprange_ignored(engine: str) -> KnownBehaviour:
    """``engine``'s MJCF parser counting every geom's mass whatever ``<compiler inertiagrouprange>`` says (Pinocchio's
    and Drake's, measured on pin 4.1 and Drake 1.51)."""
    return mjcf_reading("inertiagrouprange", f"{engine}'s MJCF parser ignores <compiler inertiagrouprange>: it counts "
                        "the mass of geoms of every group, MuJoCo only of those in the range", "group_excluded",
                        "inertiagrouprange_ignored")


def springdamper_ignored(engine: str) -> KnownBehaviour:
    """``engine``'s MJCF parser keeping the written stiffness and damping of a joint with ``springdamper`` (Pinocchio's
    and Drake's, measured on pin 4.1 and Drake 1.51)."""
    return mjcf_reading("springdamper", f"{engine}'s MJCF parser ignores a joint's springdamper, from which MuJoCo's "
                        "compiler sets the stiffness and damping (it keeps those written)", "springdamper",
                        "springdamper_ignored")
