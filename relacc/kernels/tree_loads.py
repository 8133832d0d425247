"""Compiled generalized forces of loads on a tree's bodies: the body-load part of :func:`relacc.tree_accelerations`.

A force ``F`` (fixed components, N) at body ``b``'s mass centre and a torque ``T`` (N m) on it do work through the
mass centre's partial velocities and the body's partial angular velocities, ``tau_c = V_c . F + Omega_c . T``. The
walk of :mod:`relacc.kernels.tree` carries the body origin's columns ``V_o``; the mass centre's are
``V_o + Omega x r`` with ``r = [R_b] com_b`` (fixed components), so ``tau_c = V_o . F + Omega . (r x F + T)``. Only
the loaded bodies' path columns are read, and nothing of the walk is written out: what
:func:`relacc.tree_kinematics` would return for every body (``4 x 3 x nb x nv`` numbers a state) is three times the
cost of the whole forward dynamics on gymnasium's ant.
"""

from __future__ import annotations

import numpy as np

from relacc.kernels.jit import HAVE_NUMBA, numba, parallel_pays, split
from relacc.kernels.so3 import cross_inline as cross
from relacc.kernels.so3 import mv_inline as mv
from relacc.kernels.tree import BLOCK, US_PER_BODY_SPEED, arrays_of, row9, walk_state, writable

if HAVE_NUMBA:

    @numba.njit(cache=True, nogil=True)
    def _loads_block(case, q, u, T, qadr, bodies, F, M, out, start, stop):  # pragma: no cover - compiled
        nv, nb = u.shape[1], T.parent.shape[0]
        o, R, w = np.empty((nb, 3)), np.empty((nb, 9)), np.empty((nb, 3))
        sV, sOm, sVd, sOmd = (np.zeros((nb, 3, nv)), np.zeros((nb, 3, nv)), np.zeros((nb, 3, nv)),
                              np.zeros((nb, 3, nv)))
        for i in range(start, stop):
            walk_state(case, q, u, i, T, qadr, o, R, w, sV, sOm, sVd, sOmd)
            for c in range(nv):
                out[i, c] = 0.0
            for j in range(bodies.shape[0]):
                b = bodies[j]
                r0, r1, r2 = mv(row9(R, b), T.com[b, 0], T.com[b, 1], T.com[b, 2])
                f0, f1, f2 = F[i, j, 0], F[i, j, 1], F[i, j, 2]
                m0, m1, m2 = cross(r0, r1, r2, f0, f1, f2)
                m0, m1, m2 = m0 + M[i, j, 0], m1 + M[i, j, 1], m2 + M[i, j, 2]
                for t in range(T.path_ptr[b], T.path_ptr[b + 1]):
                    c = T.path_idx[t]
                    out[i, c] += (sV[b, 0, c] * f0 + sV[b, 1, c] * f1 + sV[b, 2, c] * f2
                                  + sOm[b, 0, c] * m0 + sOm[b, 1, c] * m1 + sOm[b, 2, c] * m2)


def load_forces(tree, case: int, q, u, bodies, force, torque) -> np.ndarray:
    """``(n, nv)`` the generalized forces, conjugate to the case's speeds (N or N m per speed), of loads on bodies.

    Args:
        q, u: checked ``(n, nq)``, ``(n, nv)`` states of the case. bodies: ``(L,)`` body indices (``tree.bodies``).
        force: ``(n, L, 3)`` each load's force at its body's mass centre, fixed components (N).
        torque: ``(n, L, 3)`` its torque, fixed components (N m).
    """
    T = arrays_of(tree)
    n = q.shape[0]
    out = np.empty((n, tree.nv))
    args = (int(case), writable(q), writable(u), T, T.qadr3 if case == 3 else T.qadr,
            np.ascontiguousarray(bodies, dtype=np.int64), writable(force), writable(torque), out)
    if parallel_pays(n, US_PER_BODY_SPEED * tree.nb * tree.nv, BLOCK):
        split(_loads_block, args, n, BLOCK)
    else:
        _loads_block(*args, 0, n)
    return out


__all__ = ["load_forces"]
