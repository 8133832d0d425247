"""Why an engine's reading differs from relacc's: typed causes, and the known readings in relacc's own terms.

A :class:`Cause` is a kind, a sentence and, where relacc knows it, the place in the file (``file:line``) the
difference comes from. Kinds:

* ``explained``: a reproduced engine behaviour (the catalogue) makes the difference disappear;
* ``finding``: the file's own fault (a body that is not physical, :mod:`relacc.reading.physical`), which each engine
  reads its own way;
* ``taken``: relacc took that element from the engine (a mesh's mass properties from MuJoCo): it cannot judge it;
* ``urdf``: the URDF given for Pinocchio and the MJCF describe the element differently;
* ``singular``: a mass matrix singular over the shared speeds leaves the forward dynamics undefined;
* ``not explained``: nothing known reproduces it; the place says where to look.

:data:`READINGS` holds known engine behaviours as changes to relacc's own reading (:class:`relacc.reading.Reading`),
so that they apply whichever engine reads the file, MuJoCo included: each ``(key, text, applies(reading),
change(reading) -> Reading)``; the audit applies those that apply and takes ``text`` as the cause of the differences
that disappear. (Readings of the MJCF parsers of Pinocchio and Drake written as changes to MuJoCo's spec stay in each
adapter's ``MJCF_READINGS``; they need MuJoCo to read the file.)
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from relacc.core.tree.model import Tree

KINDS = ("explained", "finding", "taken", "urdf", "singular", "not explained")


@dataclass(frozen=True)
class Cause:
    """Why a difference is there: ``kind`` (one of :data:`KINDS`), ``text``, ``place`` (``file:line`` or empty)."""

    kind: str
    text: str
    place: str = ""

    def __str__(self) -> str:
        return self.text + (f" (see {self.place})" if self.place else "")

    @property
    def explained(self) -> bool:
        return self.kind != "not explained"


def _bodies(reading, change):
    """``reading`` with each body replaced by ``change(body)`` (None keeps it)."""
    bodies = tuple(change(b) or b for b in reading.tree.bodies)
    t = reading.tree
    return replace(reading, tree=Tree(t.name, bodies, gravity=t.gravity, points=t.points, source=t.source))


def _massless_with_inertia(reading) -> bool:
    return any(b.mass == 0 and np.any(b.inertia != 0) for b in reading.tree.bodies)


def _drop_massless_inertia(reading):
    return _bodies(reading, lambda b: replace(b, inertia=np.zeros((3, 3))) if b.mass == 0 else None)


def _massless_get_a_kilogram(reading):
    return _bodies(reading, lambda b: replace(b, mass=1.0) if b.mass == 0 and np.any(b.inertia != 0) else None)


def _urdf_inertial_turned(reading) -> bool:
    """A URDF whose inertials are turned (``rpy``): what MuJoCo up to 3.17 misreads (google-deepmind/mujoco#3559)."""
    return reading.format == "urdf" and bool(reading.turned_inertials)


def _unturned_inertials(reading):
    """Each turned inertial as if its ``rpy`` were zero: the inertia as written, in the link's axes."""
    return _bodies(reading, lambda b: replace(b, inertia=reading.turned_inertials[b.name])
                   if b.name in reading.turned_inertials else None)


READINGS = {
    "mujoco": (
        ("massless_inertia", "the file gives a body no mass but an inertia (a finding); MuJoCo's compiler drops the "
         "inertia of a massless body", _massless_with_inertia, _drop_massless_inertia),
        ("urdf_inertial_rotation", "MuJoCo's URDF reader drops the rotation of an <inertial>'s <origin rpy> "
         "(google-deepmind/mujoco#3559, fixed by pull request #3560): it takes the inertia as if written in the link's "
         "axes",
         _urdf_inertial_turned, _unturned_inertials),
    ),
    "pinocchio": (),
    "drake": (
        ("massless_kilogram", "the file gives a body no mass but an inertia (a finding); Drake's URDF parser gives "
         "such a link a mass of 1 kg", lambda r: r.format == "urdf" and _massless_with_inertia(r),
         _massless_get_a_kilogram),
    ),
}
"""Known engine behaviours as changes to relacc's reading (module docstring), per engine."""

