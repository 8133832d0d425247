"""What a test holds a value to: one quantity's reference values over a batch, with what judging them needs."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True, eq=False)
class Expected:
    """One quantity's reference values over a batch, with what judging them needs.

    Attributes:
        quantity: ``position``, ``velocity``, ``acceleration``, ``V`` or ``Vdot`` (G2, fixed-frame
            components; classical acceleration; units as :class:`relacc.G2Kinematics`).
        case: the case of the states (names the columns of V and Vdot).
        values: ``(n, 3)`` or ``(n, 3, 12)`` reference values.
        scale: ``(n,)`` magnitude of the terms of each state (:func:`relacc.core.scales.term_scales`).
        bound: ``(n,)`` the reference's own accuracy bound (normalized), e.g. an engine far from the origin.
        seed: the states' seed; source: who computed the values (``mujoco/quaternion``, ``relacc``).
        labels: for a model's bodies, their names (the ``nb`` axis after the states); empty for the chain's G2.
    """

    quantity: str
    case: int
    values: np.ndarray = field(repr=False)
    scale: np.ndarray = field(repr=False)
    bound: np.ndarray = field(repr=False)
    seed: object
    source: str
    labels: tuple = ()

    def __array__(self, dtype=None, copy=None):
        return np.asarray(self.values, dtype=dtype)

    @property
    def shape(self):
        return self.values.shape


__all__ = ["Expected"]
