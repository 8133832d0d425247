"""Fused batch kernels for the corrected formulas: the throughput path of :func:`relacc.g2_kinematics`.

The kernel evaluates, per state, the same mathematics as :mod:`relacc.core.note`
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
loop over blocks of :data:`relacc.kernels.perstate.TRIG_BLOCK` states, split over threads where that pays (no
temporaries but a 13 x 128 scratch per block: memory is the inputs plus the
outputs), and numpy runs it on whole columns when numba is unavailable; the
two give the same bits. Case 3's sines and cosines come from
:func:`relacc.kernels.trig.sincos`, vectorized over each block, rather than libm,
whose calls were half of case 3's time; states with an angle beyond
:data:`relacc.kernels.trig.LIMIT` (1.6e6 rad) use libm's.
``tests/test_fast.py`` and ``tests/test_trig.py`` hold it to the note's
reference implementation.
"""

from __future__ import annotations

import numpy as np

from relacc.kernels import trig
from relacc.kernels.jit import read_only, unfused
from relacc.kernels.perstate import (
    ANGLES,
    HAVE_NUMBA,
    NO_TRIG,
    QUAT_TOL,
    TRIG_BLOCK,
    acc_from,
    acceleration_of,
    bad_inputs,
    block_trig,
    columns,
    cross,
    jitable,
    libm_columns,
    nonfinite,
    state_quantities,
    trig_in,
)


@jitable(inline=True)
def _acc_row(case, qi, ui, di, q2p, r2p, t, out, i):
    """G2's acceleration of one state into ``out[i]``; returns its number of non-finite components."""
    a = acceleration_of(case, qi, ui, di, q2p, r2p, t)
    out[i, 0], out[i, 1], out[i, 2] = a[0], a[1], a[2]
    return nonfinite(a[0]) + nonfinite(a[1]) + nonfinite(a[2])


if HAVE_NUMBA:
    # Case 3 runs over blocks of TRIG_BLOCK states: a block first gets the sines and cosines of its
    # angles in one vectorized pass (relacc.kernels.trig); a block with an angle beyond trig.LIMIT (never,
    # in practice) then has those states' columns redone with libm, in a call that keeps libm out
    # of the vectorized pass. Counts are summed per block, then over blocks. The acceleration
    # alone of cases 1-2 loops over states directly: for them that measured about 25 % faster.

    # Compiled without reference counting or fused multiply-adds (relacc.kernels.jit.unfused), so they allocate
    # nothing: the caller hands them case 3's trigonometry scratch ``tr`` (13, TRIG_BLOCK), one per thread.

    @unfused
    def _acc_loop(case, q, u, d, q2p, r2p, out, tr, start, stop):  # pragma: no cover - compiled
        bad, bad_in = 0, 0
        if case != 3:
            for i in range(start, stop):
                bad_in += bad_inputs(case, q[i], u[i], d[i])
                bad += _acc_row(case, q[i], u[i], d[i], q2p, r2p, NO_TRIG, out, i)
            return bad, bad_in
        n = q.shape[0]
        for b in range(start // TRIG_BLOCK, (stop + TRIG_BLOCK - 1) // TRIG_BLOCK):
            i0, i1 = b * TRIG_BLOCK, min(n, (b + 1) * TRIG_BLOCK)
            if block_trig(q, i0, i1, tr):
                libm_columns(q, i0, i1, tr)
            for i in range(i0, i1):
                bad_in += bad_inputs(3, q[i], u[i], d[i])
                bad += _acc_row(3, q[i], u[i], d[i], q2p, r2p, trig_in(3, tr, i - i0), out, i)
        return bad, bad_in

    @unfused
    def _full_loop(case, q, u, d, q2p, r2p, pos, vel, acc, V, Vd, with_acc, tr, start, stop):  # pragma: no cover
        n = q.shape[0]
        nb, nb_in = 0, 0
        for b in range(start // TRIG_BLOCK, (stop + TRIG_BLOCK - 1) // TRIG_BLOCK):
            i0, i1 = b * TRIG_BLOCK, min(n, (b + 1) * TRIG_BLOCK)
            if case == 3 and block_trig(q, i0, i1, tr):
                libm_columns(q, i0, i1, tr)
            for i in range(i0, i1):
                qi, ui, di = q[i], u[i], d[i]
                nb_in += bad_inputs(case, qi, ui, di)
                C1, M, r, L, Ld, w, al, wh, hd, sd, rd, t = state_quantities(case, qi, ui, di, q2p, r2p,
                                                                             trig_in(case, tr, i - i0))
                P, P_dot, G, G_dot = columns(case, qi, ui, C1, M, w, wh, t)
                vw = cross(w[0], w[1], w[2], L[0], L[1], L[2])
                vh = cross(wh[0], wh[1], wh[2], r[0], r[1], r[2])
                for k in range(3):
                    pos[i, k] = qi[k] + L[k]
                    vel[i, k] = ui[k] + sd[k] + vw[k] + vh[k]
                    nb += nonfinite(pos[i, k]) + nonfinite(vel[i, k])
                for j in range(3):
                    pj = cross(P[j], P[3 + j], P[6 + j], L[0], L[1], L[2])
                    pdj = cross(P_dot[j], P_dot[3 + j], P_dot[6 + j], L[0], L[1], L[2])
                    pl = cross(P[j], P[3 + j], P[6 + j], Ld[0], Ld[1], Ld[2])
                    gj = cross(G[j], G[3 + j], G[6 + j], r[0], r[1], r[2])
                    gdj = cross(G_dot[j], G_dot[3 + j], G_dot[6 + j], r[0], r[1], r[2])
                    gr = cross(G[j], G[3 + j], G[6 + j], rd[0], rd[1], rd[2])
                    cw = cross(w[0], w[1], w[2], C1[j], C1[3 + j], C1[6 + j])
                    for k in range(3):
                        V[i, k, j] = 1.0 if k == j else 0.0
                        V[i, k, 3 + j] = pj[k]
                        V[i, k, 6 + j] = C1[3 * k + j]
                        V[i, k, 9 + j] = gj[k]
                        Vd[i, k, j] = 0.0
                        Vd[i, k, 3 + j] = pdj[k] + pl[k]
                        Vd[i, k, 6 + j] = cw[k]
                        Vd[i, k, 9 + j] = gdj[k] + gr[k]
                        nb += (nonfinite(pj[k]) + nonfinite(gj[k]) + nonfinite(Vd[i, k, 3 + j])
                               + nonfinite(Vd[i, k, 9 + j]))
                if with_acc:
                    a = acc_from(di, C1, r, L, Ld, w, al, wh, hd, sd, rd)
                    acc[i, 0], acc[i, 1], acc[i, 2] = a[0], a[1], a[2]
                    nb += nonfinite(a[0]) + nonfinite(a[1]) + nonfinite(a[2])
        return nb, nb_in


ACC_US_PER_STATE, FULL_US_PER_STATE = 0.07, 0.15
"""Microseconds of work a state on one thread of the acceleration alone and of every output, what
:func:`relacc.kernels.jit.parallel_pays` weighs: 0.062-0.080 and 0.133-0.168 in ``kernels-ab-2026-11-29-run1``."""


def _run(loop, args: tuple, us_per_state: float) -> tuple[int, int]:
    """``loop(*args, tr, start, stop)`` over every state, ``tr`` case 3's trigonometry scratch of the thread: on the
    calling thread, or split over numba's threads in whole blocks of :data:`TRIG_BLOCK` states where that pays
    (:func:`relacc.kernels.jit.parallel_pays`: a parallel loop's start alone cost 130-230 us here, 75 us of a single
    state's ``relacc.g2_kinematics`` when every call paid it). A state's bits are the same either way: each block's
    sines and cosines are its own."""
    from relacc.kernels.jit import parallel_pays, split

    width = TRIG_BLOCK if args[0] == 3 else 1

    def share(*a):
        return loop(*a[:-2], np.empty((13, width)), a[-2], a[-1])

    n = args[1].shape[0]
    return split(share, args, n, TRIG_BLOCK) if parallel_pays(n, us_per_state, TRIG_BLOCK) else share(*args, 0, n)


def acceleration(case: int, q, u, udot, q2p, r2p, backend: str | None = None, out=None):
    """G2's classical acceleration for validated, C-contiguous float64 ``(n, .)`` inputs (into ``out`` if given).

    Returns:
        ``(acceleration, n_nonfinite, n_bad_inputs)``: ``(n, 3)`` fixed
        components, m/s^2; the number of non-finite results (overflow; an
        upper bound, 0 when there is none) and of bad inputs (non-finite, or
        quaternions off unit norm), both counted inside the kernel. Callers
        look at the outputs, or check the inputs' values to report them, only
        when a count is non-zero.
    """
    if (backend or BACKEND) == "numba":
        out = np.empty((q.shape[0], 3)) if out is None else out
        bad, bad_in = _run(_acc_loop, (int(case), *read_only(q, u, udot, q2p, r2p), out), ACC_US_PER_STATE)
        return out, bad, bad_in
    acc = np.stack(acceleration_of(int(case), q.T, u.T, udot.T, q2p, r2p, _numpy_trig(int(case), q.T)), -1)
    if out is not None:
        out[...] = acc
        acc = out
    return acc, int(np.count_nonzero(~np.isfinite(acc))), _numpy_bad_inputs(int(case), q, u, udot)


def kinematics(case: int, q, u, udot, q2p, r2p, backend: str | None = None, out=None):
    """All outputs for validated, C-contiguous float64 ``(n, .)`` inputs (into the 5 arrays ``out`` if given).

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
        if out is None:
            out = (np.empty((n, 3)), np.empty((n, 3)), np.empty((n, 3)) if with_acc else None, np.empty((n, 3, 12)),
                   np.empty((n, 3, 12)))
        pos, vel, acc, V, Vd = out
        bad, bad_in = _run(_full_loop, (int(case), *read_only(q, u, d, q2p, r2p), pos, vel,
                                        acc if with_acc else np.empty((1, 3)), V, Vd, with_acc), FULL_US_PER_STATE)
        return (pos, vel, (acc if with_acc else None), V, Vd), bad, bad_in
    result = _numpy_kinematics(int(case), q, u, d, q2p, r2p, with_acc)
    if out is not None:
        for target, value in zip(out, result):
            if value is not None:
                target[...] = value
        result = tuple(out[k] if result[k] is not None else None for k in range(5))
    bad = sum(int(np.count_nonzero(~np.isfinite(a))) for a in result if a is not None)
    return result, bad, _numpy_bad_inputs(int(case), q, u, d)


def _numpy_trig(case, qT):
    """The numpy backend's :func:`relacc.kernels.perstate.trig_libm`: the numba loops' arithmetic on whole columns.

    :func:`relacc.kernels.trig.sincos` for every angle, and libm's ``sin``/``cos`` for every angle of a
    state with an angle beyond :data:`relacc.kernels.trig.LIMIT`, as the numba loops do, so that both
    backends agree bit for bit.
    """
    if case != 3:
        return NO_TRIG
    x = qT[list(ANGLES)]
    s, c = trig.sincos(x)
    far = np.any(np.abs(x) > trig.LIMIT, axis=0)
    s, c = np.where(far, np.sin(x), s), np.where(far, np.cos(x), c)
    return (*c[:3], *s[:3], *c[3:], *s[3:])


def _numpy_bad_inputs(case, q, u, d):
    """The numpy backend's count of bad inputs (same rule as :func:`bad_inputs`)."""
    bad = sum(int(np.count_nonzero(~np.isfinite(a))) for a in (q, u, d))
    if case != 3:
        for sl in (slice(3, 7), slice(10, 14)):
            bad += int(np.count_nonzero(np.abs(np.einsum("ij,ij->i", q[:, sl], q[:, sl]) - 1.0) > QUAT_TOL))
    return bad


def _numpy_kinematics(case, q, u, d, q2p, r2p, with_acc):
    """The same kernel on whole columns (the numpy backend)."""
    qT, uT, dT = q.T, u.T, d.T
    C1, M, r, L, Ld, w, al, wh, hd, sd, rd, t = state_quantities(case, qT, uT, dT, q2p, r2p, _numpy_trig(case, qT))
    P, P_dot, G, G_dot = columns(case, qT, uT, C1, M, w, wh, t)
    n = q.shape[0]
    pos = np.stack([qT[k] + L[k] for k in range(3)], -1)
    vw, vh = cross(*w, *L), cross(*wh, *r)
    vel = np.stack([uT[k] + sd[k] + vw[k] + vh[k] for k in range(3)], -1)
    V, Vd = np.zeros((n, 3, 12)), np.zeros((n, 3, 12))
    for j in range(3):
        cols = (
            cross(P[j], P[3 + j], P[6 + j], *L),
            (C1[j], C1[3 + j], C1[6 + j]),
            cross(G[j], G[3 + j], G[6 + j], *r),
        )
        pd, pl = cross(P_dot[j], P_dot[3 + j], P_dot[6 + j], *L), cross(P[j], P[3 + j], P[6 + j], *Ld)
        gd, gr = cross(G_dot[j], G_dot[3 + j], G_dot[6 + j], *r), cross(G[j], G[3 + j], G[6 + j], *rd)
        cw = cross(*w, C1[j], C1[3 + j], C1[6 + j])
        V[:, j, j] = 1.0
        for k in range(3):
            V[:, k, 3 + j], V[:, k, 6 + j], V[:, k, 9 + j] = cols[0][k], cols[1][k], cols[2][k]
            Vd[:, k, 3 + j], Vd[:, k, 6 + j], Vd[:, k, 9 + j] = pd[k] + pl[k], cw[k], gd[k] + gr[k]
    acc = np.stack(acc_from(dT, C1, r, L, Ld, w, al, wh, hd, sd, rd), -1) if with_acc else None
    return pos, vel, acc, V, Vd


BACKEND = "numba" if HAVE_NUMBA else "numpy"
"""The backend used by default: ``numba`` when importable, else ``numpy``."""
