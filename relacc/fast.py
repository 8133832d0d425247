"""Fused batch kernels for the corrected formulas: the throughput path of :func:`relacc.g2_kinematics`.

The kernel evaluates, per state, the same mathematics as :mod:`relacc.note`
(corrected variant), written for speed:

* every product ``[a~]{b}`` is the cross product ``a x b``;
* every case is reduced to Case 1's structure through its partial angular
  velocity columns: B1's speeds give ``omega_B1 = sum_j p_j x1_j`` (fixed
  components) and B2's give ``omega_hat_B2 = sum_j g_j x2_j`` (fixed
  components), with ``p_j = e_j``, ``[R_B1]^T e_j``, ``W(theta_B1) e_j`` and
  ``g_j = [R_B1]^T e_j``, ``[R_B2]^T e_j``, ``[R_B1]^T W(theta_B2) e_j`` for cases 1, 2, 3;
* then, with ``L = q2 + s2 + r2`` and ``r2_dot = omega_B2 x r2`` (eq7),
  the partial velocity columns are ``p_j x L`` and ``g_j x r2`` (eq3, eq10,
  case3-partials), their rates ``p_dot_j x L + p_j x L_dot`` and
  ``g_dot_j x r2 + g_j x r2_dot`` (case1-a, eq9, case2-a, case2-c,
  case3-rates), and the acceleration (eq4, eq11, eq12) is
  ``s1_ddot + alpha_B1 x L + omega_B1 x L_dot + [R_B1]^T s2'_ddot
  + omega_B1 x [R_B1]^T s2'_dot + w_hat_dot x r2 + w_hat x r2_dot``.

One source serves two backends: numba compiles it per state inside a
parallel loop (no temporaries: memory is the inputs plus the outputs), and
numpy runs it on whole columns when numba is unavailable.
``tests/test_fast.py`` holds it to the note's reference implementation.
"""

from __future__ import annotations

import numpy as np

from relacc.tolerances import QUATERNION_NORM_TOLERANCE

try:  # numba is a dependency; the numpy path stays as a fallback and a second check
    import numba
    import numba.extending

    HAVE_NUMBA = True
except ImportError:  # pragma: no cover - exercised only without numba
    numba = None
    HAVE_NUMBA = False


def _jit(fn):
    """Plain Python when called from Python (the numpy backend); compiled when called from numba code."""
    return numba.extending.register_jitable(fn) if HAVE_NUMBA else fn


@_jit
def _finite(x):
    """0 for a finite number, 1 for NaN or inf."""
    return 0 if (x == x and abs(x) < np.inf) else 1


@_jit
def _cross(a0, a1, a2, b0, b1, b2):
    return a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0


@_jit
def _quat(w, x, y, z):
    return (1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
            2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
            2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y))


@_jit
def _r123(c1, c2, c3, s1, s2, s3):
    """``Rx Ry Rz`` from the cosines and sines of the three angles."""
    return (c2 * c3, -c2 * s3, s2,
            c1 * s3 + s1 * s2 * c3, c1 * c3 - s1 * s2 * s3, -s1 * c2,
            s1 * s3 - c1 * s2 * c3, s1 * c3 + c1 * s2 * s3, c1 * c2)


@_jit
def _w123(c1, c2, s1, s2, d1, d2):
    """W(theta) and W_dot(theta, theta_dot), row-major 9-tuples, from cosines and sines of theta1, theta2."""
    z = 0.0 * c1
    W = (1.0 + z, z, s2, z, c1, -s1 * c2, z, s1, c1 * c2)
    Wd = (z, z, c2 * d2, z, -s1 * d1, -c1 * c2 * d1 + s1 * s2 * d2, z, c1 * d1, -s1 * c2 * d1 - c1 * s2 * d2)
    return W, Wd


@_jit
def _w123_mv(c1, c2, s1, s2, x0, x1, x2):
    """``W(theta) x`` written out (W has a unit entry and three zeros)."""
    return x0 + s2 * x2, c1 * x1 - s1 * c2 * x2, s1 * x1 + c1 * c2 * x2


@_jit
def _w123_dot_mv(c1, c2, s1, s2, d1, d2, x1, x2):
    """``W_dot(theta, theta_dot) x`` written out (its first column is zero, so x0 drops out)."""
    return (c2 * d2 * x2,
            -s1 * d1 * x1 + (-c1 * c2 * d1 + s1 * s2 * d2) * x2,
            c1 * d1 * x1 + (-s1 * c2 * d1 - c1 * s2 * d2) * x2)


@_jit
def _mm(A, B):
    return (A[0] * B[0] + A[1] * B[3] + A[2] * B[6], A[0] * B[1] + A[1] * B[4] + A[2] * B[7],
            A[0] * B[2] + A[1] * B[5] + A[2] * B[8],
            A[3] * B[0] + A[4] * B[3] + A[5] * B[6], A[3] * B[1] + A[4] * B[4] + A[5] * B[7],
            A[3] * B[2] + A[4] * B[5] + A[5] * B[8],
            A[6] * B[0] + A[7] * B[3] + A[8] * B[6], A[6] * B[1] + A[7] * B[4] + A[8] * B[7],
            A[6] * B[2] + A[7] * B[5] + A[8] * B[8])


@_jit
def _mv(A, x0, x1, x2):
    return (A[0] * x0 + A[1] * x1 + A[2] * x2, A[3] * x0 + A[4] * x1 + A[5] * x2,
            A[6] * x0 + A[7] * x1 + A[8] * x2)


@_jit
def _cross_cols(w0, w1, w2, A):
    """The matrix whose column j is ``w x A[:, j]``, row-major."""
    c0 = _cross(w0, w1, w2, A[0], A[3], A[6])
    c1 = _cross(w0, w1, w2, A[1], A[4], A[7])
    c2 = _cross(w0, w1, w2, A[2], A[5], A[8])
    return (c0[0], c1[0], c2[0], c0[1], c1[1], c2[1], c0[2], c1[2], c2[2])


@_jit
def _trig(q):
    """Cosines and sines of the six case-3 angles, computed once per state."""
    return (np.cos(q[3]), np.cos(q[4]), np.cos(q[5]), np.sin(q[3]), np.sin(q[4]), np.sin(q[5]),
            np.cos(q[9]), np.cos(q[10]), np.cos(q[11]), np.sin(q[9]), np.sin(q[10]), np.sin(q[11]))


@_jit
def _rotations(case, q, t):
    """``C1 = [R_B1]^T`` and ``M = [^{B2}R_{B1}]`` from quaternions (cases 1-2) or 1-2-3 angles (case 3)."""
    if case == 3:
        return _r123(t[0], t[1], t[2], t[3], t[4], t[5]), _r123(t[6], t[7], t[8], t[9], t[10], t[11])
    return _quat(q[3], q[4], q[5], q[6]), _quat(q[10], q[11], q[12], q[13])


@_jit
def _angular(case, q, u, d, C1, M, t):
    """``omega_B1``, ``alpha_B1``, ``w_hat`` (B2 in B1) and ``w_hat_dot``, fixed components.

    case 1: speeds are omega_B1 and omega_hat_B2 (B1 comps); case 2: B1 and B2
    components; case 3: ``W(theta) theta_dot``. ``w_hat_dot = omega_B1 x w_hat + R (rate of the
    reference-frame components)``. With ``d = None``-like zeros the rates are simply unused.
    """
    if case == 1:
        w = (u[3], u[4], u[5])
        al = (d[3], d[4], d[5])
        wh = _mv(C1, u[9], u[10], u[11])
        hb = _mv(C1, d[9], d[10], d[11])
    elif case == 2:
        C2 = _mm(C1, M)
        w = _mv(C1, u[3], u[4], u[5])
        al = _mv(C1, d[3], d[4], d[5])
        wh = _mv(C2, u[9], u[10], u[11])
        hb = _mv(C2, d[9], d[10], d[11])
    else:
        c1, c2, s1, s2 = t[0], t[1], t[3], t[4]
        w = _w123_mv(c1, c2, s1, s2, u[3], u[4], u[5])
        a1 = _w123_mv(c1, c2, s1, s2, d[3], d[4], d[5])
        a2 = _w123_dot_mv(c1, c2, s1, s2, u[3], u[4], u[4], u[5])
        al = (a1[0] + a2[0], a1[1] + a2[1], a1[2] + a2[2])
        c1, c2, s1, s2 = t[6], t[7], t[9], t[10]
        h1 = _w123_mv(c1, c2, s1, s2, u[9], u[10], u[11])
        wh = _mv(C1, h1[0], h1[1], h1[2])
        b1 = _w123_mv(c1, c2, s1, s2, d[9], d[10], d[11])
        b2 = _w123_dot_mv(c1, c2, s1, s2, u[9], u[10], u[10], u[11])
        hb = _mv(C1, b1[0] + b2[0], b1[1] + b2[1], b1[2] + b2[2])
    c = _cross(w[0], w[1], w[2], wh[0], wh[1], wh[2])
    return w, al, wh, (hb[0] + c[0], hb[1] + c[1], hb[2] + c[2])


@_jit
def _state(case, q, u, d, q2p, r2p):
    """The per-state quantities every output needs (fixed-frame components)."""
    t = _trig(q) if case == 3 else _NO_TRIG
    C1, M = _rotations(case, q, t)
    w, al, wh, hd = _angular(case, q, u, d, C1, M, t)
    o = 7 if case != 3 else 6  # index of s2' in q
    rb = _mv(M, r2p[0], r2p[1], r2p[2])
    r = _mv(C1, rb[0], rb[1], rb[2])
    l = _mv(C1, q2p[0] + q[o], q2p[1] + q[o + 1], q2p[2] + q[o + 2])  # q2 + s2
    sd = _mv(C1, u[6], u[7], u[8])  # [R_B1]^T s2'_dot
    rd = _cross(w[0] + wh[0], w[1] + wh[1], w[2] + wh[2], r[0], r[1], r[2])  # eq7
    wl = _cross(w[0], w[1], w[2], l[0], l[1], l[2])
    Ld = (wl[0] + sd[0] + rd[0], wl[1] + sd[1] + rd[1], wl[2] + sd[2] + rd[2])  # q2_dot + s2_dot + r2_dot
    L = (l[0] + r[0], l[1] + r[1], l[2] + r[2])
    return C1, M, r, L, Ld, w, al, wh, hd, sd, rd, t


@_jit
def _acc_from(d, C1, r, L, Ld, w, al, wh, hd, sd, rd):
    """eq4 / eq11 / eq12 in fused form (see the module docstring)."""
    sdd = _mv(C1, d[6], d[7], d[8])
    a1 = _cross(al[0], al[1], al[2], L[0], L[1], L[2])
    a2 = _cross(w[0], w[1], w[2], Ld[0] + sd[0], Ld[1] + sd[1], Ld[2] + sd[2])
    a3 = _cross(hd[0], hd[1], hd[2], r[0], r[1], r[2])
    a4 = _cross(wh[0], wh[1], wh[2], rd[0], rd[1], rd[2])
    return (d[0] + a1[0] + a2[0] + sdd[0] + a3[0] + a4[0],
            d[1] + a1[1] + a2[1] + sdd[1] + a3[1] + a4[1],
            d[2] + a1[2] + a2[2] + sdd[2] + a3[2] + a4[2])


@_jit
def _acceleration(case, q, u, d, q2p, r2p):
    C1, M, r, L, Ld, w, al, wh, hd, sd, rd, t = _state(case, q, u, d, q2p, r2p)
    return _acc_from(d, C1, r, L, Ld, w, al, wh, hd, sd, rd)


@_jit
def _columns(case, q, u, C1, M, w, wh, t):
    """Partial angular velocity columns: ``P``, ``P_dot`` (B1) and ``G``, ``G_dot`` (B2), fixed comps."""
    z = 0.0 * C1[0]
    if case == 1:
        P = (1.0 + z, z, z, z, 1.0 + z, z, z, z, 1.0 + z)
        P_dot = (z, z, z, z, z, z, z, z, z)
        return P, P_dot, C1, _cross_cols(w[0], w[1], w[2], C1)
    if case == 2:
        G = _mm(C1, M)
        return C1, _cross_cols(w[0], w[1], w[2], C1), G, _cross_cols(w[0] + wh[0], w[1] + wh[1], w[2] + wh[2], G)
    P, P_dot = _w123(t[0], t[1], t[3], t[4], u[3], u[4])
    W2, W2d = _w123(t[6], t[7], t[9], t[10], u[9], u[10])
    G = _mm(C1, W2)
    Gc, CW = _cross_cols(w[0], w[1], w[2], G), _mm(C1, W2d)
    G_dot = (Gc[0] + CW[0], Gc[1] + CW[1], Gc[2] + CW[2], Gc[3] + CW[3], Gc[4] + CW[4], Gc[5] + CW[5],
             Gc[6] + CW[6], Gc[7] + CW[7], Gc[8] + CW[8])
    return P, P_dot, G, G_dot


QUAT_TOL = QUATERNION_NORM_TOLERANCE


@_jit
def _bad_inputs(case, q, u, d):
    """Count non-finite inputs and (cases 1-2) quaternions off unit norm by more than the tolerance."""
    bad = 0
    for k in range(q.shape[0]):
        bad += _finite(q[k])
    for k in range(12):
        bad += _finite(u[k]) + _finite(d[k])
    if case != 3:
        if abs(q[3] * q[3] + q[4] * q[4] + q[5] * q[5] + q[6] * q[6] - 1.0) > QUAT_TOL:
            bad += 1
        if abs(q[10] * q[10] + q[11] * q[11] + q[12] * q[12] + q[13] * q[13] - 1.0) > QUAT_TOL:
            bad += 1
    return bad


_NO_TRIG = (0.0,) * 12
"""Placeholder for the trigonometry of cases 1 and 2 (unused there)."""





if HAVE_NUMBA:

    @numba.njit(parallel=True, cache=True)
    def _acc_loop(case, q, u, d, q2p, r2p, out):  # pragma: no cover - compiled
        bad, bad_in = 0, 0
        for i in numba.prange(q.shape[0]):
            bad_in += _bad_inputs(case, q[i], u[i], d[i])
            a = _acceleration(case, q[i], u[i], d[i], q2p, r2p)
            out[i, 0], out[i, 1], out[i, 2] = a[0], a[1], a[2]
            bad += _finite(a[0]) + _finite(a[1]) + _finite(a[2])
        return bad, bad_in

    @numba.njit(parallel=True, cache=True)
    def _full_loop(case, q, u, d, q2p, r2p, pos, vel, acc, V, Vd, with_acc):  # pragma: no cover - compiled
        bad, bad_in = 0, 0
        for i in numba.prange(q.shape[0]):
            qi, ui, di = q[i], u[i], d[i]
            bad_in += _bad_inputs(case, qi, ui, di)
            C1, M, r, L, Ld, w, al, wh, hd, sd, rd, t = _state(case, qi, ui, di, q2p, r2p)
            P, P_dot, G, G_dot = _columns(case, qi, ui, C1, M, w, wh, t)
            vw = _cross(w[0], w[1], w[2], L[0], L[1], L[2])
            vh = _cross(wh[0], wh[1], wh[2], r[0], r[1], r[2])
            nb_bad = 0
            for k in range(3):
                pos[i, k] = qi[k] + L[k]
                vel[i, k] = ui[k] + sd[k] + vw[k] + vh[k]
                nb_bad += _finite(pos[i, k]) + _finite(vel[i, k])
            for j in range(3):
                pj = _cross(P[j], P[3 + j], P[6 + j], L[0], L[1], L[2])
                pdj = _cross(P_dot[j], P_dot[3 + j], P_dot[6 + j], L[0], L[1], L[2])
                pl = _cross(P[j], P[3 + j], P[6 + j], Ld[0], Ld[1], Ld[2])
                gj = _cross(G[j], G[3 + j], G[6 + j], r[0], r[1], r[2])
                gdj = _cross(G_dot[j], G_dot[3 + j], G_dot[6 + j], r[0], r[1], r[2])
                gr = _cross(G[j], G[3 + j], G[6 + j], rd[0], rd[1], rd[2])
                cw = _cross(w[0], w[1], w[2], C1[j], C1[3 + j], C1[6 + j])
                for k in range(3):
                    V[i, k, j] = 1.0 if k == j else 0.0
                    V[i, k, 3 + j] = pj[k]
                    V[i, k, 6 + j] = C1[3 * k + j]
                    V[i, k, 9 + j] = gj[k]
                    Vd[i, k, j] = 0.0
                    Vd[i, k, 3 + j] = pdj[k] + pl[k]
                    Vd[i, k, 6 + j] = cw[k]
                    Vd[i, k, 9 + j] = gdj[k] + gr[k]
                    nb_bad += _finite(pj[k]) + _finite(gj[k]) + _finite(Vd[i, k, 3 + j]) + _finite(Vd[i, k, 9 + j])
            if with_acc:
                a = _acc_from(di, C1, r, L, Ld, w, al, wh, hd, sd, rd)
                acc[i, 0], acc[i, 1], acc[i, 2] = a[0], a[1], a[2]
                nb_bad += _finite(a[0]) + _finite(a[1]) + _finite(a[2])
            bad += nb_bad
        return bad, bad_in


def acceleration(case: int, q, u, udot, q2p, r2p, backend: str | None = None):
    """G2's classical acceleration for validated, C-contiguous float64 ``(n, .)`` inputs.

    Returns:
        ``(acceleration, n_nonfinite, n_bad_inputs)``: ``(n, 3)`` fixed
        components, m/s^2; the number of non-finite results (overflow) and of
        bad inputs (non-finite, or quaternions off unit norm), both counted
        inside the kernel. Callers check the inputs' values only when the
        latter is non-zero, to report them.
    """
    if (backend or BACKEND) == "numba":
        out = np.empty((q.shape[0], 3))
        bad, bad_in = _acc_loop(int(case), q, u, udot, q2p, r2p, out)
        return out, bad, bad_in
    out = np.stack(_acceleration(int(case), q.T, u.T, udot.T, q2p, r2p), -1)
    return out, int(np.count_nonzero(~np.isfinite(out))), _numpy_bad_inputs(int(case), q, u, udot)


def kinematics(case: int, q, u, udot, q2p, r2p, backend: str | None = None):
    """All outputs for validated, C-contiguous float64 ``(n, .)`` inputs.

    Returns:
        ``((position, velocity, acceleration or None, V, Vdot), n_nonfinite, n_bad_inputs)``:
        shapes ``(n, 3)``, ``(n, 3)``, ``(n, 3)``, ``(n, 3, 12)``, ``(n, 3, 12)``,
        fixed-frame components, units as :class:`relacc.G2Kinematics`; the
        counts as in :func:`acceleration`.
    """
    n = q.shape[0]
    with_acc = udot is not None
    d = udot if with_acc else np.zeros((n, 12))
    if (backend or BACKEND) == "numba":
        pos, vel, acc = np.empty((n, 3)), np.empty((n, 3)), np.empty((n, 3))
        V, Vd = np.empty((n, 3, 12)), np.empty((n, 3, 12))
        bad, bad_in = _full_loop(int(case), q, u, d, q2p, r2p, pos, vel, acc, V, Vd, with_acc)
        return (pos, vel, (acc if with_acc else None), V, Vd), bad, bad_in
    out = _numpy_kinematics(int(case), q, u, d, q2p, r2p, with_acc)
    bad = sum(int(np.count_nonzero(~np.isfinite(a))) for a in out if a is not None)
    return out, bad, _numpy_bad_inputs(int(case), q, u, d)


def _numpy_bad_inputs(case, q, u, d):
    """The numpy backend's count of bad inputs (same rule as :func:`_bad_inputs`)."""
    bad = sum(int(np.count_nonzero(~np.isfinite(a))) for a in (q, u, d))
    if case != 3:
        for sl in (slice(3, 7), slice(10, 14)):
            bad += int(np.count_nonzero(np.abs(np.einsum("ij,ij->i", q[:, sl], q[:, sl]) - 1.0) > QUAT_TOL))
    return bad


def _numpy_kinematics(case, q, u, d, q2p, r2p, with_acc):
    """The same kernel on whole columns (the numpy backend)."""
    qT, uT, dT = q.T, u.T, d.T
    C1, M, r, L, Ld, w, al, wh, hd, sd, rd, t = _state(case, qT, uT, dT, q2p, r2p)
    P, P_dot, G, G_dot = _columns(case, qT, uT, C1, M, w, wh, t)
    n = q.shape[0]
    pos = np.stack([qT[k] + L[k] for k in range(3)], -1)
    vw, vh = _cross(*w, *L), _cross(*wh, *r)
    vel = np.stack([uT[k] + sd[k] + vw[k] + vh[k] for k in range(3)], -1)
    V, Vd = np.zeros((n, 3, 12)), np.zeros((n, 3, 12))
    for j in range(3):
        cols = (
            _cross(P[j], P[3 + j], P[6 + j], *L),
            (C1[j], C1[3 + j], C1[6 + j]),
            _cross(G[j], G[3 + j], G[6 + j], *r),
        )
        pd, pl = _cross(P_dot[j], P_dot[3 + j], P_dot[6 + j], *L), _cross(P[j], P[3 + j], P[6 + j], *Ld)
        gd, gr = _cross(G_dot[j], G_dot[3 + j], G_dot[6 + j], *r), _cross(G[j], G[3 + j], G[6 + j], *rd)
        cw = _cross(*w, C1[j], C1[3 + j], C1[6 + j])
        V[:, j, j] = 1.0
        for k in range(3):
            V[:, k, 3 + j], V[:, k, 6 + j], V[:, k, 9 + j] = cols[0][k], cols[1][k], cols[2][k]
            Vd[:, k, 3 + j], Vd[:, k, 6 + j], Vd[:, k, 9 + j] = pd[k] + pl[k], cw[k], gd[k] + gr[k]
    acc = np.stack(_acc_from(dT, C1, r, L, Ld, w, al, wh, hd, sd, rd), -1) if with_acc else None
    return pos, vel, acc, V, Vd


BACKEND = "numba" if HAVE_NUMBA else "numpy"
"""The backend used by default: ``numba`` when importable, else ``numpy``."""
