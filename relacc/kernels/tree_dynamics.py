"""Fused forward dynamics of a tree in any case: the compiled path of :func:`relacc.tree_accelerations`.

Kane's equations of :mod:`relacc.dynamics.tree`, evaluated in O(n d) per state instead of through every
body's partial velocity matrix:

* spatial vectors ``(omega, v_O)`` about a point ``O`` fixed in space where each independent subtree's root
  is at this instant (the root's origin: levers stay relative, no digits are lost far from the world origin);
  a speed's column is ``S = [a; r x a]`` for a rotation about the unit ``a`` through ``r`` (``a`` the case's
  partial angular velocity ``A``'s column), ``[0; e]`` for a translation; its rate ``S_dot`` follows from
  ``A_dot`` and the anchor's velocity;
* the mass matrix by composite rigid bodies, ``M_ij = S_j^T Ic_b S_i`` for ``j`` on ``i``'s path;
* the bias ``S_i^T fc_b`` from each body's ``f = I a + v x* I v`` (``a`` the velocity-product and gravity
  part of its spatial acceleration), summed over subtrees (Newton-Euler);
* ``M = L^T D L`` on the tree's speed chain (MuJoCo's ``mj_factorM``, no fill-in) and its solve.

Armature follows :mod:`relacc.dynamics.tree`. Effects other than gravity go to the reference path.
``tests/test_tree_kernels.py`` holds this kernel to Kane's equations there.
"""

from __future__ import annotations

import weakref

import numpy as np

from relacc.core.tolerances import QUATERNION_NORM_TOLERANCE
from relacc.kernels.jit import HAVE_NUMBA, jitable, numba
from relacc.kernels.tree import (
    BALL,
    FREE,
    HINGE,
    SLIDE,
    angular,
    arrays_of,
    axis_rotation,
    cross3,
    mm9,
    mv9,
    readonly,
    rotation9,
    row9,
)

BLOCK = 64
"""States per parallel task."""


def dof_parents(tree) -> np.ndarray:
    """Per speed, the speed before it on its path (-1 at the start, and at a free joint's first speed)."""
    out = np.full(tree.nv, -1, np.int64)
    last_of = {}
    for b, body in enumerate(tree.bodies):
        prev = last_of.get(body.parent, -1) if body.parent >= 0 else -1
        for k in tree.body_joints[b]:
            j = tree.joints[k][1]
            d = tree.dofadr[k]
            if j.type == "free":
                prev = -1
            for i in range(j.nv):
                out[d + i] = prev
                prev = d + i
        last_of[b] = prev
    return out


def dof_paths(tree):
    """``(anc (nv, D), depth (nv,))``: each speed's earlier speeds on its path, in order (the path of an earlier speed
    is a prefix of it), and their number; ``D`` the longest."""
    par = dof_parents(tree)
    paths = []
    for k in range(tree.nv):
        chain, i = [], par[k]
        while i >= 0:
            chain.append(i)
            i = par[i]
        paths.append(chain[::-1])
    width = max([len(p) for p in paths] + [1])
    anc = np.full((tree.nv, width), -1, np.int64)
    for k, p in enumerate(paths):
        anc[k, :len(p)] = p
    return anc, np.array([len(p) for p in paths], np.int64)


def inertia_arrays(tree):
    """``(mass (nb,), com (nb, 3), inertia (nb, 9) body components, armature (nv,), free (nb,) bool)``."""
    arm = np.concatenate([j.armature for _, j in tree.joints]) if tree.joints else np.zeros(0)
    return (np.array([b.mass for b in tree.bodies]), np.array([b.com for b in tree.bodies]).reshape(-1, 3),
            np.array([b.inertia.reshape(9) for b in tree.bodies]).reshape(-1, 9), np.ascontiguousarray(arm),
            np.array([any(j.type == "free" for j in b.joints) for b in tree.bodies]))


@jitable
def _bad(case, q, u, i, T, qadr):
    """The number of non-finite inputs and non-unit quaternions of state ``i``."""
    bad = 0
    for k in range(q.shape[1]):
        bad += 0 if (q[i, k] - q[i, k]) == 0.0 else 1
    for k in range(u.shape[1]):
        bad += 0 if (u[i, k] - u[i, k]) == 0.0 else 1
    if case != 3:
        for k in range(T.jtype.shape[0]):
            if T.jtype[k] == BALL or T.jtype[k] == FREE:
                a = qadr[k] + (3 if T.jtype[k] == FREE else 0)
                n2 = q[i, a] ** 2 + q[i, a + 1] ** 2 + q[i, a + 2] ** 2 + q[i, a + 3] ** 2
                bad += 0 if abs(n2 - 1.0) <= QUATERNION_NORM_TOLERANCE else 1
    return bad


@jitable
def _state(case, q, u, i, T, qadr, anc, depth, mass, com, inertia, arm, free, g, S, o, R, V, A, Ic, f, M, b_, tmp):
    """Mass matrix and bias ``b_`` of state ``i`` (see module doc); ``M (nv, D + 1)`` holds each speed's row on its
    path: ``M[k, t]`` with speed ``anc[k, t]`` for ``t < depth[k]``, the diagonal at ``M[k, depth[k]]``."""
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
            aw = mv9(Ad, u[i, d + 3], u[i, d + 4], u[i, d + 5])
            c0, c1, c2 = cross3(pd0, pd1, pd2, w0, w1, w2)  # S_dot's linear part: p_dot x A
            V[b, 0], V[b, 1], V[b, 2], V[b, 3], V[b, 4], V[b, 5] = w0, w1, w2, pd0, pd1, pd2
            A[b, 0], A[b, 1], A[b, 2] = aw
            A[b, 3], A[b, 4], A[b, 5] = c0 - g[0], c1 - g[1], c2 - g[2]
            continue
        if p < 0:
            o[b, 0], o[b, 1], o[b, 2] = 0.0, 0.0, 0.0  # O: where the body is placed
            for k in range(9):
                R[b, k] = T.bR[b, k]
            for k in range(6):
                V[b, k] = 0.0
            A[b, 0], A[b, 1], A[b, 2] = 0.0, 0.0, 0.0
            A[b, 3], A[b, 4], A[b, 5] = -g[0], -g[1], -g[2]
        else:
            Rp = row9(R, p)
            r0, r1, r2 = mv9(Rp, T.bpos[b, 0], T.bpos[b, 1], T.bpos[b, 2])
            o[b, 0], o[b, 1], o[b, 2] = o[p, 0] + r0, o[p, 1] + r1, o[p, 2] + r2
            Rn = mm9(Rp, row9(T.bR, b))
            for k in range(9):
                R[b, k] = Rn[k]
            for k in range(6):
                V[b, k] = V[p, k]
                A[b, k] = A[p, k]
        for k in range(js, js + jn):
            kind, a, d = T.jtype[k], qadr[k], T.dofadr[k]
            Rb = row9(R, b)
            w0, w1, w2 = V[b, 0], V[b, 1], V[b, 2]
            if kind == SLIDE:
                e0, e1, e2 = mv9(Rb, T.jaxis[k, 0], T.jaxis[k, 1], T.jaxis[k, 2])
                s = q[i, a] - T.jref[k]
                ud = u[i, d]
                S[d, 0], S[d, 1], S[d, 2], S[d, 3], S[d, 4], S[d, 5] = 0.0, 0.0, 0.0, e0, e1, e2
                x0, x1, x2 = cross3(w0, w1, w2, e0, e1, e2)
                V[b, 3], V[b, 4], V[b, 5] = V[b, 3] + e0 * ud, V[b, 4] + e1 * ud, V[b, 5] + e2 * ud
                A[b, 3], A[b, 4], A[b, 5] = A[b, 3] + x0 * ud, A[b, 4] + x1 * ud, A[b, 5] + x2 * ud
                o[b, 0], o[b, 1], o[b, 2] = o[b, 0] + e0 * s, o[b, 1] + e1 * s, o[b, 2] + e2 * s
                continue
            jx, jy, jz = T.jpos[k, 0], T.jpos[k, 1], T.jpos[k, 2]
            t0, t1, t2 = mv9(Rb, jx, jy, jz)
            ra0, ra1, ra2 = o[b, 0] + t0, o[b, 1] + t1, o[b, 2] + t2  # the anchor, from O
            c0, c1, c2 = cross3(w0, w1, w2, ra0, ra1, ra2)
            va0, va1, va2 = V[b, 3] + c0, V[b, 4] + c1, V[b, 5] + c2  # the anchor's velocity
            if kind == HINGE:
                e0, e1, e2 = mv9(Rb, T.jaxis[k, 0], T.jaxis[k, 1], T.jaxis[k, 2])
                Rn = mm9(Rb, axis_rotation(T.jaxis[k, 0], T.jaxis[k, 1], T.jaxis[k, 2], q[i, a] - T.jref[k]))
                m0, m1, m2 = cross3(ra0, ra1, ra2, e0, e1, e2)
                S[d, 0], S[d, 1], S[d, 2], S[d, 3], S[d, 4], S[d, 5] = e0, e1, e2, m0, m1, m2
                ed0, ed1, ed2 = cross3(w0, w1, w2, e0, e1, e2)  # the axis' rate
                n0, n1, n2 = cross3(va0, va1, va2, e0, e1, e2)
                h0, h1, h2 = cross3(ra0, ra1, ra2, ed0, ed1, ed2)
                ud = u[i, d]
                V[b, 0], V[b, 1], V[b, 2] = w0 + e0 * ud, w1 + e1 * ud, w2 + e2 * ud
                V[b, 3], V[b, 4], V[b, 5] = V[b, 3] + m0 * ud, V[b, 4] + m1 * ud, V[b, 5] + m2 * ud
                A[b, 0], A[b, 1], A[b, 2] = A[b, 0] + ed0 * ud, A[b, 1] + ed1 * ud, A[b, 2] + ed2 * ud
                A[b, 3], A[b, 4], A[b, 5] = A[b, 3] + (n0 + h0) * ud, A[b, 4] + (n1 + h1) * ud, A[b, 5] + (n2 + h2) * ud
            else:  # ball
                Rn = mm9(Rb, rotation9(case, q, i, a))
                pp = T.parent[b]
                Rp = row9(R, pp) if pp >= 0 else eye
                wp = (V[pp, 0], V[pp, 1], V[pp, 2]) if pp >= 0 else zero3
                Am, Ad, wj = angular(case, BALL, q, u, i, a, d, Rb, (w0, w1, w2), Rp, wp, Rn)
                for c in range(3):
                    a0, a1, a2 = Am[c], Am[3 + c], Am[6 + c]
                    m0, m1, m2 = cross3(ra0, ra1, ra2, a0, a1, a2)
                    S[d + c, 0], S[d + c, 1], S[d + c, 2], S[d + c, 3], S[d + c, 4], S[d + c, 5] = \
                        a0, a1, a2, m0, m1, m2
                x0, x1, x2 = wj
                ad0, ad1, ad2 = mv9(Ad, u[i, d], u[i, d + 1], u[i, d + 2])
                m0, m1, m2 = cross3(ra0, ra1, ra2, x0, x1, x2)
                n0, n1, n2 = cross3(va0, va1, va2, x0, x1, x2)
                h0, h1, h2 = cross3(ra0, ra1, ra2, ad0, ad1, ad2)
                V[b, 0], V[b, 1], V[b, 2] = w0 + x0, w1 + x1, w2 + x2
                V[b, 3], V[b, 4], V[b, 5] = V[b, 3] + m0, V[b, 4] + m1, V[b, 5] + m2
                A[b, 0], A[b, 1], A[b, 2] = A[b, 0] + ad0, A[b, 1] + ad1, A[b, 2] + ad2
                A[b, 3], A[b, 4], A[b, 5] = A[b, 3] + n0 + h0, A[b, 4] + n1 + h1, A[b, 5] + n2 + h2
            for c in range(9):
                R[b, c] = Rn[c]
            b0, b1, b2 = mv9(Rn, -jx, -jy, -jz)
            o[b, 0], o[b, 1], o[b, 2] = ra0 + b0, ra1 + b1, ra2 + b2
    # each body's spatial inertia about O (m, m c, I_O) and its force f = I a + v x* I v
    for b in range(nb):
        Rb = row9(R, b)
        m = mass[b]
        rc = mv9(Rb, com[b, 0], com[b, 1], com[b, 2])
        r0, r1, r2 = o[b, 0] + rc[0], o[b, 1] + rc[1], o[b, 2] + rc[2]
        J = (inertia[b, 0], inertia[b, 1], inertia[b, 2], inertia[b, 3], inertia[b, 4], inertia[b, 5],
             inertia[b, 6], inertia[b, 7], inertia[b, 8])
        RJ = mm9(Rb, J)
        Iw = (RJ[0] * Rb[0] + RJ[1] * Rb[1] + RJ[2] * Rb[2], RJ[0] * Rb[3] + RJ[1] * Rb[4] + RJ[2] * Rb[5],
              RJ[0] * Rb[6] + RJ[1] * Rb[7] + RJ[2] * Rb[8], RJ[3] * Rb[3] + RJ[4] * Rb[4] + RJ[5] * Rb[5],
              RJ[3] * Rb[6] + RJ[4] * Rb[7] + RJ[5] * Rb[8], RJ[6] * Rb[6] + RJ[7] * Rb[7] + RJ[8] * Rb[8])
        rr = r0 * r0 + r1 * r1 + r2 * r2
        # Ic[b]: m, m c (3), I_O: xx, xy, xz, yy, yz, zz
        Ic[b, 0], Ic[b, 1], Ic[b, 2], Ic[b, 3] = m, m * r0, m * r1, m * r2
        Ic[b, 4] = Iw[0] + m * (rr - r0 * r0)
        Ic[b, 5] = Iw[1] - m * r0 * r1
        Ic[b, 6] = Iw[2] - m * r0 * r2
        Ic[b, 7] = Iw[3] + m * (rr - r1 * r1)
        Ic[b, 8] = Iw[4] - m * r1 * r2
        Ic[b, 9] = Iw[5] + m * (rr - r2 * r2)
        L0, L1, L2, p0, p1, p2 = _apply(Ic, b, V[b, 0], V[b, 1], V[b, 2], V[b, 3], V[b, 4], V[b, 5])
        F0, F1, F2, G0, G1, G2 = _apply(Ic, b, A[b, 0], A[b, 1], A[b, 2], A[b, 3], A[b, 4], A[b, 5])
        x0, x1, x2 = cross3(V[b, 0], V[b, 1], V[b, 2], L0, L1, L2)
        y0, y1, y2 = cross3(V[b, 3], V[b, 4], V[b, 5], p0, p1, p2)
        z0, z1, z2 = cross3(V[b, 0], V[b, 1], V[b, 2], p0, p1, p2)
        f[b, 0], f[b, 1], f[b, 2] = F0 + x0 + y0, F1 + x1 + y1, F2 + x2 + y2
        f[b, 3], f[b, 4], f[b, 5] = G0 + z0, G1 + z1, G2 + z2
    for b in range(nb - 1, -1, -1):  # composite inertias and subtree forces (not across free joints)
        p = T.parent[b]
        if p >= 0 and not free[b]:
            for k in range(10):
                Ic[p, k] += Ic[b, k]
            for k in range(6):
                f[p, k] += f[b, k]
    for b in range(nb):
        for k in range(T.jstart[b], T.jstart[b] + T.jnum[b]):
            d = T.dofadr[k]
            nd = 6 if T.jtype[k] == FREE else (3 if T.jtype[k] == BALL else 1)
            for c in range(d, d + nd):
                F0, F1, F2, G0, G1, G2 = _apply(Ic, b, S[c, 0], S[c, 1], S[c, 2], S[c, 3], S[c, 4], S[c, 5])
                dc = depth[c]
                M[c, dc] = S[c, 0] * F0 + S[c, 1] * F1 + S[c, 2] * F2 + S[c, 3] * G0 + S[c, 4] * G1 + S[c, 5] * G2
                b_[c] = S[c, 0] * f[b, 0] + S[c, 1] * f[b, 1] + S[c, 2] * f[b, 2] + S[c, 3] * f[b, 3] \
                    + S[c, 4] * f[b, 4] + S[c, 5] * f[b, 5]
                for t in range(dc):
                    j = anc[c, t]
                    M[c, t] = S[j, 0] * F0 + S[j, 1] * F1 + S[j, 2] * F2 + S[j, 3] * G0 + S[j, 4] * G1 + S[j, 5] * G2
    _armature(case, q, u, i, T, qadr, depth, arm, R, V, M, b_, tmp)


@jitable
def _apply(Ic, b, w0, w1, w2, v0, v1, v2):
    """A spatial inertia about O on a motion ``(w, v)``: ``(I_O w + m c x v, m v + w x m c)``."""
    m, h0, h1, h2 = Ic[b, 0], Ic[b, 1], Ic[b, 2], Ic[b, 3]
    xx, xy, xz, yy, yz, zz = Ic[b, 4], Ic[b, 5], Ic[b, 6], Ic[b, 7], Ic[b, 8], Ic[b, 9]
    c0, c1, c2 = cross3(h0, h1, h2, v0, v1, v2)
    d0, d1, d2 = cross3(w0, w1, w2, h0, h1, h2)
    return (xx * w0 + xy * w1 + xz * w2 + c0, xy * w0 + yy * w1 + yz * w2 + c1, xz * w0 + yz * w1 + zz * w2 + c2,
            m * v0 + d0, m * v1 + d1, m * v2 + d2)


@jitable
def _armature(case, q, u, i, T, qadr, depth, arm, R, V, M, b_, tmp):
    """Armature on MuJoCo's (case 2) speeds: diagonal there; a ball's or free joint's rotation in cases 1 and 3
    through ``u2 = B u``: ``M += B^T D B``, ``bias += B^T D B_dot u`` (:mod:`relacc.dynamics.tree`)."""
    for k in range(T.jtype.shape[0]):
        kind, d = T.jtype[k], T.dofadr[k]
        if kind == HINGE or kind == SLIDE:
            M[d, depth[d]] += arm[d]
            continue
        if kind == FREE:
            for c in range(3):
                M[d + c, depth[d + c]] += arm[d + c]
            d += 3
        if arm[d] == 0.0 and arm[d + 1] == 0.0 and arm[d + 2] == 0.0:
            continue
        if case == 2:
            for c in range(3):
                M[d + c, depth[d + c]] += arm[d + c]
            continue
        # B = R_after^T A, B_dot = R_after^T (A_dot - [w_after~] A), from the frames of the walk
        _joint_B(case, q, u, i, T, qadr, k, R, V, tmp)
        for r in range(3):
            for c in range(r + 1):
                s = 0.0
                for x in range(3):
                    s += tmp[3 * x + r] * arm[d + x] * tmp[3 * x + c]
                M[d + r, depth[d + r] - (r - c)] += s  # the block's speeds follow each other on the path
            s = 0.0
            for x in range(3):
                bd = tmp[9 + 3 * x] * u[i, d] + tmp[10 + 3 * x] * u[i, d + 1] + tmp[11 + 3 * x] * u[i, d + 2]
                s += tmp[3 * x + r] * arm[d + x] * bd
            b_[d + r] += s


@jitable
def _joint_B(case, q, u, i, T, qadr, k, R, V, tmp):
    """``B`` (tmp[0:9]) and ``B_dot`` (tmp[9:18]) of joint ``k``'s rotation, row-major (see :func:`_armature`)."""
    b = 0
    for x in range(T.jstart.shape[0]):
        if T.jstart[x] <= k < T.jstart[x] + T.jnum[x]:
            b = x
    kind, a, d = T.jtype[k], qadr[k], T.dofadr[k]
    Ra = row9(R, b)  # a ball or free joint is its body's last rotation: the body's orientation
    w0, w1, w2 = V[b, 0], V[b, 1], V[b, 2]
    if kind == FREE:
        a, d = a + 3, d + 3
        Rb, wb = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0), (0.0, 0.0, 0.0)
        Rp, wp = Rb, wb
    else:  # a ball is its body's last rotation (MuJoCo allows only slides after it): R_after is the body's
        Q = rotation9(case, q, i, a)
        Rb = mm9(Ra, (Q[0], Q[3], Q[6], Q[1], Q[4], Q[7], Q[2], Q[5], Q[8]))  # the frame it turns from
        pp = T.parent[b]
        Rp = row9(R, pp) if pp >= 0 else (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)
        wp = (V[pp, 0], V[pp, 1], V[pp, 2]) if pp >= 0 else (0.0, 0.0, 0.0)
        _, _, wj = angular(case, BALL, q, u, i, a, d, Rb, (0.0, 0.0, 0.0), Rp, wp, Ra)  # A u: A needs no w
        wb = (w0 - wj[0], w1 - wj[1], w2 - wj[2])
    Am, Ad, _ = angular(case, kind, q, u, i, a, d, Rb, wb, Rp, wp, Ra)
    for r in range(3):
        for c in range(3):
            s, t = 0.0, 0.0
            for x in range(3):
                s += Ra[3 * x + r] * Am[3 * x + c]
                t += Ra[3 * x + r] * Ad[3 * x + c]
            tmp[3 * r + c] = s
            tmp[9 + 3 * r + c] = t
    for c in range(3):  # B_dot -= R_after^T [w_after~] A: column c of A crossed by w_after, in R_after's comps
        y0, y1, y2 = cross3(w0, w1, w2, Am[c], Am[3 + c], Am[6 + c])
        z = mv9((Ra[0], Ra[3], Ra[6], Ra[1], Ra[4], Ra[7], Ra[2], Ra[5], Ra[8]), y0, y1, y2)
        tmp[9 + c] -= z[0]
        tmp[12 + c] -= z[1]
        tmp[15 + c] -= z[2]


@jitable
def factor_solve(M, x, anc, depth):
    """``x = M^-1 x`` through ``M = L^T D L`` on the speeds' paths (MuJoCo's factorization, no fill-in), in place.

    ``M`` holds path rows (see :func:`_state`): an earlier speed's path is a prefix of a later one's, so each update
    is a contiguous loop. Returns 0, or 1 when a pivot is not positive (``M`` singular or not positive definite)."""
    nv = x.shape[0]
    for k in range(nv - 1, -1, -1):
        dk = depth[k]
        piv = M[k, dk]
        if not piv > 0.0:
            return 1
        for t in range(dk - 1, -1, -1):
            i = anc[k, t]
            s = M[k, t] / piv
            for r in range(t + 1):  # row i's entries: its path is anc[k, :t], its diagonal at t
                M[i, r] -= s * M[k, r]
            M[k, t] = s
    for k in range(nv - 1, -1, -1):
        xk = x[k]
        for t in range(depth[k]):
            x[anc[k, t]] -= M[k, t] * xk
    for k in range(nv):
        x[k] /= M[k, depth[k]]
    for k in range(nv):
        s = x[k]
        for t in range(depth[k]):
            s -= M[k, t] * x[anc[k, t]]
        x[k] = s
    return 0


if HAVE_NUMBA:

    @numba.njit(parallel=True, cache=True)
    def _accelerations_loop(case, q, u, tau, T, qadr, anc, depth, mass, com, inertia, arm, free, g,
                            out):  # pragma: no cover - compiled
        n, nv, nb = q.shape[0], u.shape[1], T.parent.shape[0]
        bad_in, singular = 0, 0
        for blk in numba.prange((n + BLOCK - 1) // BLOCK):
            S, o, R = np.empty((nv, 6)), np.empty((nb, 3)), np.empty((nb, 9))
            V, A, Ic, f = np.empty((nb, 6)), np.empty((nb, 6)), np.empty((nb, 10)), np.empty((nb, 6))
            M, x, tmp = np.zeros((nv, anc.shape[1] + 1)), np.empty(nv), np.empty(18)
            nbi, nsg = 0, 0
            for i in range(blk * BLOCK, min(n, (blk + 1) * BLOCK)):
                nbi += _bad(case, q, u, i, T, qadr)
                _state(case, q, u, i, T, qadr, anc, depth, mass, com, inertia, arm, free, g, S, o, R, V, A, Ic, f, M,
                       x, tmp)
                for c in range(nv):
                    x[c] = tau[i, c] - x[c]
                failed = factor_solve(M, x, anc, depth)
                nsg += failed
                for c in range(nv):
                    out[i, c] = np.nan if failed else x[c]
            bad_in += nbi
            singular += nsg
        return bad_in, singular


def accelerations(tree, case: int, q, u, tau, gravity, out=None):
    """``udot`` of checked-shape, C-contiguous float64 ``(n, .)`` inputs (into ``out`` if given).

    Returns:
        ``(udot (n, nv), n_bad_inputs, n_singular)``: the counts of states with non-finite inputs or non-unit
        quaternions, and of states whose mass matrix has a non-positive pivot; callers check and name them.
    """
    T = arrays_of(tree)
    anc, depth = _paths(tree)
    mass, com, inertia, arm, free = inertia_arrays(tree)
    n = q.shape[0]
    out = np.empty((n, tree.nv)) if out is None else out
    ro = lambda a: readonly(np.ascontiguousarray(a, dtype=np.float64))  # noqa: E731
    bad_in, singular = _accelerations_loop(int(case), ro(q), ro(u), ro(tau), T, T.qadr3 if case == 3 else T.qadr,
                                           anc, depth, mass, com, inertia, arm, free, ro(gravity), out)
    return out, int(bad_in), int(singular)


_PATHS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def _paths(tree):
    if tree not in _PATHS:
        _PATHS[tree] = dof_paths(tree)
    return _PATHS[tree]


__all__ = ["accelerations", "dof_parents", "dof_paths", "factor_solve"]
