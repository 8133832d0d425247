"""Compiled kinematics of a tree's bodies without their partial velocities: ``tree_kinematics(..., partials=False)``.

On the spatial pass of :mod:`relacc.kernels.tree_spatial` (each body's orientation ``R``, its origin ``o`` from the
point ``O`` of its independent subtree, its spatial velocity ``(omega, v_O)`` about ``O``, each joint's columns ``S``
and velocity-product term ``c = S_dot u_j``), spatial accelerations go root to leaves, ``a_b = a_parent + sum_j (c_j +
S_j udot_j)``, and a point ``P`` of a body at ``r`` from ``O`` has

    v_P = v_O + omega x r,    a_P = a'_O + alpha x r + omega x v_P    (classical acceleration)

where ``(alpha, a'_O)`` is the spatial acceleration (``O`` fixed in space). Work per state is one pass over the
joints, ``O(nv)``, against ``O(nb nv)`` for the partial velocities; nothing of size ``nv`` per body is written.
"""

from __future__ import annotations

import weakref

import numpy as np

from relacc.kernels.jit import HAVE_NUMBA, first_touch, leaf, numba, parallel_pays, split
from relacc.kernels.so3 import cross_inline as cross
from relacc.kernels.so3 import mv_inline as mv
from relacc.kernels.tree import BALL, BLOCK, FREE, arrays_of, row9, writable

US_PER_BODY = 0.2
"""About the cost per state and per body on one core, in us (gymnasium's ant 2.4 us for 13 bodies, humanoid 3.0):
what :func:`relacc.kernels.jit.parallel_pays` weighs."""


def subtree_roots(tree) -> np.ndarray:
    """``(nb,)`` for each body the root of its independent subtree: a body on the world or on a free joint."""
    roots = np.empty(tree.nb, dtype=np.int64)
    parents = arrays_of(tree).parent
    for b, body in enumerate(tree.bodies):
        p = parents[b]
        roots[b] = b if p < 0 or any(j.type == "free" for j in body.joints) else roots[p]
    return roots


if HAVE_NUMBA:
    from relacc.kernels.tree_spatial import forward

    @leaf
    def _origin(i, r, q, T, qadr, base):  # pragma: no cover - compiled
        """Into ``base``: where the point ``O`` of the subtree rooted at body ``r`` is, fixed components (m): a free
        root's position, or the root body's placement on the world."""
        js = T.jstart[r]
        if T.jnum[r] == 1 and T.jtype[js] == FREE:
            a = qadr[js]
            base[0], base[1], base[2] = q[i, a], q[i, a + 1], q[i, a + 2]
        else:
            base[0], base[1], base[2] = T.bpos[r, 0], T.bpos[r, 1], T.bpos[r, 2]

    @leaf
    def _point(i, b, px, py, pz, base, o, R, V, acc, with_acc, pos, vel, accel, j):  # pragma: no cover - compiled
        """Body ``b``'s point at ``(px, py, pz)`` (body components) into row ``j`` of ``pos``, ``vel``, ``accel``."""
        r0, r1, r2 = mv(row9(R, b), px, py, pz)
        r0, r1, r2 = o[b, 0] + r0, o[b, 1] + r1, o[b, 2] + r2  # from O
        pos[i, j, 0], pos[i, j, 1], pos[i, j, 2] = base[0] + r0, base[1] + r1, base[2] + r2
        w0, w1, w2 = V[b, 0], V[b, 1], V[b, 2]
        c0, c1, c2 = cross(w0, w1, w2, r0, r1, r2)
        v0, v1, v2 = V[b, 3] + c0, V[b, 4] + c1, V[b, 5] + c2
        vel[i, j, 0], vel[i, j, 1], vel[i, j, 2] = v0, v1, v2
        if with_acc:
            a0, a1, a2 = cross(acc[b, 0], acc[b, 1], acc[b, 2], r0, r1, r2)
            d0, d1, d2 = cross(w0, w1, w2, v0, v1, v2)
            accel[i, j, 0] = acc[b, 3] + a0 + d0
            accel[i, j, 1] = acc[b, 4] + a1 + d1
            accel[i, j, 2] = acc[b, 5] + a2 + d2

    @numba.njit(cache=True, nogil=True)
    def motion_block(case, q, u, ud, with_acc, T, qadr, roots, mass, com, inertia, pos, vel, accel, omega, alpha,
                     rot, with_points, ppos, pvel, pacc, start, stop):  # pragma: no cover - compiled
        """States ``start .. stop - 1``: every body's mass centre and angular motion, every point's motion."""
        nv, nb, nj = u.shape[1], T.parent.shape[0], T.jtype.shape[0]
        S, C, o, R = np.empty((max(nv, 1), 6)), np.empty((max(nj, 1), 6)), np.empty((nb, 3)), np.empty((nb, 9))
        V, IA, pA, acc = np.empty((nb, 6)), np.empty((nb, 21)), np.empty((nb, 6)), np.zeros((nb, 6))
        base = np.empty(3)
        for i in range(start, stop):
            forward(case, q, u, i, T, qadr, mass, com, inertia, S, C, o, R, V, IA, pA)
            for b in range(nb):
                if with_acc:
                    p = T.parent[b]
                    for x in range(6):
                        acc[b, x] = acc[p, x] if roots[b] != b else 0.0
                    for k in range(T.jstart[b], T.jstart[b] + T.jnum[b]):
                        for x in range(6):
                            acc[b, x] += C[k, x]
                        kind = T.jtype[k]
                        for c in range(6 if kind == FREE else (3 if kind == BALL else 1)):
                            d = T.dofadr[k] + c
                            for x in range(6):
                                acc[b, x] += S[d, x] * ud[i, d]
                _origin(i, roots[b], q, T, qadr, base)
                _point(i, b, com[b, 0], com[b, 1], com[b, 2], base, o, R, V, acc, with_acc, pos, vel, accel, b)
                for x in range(3):
                    omega[i, b, x] = V[b, x]
                    if with_acc:
                        alpha[i, b, x] = acc[b, x]
                for x in range(9):
                    rot[i, b, x // 3, x % 3] = R[b, x]
            if with_points:
                for j in range(T.pbody.shape[0]):
                    b = T.pbody[j]
                    _origin(i, roots[b], q, T, qadr, base)
                    _point(i, b, T.ppos[j, 0], T.ppos[j, 1], T.ppos[j, 2], base, o, R, V, acc, with_acc, ppos, pvel,
                           pacc, j)


def motion(tree, case: int, q, u, udot, points: bool, out=None):
    """The outputs of :func:`relacc.tree_kinematics` without partial velocities, for checked C-contiguous float64
    ``(n, .)`` inputs: ``(arrays, n_nonfinite)`` as :func:`relacc.kernels.tree.kinematics` with ``V``, ``Vdot``,
    ``Omega``, ``Omegadot`` (and the points' ``V``, ``Vdot``) None."""
    from relacc.kernels.tree_dynamics import plan

    T = arrays_of(tree)
    p = plan(tree)
    mass, com, inertia = p.mass, p.com, p.inertia
    n, nb = q.shape[0], tree.nb
    npt = len(tree.points) if points else 0
    with_acc = udot is not None
    out = {} if out is None else out
    shapes = {"position": (3,), "velocity": (3,), "acceleration": (3,), "omega": (3,), "alpha": (3,),
              "rotation": (3, 3)}
    res = {k: out[k] if out.get(k) is not None else np.empty((n, nb) + t) for k, t in shapes.items()}
    pts = {k: np.empty((n, npt, 3)) for k in ("position", "velocity", "acceleration")}
    q, u, ud = (writable(a) for a in (q, u, udot if with_acc else np.zeros((n, tree.nv))))
    args = (int(case), q, u, ud, with_acc, T, T.qadr3 if case == 3 else T.qadr, _roots(tree), mass, com, inertia,
            *res.values(), npt > 0, *pts.values())
    if not parallel_pays(n, US_PER_BODY * nb, BLOCK):
        motion_block(*args, 0, n)
    else:
        first_touch(*[a for k, a in res.items() if out.get(k) is None], *pts.values())
        split(motion_block, args, n, BLOCK)
    bad = sum(int(np.count_nonzero(~np.isfinite(res[k]))) for k in shapes
              if with_acc or k not in ("acceleration", "alpha"))
    if not with_acc:
        res["acceleration"] = res["alpha"] = pts["acceleration"] = None
    res.update(V=None, Vdot=None, Omega=None, Omegadot=None)
    res["points"] = dict(pts, V=None, Vdot=None) if points else None
    return res, bad


_ROOTS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def _roots(tree):
    if tree not in _ROOTS:
        _ROOTS[tree] = subtree_roots(tree)
    return _ROOTS[tree]


__all__ = ["motion", "subtree_roots"]
