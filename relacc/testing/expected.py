"""What a test holds a value to: one quantity's reference values over a batch, with what judging them needs."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from relacc.errors import InputError


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


@dataclass(frozen=True, eq=False)
class Truth:
    """An evaluator's reference values for a batch of states, each quantity an :class:`Expected`: the chain's G2
    (:func:`relacc.testing.truth.truth`) or every body of a model (:func:`relacc.testing.trees.model_truth`,
    ``(n, nb, ...)``). ``truth.velocity`` is ``truth.of("velocity")``.

    Attributes:
        source: who computed the values (``mujoco/quaternion``, ``relacc``). states: the
            :class:`relacc.core.states.States` evaluated. quantities: ``{name: Expected}``, what the evaluator gives for
            the case.
    """

    source: str
    states: Any = field(repr=False)
    quantities: dict = field(repr=False)

    def of(self, quantity: str) -> Expected:
        """One quantity's :class:`Expected`.

        Raises:
            InputError: a quantity the evaluator does not give for the case, naming those it gives.
        """
        if quantity not in self.quantities:
            raise InputError(f"{self.source} gives no {quantity!r} for case {int(self.states.case)}; it gives "
                             f"{', '.join(self.quantities)}")
        return self.quantities[quantity]

    def __getattr__(self, name: str) -> Expected:
        quantities = self.__dict__.get("quantities", {})  # not self.quantities: no recursion before it is set
        if name in quantities:
            return quantities[name]
        raise AttributeError(name)


__all__ = ["Expected", "Truth"]
