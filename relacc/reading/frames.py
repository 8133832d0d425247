"""Frames as the description formats define them: positions and every orientation form, as rotation matrices.

A rotation matrix ``R`` here maps a child frame's components to its parent's (``v_parent = R v_child``); in the
note's notation that is ``[R_B]^T`` of the child. Formats' own definitions:

* URDF ``rpy``: fixed-axis roll, pitch, yaw, ``R = Rz(yaw) Ry(pitch) Rx(roll)``;
* MJCF ``quat``: ``(w, x, y, z)``, normalized by the compiler; ``axisangle``: a unit axis (normalized) and an angle;
  ``euler``: three angles about the axes of ``<compiler eulerseq>``, a lower-case axis turning with the frame
  (intrinsic), an upper-case one fixed (extrinsic); ``xyaxes``: the frame's x axis, then its y axis made orthogonal
  to x, both normalized, ``z = x cross y``; ``zaxis``: the frame's z axis, the rotation the shortest one taking
  ``(0, 0, 1)`` to it; angles in degrees unless ``<compiler angle="radian">``.

A quaternion or axis that the format normalizes is normalized here too, and counted (:class:`Normalized`), so that
the reading says how far from unit the file's were: nothing is adjusted without a word.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from relacc.core.rotations import matrix_from_quaternion, quaternion_from_matrix
from relacc.core.tolerances import QUATERNION_NORM_TOLERANCE
from relacc.errors import ModelError


@dataclass
class Normalized:
    """What was normalized as the format specifies: counts and the largest ``| |x|^2 - 1 |`` of each kind."""

    counts: dict = field(default_factory=dict)
    worst: dict = field(default_factory=dict)

    def unit(self, what: str, x, place: str) -> np.ndarray:
        """``x / |x|``; counted when ``x`` was not unit to :data:`QUATERNION_NORM_TOLERANCE`.

        Raises:
            ModelError: ``x`` is zero (no direction).
        """
        x = np.asarray(x, dtype=float)
        norm2 = float(x @ x)
        if norm2 == 0.0:
            raise ModelError(f"{place}: a zero {what}: it has no direction")
        off = abs(norm2 - 1.0)
        if off > QUATERNION_NORM_TOLERANCE:
            self.counts[what] = self.counts.get(what, 0) + 1
            self.worst[what] = max(self.worst.get(what, 0.0), off)
        return x / np.sqrt(norm2)

    def notes(self, fmt: str) -> list[str]:
        return [f"{n} {plural(what) if n > 1 else what} not unit in the file (largest | |x|^2 - 1 | "
                f"{self.worst[what]:.2g}): normalized, as {fmt} specifies" for what, n in self.counts.items()]


def plural(noun: str) -> str:
    """English plural of the nouns relacc's notes count: ``joint axis`` -> ``joint axes``, ``quaternion`` ->
    ``quaternions``."""
    if noun.endswith("axis"):
        return noun[:-4] + "axes"
    return noun + ("es" if noun.endswith(("s", "x", "sh", "ch")) else "s")


def axis_angle(axis, angle: float) -> np.ndarray:
    """The rotation by ``angle`` (rad) about the unit ``axis``."""
    x, y, z = axis
    c, s = np.cos(angle), np.sin(angle)
    C = 1.0 - c
    return np.array([[c + x * x * C, x * y * C - z * s, x * z * C + y * s],
                     [y * x * C + z * s, c + y * y * C, y * z * C - x * s],
                     [z * x * C - y * s, z * y * C + x * s, c + z * z * C]])


E = np.eye(3)


def rpy(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """URDF's fixed-axis roll, pitch, yaw: ``Rz(yaw) Ry(pitch) Rx(roll)``."""
    return axis_angle(E[2], yaw) @ axis_angle(E[1], pitch) @ axis_angle(E[0], roll)


def euler(sequence: str, angles) -> np.ndarray:
    """MJCF's ``euler`` for ``<compiler eulerseq>`` (module docstring): each lower-case axis turns with the frame
    (multiplied on the right), each upper-case one is fixed (on the left)."""
    R = np.eye(3)
    for axis, angle in zip(sequence, angles):
        Ri = axis_angle(E["xyz".index(axis.lower())], angle)
        R = R @ Ri if axis.islower() else Ri @ R
    return R


def xyaxes(values, normalized: Normalized, place: str) -> np.ndarray:
    """MJCF's ``xyaxes``: columns x, y (made orthogonal to x), z = x cross y."""
    x = normalized.unit("xyaxes x axis", values[:3], place)
    y = np.asarray(values[3:], dtype=float)
    y = y - (x @ y) * x
    y = normalized.unit("xyaxes y axis", y, place)
    return np.column_stack([x, y, np.cross(x, y)])


def zaxis(values, normalized: Normalized, place: str) -> np.ndarray:
    """MJCF's ``zaxis``: the shortest rotation taking ``(0, 0, 1)`` to the (normalized) axis."""
    z = normalized.unit("zaxis", values, place)
    axis = np.cross(E[2], z)
    s, c = float(np.linalg.norm(axis)), float(z[2])
    if s == 0.0:
        return np.eye(3) if c > 0 else axis_angle(E[0], np.pi)
    return axis_angle(axis / s, np.arctan2(s, c))


def quaternion(values, normalized: Normalized, place: str) -> np.ndarray:
    """The rotation of a quaternion ``(w, x, y, z)`` (normalized as MJCF specifies)."""
    return matrix_from_quaternion(normalized.unit("quaternion", values, place))


def quaternion_of(R) -> np.ndarray:
    """A unit quaternion ``(w, x, y, z)``, ``w >= 0``, of a rotation matrix (child to parent): the core's
    (:func:`relacc.core.rotations.quaternion_from_matrix`; scipy's ``Rotation`` gives the same within an ulp, but
    importing ``scipy.spatial`` took 0.47 s of every reading, about a tenth of a ``compare``)."""
    return quaternion_from_matrix(R)
