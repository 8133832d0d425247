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

import ctypes
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


def _lanes(tree, case, algorithm, width=None):
    """The tree's :class:`relacc.kernels.lanes.Kernel` for ``case`` over ``width`` states a step (default the CPU's
    vector) when ``algorithm`` asks for it or leaves the choice (None where it is not available and not asked for by
    name)."""
    if algorithm not in (None, "lanes"):
        return None
    from relacc.kernels import lanes

    folded = welded_folded(tree)
    lane = lanes.kernel(folded, int(case), plan(folded).method, width)
    if lane is None and algorithm == "lanes":
        raise ValueError(f"the lanes kernel is not available for tree {tree.name!r} (llvmlite, its size)")
    return lane


def optimize(tree, case: int) -> None:
    """The tree's lanes kernel for ``case`` at its fastest now (LLVM's ``-O2``, :data:`relacc.kernels.lanes.
    UPGRADE_STATES`) rather than after 100,000 states: the same bits. What a benchmark of the steady state calls
    before timing: the batch's kernel and the single-state lane's (one lane); nothing where the lanes do not run the
    tree."""
    for width in (None, 1):
        lane = _lanes(tree, case, None, width)
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
    """``udot (nv,)`` (m/s^2, rad/s^2) of one state ``q (nq,)``, ``u (nv,)`` in case 1 or 2, no applied forces, gravity
    ``(3,)`` m/s^2 in world components; or None where the state is not plain (not a float64 row of the case's size,
    a bad input, singular or ill-conditioned equations, a non-finite answer: the general path then says what is
    wrong). The single-state lane of :func:`relacc.tree_accelerations`, on the calling thread (:func:`single`)."""
    return single(tree, case, gravity)(q, u)


def single(tree, case: int, gravity):
    """The callable ``(q, u) -> udot or None`` of :func:`one_state` for this tree, case (1 or 2) and gravity on the
    calling thread, with its buffers and arguments gathered once (each thread writes its own), cached; the tree's own
    gravity is keyed without reading it (a call's fixed cost is what this lane is for). Once the lanes kernel runs its
    ``-O2`` code, the callable is a builtin whose checks, copies and call are compiled (:func:`_direct`)."""
    grav = None if gravity is tree.gravity else bytes(np.asarray(gravity, dtype=float))
    key = (case, grav, threading.get_ident())
    cache = SINGLE.get(tree)
    if cache is None:
        cache = SINGLE[tree] = {}
    one = cache.get(key)
    if one is None:
        lane = _lanes(tree, case, None, width=1)
        one = cache[key] = (_OneBlock(tree, case, gravity) if lane is None
                            else _direct(lane, tree.nq_in(case), tree.nv, gravity)
                            or _OneLane(lane, tree.nq_in(case), tree.nv, gravity, (cache, key)))
    return one


def _direct(lane, nq: int, nv: int, gravity):
    """The lane's compiled single-state entry point called from CPython directly (:func:`relacc.kernels.direct.builtin`:
    checks, copies and call compiled), once the lane runs its ``-O2`` code (before that, :class:`_OneLane` counts the
    states that decide the upgrade); None before, or where the builtin cannot be made."""
    if lane.level != 2:
        return None
    from relacc.kernels.direct import builtin

    address = ctypes.cast(lane.one, ctypes.c_void_p).value
    return None if address is None else builtin(address, nq, nv, gravity, lane)


class _OneLane:
    """One state through the lanes kernel's single-state entry point (:meth:`relacc.kernels.lanes.Kernel.run_one`):
    the state copied into a buffer laid out as that entry point reads it, one ctypes argument, the answer copied
    out. Once the kernel runs its ``-O2`` code, it puts :func:`_direct`'s builtin in its place in the cache
    (``slot``: the cache and key)."""

    __slots__ = ("kernel", "buf", "q", "u", "out", "at", "shapes", "slot", "gravity")

    def __init__(self, kernel, nq: int, nv: int, gravity, slot=None):
        self.kernel, self.buf, self.shapes, self.slot = kernel, np.zeros(nq + 3 * nv + 3), ((nq,), (nv,)), slot
        self.gravity = gravity
        self.q, self.u, self.out = self.buf[:nq], self.buf[nq:nq + nv], self.buf[nq + 2 * nv + 3:]
        self.buf[nq + 2 * nv:nq + 2 * nv + 3] = gravity
        self.at = self.buf.ctypes.data

    def __call__(self, q, u):
        if not _plain(q, u, self.shapes):
            return None
        self.q[...] = q
        self.u[...] = u
        flags = self.kernel.run_one(self.at)
        if self.slot is not None and self.kernel.level == 2:
            cache, key = self.slot
            cache[key], self.slot = _direct(self.kernel, len(self.q), len(self.u), self.gravity) or self, None
        if flags:
            return None
        res = self.out.copy()
        res.setflags(write=False)
        return res


class _OneBlock:
    """One state through the numba block function (a tree beyond the lanes), its compiled function called without
    dispatch (:func:`_entry_point`)."""

    __slots__ = ("fn", "args", "Q", "U", "out", "shapes")

    def __init__(self, tree, case, gravity):
        self.shapes = ((tree.nq_in(case),), (tree.nv,))
        self.Q, self.U, tau, self.out = (np.zeros((1, tree.nq_in(case))), np.zeros((1, tree.nv)),
                                         np.zeros((1, tree.nv)), np.zeros((1, tree.nv)))
        fn, args = _block_call(tree, case, None, self.Q, self.U, tau, np.array(gravity, dtype=float), self.out)
        self.args = args + (0, 1)
        self.fn = _entry_point(fn, self.args)

    def __call__(self, q, u):
        if not _plain(q, u, self.shapes):
            return None
        self.Q[0], self.U[0] = q, u
        bad_in, singular, ill = self.fn(*self.args)
        res = self.out[0].copy()
        if bad_in or singular or ill or not np.isfinite(res).all():
            return None
        res.setflags(write=False)
        return res


def _plain(q, u, shapes) -> bool:
    """``q`` and ``u`` are float64 arrays of exactly ``shapes``: one state the single-state lane takes as it is."""
    return (type(q) is np.ndarray and type(u) is np.ndarray and q.dtype is _F64 and u.dtype is _F64
            and (q.shape, u.shape) == shapes)


_F64 = np.dtype(np.float64)


def _entry_point(fn, args):
    """The compiled function of a numba dispatcher for these arguments' types, called without dispatch (which costs
    about 3 us of the 9 a single state's call takes, measured on gymnasium's ant); the dispatcher itself without
    numba or where the compiled function cannot be found."""
    if not HAVE_NUMBA:
        return fn
    fn(*args)  # compiles or loads the specialization
    compiled = getattr(fn, "overloads", {}).get(tuple(fn.typeof_pyval(a) for a in args))
    return getattr(compiled, "entry_point", fn)


SINGLE: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()
"""Per tree, ``{(case, gravity's key, thread): the single-state callable}`` (:func:`single`; the key of the tree's own
gravity is None): where :func:`relacc.tree_accelerations` finds a lane in two lookups."""


__all__ = ["ABA_FROM", "SINGLE", "accelerations", "algorithm_used", "method", "one_state", "optimize", "plan",
           "single"]
