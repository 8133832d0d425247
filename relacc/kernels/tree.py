"""Fused batch kernel behind :func:`relacc.tree_kinematics`: the walk of :mod:`relacc.core.tree.walk`, compiled.

Per state, for every body in order, the kernel carries the body frame's origin, orientation and angular
velocity, and the partial velocities ``V``, ``Omega`` of the origin and their rates, on the columns of the
speeds that move the body only (its *path*: the parent's path, then its own joints' speeds). A child's
columns are its parent's moved by the placement lever (``[V] - [r~][Omega]``), then each joint adds its
columns exactly as the reference walk does; the mass centre and the named points are levers from the
origin. Work per state is ``sum_b |path_b|`` column operations, not ``nb * nv``.

The tree enters as flat arrays (:class:`TreeArrays`, built once per tree by :func:`arrays_of`). States run in
parallel, in blocks that share one scratch of ``nb x 3 x nv`` doubles per field. ``tests/test_tree_kernels.py``
holds the kernel to the reference walk.
"""

from __future__ import annotations

import math
import weakref
from typing import NamedTuple

import numpy as np

from relacc.kernels.jit import HAVE_NUMBA, first_touch, jitable, leaf, numba, parallel_pays, split
from relacc.kernels.so3 import cross_inline as cross
from relacc.kernels.so3 import mm_inline as mm
from relacc.kernels.so3 import mv_inline as mv
from relacc.kernels.so3 import quat_matrix_inline as quat_matrix
from relacc.kernels.so3 import r123_inline as r123

FREE, BALL, SLIDE, HINGE = 0, 1, 2, 3
ANGLES_CASE2 = 4
"""A kernel-only mode: case-3 coordinates (1-2-3 angles) with case-2 speeds (body angular velocities), in which
:mod:`relacc.kernels.tree_dynamics` solves case 3 (well conditioned; mapped to the rates after)."""
KINDS = {"free": FREE, "ball": BALL, "slide": SLIDE, "hinge": HINGE}
BLOCK = 32
"""States per parallel task (one scratch each)."""

US_PER_BODY_SPEED = 0.07
"""About the kinematics' cost per state, per body and per speed on one core, in us (gymnasium's ant 13 us for 13
bodies and 14 speeds, humanoid 17.5 us for 13 and 23): what :func:`relacc.kernels.jit.parallel_pays` weighs."""


class TreeArrays(NamedTuple):
    """A tree as flat arrays (see the module docstring); ``qadr`` per case in ``qadr3`` for case 3."""

    parent: np.ndarray
    jstart: np.ndarray
    jnum: np.ndarray
    jtype: np.ndarray
    qadr: np.ndarray
    qadr3: np.ndarray
    dofadr: np.ndarray
    jcols: np.ndarray
    path_ptr: np.ndarray
    path_idx: np.ndarray
    bpos: np.ndarray
    bR: np.ndarray
    com: np.ndarray
    jpos: np.ndarray
    jaxis: np.ndarray
    jref: np.ndarray
    pbody: np.ndarray
    ppos: np.ndarray


_CACHE: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def arrays_of(tree) -> TreeArrays:
    """The flat arrays of a tree (computed once per :class:`relacc.Tree` object)."""
    if tree in _CACHE:
        return _CACHE[tree]
    from relacc.core.rotations import matrix_from_quaternion

    nb = tree.nb
    joints = [j for _, j in tree.joints]
    jstart, jnum = np.zeros(nb, np.int64), np.zeros(nb, np.int64)
    for b, ks in enumerate(tree.body_joints):
        jstart[b], jnum[b] = (ks[0] if ks else 0), len(ks)
    path_ptr = np.zeros(nb + 1, np.int64)
    for b in range(nb):
        path_ptr[b + 1] = path_ptr[b] + len(tree.path_dofs[b])
    path_idx = np.array([d for dofs in tree.path_dofs for d in dofs], np.int64)
    jcols = np.zeros(len(joints), np.int64)  # per joint: its first column's place in its body's path
    for b, ks in enumerate(tree.body_joints):
        at = len(tree.path_dofs[tree.bodies[b].parent]) if tree.bodies[b].parent >= 0 else 0
        for k in ks:
            if joints[k].type == "free":
                at = 0
            jcols[k] = at
            at += joints[k].nv
    out = TreeArrays(
        np.array([b.parent for b in tree.bodies], np.int64), jstart, jnum,
        np.array([KINDS[j.type] for j in joints], np.int64), np.array(tree.qadr(2), np.int64),
        np.array(tree.qadr(3), np.int64), np.array(tree.dofadr, np.int64), jcols, path_ptr, path_idx,
        np.array([b.pos for b in tree.bodies]).reshape(nb, 3),
        np.array([matrix_from_quaternion(b.quat).reshape(9) for b in tree.bodies]).reshape(nb, 9),
        np.array([b.com for b in tree.bodies]).reshape(nb, 3),
        np.array([j.pos for j in joints]).reshape(-1, 3), np.array([j.axis for j in joints]).reshape(-1, 3),
        np.array([j.ref for j in joints], float),
        np.array([p.body for p in tree.points], np.int64), np.array([p.pos for p in tree.points]).reshape(-1, 3))
    _CACHE[tree] = out
    return out


@jitable
def rotation9(case, q, i, a):
    """The rotation (row-major 9-tuple) of a quaternion (cases 1-2) or 1-2-3 angles (case 3, and
    :data:`ANGLES_CASE2`) at ``q[i, a:]``."""
    if case >= 3:
        return r123(math.cos(q[i, a]), math.cos(q[i, a + 1]), math.cos(q[i, a + 2]), math.sin(q[i, a]),
                    math.sin(q[i, a + 1]), math.sin(q[i, a + 2]))
    return quat_matrix(q[i, a], q[i, a + 1], q[i, a + 2], q[i, a + 3])


@jitable(inline=True)
def axis_rotation(x, y, z, angle):
    """The rotation by ``angle`` about the unit axis ``(x, y, z)``, through its quaternion (as the walk and MuJoCo)."""
    h = 0.5 * angle
    s = math.sin(h)
    return quat_matrix(math.cos(h), s * x, s * y, s * z)


@jitable(inline=True)
def row9(R, b):
    return (R[b, 0], R[b, 1], R[b, 2], R[b, 3], R[b, 4], R[b, 5], R[b, 6], R[b, 7], R[b, 8])


@jitable
def _move(V, Om, Vd, Omd, b, cols, c0, c1, r0, r1, r2, d0, d1, d2):
    """Body ``b``'s columns ``cols[c0:c1]`` moved by the lever ``r`` with rate ``d``: ``V -= r x Om``,
    ``Vd -= d x Om + r x Omd`` (the scratch arrays ``(nb, 3, nv)``, indexed, never sliced)."""
    for t in range(c0, c1):
        c = cols[t]
        o0, o1, o2 = Om[b, 0, c], Om[b, 1, c], Om[b, 2, c]
        p0, p1, p2 = Omd[b, 0, c], Omd[b, 1, c], Omd[b, 2, c]
        V[b, 0, c] -= r1 * o2 - r2 * o1
        V[b, 1, c] -= r2 * o0 - r0 * o2
        V[b, 2, c] -= r0 * o1 - r1 * o0
        Vd[b, 0, c] -= d1 * o2 - d2 * o1 + r1 * p2 - r2 * p1
        Vd[b, 1, c] -= d2 * o0 - d0 * o2 + r2 * p0 - r0 * p2
        Vd[b, 2, c] -= d0 * o1 - d1 * o0 + r0 * p1 - r1 * p0


@jitable
def _moved_copy(V, Om, Vd, Omd, p, b, cols, c0, c1, r0, r1, r2, d0, d1, d2):
    """Parent ``p``'s columns ``cols[c0:c1]`` into body ``b``'s, moved by the placement lever ``r`` (rate ``d``)."""
    for t in range(c0, c1):
        c = cols[t]
        o0, o1, o2 = Om[p, 0, c], Om[p, 1, c], Om[p, 2, c]
        q0, q1, q2 = Omd[p, 0, c], Omd[p, 1, c], Omd[p, 2, c]
        Om[b, 0, c], Om[b, 1, c], Om[b, 2, c] = o0, o1, o2
        Omd[b, 0, c], Omd[b, 1, c], Omd[b, 2, c] = q0, q1, q2
        V[b, 0, c] = V[p, 0, c] - (r1 * o2 - r2 * o1)
        V[b, 1, c] = V[p, 1, c] - (r2 * o0 - r0 * o2)
        V[b, 2, c] = V[p, 2, c] - (r0 * o1 - r1 * o0)
        Vd[b, 0, c] = Vd[p, 0, c] - (d1 * o2 - d2 * o1 + r1 * q2 - r2 * q1)
        Vd[b, 1, c] = Vd[p, 1, c] - (d2 * o0 - d0 * o2 + r2 * q0 - r0 * q2)
        Vd[b, 2, c] = Vd[p, 2, c] - (d0 * o1 - d1 * o0 + r0 * q1 - r1 * q0)


@jitable
def _set_block(Om, Omd, V, Vd, b, d, m, A, Ad):
    """Body ``b``'s columns ``d .. d+m-1``: ``Om = A``, ``Omd = Ad`` (row-major 9-tuples, first ``m`` columns),
    ``V = Vd = 0`` (a rotation about the frame's origin moves it not)."""
    for j in range(m):
        for i in range(3):
            Om[b, i, d + j] = A[3 * i + j]
            Omd[b, i, d + j] = Ad[3 * i + j]
            V[b, i, d + j] = 0.0
            Vd[b, i, d + j] = 0.0


@jitable
def angular(case, kind, q, u, i, a, d, Rb, wb, Rp, wp, Ra):
    """A ball's or free joint's partial angular velocities ``A``, their rate ``Ad`` (row-major 9-tuples) and
    ``A u_j``, as :func:`relacc.core.tree.walk.angular_map`; ``Rb``, ``wb``: the frame it turns from, ``Rp``, ``wp``:
    its body's parent (a free joint's callers pass the world: identity and zero, so that case 1 gives ``A = I``),
    ``Ra``: the frame after it. (Every variable is bound before the branches: numba inlines it.)"""
    u0, u1, u2 = u[i, d], u[i, d + 1], u[i, d + 2]
    A = Rp  # case 1: the parent body's components (a free joint: fixed components)
    Ad0 = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    w0, w1, w2 = wp[0], wp[1], wp[2]
    if case == 3:
        c1, s1 = math.cos(q[i, a]), math.sin(q[i, a])
        c2, s2 = math.cos(q[i, a + 1]), math.sin(q[i, a + 1])
        W = (1.0, 0.0, s2, 0.0, c1, -s1 * c2, 0.0, s1, c1 * c2)
        Wd = (0.0, 0.0, c2 * u1, 0.0, -s1 * u0, -c1 * c2 * u0 + s1 * s2 * u1, 0.0, c1 * u0,
              -s1 * c2 * u0 - c1 * s2 * u1)
        A, Ad0 = mm(Rb, W), mm(Rb, Wd)
        w0, w1, w2 = wb[0], wb[1], wb[2]
    elif case == 2 or case == ANGLES_CASE2:
        A = Ra
        x0, x1, x2 = mv(Ra, u0, u1, u2)
        w0, w1, w2 = wb[0] + x0, wb[1] + x1, wb[2] + x2  # the frame after the joint
    # Ad = Ad0 + [w~] A, column by column
    c00, c10, c20 = cross(w0, w1, w2, A[0], A[3], A[6])
    c01, c11, c21 = cross(w0, w1, w2, A[1], A[4], A[7])
    c02, c12, c22 = cross(w0, w1, w2, A[2], A[5], A[8])
    Ad = (Ad0[0] + c00, Ad0[1] + c01, Ad0[2] + c02, Ad0[3] + c10, Ad0[4] + c11, Ad0[5] + c12,
          Ad0[6] + c20, Ad0[7] + c21, Ad0[8] + c22)
    return A, Ad, mv(A, u0, u1, u2)


@leaf
def walk_state(case, q, u, i, T, qadr, o, R, w, V, Om, Vd, Omd):
    """The walk of state ``i``: every body's origin ``o (nb, 3)``, orientation ``R (nb, 9)``, angular velocity
    ``w (nb, 3)`` and the path columns of the scratch ``V``, ``Om``, ``Vd``, ``Omd`` ``(nb, 3, nv)``."""
    cols = T.path_idx
    eye = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)
    for b in range(T.parent.shape[0]):
        p = T.parent[b]
        c0, c1 = T.path_ptr[b], T.path_ptr[b + 1]
        js = T.jstart[b]
        if T.jnum[b] == 1 and T.jtype[js] == FREE:
            a, d = qadr[js], T.dofadr[js]
            Ra = rotation9(case, q, i, a + 3)
            for k in range(3):
                o[b, k] = q[i, a + k]
            for k in range(9):
                R[b, k] = Ra[k]
            for t in range(c0, c1):
                c = cols[t]
                for k in range(3):
                    V[b, k, c] = 1.0 if c - d == k else 0.0
                    Om[b, k, c], Vd[b, k, c], Omd[b, k, c] = 0.0, 0.0, 0.0
            A, Ad, wj = angular(case, FREE, q, u, i, a + 3, d + 3, eye, (0.0, 0.0, 0.0), eye, (0.0, 0.0, 0.0), Ra)
            for jj in range(3):
                for ii in range(3):
                    Om[b, ii, d + 3 + jj] = A[3 * ii + jj]
                    Omd[b, ii, d + 3 + jj] = Ad[3 * ii + jj]
            w[b, 0], w[b, 1], w[b, 2] = wj
            continue
        if p < 0:
            for k in range(3):
                o[b, k] = T.bpos[b, k]
                w[b, k] = 0.0
            for k in range(9):
                R[b, k] = T.bR[b, k]
        else:
            Rp = row9(R, p)
            r0, r1, r2 = mv(Rp, T.bpos[b, 0], T.bpos[b, 1], T.bpos[b, 2])
            wp0, wp1, wp2 = w[p, 0], w[p, 1], w[p, 2]
            d0, d1, d2 = cross(wp0, wp1, wp2, r0, r1, r2)
            _moved_copy(V, Om, Vd, Omd, p, b, cols, c0, c0 + T.path_ptr[p + 1] - T.path_ptr[p], r0, r1, r2,
                        d0, d1, d2)
            o[b, 0], o[b, 1], o[b, 2] = o[p, 0] + r0, o[p, 1] + r1, o[p, 2] + r2
            Rn = mm(Rp, row9(T.bR, b))
            for k in range(9):
                R[b, k] = Rn[k]
            w[b, 0], w[b, 1], w[b, 2] = wp0, wp1, wp2
        for k in range(js, js + T.jnum[b]):
            kind, a, d, at = T.jtype[k], qadr[k], T.dofadr[k], c0 + T.jcols[k]
            Rb = row9(R, b)
            wb0, wb1, wb2 = w[b, 0], w[b, 1], w[b, 2]
            if kind == SLIDE:
                e0, e1, e2 = mv(Rb, T.jaxis[k, 0], T.jaxis[k, 1], T.jaxis[k, 2])
                s = q[i, a] - T.jref[k]
                r0, r1, r2 = e0 * s, e1 * s, e2 * s
                sd = u[i, d]
                d0, d1, d2 = cross(wb0, wb1, wb2, r0, r1, r2)
                _move(V, Om, Vd, Omd, b, cols, c0, at, r0, r1, r2, d0 + e0 * sd, d1 + e1 * sd, d2 + e2 * sd)
                f0, f1, f2 = cross(wb0, wb1, wb2, e0, e1, e2)
                V[b, 0, d], V[b, 1, d], V[b, 2, d] = e0, e1, e2
                Vd[b, 0, d], Vd[b, 1, d], Vd[b, 2, d] = f0, f1, f2
                for ii in range(3):
                    Om[b, ii, d], Omd[b, ii, d] = 0.0, 0.0
                o[b, 0], o[b, 1], o[b, 2] = o[b, 0] + r0, o[b, 1] + r1, o[b, 2] + r2
                continue
            jx, jy, jz = T.jpos[k, 0], T.jpos[k, 1], T.jpos[k, 2]
            r0, r1, r2 = mv(Rb, jx, jy, jz)
            da0, da1, da2 = cross(wb0, wb1, wb2, r0, r1, r2)
            if kind == HINGE:
                e0, e1, e2 = mv(Rb, T.jaxis[k, 0], T.jaxis[k, 1], T.jaxis[k, 2])
                Rn = mm(Rb, axis_rotation(T.jaxis[k, 0], T.jaxis[k, 1], T.jaxis[k, 2], q[i, a] - T.jref[k]))
                f0, f1, f2 = cross(wb0, wb1, wb2, e0, e1, e2)
                Om[b, 0, d], Om[b, 1, d], Om[b, 2, d] = e0, e1, e2
                Omd[b, 0, d], Omd[b, 1, d], Omd[b, 2, d] = f0, f1, f2
                for ii in range(3):
                    V[b, ii, d], Vd[b, ii, d] = 0.0, 0.0
                ud = u[i, d]
                n0, n1, n2 = wb0 + e0 * ud, wb1 + e1 * ud, wb2 + e2 * ud
                nd = 1
            else:  # ball
                Rn = mm(Rb, rotation9(case, q, i, a))
                pp = T.parent[b]
                Rp = row9(R, pp) if pp >= 0 else eye
                wp = (w[pp, 0], w[pp, 1], w[pp, 2]) if pp >= 0 else (0.0, 0.0, 0.0)
                A, Ad, wj = angular(case, BALL, q, u, i, a, d, Rb, (wb0, wb1, wb2), Rp, wp, Rn)
                _set_block(Om, Omd, V, Vd, b, d, 3, A, Ad)
                n0, n1, n2 = wb0 + wj[0], wb1 + wj[1], wb2 + wj[2]
                nd = 3
            for ii in range(9):
                R[b, ii] = Rn[ii]
            w[b, 0], w[b, 1], w[b, 2] = n0, n1, n2
            if jx != 0.0 or jy != 0.0 or jz != 0.0:
                # out to the anchor in the old frame, back to the origin in the turned one: the earlier columns'
                # Omega is the same for both moves, so they make one; the joint's own columns take the second
                t0, t1, t2 = mv(Rn, -jx, -jy, -jz)
                e0, e1, e2 = cross(n0, n1, n2, t0, t1, t2)
                _move(V, Om, Vd, Omd, b, cols, c0, at, r0 + t0, r1 + t1, r2 + t2, da0 + e0, da1 + e1, da2 + e2)
                _move(V, Om, Vd, Omd, b, cols, at, at + nd, t0, t1, t2, e0, e1, e2)
                o[b, 0], o[b, 1], o[b, 2] = o[b, 0] + r0 + t0, o[b, 1] + r1 + t1, o[b, 2] + r2 + t2


@jitable
def _nonfinite(x):
    return 0 if (x - x) == 0.0 else 1


@leaf
def point_out(T, b, px, py, pz, o, R, w, V, Om, Vd, Omd, u, ud, i, with_acc, j, pos, vel, acc, PV, PVd):
    """A point fixed in body ``b`` at ``p`` (body frame) into row ``(i, j)`` of the outputs: position, velocity,
    acceleration (if ``with_acc``) and every column of ``V``, ``Vdot``. Returns the count of non-finite values.

    Indexed, never sliced; each output row is zeroed, then the body's path columns are written."""
    nv = PV.shape[3]
    for k in range(3):
        for c in range(nv):
            PV[i, j, k, c] = 0.0
            PVd[i, j, k, c] = 0.0
    if b < 0:  # fixed in the world
        for k in range(3):
            vel[i, j, k] = 0.0
            acc[i, j, k] = 0.0
        pos[i, j, 0], pos[i, j, 1], pos[i, j, 2] = px, py, pz
        return 0
    r0, r1, r2 = mv(row9(R, b), px, py, pz)
    d0, d1, d2 = cross(w[b, 0], w[b, 1], w[b, 2], r0, r1, r2)
    v0, v1, v2, a0, a1, a2 = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    for t in range(T.path_ptr[b], T.path_ptr[b + 1]):
        c = T.path_idx[t]
        o0, o1, o2 = Om[b, 0, c], Om[b, 1, c], Om[b, 2, c]
        q0, q1, q2 = Omd[b, 0, c], Omd[b, 1, c], Omd[b, 2, c]
        x0 = V[b, 0, c] - (r1 * o2 - r2 * o1)
        x1 = V[b, 1, c] - (r2 * o0 - r0 * o2)
        x2 = V[b, 2, c] - (r0 * o1 - r1 * o0)
        y0 = Vd[b, 0, c] - (d1 * o2 - d2 * o1 + r1 * q2 - r2 * q1)
        y1 = Vd[b, 1, c] - (d2 * o0 - d0 * o2 + r2 * q0 - r0 * q2)
        y2 = Vd[b, 2, c] - (d0 * o1 - d1 * o0 + r0 * q1 - r1 * q0)
        PV[i, j, 0, c], PV[i, j, 1, c], PV[i, j, 2, c] = x0, x1, x2
        PVd[i, j, 0, c], PVd[i, j, 1, c], PVd[i, j, 2, c] = y0, y1, y2
        uc, dc = u[i, c], ud[i, c]
        v0, v1, v2 = v0 + x0 * uc, v1 + x1 * uc, v2 + x2 * uc
        a0, a1, a2 = a0 + x0 * dc + y0 * uc, a1 + x1 * dc + y1 * uc, a2 + x2 * dc + y2 * uc
    vel[i, j, 0], vel[i, j, 1], vel[i, j, 2] = v0, v1, v2
    bad = _nonfinite(v0 + v1 + v2)
    if with_acc:
        acc[i, j, 0], acc[i, j, 1], acc[i, j, 2] = a0, a1, a2
        bad += _nonfinite(a0 + a1 + a2)
    pos[i, j, 0], pos[i, j, 1], pos[i, j, 2] = o[b, 0] + r0, o[b, 1] + r1, o[b, 2] + r2
    return bad + _nonfinite(pos[i, j, 0] + pos[i, j, 1] + pos[i, j, 2])


@leaf
def body_out(T, b, o, R, w, V, Om, Vd, Omd, u, ud, i, with_acc, pos, vel, acc, omega, alpha, rot, BV, BVd, BOm,
             BOmd):
    """Body ``b``'s mass centre, angular velocity and acceleration, orientation and all partial columns, row ``i``."""
    bad = point_out(T, b, T.com[b, 0], T.com[b, 1], T.com[b, 2], o, R, w, V, Om, Vd, Omd, u, ud, i, with_acc, b, pos,
                    vel, acc, BV, BVd)
    nv = BOm.shape[3]
    for k in range(3):
        for c in range(nv):
            BOm[i, b, k, c] = 0.0
            BOmd[i, b, k, c] = 0.0
    w0, w1, w2, a0, a1, a2 = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    for t in range(T.path_ptr[b], T.path_ptr[b + 1]):
        c = T.path_idx[t]
        o0, o1, o2 = Om[b, 0, c], Om[b, 1, c], Om[b, 2, c]
        q0, q1, q2 = Omd[b, 0, c], Omd[b, 1, c], Omd[b, 2, c]
        BOm[i, b, 0, c], BOm[i, b, 1, c], BOm[i, b, 2, c] = o0, o1, o2
        BOmd[i, b, 0, c], BOmd[i, b, 1, c], BOmd[i, b, 2, c] = q0, q1, q2
        uc, dc = u[i, c], ud[i, c]
        w0, w1, w2 = w0 + o0 * uc, w1 + o1 * uc, w2 + o2 * uc
        a0, a1, a2 = a0 + o0 * dc + q0 * uc, a1 + o1 * dc + q1 * uc, a2 + o2 * dc + q2 * uc
    omega[i, b, 0], omega[i, b, 1], omega[i, b, 2] = w0, w1, w2
    if with_acc:
        alpha[i, b, 0], alpha[i, b, 1], alpha[i, b, 2] = a0, a1, a2
    for k in range(9):
        rot[i, b, k // 3, k % 3] = R[b, k]
    return bad


if HAVE_NUMBA:

    @numba.njit(cache=True, nogil=True)
    def _kinematics_block(case, q, u, ud, with_acc, T, qadr, pos, vel, acc, omega, alpha, rot, V, Vd, Om, Omd,
                          with_points, ppos, pvel, pacc, PV, PVd, start, stop):  # pragma: no cover - compiled
        """States ``start .. stop - 1``; the count of non-finite results (without the GIL: a batch's shares run on
        Python threads at once, :func:`relacc.kernels.jit.split`)."""
        nv, nb = u.shape[1], T.parent.shape[0]
        o, R, w = np.empty((nb, 3)), np.empty((nb, 9)), np.empty((nb, 3))
        sV, sOm, sVd, sOmd = (np.zeros((nb, 3, nv)), np.zeros((nb, 3, nv)), np.zeros((nb, 3, nv)),
                              np.zeros((nb, 3, nv)))
        bad = 0
        for i in range(start, stop):
            walk_state(case, q, u, i, T, qadr, o, R, w, sV, sOm, sVd, sOmd)
            for b in range(nb):
                bad += body_out(T, b, o, R, w, sV, sOm, sVd, sOmd, u, ud, i, with_acc, pos, vel, acc, omega, alpha,
                                rot, V, Vd, Om, Omd)
            if with_points:
                for j in range(T.pbody.shape[0]):
                    bad += point_out(T, T.pbody[j], T.ppos[j, 0], T.ppos[j, 1], T.ppos[j, 2], o, R, w, sV, sOm, sVd,
                                     sOmd, u, ud, i, with_acc, j, ppos, pvel, pacc, PV, PVd)
        return bad


def writable(a):
    """``a`` as a writable C-contiguous float64 array (a copy only when it is not one already): inputs reach the
    compiled loops with one type, so one specialization serves every caller. (Not read-only views: numba's loops
    over read-only arrays measured 1.7x slower.) The kernels never write their inputs."""
    if isinstance(a, np.ndarray) and a.dtype == np.float64 and a.flags.c_contiguous and a.flags.writeable:
        return a
    return np.require(a, np.float64, ["C", "W"])


def kinematics(tree, case: int, q, u, udot, points: bool, out=None):
    """Every output of :func:`relacc.tree_kinematics` for checked, C-contiguous float64 ``(n, .)`` inputs.

    Returns:
        ``(arrays, n_nonfinite)``: ``arrays`` a dict of ``position``, ``velocity``, ``acceleration``, ``omega``,
        ``alpha`` ``(n, nb, 3)`` (the accelerations None without ``udot``), ``rotation`` ``(n, nb, 3, 3)``, ``V``,
        ``Vdot``, ``Omega``, ``Omegadot`` ``(n, nb, 3, nv)`` and ``points``: None, or (with ``points``) a dict of
        ``position``, ``velocity``, ``acceleration`` ``(n, np, 3)``, ``V``, ``Vdot`` ``(n, np, 3, nv)`` of every
        tree point; the count of non-finite results. ``out``: a dict of arrays of those shapes to write into
        (a missing key is allocated).
    """
    T = arrays_of(tree)
    n, nb, nv = q.shape[0], tree.nb, tree.nv
    npt = len(tree.points) if points else 0
    with_acc = udot is not None
    out = {} if out is None else out
    body: dict[str, int | tuple[int, ...]] = {
        "position": 3, "velocity": 3, "acceleration": 3, "omega": 3, "alpha": 3, "rotation": (3, 3),
        "V": (3, nv), "Vdot": (3, nv), "Omega": (3, nv), "Omegadot": (3, nv)}
    res = {k: out[k] if out.get(k) is not None else np.empty((n, nb) + ((t,) if isinstance(t, int) else t))
           for k, t in body.items()}
    pts = {k: np.empty((n, npt) + t) for k, t in (("position", (3,)), ("velocity", (3,)), ("acceleration", (3,)),
                                                  ("V", (3, nv)), ("Vdot", (3, nv)))}
    q, u, ud = (writable(a) for a in (q, u, udot if with_acc else np.zeros((n, nv))))
    args = (int(case), q, u, ud, with_acc, T, T.qadr3 if case == 3 else T.qadr, *res.values(), npt > 0,
            *pts.values())
    if parallel_pays(n, US_PER_BODY_SPEED * nb * nv, BLOCK):
        first_touch(*[a for k, a in res.items() if out.get(k) is None], *pts.values())
        bad = split(_kinematics_block, args, n, BLOCK)
    else:
        bad = _kinematics_block(*args, 0, n)
    if not with_acc:
        res["acceleration"] = res["alpha"] = pts["acceleration"] = None
    res["points"] = pts if points else None
    return res, int(bad)
