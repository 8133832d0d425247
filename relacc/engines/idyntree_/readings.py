"""How iDynTree reads a URDF differently from the specification, as changes to relacc's reading (imports no engine).

* **A massless leaf link on a fixed joint becomes a frame** of the link it is welded to ("additional frame"), so an
  inertia it carries without a mass is dropped (a massless link with a link below it stays: genesis' Panda, whose
  massless ``panda_link8`` holds the hand) (example-robot-data's bolt: its feet, mass 0 and an inertia; the same
  thing MuJoCo's fusion does). Measured with idyntree 15.1.0: a root ``world`` link turned into a frame of the robot's
  first link is handled in the adapter (the base is held so that the frame sits at the world's origin).
* **A link's repeated ``<inertia>`` or ``<inertial>``: the last** (deep_robotics' Lite3 in
  fiveages-sim/robot_descriptions ``f609e7f``: 8 links with two ``<inertia>``, whose products of inertia differ in
  sign; mani_skill 3.0.1's TriFinger Pro: its fingertips have two ``<inertial>``), where urdfdom, Pinocchio and Drake
  read the first.

No difference in its algorithms is known (:data:`ENGINE_READINGS`). What it was tried on is in docs/compare.md.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from relacc.engines.base import KnownBehaviour
from relacc.engines.known import reread, with_bodies


def _fake_links(reading) -> set:
    """The names of the links iDynTree makes frames: massless, on a fixed joint, with an inertia, and leaves (no link
    below them: measured on idyntree 15.1.0, a massless link between two others stays a link with its inertia, and
    one made a leaf only by another's removal stays too)."""
    bodies = reading.tree.bodies
    parents = {b.parent for b in bodies}
    return {b.name for k, b in enumerate(bodies)
            if k not in parents and b.mass == 0 and not b.joints and np.any(b.inertia != 0)}


def _welded_massless_with_inertia(reading) -> bool:
    return bool(_fake_links(reading))


def _as_frames(reading):
    fake = _fake_links(reading)
    return with_bodies(reading, lambda b: replace(b, inertia=np.zeros((3, 3))) if b.name in fake else None)


FILE_READINGS = (
    KnownBehaviour(
        "massless_link_a_frame",
        "iDynTree's URDF parser makes a massless leaf link on a fixed joint a frame of the link it is welded to, "
        "dropping the inertia the file gives it without a mass",
        _welded_massless_with_inertia,
        _as_frames,
    ),
    KnownBehaviour(
        "last_inertia",
        "iDynTree's URDF parser reads the last of a link's repeated <inertial> or <inertia> elements (urdfdom, "
        "Pinocchio and Drake the first; MuJoCo refuses the file)",
        lambda r: r.format == "urdf" and bool(r.facts.get("repeated_inertia")),
        reread("last_inertia"),
    ),
)
"""iDynTree's known readings of a URDF."""

ENGINE_READINGS: tuple = ()
"""No known difference in iDynTree's algorithms."""
