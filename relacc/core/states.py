"""Seeded random states of the chain, for tests, ``relacc check`` and the report."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from relacc.core.cases import Case, as_case, check_int

if TYPE_CHECKING:
    from relacc.core.tree import Tree


@dataclass(frozen=True)
class States:
    """A batch of states of one case, of the chain or of a model's tree: the one kind of states relacc draws.

    Attributes:
        case: the choice of generalized speeds (a model's case 2 is MuJoCo's ``qpos``/``qvel``).
        q: ``(n, nq)`` coordinates (the chain: ``(n, 14)`` or ``(n, 12)``; m, unit quaternions or rad).
        u: ``(n, nv)`` speeds (m/s, rad/s). udot: ``(n, nv)`` their rates.
        seed: the seed they were drawn with, an int or a list of ints given
            to ``numpy.random.default_rng`` (print it when a check fails).
        tree: the :class:`relacc.Tree` they are states of, or None for the note's chain.
    """

    case: Case
    q: np.ndarray
    u: np.ndarray
    udot: np.ndarray
    seed: int | list
    tree: "Tree | None" = None

    def __len__(self) -> int:
        return self.q.shape[0]

    def and_then(self, other: "States", seed) -> "States":
        """These states followed by ``other``'s (one case, one tree), drawn with ``seed``."""
        q, u, udot = (np.concatenate([getattr(self, k), getattr(other, k)]) for k in ("q", "u", "udot"))
        return States(self.case, q, u, udot, seed, self.tree)

    def frozen(self) -> "States":
        """The same states with read-only arrays (what a cache hands out: a test that changes them copies first)."""
        q, u, udot = (np.array(a) for a in (self.q, self.u, self.udot))
        for a in (q, u, udot):
            a.setflags(write=False)
        return States(self.case, q, u, udot, self.seed, self.tree)


def random_unit_quaternions(rng: np.random.Generator, n: int) -> np.ndarray:
    """``(n, 4)`` quaternions uniform on SO(3) (normalized Gaussians), both signs of ``w``."""
    quat = rng.normal(size=(n, 4))
    return quat / np.linalg.norm(quat, axis=-1, keepdims=True)


def random_states(case, n: int, seed) -> States:
    """``n`` states of ``case`` drawn from ``numpy.random.default_rng(seed)``.

    Distributions: ``s1 ~ N(0, 1 m)``, ``s2' ~ N(0, 0.2 m)``, orientations
    uniform on SO(3) (cases 1-2) or angles uniform in ``(-pi, pi)`` (case 3),
    speeds ``N(0, 1)`` in m/s and rad/s, their rates ``N(0, 1)``.
    """
    c = as_case(case)
    n = check_int("n", n, minimum=0)
    rng = np.random.default_rng(seed)
    s1 = rng.normal(size=(n, 3))
    s2 = 0.2 * rng.normal(size=(n, 3))
    if c is Case.ANGLE_RATES:
        q = np.concatenate([s1, rng.uniform(-np.pi, np.pi, (n, 3)), s2, rng.uniform(-np.pi, np.pi, (n, 3))], -1)
    else:
        q = np.concatenate([s1, random_unit_quaternions(rng, n), s2, random_unit_quaternions(rng, n)], -1)
    u = rng.normal(size=(n, 12))
    udot = rng.normal(size=(n, 12))
    return States(c, q, u, udot, seed)
