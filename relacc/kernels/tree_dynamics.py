"""Compiled forward dynamics of a tree in any case: the fast path of :func:`relacc.tree_accelerations`.

Two algorithms on one spatial pass (:mod:`~relacc.kernels.tree_spatial`), chosen per tree by the work each needs:
composite rigid bodies with ``L^T D L`` (:mod:`~relacc.kernels.tree_crba`, O(n d^2): the faster one for shallow
trees such as gymnasium's ant and humanoid) and the articulated-body algorithm (:mod:`~relacc.kernels.tree_aba`,
O(n): the faster one for deep chains). :func:`method` picks ABA when the factorization's work per speed,
``sum_k d_k^2 / (2 nv)`` (``d_k`` the speeds before speed ``k`` on its path), exceeds :data:`ABA_FROM`, the crossover
measured on chains (``docs/benchmarks.md``). Both agree with Kane's equations of :mod:`relacc.dynamics.tree` to
rounding (``tests/test_tree_kernels.py``).
"""

from __future__ import annotations

import weakref

import numpy as np

from relacc.kernels.tree import arrays_of, writable
from relacc.kernels.tree_crba import dof_paths
from relacc.kernels.tree_spatial import inertia_arrays

ABA_FROM = 100.0
"""``sum_k d_k^2 / (2 nv)`` above which the articulated-body algorithm is faster (measured on hinge chains: the
two meet near 25 speeds, where this is about 100)."""

_PLANS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def plan(tree):
    """``(method, anc, depth, mass, com, inertia, armature, free)`` of a tree, computed once per tree."""
    if tree not in _PLANS:
        anc, depth = dof_paths(tree)
        work = float(np.sum(depth.astype(float) ** 2) / (2 * max(tree.nv, 1)))
        _PLANS[tree] = ("aba" if work > ABA_FROM else "crba", anc, depth, *inertia_arrays(tree))
    return _PLANS[tree]


def method(tree) -> str:
    """``"crba"`` or ``"aba"``: the algorithm :func:`accelerations` uses for this tree."""
    return plan(tree)[0]


def accelerations(tree, case: int, q, u, tau, gravity, out=None, algorithm: str | None = None):
    """``udot`` of checked-shape, C-contiguous float64 ``(n, .)`` inputs (into ``out`` if given).

    ``algorithm``: ``"crba"`` or ``"aba"`` to force one (default: :func:`method`).

    Returns:
        ``(udot (n, nv), n_bad_inputs, n_singular)``: the counts of states with non-finite inputs or non-unit
        quaternions, and of states whose equations are singular (their rows are NaN); callers check and name them.
    """
    T = arrays_of(tree)
    chosen, anc, depth, mass, com, inertia, arm, free = plan(tree)
    algorithm = chosen if algorithm is None else algorithm
    n = q.shape[0]
    out = np.empty((n, tree.nv)) if out is None else out
    qadr = T.qadr3 if case == 3 else T.qadr
    if algorithm == "aba":
        from relacc.kernels.tree_aba import aba_loop

        bad_in, singular = aba_loop(int(case), writable(q), writable(u), writable(tau), T, qadr, mass, com, inertia,
                                    arm, free, writable(gravity), out)
    else:
        from relacc.kernels.tree_crba import crba_loop

        bad_in, singular = crba_loop(int(case), writable(q), writable(u), writable(tau), T, qadr, anc, depth, mass,
                                     com, inertia, arm, free, writable(gravity), out)
    return out, int(bad_in), int(singular)


__all__ = ["ABA_FROM", "accelerations", "method", "plan"]
