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

import threading
import weakref
from dataclasses import dataclass

import numpy as np

from relacc.core.tree.model import welded_folded
from relacc.kernels.jit import HAVE_NUMBA, parallel_pays, split
from relacc.kernels.tree import arrays_of, writable
from relacc.kernels.tree_crba import BLOCK, dof_paths
from relacc.kernels.tree_spatial import inertia_arrays

ABA_FROM = 100.0
"""``sum_k d_k^2 / (2 nv)`` above which the articulated-body algorithm is faster (measured on hinge chains: the
two meet near 25 speeds, where this is about 100)."""

US_PER_SPEED = 0.14
"""About the forward dynamics' cost per state and per speed on one core, in us (gymnasium's ant 1.8 us for 14 speeds,
humanoid 3.2 us for 23, a 30-link chain 6.0 us for 35: ``trees-2026-11-25-run{8,9,10}``): what
:func:`relacc.kernels.jit.parallel_pays` weighs."""

_PLANS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


@dataclass(frozen=True, eq=False)
class TreePlan:
    """What the compiled dynamics of one tree needs besides the states, computed once per tree (:func:`plan`).

    Attributes:
        method: ``"crba"`` or ``"aba"``, the algorithm chosen for the tree's shape.
        anc: ``(nv, width)`` each speed's ancestor speeds (-1 padded). depth: ``(nv,)`` their counts.
        mass: ``(nb,)`` kg. com: ``(nb, 3)`` m, body components. inertia: ``(nb, 9)`` kg m^2 about the mass centre,
            body components. armature: ``(nv,)``. free: ``(nb,)`` bool, bodies on a free joint.
    """

    method: str
    anc: np.ndarray
    depth: np.ndarray
    mass: np.ndarray
    com: np.ndarray
    inertia: np.ndarray
    armature: np.ndarray
    free: np.ndarray

    def arrays(self) -> tuple:
        """``(anc, depth, mass, com, inertia, armature, free)`` in the compiled kernels' argument order."""
        return self.anc, self.depth, self.mass, self.com, self.inertia, self.armature, self.free


def plan(tree) -> TreePlan:
    """The tree's :class:`TreePlan`, computed once per tree."""
    if tree not in _PLANS:
        anc, depth = dof_paths(tree)
        work = float(np.sum(depth.astype(float) ** 2) / (2 * max(tree.nv, 1)))
        _PLANS[tree] = TreePlan("aba" if work > ABA_FROM else "crba", anc, depth, *inertia_arrays(tree))
    return _PLANS[tree]


def method(tree) -> str:
    """``"crba"`` or ``"aba"``: the algorithm :func:`accelerations` uses for this tree."""
    return plan(welded_folded(tree)).method


def accelerations(tree, case: int, q, u, tau, gravity, out=None, algorithm: str | None = None):
    """``udot`` of checked-shape, C-contiguous float64 ``(n, .)`` inputs (into ``out`` if given).

    ``algorithm``: ``"lanes"``, ``"crba"`` or ``"aba"`` to force one. By default :func:`method`'s algorithm traced
    and compiled over several states at once (:mod:`relacc.kernels.lanes`) where it is available (llvmlite, a tree
    within :data:`relacc.kernels.lanes.MAX_OPS`), else the same algorithm's numba kernel. Case 3 is solved in
    case-2 speeds on its own coordinates and mapped to the rates, state by state inside the kernel
    (:func:`relacc.kernels.tree_spatial.row_to_speeds`, :func:`~relacc.kernels.tree_spatial.row_to_rates`): its
    error is ``cond(W)`` times case 2's, where Kane's equations in the rates would have it squared. The kernels run
    on the tree with its welded bodies folded into their parents (:func:`relacc.core.tree.model.welded_folded`).

    Returns:
        ``(udot (n, nv), n_bad_inputs, n_singular, n_ill)``: the counts of states with non-finite inputs or non-unit
        quaternions, of states whose equations are singular (their rows are NaN), and of states answered with a mass
        matrix conditioned beyond :data:`relacc.core.tolerances.MASS_CONDITION_WARNING`; callers check and name them.
    """
    n = q.shape[0]
    out = np.empty((n, tree.nv)) if out is None else out
    lane = _lanes(tree, case, algorithm)
    if lane is not None:
        args = (writable(q), writable(u), writable(tau), writable(np.asarray(gravity, dtype=float)), out)
        lane.will_run(n)
        serial = not parallel_pays(n, LANES_US_PER_SPEED * tree.nv, BLOCK)
        bad_in, singular, ill = lane.block(*args, 0, n) if serial else split(lane.block, args, n, BLOCK)
        return out, int(bad_in), int(singular), int(ill)
    fn, args = _block_call(tree, case, algorithm, writable(q), writable(u), writable(tau), writable(gravity), out)
    serial = not parallel_pays(n, US_PER_SPEED * tree.nv, BLOCK)
    bad_in, singular, ill = fn(*args, 0, n) if serial else split(fn, args, n, BLOCK)
    return out, int(bad_in), int(singular), int(ill)


LANES_US_PER_SPEED = 0.025
"""The lanes' cost per state and per speed on one core, in us (gymnasium's ant 0.32 us for 14 speeds, humanoid 0.6 us
for 23: ``trees-2026-11-25-run18``), what :func:`relacc.kernels.jit.parallel_pays` weighs for them."""


def _lanes(tree, case, algorithm):
    """The tree's :class:`relacc.kernels.lanes.Kernel` for ``case`` when ``algorithm`` asks for it or leaves the choice
    (None where it is not available and not asked for by name)."""
    if algorithm not in (None, "lanes"):
        return None
    from relacc.kernels import lanes

    folded = welded_folded(tree)
    lane = lanes.kernel(folded, int(case), plan(folded).method)
    if lane is None and algorithm == "lanes":
        raise ValueError(f"the lanes kernel is not available for tree {tree.name!r} (llvmlite, its size)")
    return lane


def optimize(tree, case: int) -> None:
    """The tree's lanes kernel for ``case`` at its fastest now (LLVM's ``-O2``, :data:`relacc.kernels.lanes.
    UPGRADE_STATES`) rather than after 100,000 states: the same bits. What a benchmark of the steady state calls
    before timing; nothing where the lanes do not run the tree."""
    lane = _lanes(tree, case, None)
    if lane is not None:
        lane.optimize()


def algorithm_used(tree, case: int) -> str:
    """``"lanes"``, ``"crba"`` or ``"aba"``: what :func:`accelerations` runs for this tree and case by default."""
    return "lanes" if _lanes(tree, case, None) is not None else method(tree)


def _block_call(tree, case, algorithm, q, u, tau, gravity, out):
    """``(block function, its arguments but the states' range)``: the algorithm (``algorithm``, else the plan's) on
    the folded tree's arrays (:func:`relacc.core.tree.model.welded_folded`: the same joints and speeds, fewer
    bodies)."""
    folded = welded_folded(tree)
    T, p = arrays_of(folded), plan(folded)
    anc, depth, mass, com, inertia, arm, free = p.arrays()
    qadr = T.qadr3 if case >= 3 else T.qadr
    if (algorithm or p.method) == "aba":
        from relacc.kernels.tree_aba import aba_block

        return aba_block, (int(case), q, u, tau, T, qadr, mass, com, inertia, arm, free, gravity, out)
    from relacc.kernels.tree_crba import crba_block

    return crba_block, (int(case), q, u, tau, T, qadr, anc, depth, mass, com, inertia, arm, free, gravity, out)


def one_state(tree, case: int, q, u, gravity):
    """``(udot (nv,), bad input, singular, ill-conditioned)`` of one state ``q (nq,)``, ``u (nv,)`` (float64, shapes
    checked by the caller), no applied forces: the single-state lane of :func:`relacc.tree_accelerations`, on the
    calling thread with the kernel's arguments gathered once per tree, case, gravity and thread (:func:`_single`), so
    that a call costs the kernel and little else."""
    fn, args, Q, U, out = _single(tree, case, gravity)
    Q[0], U[0] = q, u
    bad_in, singular, ill = fn(*args)
    return out[0].copy(), bad_in, singular, ill


def _single(tree, case, gravity):
    """``(block function, its arguments, q (1, nq), u (1, nv), out (1, nv))``: buffers and arguments of the block
    function for one state, cached per tree, case, gravity and thread (each thread writes its own buffers); the
    tree's own gravity is keyed without reading it (a call's fixed cost is what this lane is for)."""
    grav = None if gravity is tree.gravity else bytes(np.asarray(gravity, dtype=float))
    key = (case, grav, threading.get_ident())
    cache = _SINGLE.get(tree)
    if cache is None:
        cache = _SINGLE[tree] = {}
    if key not in cache:
        Q, U, tau, out = np.zeros((1, tree.nq_in(case))), np.zeros((1, tree.nv)), np.zeros((1, tree.nv)), \
            np.zeros((1, tree.nv))
        lane = _lanes(tree, case, None)
        if lane is not None:  # the compiled function on the buffers' addresses: a call is the kernel and ctypes
            g, bad = np.array(gravity, dtype=float), np.zeros(2, np.int64)
            keep = (Q, U, tau, g, out, bad)
            fn = _ZeroingCall(lane, bad, keep)
            cache[key] = (fn, tuple(a.ctypes.data for a in keep[:5]) + (bad, 0, 1), Q, U, out)
            return cache[key]
        fn, args = _block_call(tree, case, None, Q, U, tau, np.array(gravity, dtype=float), out)
        args = args + (0, 1)
        cache[key] = (_entry_point(fn, args), args, Q, U, out)
    return cache[key]


class _ZeroingCall:
    """The lanes kernel's compiled function for one state on fixed buffers: counts the state
    (:meth:`relacc.kernels.lanes.Kernel.will_run`), zeroes the bad-input and ill-conditioned counts, passes their
    address (the arguments' sixth is the counts' array), keeps the buffers alive as long as the call is cached, and
    returns ``(bad inputs, singular, ill-conditioned)`` as the numba block function does."""

    __slots__ = ("lane", "bad", "at", "keep")

    def __init__(self, lane, bad, keep):
        self.lane, self.bad, self.at, self.keep = lane, bad, bad.ctypes.data, keep

    def __call__(self, q, u, tau, g, out, _bad, start, stop):
        self.lane.will_run(1)
        self.bad[0] = self.bad[1] = 0
        singular = self.lane.fn(q, u, tau, g, out, self.at, start, stop)
        return int(self.bad[0]), singular, int(self.bad[1])


def _entry_point(fn, args):
    """The compiled function of a numba dispatcher for these arguments' types, called without dispatch (which costs
    about 3 us of the 9 a single state's call takes, measured on gymnasium's ant); the dispatcher itself without
    numba or where the compiled function cannot be found."""
    if not HAVE_NUMBA:
        return fn
    fn(*args)  # compiles or loads the specialization
    compiled = getattr(fn, "overloads", {}).get(tuple(fn.typeof_pyval(a) for a in args))
    return getattr(compiled, "entry_point", fn)


_SINGLE: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


__all__ = ["ABA_FROM", "accelerations", "algorithm_used", "method", "one_state", "optimize", "plan"]
