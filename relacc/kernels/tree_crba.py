"""Forward dynamics of a tree by composite rigid bodies and ``L^T D L``, compiled: O(n d^2) per state.

On the spatial pass of :mod:`relacc.kernels.tree_spatial`: each body's spatial acceleration from velocity products
and gravity (``a_b = a_parent + sum_k c_k``, ``-g`` at a root) and its force ``f = I a + v x* I v``; composites
summed leaves to root (not across free joints); ``M_ij = S_j^T Ic_b S_i`` for ``j`` on ``i``'s path, the bias
``S_i^T fc_b``; then ``M = L^T D L`` on the speeds' paths (MuJoCo's ``mj_factorM``: no fill-in on a tree) and its
solve. The factorization's ``sum_k d_k^2`` makes this the faster algorithm for shallow trees (``d`` the speeds on a
path) and the articulated-body algorithm (:mod:`relacc.kernels.tree_aba`) for deep ones.
"""

from __future__ import annotations

import numpy as np

from relacc.core.tolerances import ILL_FLOOR, PIVOT_FLOOR
from relacc.kernels.jit import HAVE_NUMBA, jitable, leaf, numba
from relacc.kernels.tree import ANGLES_CASE2, BALL, FREE, HINGE, SLIDE
from relacc.kernels.tree_spatial import SYM, bad_inputs, forward, ill, joint_B, rigid_mv, row_to_rates, row_to_speeds

BLOCK = 64
"""States per parallel task."""


def dof_paths(tree):
    """``(anc (nv, D), depth (nv,))``: each speed's earlier speeds on its path, in order (an earlier speed's path is
    a prefix of a later one's), and their number; ``D`` the longest (at least 1). A free joint starts a path."""
    parents = np.full(tree.nv, -1, np.int64)
    last_of = {}
    for b, body in enumerate(tree.bodies):
        prev = last_of.get(body.parent, -1) if body.parent >= 0 else -1
        for k in tree.body_joints[b]:
            j, d = tree.joints[k][1], tree.dofadr[k]
            if j.type == "free":
                prev = -1
            for i in range(j.nv):
                parents[d + i], prev = prev, d + i
        last_of[b] = prev
    paths = []
    for k in range(tree.nv):
        chain, i = [], parents[k]
        while i >= 0:
            chain.append(i)
            i = parents[i]
        paths.append(chain[::-1])
    anc = np.full((tree.nv, max([len(p) for p in paths] + [1])), -1, np.int64)
    for k, p in enumerate(paths):
        anc[k, :len(p)] = p
    return anc, np.array([len(p) for p in paths], np.int64)


@leaf
def mass_matrix(case, q, u, tau, i, T, qadr, anc, depth, arm, free, g, S, C, R, V, IA, pA, A, f, M, x, tmp):
    """``M`` (path rows: ``M[k, t]`` with speed ``anc[k, t]``, the diagonal at ``M[k, depth[k]]``) and
    ``x = tau - bias`` of state ``i``, after :func:`relacc.kernels.tree_spatial.forward`."""
    nb = T.parent.shape[0]
    for b in range(nb):
        p = T.parent[b]
        if p >= 0 and not free[b]:
            for k in range(6):
                A[b, k] = A[p, k]
        else:
            A[b, 0], A[b, 1], A[b, 2], A[b, 3], A[b, 4], A[b, 5] = 0.0, 0.0, 0.0, -g[0], -g[1], -g[2]
        for k in range(T.jstart[b], T.jstart[b] + T.jnum[b]):
            for c in range(6):
                A[b, c] += C[k, c]
        fa = rigid_mv(IA, b, A, b)
        for c in range(6):
            f[b, c] = fa[c] + pA[b, c]
    for b in range(nb - 1, -1, -1):  # composite inertias and subtree forces (not across free joints)
        p = T.parent[b]
        if p >= 0 and not free[b]:
            for k in range(21):
                IA[p, k] += IA[b, k]
            for k in range(6):
                f[p, k] += f[b, k]
    for b in range(nb):
        r = b  # a path that starts at a free joint starts with its three translations along the world's axes (their
        while T.parent[r] >= 0 and not free[r]:  # columns [0; e_k]) and three rotations about O ([a; 0])
            r = T.parent[r]
        floating = free[r]
        for k in range(T.jstart[b], T.jstart[b] + T.jnum[b]):
            d = T.dofadr[k]
            kind = T.jtype[k]
            nd = 6 if kind == FREE else (3 if kind == BALL else 1)
            for c in range(d, d + nd):
                if kind == FREE and c < d + 3:  # Ic [0; e_k]: a column of Ic
                    e = 3 + c - d
                    F = (IA[b, SYM[0, e]], IA[b, SYM[1, e]], IA[b, SYM[2, e]], IA[b, SYM[3, e]], IA[b, SYM[4, e]],
                         IA[b, SYM[5, e]])
                elif kind == FREE:  # Ic [a; 0]
                    a0, a1, a2 = S[c, 0], S[c, 1], S[c, 2]
                    F = (IA[b, 0] * a0 + IA[b, 1] * a1 + IA[b, 2] * a2,
                         IA[b, 1] * a0 + IA[b, 6] * a1 + IA[b, 7] * a2,
                         IA[b, 2] * a0 + IA[b, 7] * a1 + IA[b, 11] * a2,
                         IA[b, 3] * a0 + IA[b, 8] * a1 + IA[b, 12] * a2,
                         IA[b, 4] * a0 + IA[b, 9] * a1 + IA[b, 13] * a2,
                         IA[b, 5] * a0 + IA[b, 10] * a1 + IA[b, 14] * a2)
                else:
                    F = rigid_mv(IA, b, S, c)
                dc = depth[c]
                M[c, dc] = S[c, 0] * F[0] + S[c, 1] * F[1] + S[c, 2] * F[2] + S[c, 3] * F[3] + S[c, 4] * F[4] \
                    + S[c, 5] * F[5] + arm[c]
                x[c] = tau[i, c] - (S[c, 0] * f[b, 0] + S[c, 1] * f[b, 1] + S[c, 2] * f[b, 2] + S[c, 3] * f[b, 3]
                                    + S[c, 4] * f[b, 4] + S[c, 5] * f[b, 5])
                t0 = 0
                if floating and dc >= 6:  # a column below the free root: its six written out
                    M[c, 0], M[c, 1], M[c, 2] = F[3], F[4], F[5]
                    j3, j4, j5 = anc[c, 3], anc[c, 4], anc[c, 5]
                    M[c, 3] = S[j3, 0] * F[0] + S[j3, 1] * F[1] + S[j3, 2] * F[2]
                    M[c, 4] = S[j4, 0] * F[0] + S[j4, 1] * F[1] + S[j4, 2] * F[2]
                    M[c, 5] = S[j5, 0] * F[0] + S[j5, 1] * F[1] + S[j5, 2] * F[2]
                    t0 = 6
                elif floating:  # the free joint's own columns
                    for t in range(min(dc, 3)):
                        M[c, t] = F[3 + t]
                    for t in range(3, dc):
                        j = anc[c, t]
                        M[c, t] = S[j, 0] * F[0] + S[j, 1] * F[1] + S[j, 2] * F[2]
                    t0 = dc
                for t in range(t0, dc):
                    j = anc[c, t]
                    M[c, t] = S[j, 0] * F[0] + S[j, 1] * F[1] + S[j, 2] * F[2] + S[j, 3] * F[3] + S[j, 4] * F[4] \
                        + S[j, 5] * F[5]
            kind = T.jtype[k]
            if (case == 1 or case == 3) and (kind == BALL or kind == FREE):
                at = d + (3 if kind == FREE else 0)
                if arm[at] != 0.0 or arm[at + 1] != 0.0 or arm[at + 2] != 0.0:
                    _rotational_armature(case, q, u, i, T, qadr, k, b, at, depth, arm, R, V, M, x, tmp)


@jitable
def _rotational_armature(case, q, u, i, T, qadr, k, b, at, depth, arm, R, V, M, x, tmp):
    """In cases 1 and 3 a ball's or free joint's rotational armature is ``B^T D B`` (not diagonal) and adds
    ``-B^T D B_dot u`` to the forces (:mod:`relacc.dynamics.tree`): undo the diagonal, add those."""
    joint_B(case, q, u, i, T, qadr, k, b, R, V, tmp, 0)
    for r in range(3):
        M[at + r, depth[at + r]] -= arm[at + r]
        for c in range(r + 1):
            s = 0.0
            for y in range(3):
                s += tmp[3 * y + r] * arm[at + y] * tmp[3 * y + c]
            M[at + r, depth[at + r] - (r - c)] += s  # the block's speeds follow each other on the path
        s = 0.0
        for y in range(3):
            bd = tmp[9 + 3 * y] * u[i, at] + tmp[10 + 3 * y] * u[i, at + 1] + tmp[11 + 3 * y] * u[i, at + 2]
            s += tmp[3 * y + r] * arm[at + y] * bd
        x[at + r] -= s


@jitable(inline=True)
def _past_six(M, x, anc, k, dk, piv, xk):
    """:func:`factor_solve`'s elimination of row ``k`` (``depth >= 6``) into its ancestors' rows, with the entries of
    its first six ancestors written out: the same operations in the same order as the loops, without short loops
    (numba's vectorized short loops cost more than their arithmetic here)."""
    v0, v1, v2, v3, v4, v5 = M[k, 0], M[k, 1], M[k, 2], M[k, 3], M[k, 4], M[k, 5]
    for t in range(dk - 1, 5, -1):
        i = anc[k, t]
        s = M[k, t] / piv
        M[i, 0], M[i, 1], M[i, 2] = M[i, 0] - s * v0, M[i, 1] - s * v1, M[i, 2] - s * v2
        M[i, 3], M[i, 4], M[i, 5] = M[i, 3] - s * v3, M[i, 4] - s * v4, M[i, 5] - s * v5
        r = 6
        while r <= t:
            M[i, r] -= s * M[k, r]
            r += 1
        M[k, t] = s
        x[i] -= s * xk
    s0, s1, s2, s3, s4, s5 = v0 / piv, v1 / piv, v2 / piv, v3 / piv, v4 / piv, v5 / piv
    i = anc[k, 5]
    M[i, 0], M[i, 1], M[i, 2] = M[i, 0] - s5 * v0, M[i, 1] - s5 * v1, M[i, 2] - s5 * v2
    M[i, 3], M[i, 4], M[i, 5] = M[i, 3] - s5 * v3, M[i, 4] - s5 * v4, M[i, 5] - s5 * v5
    x[i] -= s5 * xk
    i = anc[k, 4]
    M[i, 0], M[i, 1], M[i, 2] = M[i, 0] - s4 * v0, M[i, 1] - s4 * v1, M[i, 2] - s4 * v2
    M[i, 3], M[i, 4] = M[i, 3] - s4 * v3, M[i, 4] - s4 * v4
    x[i] -= s4 * xk
    i = anc[k, 3]
    M[i, 0], M[i, 1], M[i, 2], M[i, 3] = M[i, 0] - s3 * v0, M[i, 1] - s3 * v1, M[i, 2] - s3 * v2, M[i, 3] - s3 * v3
    x[i] -= s3 * xk
    i = anc[k, 2]
    M[i, 0], M[i, 1], M[i, 2] = M[i, 0] - s2 * v0, M[i, 1] - s2 * v1, M[i, 2] - s2 * v2
    x[i] -= s2 * xk
    i = anc[k, 1]
    M[i, 0], M[i, 1] = M[i, 0] - s1 * v0, M[i, 1] - s1 * v1
    x[i] -= s1 * xk
    i = anc[k, 0]
    M[i, 0] -= s0 * v0
    x[i] -= s0 * xk
    M[k, 0], M[k, 1], M[k, 2], M[k, 3], M[k, 4], M[k, 5] = s0, s1, s2, s3, s4, s5


@jitable(inline=True)
def _block_measure(M, anc, depth, k, dk):
    """``(det, e)`` of the current (Schur complement) block of speed ``k`` and its one or two nearest ancestors on
    the path (``dk >= 1``), ``e`` the sum of its principal minors one size down: ``det / e`` lies between
    ``lambda_min / n`` and ``lambda_min`` for an ``n x n`` positive definite block, whatever the order of its speeds.
    The rows of the speeds not yet eliminated hold the Schur complement of those that are, whose ``lambda_min`` is at
    least ``M``'s, so a small ``det / e`` proves ``M`` singular to working precision however the speeds are ordered;
    a single pivot does not (a point mass on a ball: the pivot of the speed eliminated last is ``lambda_min / v_k^2``,
    large where the null direction ``v`` is nearly orthogonal to that speed's axis)."""
    p = anc[k, dk - 1]
    a, b, d = M[k, dk], M[p, depth[p]], M[k, dk - 1]
    if dk == 1:
        return a * b - d * d, a + b
    g = anc[k, dk - 2]
    c, e, f = M[g, depth[g]], M[k, dk - 2], M[p, depth[p] - 1]
    minors = (b * c - f * f) + (a * c - e * e) + (a * b - d * d)
    det = a * (b * c - f * f) - d * (d * c - f * e) + e * (d * f - b * e)
    return det, minors


@leaf
def factor_solve(M, x, anc, depth, diag, floor):
    """``x = M^-1 x`` through ``M = L^T D L`` on the speeds' paths, in place; each update a contiguous loop (an
    earlier speed's path is a prefix of a later one's). Returns 1 when a pivot, or the smallest eigenvalue of its
    block with its two nearest ancestors (:func:`_block_measure`), is not above ``floor`` times its scale, its
    diagonal entry before elimination plus the mean diagonal entry (``diag``, scratch ``(nv,)``:
    :data:`relacc.core.tolerances.PIVOT_FLOOR`); else 2 when one is at most :data:`relacc.core.tolerances.ILL_FLOOR`
    times it (solved, fewer than six digits certain), else 0."""
    nv = x.shape[0]
    total = 0.0
    for k in range(nv):
        diag[k] = M[k, depth[k]]
        total += diag[k]
    mean = total / max(nv, 1)
    warned = 0
    for k in range(nv - 1, -1, -1):  # with the solve of L^T D y = x: x[k] is final once its descendants are done
        dk = depth[k]
        piv = M[k, dk]
        scale = diag[k] + mean
        if not piv > floor * scale:
            return 1
        if ill(piv, ILL_FLOOR * scale):
            warned = 2
        if dk >= 1:
            det, minors = _block_measure(M, anc, depth, k, dk)
            if not det > floor * scale * minors:
                return 1
            if ill(det, ILL_FLOOR * scale * minors):
                warned = 2
        xk = x[k]
        if dk >= 6:  # the path's first six speeds (a free root's, on a floating tree) written out
            _past_six(M, x, anc, k, dk, piv, xk)
        else:
            for t in range(dk - 1, -1, -1):
                i = anc[k, t]
                s = M[k, t] / piv
                for r in range(t + 1):  # row i's entries: its path is anc[k, :t], its diagonal at t
                    M[i, r] -= s * M[k, r]
                M[k, t] = s
                x[i] -= s * xk
        x[k] = xk / piv
    for k in range(nv):
        s = x[k]
        for t in range(depth[k]):
            s -= M[k, t] * x[anc[k, t]]
        x[k] = s
    return warned


if HAVE_NUMBA:

    @numba.njit(cache=True, nogil=True)
    def crba_block(case, q, u, tau, T, qadr, anc, depth, mass, com, inertia, arm, free, g, out, start,
                   stop):  # pragma: no cover - compiled
        """States ``start .. stop - 1``; ``(bad inputs, singular states, ill-conditioned states)``. Case 3 is solved
        in case-2 speeds on its angles, state by state (:func:`relacc.kernels.tree_spatial.row_to_speeds`). Without
        the GIL: a batch's shares run on Python threads at once (:func:`relacc.kernels.jit.split`)."""
        nv, nb, nj = u.shape[1], T.parent.shape[0], T.jtype.shape[0]
        S, C, o, R = np.empty((nv, 6)), np.empty((max(nj, 1), 6)), np.empty((nb, 3)), np.empty((nb, 9))
        V, IA, pA = np.empty((nb, 6)), np.empty((nb, 21)), np.empty((nb, 6))
        A, f = np.empty((nb, 6)), np.empty((nb, 6))
        M, x, tmp, diag = np.zeros((nv, anc.shape[1] + 1)), np.empty(nv), np.empty(18), np.empty(nv)
        Q1, U1, F1 = np.empty((1, q.shape[1])), np.empty((1, nv)), np.empty((1, nv))  # case 3's state in case 2
        trig = np.empty((max(nj, 1), 6))
        bad_in, singular, warned = 0, 0, 0
        mode = ANGLES_CASE2 if case == 3 else case
        for i in range(start, stop):
            bad_in += bad_inputs(case, q, u, i, T, qadr)
            if mode == ANGLES_CASE2:
                for c in range(q.shape[1]):
                    Q1[0, c] = q[i, c]
                row_to_speeds(q, u, tau, i, T, U1, F1, 0, trig)
                qq, uu, tt, r = Q1, U1, F1, 0
            else:
                qq, uu, tt, r = q, u, tau, i
            forward(mode, qq, uu, r, T, qadr, mass, com, inertia, S, C, o, R, V, IA, pA)
            mass_matrix(mode, qq, uu, tt, r, T, qadr, anc, depth, arm, free, g, S, C, R, V, IA, pA, A, f, M, x, tmp)
            code = factor_solve(M, x, anc, depth, diag, PIVOT_FLOOR)
            failed = 1 if code == 1 else 0
            warned += 1 if code == 2 else 0
            if failed:
                for c in range(nv):
                    out[i, c] = np.nan
            elif mode == ANGLES_CASE2:
                for c in range(nv):
                    U1[0, c] = x[c]
                row_to_rates(q, u, i, U1, 0, T, out, trig)
            else:
                for c in range(nv):
                    out[i, c] = x[c]
            singular += failed
        return bad_in, singular, warned


__all__ = ["HINGE", "SLIDE", "dof_paths", "factor_solve", "mass_matrix"]
