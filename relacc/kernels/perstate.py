"""The per-state mathematics of the fused kernels, shared by :mod:`~relacc.kernels.kinematics` and
:mod:`~relacc.kernels.dynamics`.

Every function here is plain arithmetic on scalars or tuples, so it runs as
Python on whole numpy columns (the numpy backend) and compiles under numba
when called from jitted code (``numba.extending.register_jitable``). The
mathematics is described in :mod:`relacc.kernels.kinematics`.
"""

from __future__ import annotations

import numpy as np

from relacc.core.tolerances import QUATERNION_NORM_TOLERANCE
from relacc.kernels import trig
from relacc.kernels.jit import HAVE_NUMBA, jitable, numba  # noqa: F401  (re-exported)
from relacc.kernels.so3 import (  # noqa: F401  (re-exported to the chain's kernels)
    cross,
    cross_cols,
    mm,
    mv,
    quat_matrix,
    r123,
    w123,
    w123_dot_mv,
    w123_mv,
)


@jitable
def nonfinite(x):
    """0 for a finite number, 1 for NaN or inf."""
    return 0 if (x == x and abs(x) < np.inf) else 1


@jitable
def trig_libm(q):
    """Cosines and sines of the six case-3 angles (libm), computed once per state."""
    return (np.cos(q[3]), np.cos(q[4]), np.cos(q[5]), np.sin(q[3]), np.sin(q[4]), np.sin(q[5]),
            np.cos(q[9]), np.cos(q[10]), np.cos(q[11]), np.sin(q[9]), np.sin(q[10]), np.sin(q[11]))


ANGLES = (3, 4, 5, 9, 10, 11)
"""Columns of a case-3 ``q`` that hold the 1-2-3 angles, rad: theta_B1 in 3-5, theta_B2 (relative to B1) in 9-11."""

TRIG_BLOCK = 128
"""States per block whose case-3 sines and cosines :func:`block_trig` computes in one vectorized pass."""


@jitable
def block_trig(q, i0, i1, tr):
    """:func:`trig_libm` of states ``i0 .. i1-1`` into the columns of ``tr`` (13, TRIG_BLOCK), through
    :func:`relacc.kernels.trig.sincos`.

    Per angle, its values are first copied to the contiguous scratch row ``tr[12]``; the loop over
    that row has a fixed trip count and contiguous loads and stores, so LLVM vectorizes it.

    Returns:
        The number of angles in the block beyond :data:`relacc.kernels.trig.LIMIT` in magnitude, whose
        columns are inaccurate: their states must be redone with :func:`trig_libm`.
    """
    x = tr[12]
    far = 0
    for a in range(6):
        col = ANGLES[a]
        row = a if a < 3 else a + 3  # cosines in rows 0-2 and 6-8, sines 3 rows below
        for j in range(i1 - i0):
            x[j] = q[i0 + j, col]
        for j in range(i1 - i0, TRIG_BLOCK):
            x[j] = 0.0
        cos_row, sin_row = tr[row], tr[row + 3]
        for j in range(TRIG_BLOCK):
            s, c = trig.sincos(x[j])
            cos_row[j] = c
            sin_row[j] = s
            far += 1 if abs(x[j]) > trig.LIMIT else 0
    return far


@jitable
def trig_in(case, tr, j):
    """Column ``j`` of :func:`block_trig`'s ``tr`` as :func:`trig_libm`'s tuple (case 3), :data:`NO_TRIG` otherwise."""
    if case != 3:
        return NO_TRIG
    return (tr[0, j], tr[1, j], tr[2, j], tr[3, j], tr[4, j], tr[5, j],
            tr[6, j], tr[7, j], tr[8, j], tr[9, j], tr[10, j], tr[11, j])


@jitable
def libm_columns(q, i0, i1, tr):
    """Redo with :func:`trig_libm` the columns of ``tr`` whose state has an angle beyond
    :data:`relacc.kernels.trig.LIMIT`."""
    for i in range(i0, i1):
        m = 0.0
        for k in ANGLES:
            m = max(m, abs(q[i, k]))
        if m > trig.LIMIT:
            t = trig_libm(q[i])
            for k in range(12):
                tr[k, i - i0] = t[k]


@jitable
def rotations(case, q, t):
    """``C1 = [R_B1]^T`` and ``M = [^{B2}R_{B1}]`` from quaternions (cases 1-2) or 1-2-3 angles (case 3)."""
    if case == 3:
        return r123(t[0], t[1], t[2], t[3], t[4], t[5]), r123(t[6], t[7], t[8], t[9], t[10], t[11])
    return quat_matrix(q[3], q[4], q[5], q[6]), quat_matrix(q[10], q[11], q[12], q[13])


@jitable
def angular(case, q, u, d, C1, M, t):
    """``omega_B1``, ``alpha_B1``, ``w_hat`` (B2 in B1) and ``w_hat_dot``, fixed components.

    case 1: speeds are omega_B1 and omega_hat_B2 (B1 comps); case 2: B1 and B2
    components; case 3: ``W(theta) theta_dot``. ``w_hat_dot = omega_B1 x w_hat + R (rate of the
    reference-frame components)``. With ``d = None``-like zeros the rates are simply unused.
    """
    if case == 1:
        w = (u[3], u[4], u[5])
        al = (d[3], d[4], d[5])
        wh = mv(C1, u[9], u[10], u[11])
        hb = mv(C1, d[9], d[10], d[11])
    elif case == 2:
        C2 = mm(C1, M)
        w = mv(C1, u[3], u[4], u[5])
        al = mv(C1, d[3], d[4], d[5])
        wh = mv(C2, u[9], u[10], u[11])
        hb = mv(C2, d[9], d[10], d[11])
    else:
        c1, c2, s1, s2 = t[0], t[1], t[3], t[4]
        w = w123_mv(c1, c2, s1, s2, u[3], u[4], u[5])
        a1 = w123_mv(c1, c2, s1, s2, d[3], d[4], d[5])
        a2 = w123_dot_mv(c1, c2, s1, s2, u[3], u[4], u[4], u[5])
        al = (a1[0] + a2[0], a1[1] + a2[1], a1[2] + a2[2])
        c1, c2, s1, s2 = t[6], t[7], t[9], t[10]
        h1 = w123_mv(c1, c2, s1, s2, u[9], u[10], u[11])
        wh = mv(C1, h1[0], h1[1], h1[2])
        b1 = w123_mv(c1, c2, s1, s2, d[9], d[10], d[11])
        b2 = w123_dot_mv(c1, c2, s1, s2, u[9], u[10], u[10], u[11])
        hb = mv(C1, b1[0] + b2[0], b1[1] + b2[1], b1[2] + b2[2])
    c = cross(w[0], w[1], w[2], wh[0], wh[1], wh[2])
    return w, al, wh, (hb[0] + c[0], hb[1] + c[1], hb[2] + c[2])


@jitable
def state_quantities(case, q, u, d, q2p, r2p, t):
    """The per-state quantities every output needs (fixed-frame components).

    ``t`` is :func:`trig_libm` of ``q`` (or its :func:`block_trig` column) in case 3, :data:`NO_TRIG` otherwise.
    """
    C1, M = rotations(case, q, t)
    w, al, wh, hd = angular(case, q, u, d, C1, M, t)
    o = 7 if case != 3 else 6  # index of s2' in q
    rb = mv(M, r2p[0], r2p[1], r2p[2])
    r = mv(C1, rb[0], rb[1], rb[2])
    l = mv(C1, q2p[0] + q[o], q2p[1] + q[o + 1], q2p[2] + q[o + 2])  # q2 + s2
    sd = mv(C1, u[6], u[7], u[8])  # [R_B1]^T s2'_dot
    rd = cross(w[0] + wh[0], w[1] + wh[1], w[2] + wh[2], r[0], r[1], r[2])  # eq7
    wl = cross(w[0], w[1], w[2], l[0], l[1], l[2])
    Ld = (wl[0] + sd[0] + rd[0], wl[1] + sd[1] + rd[1], wl[2] + sd[2] + rd[2])  # q2_dot + s2_dot + r2_dot
    L = (l[0] + r[0], l[1] + r[1], l[2] + r[2])
    return C1, M, r, L, Ld, w, al, wh, hd, sd, rd, t


@jitable
def acc_from(d, C1, r, L, Ld, w, al, wh, hd, sd, rd):
    """eq4 / eq11 / eq12 in fused form (see the module docstring)."""
    sdd = mv(C1, d[6], d[7], d[8])
    a1 = cross(al[0], al[1], al[2], L[0], L[1], L[2])
    a2 = cross(w[0], w[1], w[2], Ld[0] + sd[0], Ld[1] + sd[1], Ld[2] + sd[2])
    a3 = cross(hd[0], hd[1], hd[2], r[0], r[1], r[2])
    a4 = cross(wh[0], wh[1], wh[2], rd[0], rd[1], rd[2])
    return (d[0] + a1[0] + a2[0] + sdd[0] + a3[0] + a4[0],
            d[1] + a1[1] + a2[1] + sdd[1] + a3[1] + a4[1],
            d[2] + a1[2] + a2[2] + sdd[2] + a3[2] + a4[2])


@jitable
def acceleration_of(case, q, u, d, q2p, r2p, t):
    C1, M, r, L, Ld, w, al, wh, hd, sd, rd, t = state_quantities(case, q, u, d, q2p, r2p, t)
    return acc_from(d, C1, r, L, Ld, w, al, wh, hd, sd, rd)


@jitable
def columns(case, q, u, C1, M, w, wh, t):
    """Partial angular velocity columns: ``P``, ``P_dot`` (B1) and ``G``, ``G_dot`` (B2), fixed comps."""
    z = 0.0 * C1[0]
    if case == 1:
        P = (1.0 + z, z, z, z, 1.0 + z, z, z, z, 1.0 + z)
        P_dot = (z, z, z, z, z, z, z, z, z)
        return P, P_dot, C1, cross_cols(w[0], w[1], w[2], C1)
    if case == 2:
        G = mm(C1, M)
        return C1, cross_cols(w[0], w[1], w[2], C1), G, cross_cols(w[0] + wh[0], w[1] + wh[1], w[2] + wh[2], G)
    P, P_dot = w123(t[0], t[1], t[3], t[4], u[3], u[4])
    W2, W2d = w123(t[6], t[7], t[9], t[10], u[9], u[10])
    G = mm(C1, W2)
    Gc, CW = cross_cols(w[0], w[1], w[2], G), mm(C1, W2d)
    G_dot = (Gc[0] + CW[0], Gc[1] + CW[1], Gc[2] + CW[2], Gc[3] + CW[3], Gc[4] + CW[4], Gc[5] + CW[5],
             Gc[6] + CW[6], Gc[7] + CW[7], Gc[8] + CW[8])
    return P, P_dot, G, G_dot


QUAT_TOL = QUATERNION_NORM_TOLERANCE


@jitable
def bad_inputs(case, q, u, d):
    """Non-zero when an input is NaN or inf, or (cases 1-2) a quaternion is off unit norm beyond the tolerance.

    Branch-free: ``sum(x * 0)`` is 0 for finite inputs and NaN as soon as one is NaN or inf.
    """
    z = 0.0
    for k in range(q.shape[0]):
        z += q[k] * 0.0
    for k in range(12):
        z += u[k] * 0.0 + d[k] * 0.0
    bad = 0 if z == 0.0 else 1
    if case != 3:
        if abs(q[3] * q[3] + q[4] * q[4] + q[5] * q[5] + q[6] * q[6] - 1.0) > QUAT_TOL:
            bad += 1
        if abs(q[10] * q[10] + q[11] * q[11] + q[12] * q[12] + q[13] * q[13] - 1.0) > QUAT_TOL:
            bad += 1
    return bad


NO_TRIG = (0.0,) * 12
"""Placeholder for the trigonometry of cases 1 and 2 (unused there)."""
