"""The spatial pass shared by the compiled tree dynamics (:mod:`~relacc.kernels.tree_aba`, :mod:`~.tree_crba`).

Spatial vectors ``(omega, v_O)`` about a point ``O`` fixed in space where each independent subtree's root is at
this instant (the root's origin: levers stay relative, no digits are lost far from the world origin); in one frame
fixed in space, no transform is needed between a parent and its child. A speed's column is ``S = [a; r x a]`` for a
rotation about ``a`` through ``r`` (``a`` a column of the case's partial angular velocities ``A``: the note's choice
of speeds enters here and nowhere else), ``[0; e]`` for a translation; a joint's velocity-product acceleration is
``c = S_dot u_j``, from ``A_dot`` and the anchor's velocity. Each body's spatial inertia about ``O`` is packed as the
upper triangle of a symmetric 6x6 (:data:`SYM`), its bias force is ``v x* I v``.
"""

from __future__ import annotations

import numpy as np

from relacc.core.tolerances import ILL_FLOOR, QUATERNION_NORM_TOLERANCE
from relacc.kernels.jit import jitable, leaf
from relacc.kernels.so3 import cross_inline as cross
from relacc.kernels.so3 import mm_inline as mm
from relacc.kernels.so3 import mv_inline as mv
from relacc.kernels.so3 import r123, w123_dot_mv, w123_mv, w123_solve
from relacc.kernels.tree import BALL, FREE, HINGE, SLIDE, angular, axis_rotation, rotation9, row9


def inertia_arrays(tree):
    """``(mass (nb,), com (nb, 3), inertia (nb, 9) body components, armature (nv,), free (nb,) bool)``."""
    arm = np.concatenate([j.armature for _, j in tree.joints]) if tree.joints else np.zeros(0)
    return (np.array([b.mass for b in tree.bodies]), np.array([b.com for b in tree.bodies]).reshape(-1, 3),
            np.array([b.inertia.reshape(9) for b in tree.bodies]).reshape(-1, 9), np.ascontiguousarray(arm),
            np.array([any(j.type == "free" for j in b.joints) for b in tree.bodies]))


@leaf
def bad_inputs(case, q, u, i, T, qadr):
    """The number of non-finite inputs and non-unit quaternions of state ``i``."""
    bad = 0
    for k in range(q.shape[1]):
        bad += 0 if (q[i, k] - q[i, k]) == 0.0 else 1
    for k in range(u.shape[1]):
        bad += 0 if (u[i, k] - u[i, k]) == 0.0 else 1
    if case < 3:  # quaternions
        for k in range(T.jtype.shape[0]):
            if T.jtype[k] == BALL or T.jtype[k] == FREE:
                a = qadr[k] + (3 if T.jtype[k] == FREE else 0)
                n2 = q[i, a] ** 2 + q[i, a + 1] ** 2 + q[i, a + 2] ** 2 + q[i, a + 3] ** 2
                bad += 0 if abs(n2 - 1.0) <= QUATERNION_NORM_TOLERANCE else 1
    return bad


@leaf
def forward(case, q, u, i, T, qadr, mass, com, inertia, S, C, o, R, V, IA, pA):
    """State ``i``, root to leaves: every speed's column ``S (nv, 6)``, every joint's ``c = S_dot u_j`` (``C (nj,
    6)``), every body's origin from ``O`` (``o``), orientation ``R``, spatial velocity ``V (nb, 6)``, spatial inertia
    ``IA (nb, 21)`` (packed upper triangle) and bias force ``pA = v x* I v``."""
    nb = T.parent.shape[0]
    eye = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)
    zero3 = (0.0, 0.0, 0.0)
    for b in range(nb):
        p = T.parent[b]
        js, jn = T.jstart[b], T.jnum[b]
        if jn == 1 and T.jtype[js] == FREE:
            a, d = qadr[js], T.dofadr[js]
            Ra = rotation9(case, q, i, a + 3)
            Am, Ad, wj = angular(case, FREE, q, u, i, a + 3, d + 3, eye, zero3, eye, zero3, Ra)
            pd0, pd1, pd2 = u[i, d], u[i, d + 1], u[i, d + 2]
            for k in range(3):
                S[d + k, 0], S[d + k, 1], S[d + k, 2] = 0.0, 0.0, 0.0
                S[d + k, 3], S[d + k, 4], S[d + k, 5] = 1.0 if k == 0 else 0.0, 1.0 if k == 1 else 0.0, \
                    1.0 if k == 2 else 0.0
                S[d + 3 + k, 0], S[d + 3 + k, 1], S[d + 3 + k, 2] = Am[k], Am[3 + k], Am[6 + k]
                S[d + 3 + k, 3], S[d + 3 + k, 4], S[d + 3 + k, 5] = 0.0, 0.0, 0.0  # r = 0: O is the origin
            for k in range(9):
                R[b, k] = Ra[k]
            o[b, 0], o[b, 1], o[b, 2] = 0.0, 0.0, 0.0
            w0, w1, w2 = wj
            aw = mv(Ad, u[i, d + 3], u[i, d + 4], u[i, d + 5])
            c0, c1, c2 = cross(pd0, pd1, pd2, w0, w1, w2)  # S_dot's linear part: p_dot x A
            V[b, 0], V[b, 1], V[b, 2], V[b, 3], V[b, 4], V[b, 5] = w0, w1, w2, pd0, pd1, pd2
            C[js, 0], C[js, 1], C[js, 2] = aw
            C[js, 3], C[js, 4], C[js, 5] = c0, c1, c2
            body_inertia(b, mass, com, inertia, o, R, V, IA, pA)
            continue
        if p < 0:
            o[b, 0], o[b, 1], o[b, 2] = 0.0, 0.0, 0.0  # O: where the body is placed
            for k in range(9):
                R[b, k] = T.bR[b, k]
            for k in range(6):
                V[b, k] = 0.0
        else:
            Rp = row9(R, p)
            r0, r1, r2 = mv(Rp, T.bpos[b, 0], T.bpos[b, 1], T.bpos[b, 2])
            o[b, 0], o[b, 1], o[b, 2] = o[p, 0] + r0, o[p, 1] + r1, o[p, 2] + r2
            Rn = mm(Rp, row9(T.bR, b))
            for k in range(9):
                R[b, k] = Rn[k]
            for k in range(6):
                V[b, k] = V[p, k]
        for k in range(js, js + jn):
            kind, a, d = T.jtype[k], qadr[k], T.dofadr[k]
            Rb = row9(R, b)
            w0, w1, w2 = V[b, 0], V[b, 1], V[b, 2]
            if kind == SLIDE:
                e0, e1, e2 = mv(Rb, T.jaxis[k, 0], T.jaxis[k, 1], T.jaxis[k, 2])
                s = q[i, a] - T.jref[k]
                ud = u[i, d]
                S[d, 0], S[d, 1], S[d, 2], S[d, 3], S[d, 4], S[d, 5] = 0.0, 0.0, 0.0, e0, e1, e2
                x0, x1, x2 = cross(w0, w1, w2, e0, e1, e2)
                V[b, 3], V[b, 4], V[b, 5] = V[b, 3] + e0 * ud, V[b, 4] + e1 * ud, V[b, 5] + e2 * ud
                C[k, 0], C[k, 1], C[k, 2], C[k, 3], C[k, 4], C[k, 5] = 0.0, 0.0, 0.0, x0 * ud, x1 * ud, x2 * ud
                o[b, 0], o[b, 1], o[b, 2] = o[b, 0] + e0 * s, o[b, 1] + e1 * s, o[b, 2] + e2 * s
                continue
            jx, jy, jz = T.jpos[k, 0], T.jpos[k, 1], T.jpos[k, 2]
            t0, t1, t2 = mv(Rb, jx, jy, jz)
            ra0, ra1, ra2 = o[b, 0] + t0, o[b, 1] + t1, o[b, 2] + t2  # the anchor, from O
            c0, c1, c2 = cross(w0, w1, w2, ra0, ra1, ra2)
            va0, va1, va2 = V[b, 3] + c0, V[b, 4] + c1, V[b, 5] + c2  # the anchor's velocity
            if kind == HINGE:
                e0, e1, e2 = mv(Rb, T.jaxis[k, 0], T.jaxis[k, 1], T.jaxis[k, 2])
                Rn = mm(Rb, axis_rotation(T.jaxis[k, 0], T.jaxis[k, 1], T.jaxis[k, 2], q[i, a] - T.jref[k]))
                m0, m1, m2 = cross(ra0, ra1, ra2, e0, e1, e2)
                S[d, 0], S[d, 1], S[d, 2], S[d, 3], S[d, 4], S[d, 5] = e0, e1, e2, m0, m1, m2
                ed0, ed1, ed2 = cross(w0, w1, w2, e0, e1, e2)  # the axis' rate
                n0, n1, n2 = cross(va0, va1, va2, e0, e1, e2)
                h0, h1, h2 = cross(ra0, ra1, ra2, ed0, ed1, ed2)
                ud = u[i, d]
                V[b, 0], V[b, 1], V[b, 2] = w0 + e0 * ud, w1 + e1 * ud, w2 + e2 * ud
                V[b, 3], V[b, 4], V[b, 5] = V[b, 3] + m0 * ud, V[b, 4] + m1 * ud, V[b, 5] + m2 * ud
                C[k, 0], C[k, 1], C[k, 2] = ed0 * ud, ed1 * ud, ed2 * ud
                C[k, 3], C[k, 4], C[k, 5] = (n0 + h0) * ud, (n1 + h1) * ud, (n2 + h2) * ud
            else:  # ball
                Rn = mm(Rb, rotation9(case, q, i, a))
                pp = T.parent[b]
                Rp = row9(R, pp) if pp >= 0 else eye
                wp = (V[pp, 0], V[pp, 1], V[pp, 2]) if pp >= 0 else zero3
                Am, Ad, wj = angular(case, BALL, q, u, i, a, d, Rb, (w0, w1, w2), Rp, wp, Rn)
                for c in range(3):
                    a0, a1, a2 = Am[c], Am[3 + c], Am[6 + c]
                    m0, m1, m2 = cross(ra0, ra1, ra2, a0, a1, a2)
                    S[d + c, 0], S[d + c, 1], S[d + c, 2], S[d + c, 3], S[d + c, 4], S[d + c, 5] = \
                        a0, a1, a2, m0, m1, m2
                x0, x1, x2 = wj
                ad0, ad1, ad2 = mv(Ad, u[i, d], u[i, d + 1], u[i, d + 2])
                m0, m1, m2 = cross(ra0, ra1, ra2, x0, x1, x2)
                n0, n1, n2 = cross(va0, va1, va2, x0, x1, x2)
                h0, h1, h2 = cross(ra0, ra1, ra2, ad0, ad1, ad2)
                V[b, 0], V[b, 1], V[b, 2] = w0 + x0, w1 + x1, w2 + x2
                V[b, 3], V[b, 4], V[b, 5] = V[b, 3] + m0, V[b, 4] + m1, V[b, 5] + m2
                C[k, 0], C[k, 1], C[k, 2] = ad0, ad1, ad2
                C[k, 3], C[k, 4], C[k, 5] = n0 + h0, n1 + h1, n2 + h2
            for c in range(9):
                R[b, c] = Rn[c]
            b0, b1, b2 = mv(Rn, -jx, -jy, -jz)
            o[b, 0], o[b, 1], o[b, 2] = ra0 + b0, ra1 + b1, ra2 + b2
        body_inertia(b, mass, com, inertia, o, R, V, IA, pA)


# the packed upper triangle of a symmetric 6x6 matrix: SYM[r, c] is the index of entry (r, c)
SYM = np.array([[0, 1, 2, 3, 4, 5], [1, 6, 7, 8, 9, 10], [2, 7, 11, 12, 13, 14], [3, 8, 12, 15, 16, 17],
                [4, 9, 13, 16, 18, 19], [5, 10, 14, 17, 19, 20]], dtype=np.int64)


@jitable(inline=True)
def body_inertia(b, mass, com, inertia, o, R, V, IA, pA):
    """Body ``b``'s spatial inertia about ``O`` into ``IA[b]`` (packed) and its bias force ``v x* I v`` into ``pA[b]``.

    ``I = [[I_O, [h~]], [[h~]^T, m 1]]`` with ``h = m c`` (``c`` the mass centre from ``O``) and
    ``I_O = I_c + m (|c|^2 1 - c c^T)``: ``I (w, v) = (I_O w + h x v, m v + w x h)``."""
    Rb = row9(R, b)
    m = mass[b]
    rc = mv(Rb, com[b, 0], com[b, 1], com[b, 2])
    r0, r1, r2 = o[b, 0] + rc[0], o[b, 1] + rc[1], o[b, 2] + rc[2]
    J = (inertia[b, 0], inertia[b, 1], inertia[b, 2], inertia[b, 3], inertia[b, 4], inertia[b, 5], inertia[b, 6],
         inertia[b, 7], inertia[b, 8])
    RJ = mm(Rb, J)
    xx = RJ[0] * Rb[0] + RJ[1] * Rb[1] + RJ[2] * Rb[2]
    xy = RJ[0] * Rb[3] + RJ[1] * Rb[4] + RJ[2] * Rb[5]
    xz = RJ[0] * Rb[6] + RJ[1] * Rb[7] + RJ[2] * Rb[8]
    yy = RJ[3] * Rb[3] + RJ[4] * Rb[4] + RJ[5] * Rb[5]
    yz = RJ[3] * Rb[6] + RJ[4] * Rb[7] + RJ[5] * Rb[8]
    zz = RJ[6] * Rb[6] + RJ[7] * Rb[7] + RJ[8] * Rb[8]
    rr = r0 * r0 + r1 * r1 + r2 * r2
    xx, yy, zz = xx + m * (rr - r0 * r0), yy + m * (rr - r1 * r1), zz + m * (rr - r2 * r2)
    xy, xz, yz = xy - m * r0 * r1, xz - m * r0 * r2, yz - m * r1 * r2
    h0, h1, h2 = m * r0, m * r1, m * r2
    # rows of I: [xx xy xz | 0 -h2 h1], [. yy yz | h2 0 -h0], [. . zz | -h1 h0 0], [. . . | m 0 0] ...
    IA[b, 0], IA[b, 1], IA[b, 2], IA[b, 3], IA[b, 4], IA[b, 5] = xx, xy, xz, 0.0, -h2, h1
    IA[b, 6], IA[b, 7], IA[b, 8], IA[b, 9], IA[b, 10] = yy, yz, h2, 0.0, -h0
    IA[b, 11], IA[b, 12], IA[b, 13], IA[b, 14] = zz, -h1, h0, 0.0
    IA[b, 15], IA[b, 16], IA[b, 17], IA[b, 18], IA[b, 19], IA[b, 20] = m, 0.0, 0.0, m, 0.0, m
    w0, w1, w2, v0, v1, v2 = V[b, 0], V[b, 1], V[b, 2], V[b, 3], V[b, 4], V[b, 5]
    c0, c1, c2 = cross(h0, h1, h2, v0, v1, v2)
    d0, d1, d2 = cross(w0, w1, w2, h0, h1, h2)
    L0, L1, L2 = xx * w0 + xy * w1 + xz * w2 + c0, xy * w0 + yy * w1 + yz * w2 + c1, xz * w0 + yz * w1 + zz * w2 + c2
    p0, p1, p2 = m * v0 + d0, m * v1 + d1, m * v2 + d2
    x0, x1, x2 = cross(w0, w1, w2, L0, L1, L2)
    y0, y1, y2 = cross(v0, v1, v2, p0, p1, p2)
    z0, z1, z2 = cross(w0, w1, w2, p0, p1, p2)
    pA[b, 0], pA[b, 1], pA[b, 2], pA[b, 3], pA[b, 4], pA[b, 5] = x0 + y0, x1 + y1, x2 + y2, z0, z1, z2


@jitable(inline=True)
def sym_mv(P, b, x, j):
    """``P[b] x[j]`` for a packed symmetric 6x6 ``P[b]`` (a 6-tuple; indexed, never sliced)."""
    x0, x1, x2, x3, x4, x5 = x[j, 0], x[j, 1], x[j, 2], x[j, 3], x[j, 4], x[j, 5]
    return (P[b, 0] * x0 + P[b, 1] * x1 + P[b, 2] * x2 + P[b, 3] * x3 + P[b, 4] * x4 + P[b, 5] * x5,
            P[b, 1] * x0 + P[b, 6] * x1 + P[b, 7] * x2 + P[b, 8] * x3 + P[b, 9] * x4 + P[b, 10] * x5,
            P[b, 2] * x0 + P[b, 7] * x1 + P[b, 11] * x2 + P[b, 12] * x3 + P[b, 13] * x4 + P[b, 14] * x5,
            P[b, 3] * x0 + P[b, 8] * x1 + P[b, 12] * x2 + P[b, 15] * x3 + P[b, 16] * x4 + P[b, 17] * x5,
            P[b, 4] * x0 + P[b, 9] * x1 + P[b, 13] * x2 + P[b, 16] * x3 + P[b, 18] * x4 + P[b, 19] * x5,
            P[b, 5] * x0 + P[b, 10] * x1 + P[b, 14] * x2 + P[b, 17] * x3 + P[b, 19] * x4 + P[b, 20] * x5)


@jitable(inline=True)
def rigid_mv(P, b, x, j):
    """``P[b] x[j]`` for a packed rigid-body spatial inertia, a body's own or a sum of them (:func:`body_inertia`: its
    lower right block ``m 1``, its upper right ``[h~]``), skipping the entries that are 0 and reading ``m`` once; the
    other products are summed in :func:`sym_mv`'s order, so the result is its, bit for bit (an articulated inertia
    is not rigid: :func:`sym_mv`)."""
    x0, x1, x2, x3, x4, x5 = x[j, 0], x[j, 1], x[j, 2], x[j, 3], x[j, 4], x[j, 5]
    m = P[b, 15]
    return (P[b, 0] * x0 + P[b, 1] * x1 + P[b, 2] * x2 + P[b, 4] * x4 + P[b, 5] * x5,
            P[b, 1] * x0 + P[b, 6] * x1 + P[b, 7] * x2 + P[b, 8] * x3 + P[b, 10] * x5,
            P[b, 2] * x0 + P[b, 7] * x1 + P[b, 11] * x2 + P[b, 12] * x3 + P[b, 13] * x4,
            P[b, 8] * x1 + P[b, 12] * x2 + m * x3,
            P[b, 4] * x0 + P[b, 13] * x2 + m * x4,
            P[b, 5] * x0 + P[b, 10] * x1 + m * x5)


@jitable(inline=True)
def ill(pivot, bound):
    """Whether a pivot that passed the singularity test is at most ``bound`` (:data:`relacc.core.tolerances.
    ILL_FLOOR` times its scale): the state's accelerations then carry fewer than six certain digits. A call of its
    own, not a comparison in the kernels' code, so that the lanes' trace (:mod:`relacc.kernels.lanes`) records it as
    the state's warning flag rather than as a pivot test."""
    return not pivot > bound


@jitable
def spd_inverse(D, n, out, slot, diag, floor):
    """``out[slot]`` (n x n, row-major) = ``D^-1`` for a symmetric positive definite ``D`` (row-major, n <= 6), by
    Cholesky; ``D`` is overwritten. ``diag`` ``(8,)``: the mass matrix's diagonal entries of the ``n`` speeds, then at
    6 the mean of its diagonal entries met so far and at 7 a flag. Returns 1 when a pivot is not above ``floor``
    times its scale, ``diag[j] + diag[6]`` (:data:`relacc.core.tolerances.PIVOT_FLOOR`), or when ``D``'s smallest
    eigenvalue, judged whatever the order of its speeds by ``1 / trace(D^-1)`` (between ``lambda_min / n`` and
    ``lambda_min``), is not above ``floor`` times the block's scale (its mean diagonal entry plus ``diag[6]``); else
    0, having set ``diag[7]`` to 1 when either is at most :data:`relacc.core.tolerances.ILL_FLOOR` times its
    scale."""
    for j in range(n):
        s = D[j * n + j]
        for k in range(j):
            s -= D[j * n + k] * D[j * n + k]
        scale = diag[j] + diag[6]
        if not s > floor * scale:
            return 1
        if ill(s, ILL_FLOOR * scale):
            diag[7] = 1.0
        s = np.sqrt(s)
        D[j * n + j] = s
        for r in range(j + 1, n):
            t = D[r * n + j]
            for k in range(j):
                t -= D[r * n + k] * D[j * n + k]
            D[r * n + j] = t / s
    for c in range(n):  # solve L L^T x = e_c
        for r in range(n):
            t = 1.0 if r == c else 0.0
            for x in range(r):
                t -= D[r * n + x] * out[slot, x * n + c]
            out[slot, r * n + c] = t / D[r * n + r]
        for r in range(n - 1, -1, -1):
            t = out[slot, r * n + c]
            for x in range(r + 1, n):
                t -= D[x * n + r] * out[slot, x * n + c]
            out[slot, r * n + c] = t / D[r * n + r]
    trace, own = 0.0, 0.0  # 1 / trace(D^-1) lies between lambda_min / n and lambda_min, whatever the speeds' order
    for r in range(n):
        trace += out[slot, r * n + r]
        own += diag[r]
    least = 1.0 / trace
    scale = own / n + diag[6]
    if not least > floor * scale:
        return 1
    if ill(least, ILL_FLOOR * scale):
        diag[7] = 1.0
    return 0


@jitable
def joint_B(case, q, u, i, T, qadr, k, b, R, V, tmp, at):
    """``B`` (``tmp[at:at+9]``) and ``B_dot`` (``tmp[at+9:at+18]``), row-major, of joint ``k``'s rotation (body
    ``b``): a ball's or free joint's MuJoCo speeds are ``B u`` of the case's, ``B = R_after^T A``,
    ``B_dot = R_after^T (A_dot - [w~] A)`` with ``w`` the frame after it (a ball is its body's last rotation: MuJoCo
    allows only slides after it)."""
    kind, a, d = T.jtype[k], qadr[k], T.dofadr[k]
    Ra = row9(R, b)
    w0, w1, w2 = V[b, 0], V[b, 1], V[b, 2]
    eye, zero = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0), (0.0, 0.0, 0.0)
    if kind == FREE:
        a, d = a + 3, d + 3
        Rb, wb, Rp, wp = eye, zero, eye, zero
    else:
        Q = rotation9(case, q, i, a)
        Rb = mm(Ra, (Q[0], Q[3], Q[6], Q[1], Q[4], Q[7], Q[2], Q[5], Q[8]))  # the frame it turns from
        pp = T.parent[b]
        Rp = row9(R, pp) if pp >= 0 else eye
        wp = (V[pp, 0], V[pp, 1], V[pp, 2]) if pp >= 0 else zero
        _, _, wj = angular(case, BALL, q, u, i, a, d, Rb, zero, Rp, wp, Ra)  # A u: A needs no w
        wb = (w0 - wj[0], w1 - wj[1], w2 - wj[2])
    Am, Ad, _ = angular(case, kind, q, u, i, a, d, Rb, wb, Rp, wp, Ra)
    for r in range(3):
        for c in range(3):
            s, t = 0.0, 0.0
            for x in range(3):
                s += Ra[3 * x + r] * Am[3 * x + c]
                t += Ra[3 * x + r] * Ad[3 * x + c]
            tmp[at + 3 * r + c] = s
            tmp[at + 9 + 3 * r + c] = t
    for c in range(3):  # B_dot -= R_after^T [w_after~] A, column by column
        y0, y1, y2 = cross(w0, w1, w2, Am[c], Am[3 + c], Am[6 + c])
        z = mv((Ra[0], Ra[3], Ra[6], Ra[1], Ra[4], Ra[7], Ra[2], Ra[5], Ra[8]), y0, y1, y2)
        tmp[at + 9 + c] -= z[0]
        tmp[at + 12 + c] -= z[1]
        tmp[at + 15 + c] -= z[2]


@jitable(inline=True)
def rank_one(IA, b, U0, U1, U2, U3, U4, U5, Di):
    """``IA[b] -= U U^T / D`` on the packed upper triangle, written out (21 entries)."""
    V0, V1, V2, V3, V4, V5 = U0 * Di, U1 * Di, U2 * Di, U3 * Di, U4 * Di, U5 * Di
    IA[b, 0] -= V0 * U0
    IA[b, 1] -= V0 * U1
    IA[b, 2] -= V0 * U2
    IA[b, 3] -= V0 * U3
    IA[b, 4] -= V0 * U4
    IA[b, 5] -= V0 * U5
    IA[b, 6] -= V1 * U1
    IA[b, 7] -= V1 * U2
    IA[b, 8] -= V1 * U3
    IA[b, 9] -= V1 * U4
    IA[b, 10] -= V1 * U5
    IA[b, 11] -= V2 * U2
    IA[b, 12] -= V2 * U3
    IA[b, 13] -= V2 * U4
    IA[b, 14] -= V2 * U5
    IA[b, 15] -= V3 * U3
    IA[b, 16] -= V3 * U4
    IA[b, 17] -= V3 * U5
    IA[b, 18] -= V4 * U4
    IA[b, 19] -= V4 * U5
    IA[b, 20] -= V5 * U5


# Case 3 is solved in case-2 speeds: each ball's and free joint's rates ``theta_dot`` to its body angular velocity
# ``u2 = R^T W theta_dot`` and ``tau`` to ``tau2 = R^T W^-T tau`` (``R = Rx Ry Rz``, ``W`` the 1-2-3 rate map; hinges
# and slides unchanged), the forward dynamics in ANGLES_CASE2 (the angles, case-2 speeds), then
# ``theta_ddot = W^-1 (R u2_dot - W_dot theta_dot)`` (``R^T W_dot``'s other term, ``omega x omega``, is zero). The
# error is ``cond(W)`` times case 2's, as :func:`relacc.dynamics.tree._angle_rates`.


@jitable
def _trig(q, i, k, T):
    """``(d, c1, c2, c3, s1, s2, s3)``: joint ``k``'s (a ball's or free joint's) first angular speed and the cosines and
    sines of its three 1-2-3 angles at state ``i`` (case-3 coordinates)."""
    kind = T.jtype[k]
    a, d = T.qadr3[k] + (3 if kind == FREE else 0), T.dofadr[k] + (3 if kind == FREE else 0)
    c1, c2, c3 = np.cos(q[i, a]), np.cos(q[i, a + 1]), np.cos(q[i, a + 2])
    s1, s2, s3 = np.sin(q[i, a]), np.sin(q[i, a + 1]), np.sin(q[i, a + 2])
    return d, c1, c2, c3, s1, s2, s3


@leaf
def row_to_speeds(q, u, tau, i, T, u2, tau2, r, trig):
    """Row ``i`` of case 3's ``(u, tau)`` to case-2 speeds and forces, into row ``r`` of ``(u2, tau2)``; each ball's
    and free joint's cosines and sines into ``trig[k, :6]`` (``(nj, >= 6)`` scratch) for :func:`row_to_rates`."""
    for c in range(u.shape[1]):
        u2[r, c], tau2[r, c] = u[i, c], tau[i, c]
    for k in range(T.jtype.shape[0]):
        kind = T.jtype[k]
        if kind != BALL and kind != FREE:
            continue
        d, c1, c2, c3, s1, s2, s3 = _trig(q, i, k, T)
        trig[k, 0], trig[k, 1], trig[k, 2], trig[k, 3], trig[k, 4], trig[k, 5] = c1, c2, c3, s1, s2, s3
        R = r123(c1, c2, c3, s1, s2, s3)
        w0, w1, w2 = w123_mv(c1, c2, s1, s2, u[i, d], u[i, d + 1], u[i, d + 2])
        u2[r, d] = R[0] * w0 + R[3] * w1 + R[6] * w2  # R^T (W theta_dot)
        u2[r, d + 1] = R[1] * w0 + R[4] * w1 + R[7] * w2
        u2[r, d + 2] = R[2] * w0 + R[5] * w1 + R[8] * w2
        b0, b1, b2 = tau[i, d], tau[i, d + 1], tau[i, d + 2]
        e = (b2 - s2 * b0) / c2  # W^-T b: x0 = b0, then a rotation by theta1
        x0, x1, x2 = b0, c1 * b1 - s1 * e, s1 * b1 + c1 * e
        tau2[r, d] = R[0] * x0 + R[3] * x1 + R[6] * x2
        tau2[r, d + 1] = R[1] * x0 + R[4] * x1 + R[7] * x2
        tau2[r, d + 2] = R[2] * x0 + R[5] * x1 + R[8] * x2


@leaf
def row_to_rates(q, u, i, a2, r, T, out, trig):
    """Row ``r`` of ``a2``, the case-2 speeds' accelerations of state ``i`` (case 3's ``q``, ``u``), to case 3's, into
    ``out[i]``, with the cosines and sines :func:`row_to_speeds` left in ``trig`` for this state."""
    for c in range(u.shape[1]):
        out[i, c] = a2[r, c]
    for k in range(T.jtype.shape[0]):
        kind = T.jtype[k]
        if kind != BALL and kind != FREE:
            continue
        d = T.dofadr[k] + (3 if kind == FREE else 0)
        c1, c2, c3, s1, s2, s3 = trig[k, 0], trig[k, 1], trig[k, 2], trig[k, 3], trig[k, 4], trig[k, 5]
        R = r123(c1, c2, c3, s1, s2, s3)
        x0, x1, x2 = a2[r, d], a2[r, d + 1], a2[r, d + 2]
        r0 = R[0] * x0 + R[1] * x1 + R[2] * x2  # R u2_dot
        r1 = R[3] * x0 + R[4] * x1 + R[5] * x2
        r2 = R[6] * x0 + R[7] * x1 + R[8] * x2
        h0, h1, h2 = w123_dot_mv(c1, c2, s1, s2, u[i, d], u[i, d + 1], u[i, d + 1], u[i, d + 2])
        out[i, d], out[i, d + 1], out[i, d + 2] = w123_solve(c1, c2, s1, s2, r0 - h0, r1 - h1, r2 - h2)
