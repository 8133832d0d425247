"""Forward dynamics of a tree by the articulated-body algorithm, compiled: O(n) per state.

On the spatial pass of :mod:`relacc.kernels.tree_spatial`: backwards, joint by joint (stacked joints are massless
links between), ``U = IA S``, ``D = S^T U`` (plus armature), ``u = tau - S^T pA``, and the parent side gets
``IA - U D^-1 U^T`` and ``pA + (IA - U D^-1 U^T) c + U D^-1 u``; forwards from the base acceleration ``-g``,
``a' = a_parent + c``, ``udot = D^-1 (u - U^T a')``, ``a = a' + S udot``. Armature adds to ``D`` (in cases 1 and 3
a ball's or free joint's ``B^T D B``, and ``B^T D B_dot u`` to ``u``), as :mod:`relacc.dynamics.tree`.
"""

from __future__ import annotations

import numpy as np

from relacc.core.tolerances import ILL_FLOOR, PIVOT_FLOOR
from relacc.kernels.jit import HAVE_NUMBA, jitable, leaf, numba
from relacc.kernels.tree import ANGLES_CASE2, FREE, HINGE, SLIDE
from relacc.kernels.tree_spatial import (
    SYM,
    bad_inputs,
    forward,
    ill,
    joint_B,
    rank_one,
    row_to_rates,
    row_to_speeds,
    spd_inverse,
    sym_mv,
)

BLOCK = 64
"""States per parallel task."""


@jitable
def _composite_diagonal(Ic, b, S, d):
    """``S_d^T Ic_b S_d``: the mass matrix's diagonal entry of speed ``d`` (without armature: at most the entry),
    from the composite rigid inertia ``Ic`` of body ``b``'s subtree."""
    c0, c1, c2, c3, c4, c5 = sym_mv(Ic, b, S, d)
    return S[d, 0] * c0 + S[d, 1] * c1 + S[d, 2] * c2 + S[d, 3] * c3 + S[d, 4] * c4 + S[d, 5] * c5


@jitable(inline=True)
def _one_speed(b, k, d, tau, i, arm, S, C, IA, pA, U, uu, Dinv, free_parent, Ic, cd, floor):
    """A hinge or slide (one speed ``d``) across the articulated inertia of body ``b``, in scalars. Returns 1 when
    its pivot ``D`` is not above ``floor`` times its scale, the speed's diagonal entry of the mass matrix plus the
    mean of those met so far (``cd[6]``, updated here); sets ``cd[7]`` when it is at most
    :data:`relacc.core.tolerances.ILL_FLOOR` times it."""
    U0, U1, U2, U3, U4, U5 = sym_mv(IA, b, S, d)
    U[d, 0], U[d, 1], U[d, 2], U[d, 3], U[d, 4], U[d, 5] = U0, U1, U2, U3, U4, U5
    D = S[d, 0] * U0 + S[d, 1] * U1 + S[d, 2] * U2 + S[d, 3] * U3 + S[d, 4] * U4 + S[d, 5] * U5 + arm[d]
    own = _composite_diagonal(Ic, b, S, d)
    cd[6] += own / uu.shape[0]
    scale = own + cd[6]
    if not D > floor * scale:
        return 1
    if ill(D, ILL_FLOOR * scale):
        cd[7] = 1.0
    ud = tau[i, d] - (S[d, 0] * pA[b, 0] + S[d, 1] * pA[b, 1] + S[d, 2] * pA[b, 2] + S[d, 3] * pA[b, 3]
                      + S[d, 4] * pA[b, 4] + S[d, 5] * pA[b, 5])
    uu[d] = ud
    Di = 1.0 / D
    Dinv[k, 0] = Di
    if free_parent:
        return 0
    rank_one(IA, b, U0, U1, U2, U3, U4, U5, Di)
    c0, c1, c2, c3, c4, c5 = sym_mv(IA, b, C, k)
    g = ud * Di
    pA[b, 0] += c0 + U0 * g
    pA[b, 1] += c1 + U1 * g
    pA[b, 2] += c2 + U2 * g
    pA[b, 3] += c3 + U3 * g
    pA[b, 4] += c4 + U4 * g
    pA[b, 5] += c5 + U5 * g
    return 0


@leaf
def backward(case, q, u, tau, i, T, qadr, arm, free, S, C, R, V, IA, pA, U, uu, Dinv, tmp, Ic, cd, floor):
    """The articulated inertias, leaves to root (module docstring), and the composite rigid inertias ``Ic`` (from
    the bodies' own, in ``Ic`` on entry) for the pivots' test. Returns 1 when a joint's ``D`` is not positive
    definite to working precision (a pivot not above ``floor`` times its scale, its speed's diagonal entry of the
    mass matrix plus the mean of those met so far: :data:`relacc.core.tolerances.PIVOT_FLOOR`), else 2 when a pivot
    is at most :data:`relacc.core.tolerances.ILL_FLOOR` times it, else 0. ``cd``: scratch ``(8,)`` (a joint's
    diagonal entries, the running mean at 6, the flag at 7)."""
    cd[6], cd[7] = 0.0, 0.0
    for b in range(T.parent.shape[0] - 1, -1, -1):
        js, jn = T.jstart[b], T.jnum[b]
        for k in range(js + jn - 1, js - 1, -1):
            kind, d = T.jtype[k], T.dofadr[k]
            if kind == HINGE or kind == SLIDE:
                if _one_speed(b, k, d, tau, i, arm, S, C, IA, pA, U, uu, Dinv, free[b] and k == js, Ic, cd, floor):
                    return 1
                continue
            nd = 6 if kind == FREE else 3
            for c in range(nd):
                col = sym_mv(IA, b, S, d + c)
                s = tau[i, d + c]
                for r in range(6):
                    U[d + c, r] = col[r]
                    s -= S[d + c, r] * pA[b, r]
                uu[d + c] = s
            for r in range(nd):
                for c in range(nd):
                    s = 0.0
                    for x in range(6):
                        s += S[d + r, x] * U[d + c, x]
                    tmp[r * nd + c] = s
                tmp[r * nd + r] += arm[d + r]  # MuJoCo's armature, diagonal on case 2 speeds
            if case == 1 or case == 3:
                at = 3 if kind == FREE else 0
                if arm[d + at] != 0.0 or arm[d + at + 1] != 0.0 or arm[d + at + 2] != 0.0:
                    for r in range(3):  # in cases 1 and 3 the rotation's armature is B^T D B, not diagonal
                        tmp[(at + r) * nd + at + r] -= arm[d + at + r]
                    joint_B(case, q, u, i, T, qadr, k, b, R, V, tmp, 42)
                    for r in range(3):
                        for c in range(3):
                            s = 0.0
                            for x in range(3):
                                s += tmp[42 + 3 * x + r] * arm[d + at + x] * tmp[42 + 3 * x + c]
                            tmp[(at + r) * nd + at + c] += s
                        s = 0.0
                        for x in range(3):
                            bd = tmp[51 + 3 * x] * u[i, d + at] + tmp[52 + 3 * x] * u[i, d + at + 1] \
                                + tmp[53 + 3 * x] * u[i, d + at + 2]
                            s += tmp[42 + 3 * x + r] * arm[d + at + x] * bd
                        uu[d + at + r] -= s
            for r in range(nd):
                cd[r] = _composite_diagonal(Ic, b, S, d + r)
            for r in range(nd):
                cd[6] += cd[r] / uu.shape[0]
            if spd_inverse(tmp, nd, Dinv, k, cd, floor):
                return 1
            if free[b] and k == js:
                break  # nothing moves a free joint's parent side
            # IA -= U D^-1 U^T; pA += IA' c + U D^-1 u
            for r in range(6):
                for c in range(r, 6):
                    s = 0.0
                    for x in range(nd):
                        t = 0.0
                        for y in range(nd):
                            t += Dinv[k, x * nd + y] * U[d + y, c]
                        s += U[d + x, r] * t
                    IA[b, SYM[r, c]] -= s
            for x in range(nd):
                t = 0.0
                for y in range(nd):
                    t += Dinv[k, x * nd + y] * uu[d + y]
                tmp[42 + x] = t
            ic = sym_mv(IA, b, C, k)
            for r in range(6):
                s = ic[r]
                for x in range(nd):
                    s += U[d + x, r] * tmp[42 + x]
                pA[b, r] += s
        p = T.parent[b]
        if p >= 0 and not free[b]:
            for x in range(21):
                IA[p, x] += IA[b, x]
                Ic[p, x] += Ic[b, x]
            for x in range(6):
                pA[p, x] += pA[b, x]
    return 2 if cd[7] != 0.0 else 0


@leaf
def accelerate(T, g, free, S, C, U, uu, Dinv, acc, i, out):
    """Root to leaves: each joint's ``udot = D^-1 (u - U^T a')`` into ``out[i]``, bodies' spatial accelerations."""
    for b in range(T.parent.shape[0]):
        p = T.parent[b]
        if p >= 0 and not free[b]:
            for x in range(6):
                acc[b, x] = acc[p, x]
        else:
            acc[b, 0], acc[b, 1], acc[b, 2], acc[b, 3], acc[b, 4], acc[b, 5] = 0.0, 0.0, 0.0, -g[0], -g[1], -g[2]
        for k in range(T.jstart[b], T.jstart[b] + T.jnum[b]):
            kind, d = T.jtype[k], T.dofadr[k]
            for x in range(6):
                acc[b, x] += C[k, x]
            if kind == HINGE or kind == SLIDE:
                t = uu[d]
                for y in range(6):
                    t -= U[d, y] * acc[b, y]
                a = Dinv[k, 0] * t
                out[i, d] = a
                for x in range(6):
                    acc[b, x] += S[d, x] * a
                continue
            nd = 6 if kind == FREE else 3
            for r in range(nd):
                s = 0.0
                for x in range(nd):
                    t = uu[d + x]
                    for y in range(6):
                        t -= U[d + x, y] * acc[b, y]
                    s += Dinv[k, r * nd + x] * t
                out[i, d + r] = s
            for r in range(nd):
                for x in range(6):
                    acc[b, x] += S[d + r, x] * out[i, d + r]


if HAVE_NUMBA:

    @numba.njit(cache=True, nogil=True)
    def aba_block(case, q, u, tau, T, qadr, mass, com, inertia, arm, free, g, out, start,
                  stop):  # pragma: no cover - compiled
        """States ``start .. stop - 1``; ``(bad inputs, singular states, ill-conditioned states)``; case 3 and threads
        as :func:`relacc.kernels.tree_crba.crba_block`."""
        nv, nb, nj = u.shape[1], T.parent.shape[0], T.jtype.shape[0]
        S, C, o, R = np.empty((nv, 6)), np.empty((max(nj, 1), 6)), np.empty((nb, 3)), np.empty((nb, 9))
        V, IA, pA, acc = np.empty((nb, 6)), np.empty((nb, 21)), np.empty((nb, 6)), np.empty((nb, 6))
        U, uu, Dinv, tmp = np.empty((nv, 6)), np.empty(nv), np.empty((max(nj, 1), 36)), np.empty(60)
        Ic, cd = np.empty((nb, 21)), np.empty(8)
        Q1, U1, F1, X1 = np.empty((1, q.shape[1])), np.empty((1, nv)), np.empty((1, nv)), np.empty((1, nv))
        trig = np.empty((max(nj, 1), 6))
        bad_in, singular, warned = 0, 0, 0
        mode = ANGLES_CASE2 if case == 3 else case
        for i in range(start, stop):
            bad_in += bad_inputs(case, q, u, i, T, qadr)
            if mode == ANGLES_CASE2:
                for c in range(q.shape[1]):
                    Q1[0, c] = q[i, c]
                row_to_speeds(q, u, tau, i, T, U1, F1, 0, trig)
                qq, uu_, tt, r = Q1, U1, F1, 0
            else:
                qq, uu_, tt, r = q, u, tau, i
            forward(mode, qq, uu_, r, T, qadr, mass, com, inertia, S, C, o, R, V, IA, pA)
            for b in range(nb):  # the bodies' own spatial inertias: the composite ones grow from them
                for x in range(21):
                    Ic[b, x] = IA[b, x]
            code = backward(mode, qq, uu_, tt, r, T, qadr, arm, free, S, C, R, V, IA, pA, U, uu, Dinv, tmp, Ic, cd,
                            PIVOT_FLOOR)
            failed = 1 if code == 1 else 0
            warned += 1 if code == 2 else 0
            if failed:
                for c in range(nv):
                    out[i, c] = np.nan
            elif mode == ANGLES_CASE2:
                accelerate(T, g, free, S, C, U, uu, Dinv, acc, np.int64(0), X1)  # int64: one compilation
                row_to_rates(q, u, i, X1, 0, T, out, trig)
            else:
                accelerate(T, g, free, S, C, U, uu, Dinv, acc, i, out)
            singular += failed
        return bad_in, singular, warned
