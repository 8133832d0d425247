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

from relacc.kernels.jit import HAVE_NUMBA, parallel_pays
from relacc.kernels.tree import arrays_of, writable
from relacc.kernels.tree_crba import BLOCK, dof_paths
from relacc.kernels.tree_spatial import inertia_arrays

ABA_FROM = 100.0
"""``sum_k d_k^2 / (2 nv)`` above which the articulated-body algorithm is faster (measured on hinge chains: the
two meet near 25 speeds, where this is about 100)."""

US_PER_SPEED = 0.2
"""About the forward dynamics' cost per state and per speed on one core, in us (gymnasium's ant 2.8 us for 14 speeds,
humanoid 4.4 us for 23, a 30-link chain 5.8 us for 35): what :func:`relacc.kernels.jit.parallel_pays` weighs."""

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
    return plan(tree).method


def accelerations(tree, case: int, q, u, tau, gravity, out=None, algorithm: str | None = None, rates: bool = True):
    """``udot`` of checked-shape, C-contiguous float64 ``(n, .)`` inputs (into ``out`` if given).

    ``algorithm``: ``"crba"`` or ``"aba"`` to force one (default: :func:`method`). Case 3 is solved in case-2 speeds
    on its own coordinates and mapped to the rates (:func:`_angle_rates`); ``rates=False`` solves Kane's equations in
    the rates themselves (whose error grows as the rate map's condition number squared: for tests).

    Returns:
        ``(udot (n, nv), n_bad_inputs, n_singular)``: the counts of states with non-finite inputs or non-unit
        quaternions, and of states whose equations are singular (their rows are NaN); callers check and name them.
    """
    T = arrays_of(tree)
    p = plan(tree)
    chosen = p.method
    anc, depth, mass, com, inertia, arm, free = p.arrays()
    algorithm = chosen if algorithm is None else algorithm
    n = q.shape[0]
    out = np.empty((n, tree.nv)) if out is None else out
    qadr = T.qadr3 if case >= 3 else T.qadr
    if case == 3 and HAVE_NUMBA and rates:
        return _angle_rates(tree, q, u, tau, gravity, out, algorithm)
    serial = not parallel_pays(n, US_PER_SPEED * tree.nv, BLOCK)
    if algorithm == "aba":
        from relacc.kernels.tree_aba import aba_block, aba_loop

        args = (int(case), writable(q), writable(u), writable(tau), T, qadr, mass, com, inertia, arm, free,
                writable(gravity), out)
        bad_in, singular = aba_block(*args, 0, n) if serial else aba_loop(*args)
    else:
        from relacc.kernels.tree_crba import crba_block, crba_loop

        args = (int(case), writable(q), writable(u), writable(tau), T, qadr, anc, depth, mass, com, inertia, arm,
                free, writable(gravity), out)
        bad_in, singular = crba_block(*args, 0, n) if serial else crba_loop(*args)
    return out, int(bad_in), int(singular)


def _angle_rates(tree, q, u, tau, gravity, out, algorithm):
    """Case 3 in case-2 speeds, compiled: each ball's and free joint's rates ``theta_dot`` to its body angular
    velocity ``u2 = R^T W theta_dot`` and ``tau`` to ``tau2 = R^T W^-T tau`` (``R = Rx Ry Rz``, ``W`` the 1-2-3 rate
    map; hinges and slides unchanged), the forward dynamics in :data:`~relacc.kernels.tree.ANGLES_CASE2` (the angles,
    case-2 speeds), then ``theta_ddot = W^-1 (R u2_dot - W_dot theta_dot)`` (``R^T W_dot``'s other term, ``omega x
    omega``, is zero). The error is ``cond(W)`` times case 2's, as :func:`relacc.dynamics.tree._angle_rates`."""
    from relacc.kernels.tree import ANGLES_CASE2

    T = arrays_of(tree)
    u2, tau2 = np.empty_like(u), np.empty_like(tau)
    rates_to_speeds(q, u, tau, T, u2, tau2)
    a2 = np.empty_like(u)
    _, bad_in, singular = accelerations(tree, ANGLES_CASE2, q, u2, tau2, gravity, a2, algorithm)
    speeds_to_rates(q, u, a2, T, out)
    return out, bad_in, singular


if HAVE_NUMBA:
    from relacc.kernels.jit import leaf
    from relacc.kernels.so3 import r123, w123_dot_mv, w123_mv, w123_solve
    from relacc.kernels.tree import BALL, FREE

    @leaf
    def _angles(q, i, k, T):  # pragma: no cover - compiled
        """``(a, d, c1, c2, s1, s2, R)``: joint ``k``'s (a ball's or free joint's) first angle and first angular
        speed, the cosines and sines of ``theta1``, ``theta2`` and ``R = Rx Ry Rz`` (row-major) at state ``i``."""
        kind = T.jtype[k]
        a, d = T.qadr3[k] + (3 if kind == FREE else 0), T.dofadr[k] + (3 if kind == FREE else 0)
        c1, c2, c3 = np.cos(q[i, a]), np.cos(q[i, a + 1]), np.cos(q[i, a + 2])
        s1, s2, s3 = np.sin(q[i, a]), np.sin(q[i, a + 1]), np.sin(q[i, a + 2])
        return a, d, c1, c2, s1, s2, r123(c1, c2, c3, s1, s2, s3)

    @leaf  # ~50 ns a state (a parallel loop would not pay below ~5000)
    def rates_to_speeds(q, u, tau, T, u2, tau2):  # pragma: no cover - compiled
        for i in range(q.shape[0]):
            for c in range(u.shape[1]):
                u2[i, c], tau2[i, c] = u[i, c], tau[i, c]
            for k in range(T.jtype.shape[0]):
                kind = T.jtype[k]
                if kind != BALL and kind != FREE:
                    continue
                _, d, c1, c2, s1, s2, R = _angles(q, i, k, T)
                w0, w1, w2 = w123_mv(c1, c2, s1, s2, u[i, d], u[i, d + 1], u[i, d + 2])
                u2[i, d] = R[0] * w0 + R[3] * w1 + R[6] * w2  # R^T (W theta_dot)
                u2[i, d + 1] = R[1] * w0 + R[4] * w1 + R[7] * w2
                u2[i, d + 2] = R[2] * w0 + R[5] * w1 + R[8] * w2
                b0, b1, b2 = tau[i, d], tau[i, d + 1], tau[i, d + 2]
                e = (b2 - s2 * b0) / c2  # W^-T b: x0 = b0, then a rotation by theta1
                x0, x1, x2 = b0, c1 * b1 - s1 * e, s1 * b1 + c1 * e
                tau2[i, d] = R[0] * x0 + R[3] * x1 + R[6] * x2
                tau2[i, d + 1] = R[1] * x0 + R[4] * x1 + R[7] * x2
                tau2[i, d + 2] = R[2] * x0 + R[5] * x1 + R[8] * x2

    @leaf
    def speeds_to_rates(q, u, a2, T, out):  # pragma: no cover - compiled
        for i in range(q.shape[0]):
            for c in range(u.shape[1]):
                out[i, c] = a2[i, c]
            for k in range(T.jtype.shape[0]):
                kind = T.jtype[k]
                if kind != BALL and kind != FREE:
                    continue
                _, d, c1, c2, s1, s2, R = _angles(q, i, k, T)
                x0, x1, x2 = a2[i, d], a2[i, d + 1], a2[i, d + 2]
                r0 = R[0] * x0 + R[1] * x1 + R[2] * x2  # R u2_dot
                r1 = R[3] * x0 + R[4] * x1 + R[5] * x2
                r2 = R[6] * x0 + R[7] * x1 + R[8] * x2
                h0, h1, h2 = w123_dot_mv(c1, c2, s1, s2, u[i, d], u[i, d + 1], u[i, d + 1], u[i, d + 2])
                out[i, d], out[i, d + 1], out[i, d + 2] = w123_solve(c1, c2, s1, s2, r0 - h0, r1 - h1, r2 - h2)


def one_state(tree, case: int, q, u, gravity):
    """``(udot (nv,), bad input, singular)`` of one state ``q (nq,)``, ``u (nv,)`` (float64, shapes checked by the
    caller), no applied forces: the single-state lane of :func:`relacc.tree_accelerations`, on the calling thread with
    the kernel's arguments gathered once per tree, case, gravity and thread (:func:`_single`), so that a call costs
    the kernel and little else."""
    fn, args, Q, U, out = _single(tree, case, gravity)
    Q[0], U[0] = q, u
    bad_in, singular = fn(*args)
    return out[0].copy(), bad_in, singular


def _single(tree, case, gravity):
    """``(block function, its arguments, q (1, nq), u (1, nv), out (1, nv))``: buffers and arguments of the block
    function for one state, cached per tree, case, gravity and thread (each thread writes its own buffers)."""
    key = (int(case), bytes(np.asarray(gravity, dtype=float)), threading.get_ident())
    cache = _SINGLE.setdefault(tree, {})
    if key not in cache:
        T = arrays_of(tree)
        p = plan(tree)
        chosen = p.method
        anc, depth, mass, com, inertia, arm, free = p.arrays()
        qadr = T.qadr3 if case >= 3 else T.qadr
        Q, U, tau, out = np.zeros((1, tree.nq(case))), np.zeros((1, tree.nv)), np.zeros((1, tree.nv)), \
            np.zeros((1, tree.nv))
        g = np.array(gravity, dtype=float)
        if chosen == "aba":
            from relacc.kernels.tree_aba import aba_block as fn

            args = (int(case), Q, U, tau, T, qadr, mass, com, inertia, arm, free, g, out, 0, 1)
        else:
            from relacc.kernels.tree_crba import crba_block as fn

            args = (int(case), Q, U, tau, T, qadr, anc, depth, mass, com, inertia, arm, free, g, out, 0, 1)
        cache[key] = (_entry_point(fn, args), args, Q, U, out)
    return cache[key]


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


__all__ = ["ABA_FROM", "accelerations", "method", "one_state", "plan"]
