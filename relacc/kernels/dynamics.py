"""Fused kernel for Kane's equations: the throughput path of :mod:`relacc.dynamics`.

Same mathematics as :func:`relacc.dynamics.equations_of_motion`, per state,
with the partial velocities in the column form of :mod:`relacc.kernels.kinematics`:

* ``V_G2`` columns ``[e_j | p_j x L | C1_j | g_j x r2]``, ``V_G1`` columns
  ``[e_j | p_j x r1 | 0 | 0]``, ``Om_B1 = [0 | p_j | 0 | 0]``, ``Om_B2 = [0 | p_j | 0 | g_j]``;
* the velocity-product terms ``Vdot u`` and ``Omdot u`` are the
  accelerations of :mod:`relacc.kernels.kinematics` evaluated with ``udot = 0``.

Each effect is assembled only when its flag is set: an absent effect costs
nothing. ``tests/test_dynamics.py`` holds the kernel to the reference.
"""

from __future__ import annotations

import numpy as np

from relacc.kernels import kinematics as fast
from relacc.kernels.perstate import HAVE_NUMBA, acc_from, columns, cross, jitable, mm, mv, state_quantities, trig_of

if HAVE_NUMBA:
    import numba

# Offsets into the chain parameters ``cp`` (:func:`chain_params`), all in the chain's own components.
Q2, R2, R1 = 0, 3, 6          # q2' (B1), r2' (B2), r1' (B1): 3 each, m
M1, M2 = 9, 10                # masses, kg
INERTIA_B1, INERTIA_B2 = 11, 20  # inertias about G1 (B1 comps), G2 (B2 comps): 9 each, row-major, kg m^2
N_CHAIN = 29

# Offsets into the effect parameters ``ep`` (:func:`effect_params`): each effect has a flag (1.0 on, 0.0 off:
# off means not computed) followed by its values.
GRAVITY_ON, GRAVITY = 0, 1                    # g (3), m/s^2, fixed components
SPRING_ON, STIFFNESS, REST = 4, 5, 8          # K (3) N/m, rest (3) m; on s2' (B1 components)
DAMPING_ON, DAMPING = 11, 12                  # C (3) N s/m, on s2'_dot
BALL_ON, BALL = 15, 16                        # c (1) N m s/rad, on the spherical joint
FORCE_ON, FORCE = 17, 18                      # F (3) N at G2, fixed components
TORQUE1_ON, TORQUE1 = 21, 22                  # T1 (3) N m on B1, fixed components
TORQUE2_ON, TORQUE2 = 25, 26                  # T2 (3) N m on B2, fixed components
N_EFFECTS = 29


def chain_params(chain) -> np.ndarray:
    """The chain's constants as one float array laid out by ``Q2`` ... ``INERTIA_B2`` (``N_CHAIN`` values)."""
    out = np.empty(N_CHAIN)
    out[Q2:Q2 + 3], out[R2:R2 + 3], out[R1:R1 + 3] = chain.q2, chain.r2, chain.r1
    out[M1], out[M2] = chain.m1, chain.m2
    out[INERTIA_B1:INERTIA_B1 + 9], out[INERTIA_B2:INERTIA_B2 + 9] = chain.I1.ravel(), chain.I2.ravel()
    return out


def effect_params(effects) -> np.ndarray:
    """Flags and values of :class:`relacc.dynamics.Effects`, laid out by ``GRAVITY_ON`` ... ``TORQUE2``."""
    out = np.zeros(N_EFFECTS)
    for flag, slots in ((GRAVITY_ON, ((GRAVITY, effects.gravity),)),
                        (SPRING_ON, ((STIFFNESS, effects.spring_stiffness), (REST, effects.spring_rest))),
                        (DAMPING_ON, ((DAMPING, effects.spring_damping),)),
                        (BALL_ON, ((BALL, effects.ball_damping),)),
                        (FORCE_ON, ((FORCE, effects.force_G2),)),
                        (TORQUE1_ON, ((TORQUE1, effects.torque_B1),)),
                        (TORQUE2_ON, ((TORQUE2, effects.torque_B2),))):
        if slots[0][1] is not None:
            out[flag] = 1.0
            for at, value in slots:
                value = np.atleast_1d(np.asarray(value, dtype=float))
                out[at:at + value.size] = value
    return out


@jitable
def _col(A, j):
    return A[j], A[3 + j], A[6 + j]


@jitable
def _eom(case, q, u, cp, ep, M, f, nu):
    """Kane's ``M`` (12x12) and ``f`` (12) and the body speeds ``nu`` (12) of one state, into the arrays."""
    z = np.zeros(12)
    q2p, r2p, r1p = cp[Q2:Q2 + 3], cp[R2:R2 + 3], cp[R1:R1 + 3]
    m1, m2 = cp[M1], cp[M2]
    C1, Mr, r, L, Ld, w, al, wh, hd, sd, rd, t = state_quantities(case, q, u, z, q2p, r2p, trig_of(case, q))
    P, P_dot, G, G_dot = columns(case, q, u, C1, Mr, w, wh, t)
    C2 = mm(C1, Mr)
    r1 = mv(C1, r1p[0], r1p[1], r1p[2])
    # partial velocity (V1, V2) and angular velocity (O1, O2) columns, fixed components: (3, 12)
    V1, V2, O1, O2 = np.zeros((3, 12)), np.zeros((3, 12)), np.zeros((3, 12)), np.zeros((3, 12))
    for j in range(3):
        pj, gj, cj = _col(P, j), _col(G, j), _col(C1, j)
        a = cross(pj[0], pj[1], pj[2], L[0], L[1], L[2])
        b = cross(pj[0], pj[1], pj[2], r1[0], r1[1], r1[2])
        c = cross(gj[0], gj[1], gj[2], r[0], r[1], r[2])
        for k in range(3):
            V1[k, j] = V2[k, j] = 1.0 if k == j else 0.0
            V2[k, 3 + j], V2[k, 6 + j], V2[k, 9 + j] = a[k], cj[k], c[k]
            V1[k, 3 + j] = b[k]
            O1[k, 3 + j] = O2[k, 3 + j] = pj[k]
            O2[k, 9 + j] = gj[k]
    # velocity-product terms: accelerations with udot = 0
    a2 = acc_from(z, C1, r, L, Ld, w, al, wh, hd, sd, rd)
    wr = cross(w[0], w[1], w[2], r1[0], r1[1], r1[2])
    t1, t2 = cross(al[0], al[1], al[2], r1[0], r1[1], r1[2]), cross(w[0], w[1], w[2], wr[0], wr[1], wr[2])
    a1 = (t1[0] + t2[0], t1[1] + t2[1], t1[2] + t2[2])
    w2 = (w[0] + wh[0], w[1] + wh[1], w[2] + wh[2])
    al2 = (al[0] + hd[0], al[1] + hd[1], al[2] + hd[2])
    I1 = np.empty((3, 3))
    I2 = np.empty((3, 3))
    for R, Ib, out in ((C1, cp[INERTIA_B1:INERTIA_B1 + 9], I1), (C2, cp[INERTIA_B2:INERTIA_B2 + 9], I2)):
        RI = mm(R, (Ib[0], Ib[1], Ib[2], Ib[3], Ib[4], Ib[5], Ib[6], Ib[7], Ib[8]))
        RIRt = mm(RI, (R[0], R[3], R[6], R[1], R[4], R[7], R[2], R[5], R[8]))
        for k in range(9):
            out[k // 3, k % 3] = RIRt[k]
    for i in range(12):
        for j in range(12):
            s = 0.0
            for k in range(3):
                s += m1 * V1[k, i] * V1[k, j] + m2 * V2[k, i] * V2[k, j]
                for l in range(3):
                    s += O1[k, i] * I1[k, l] * O1[l, j] + O2[k, i] * I2[k, l] * O2[l, j]
            M[i, j] = s
    # inertia terms: -m V^T (Vdot u) - Om^T (I Omdot u + omega x I omega)
    h1 = np.empty(3)
    h2 = np.empty(3)
    for k in range(3):
        h1[k] = I1[k, 0] * al[0] + I1[k, 1] * al[1] + I1[k, 2] * al[2]
        h2[k] = I2[k, 0] * al2[0] + I2[k, 1] * al2[1] + I2[k, 2] * al2[2]
    Iw1 = (I1[0, 0] * w[0] + I1[0, 1] * w[1] + I1[0, 2] * w[2], I1[1, 0] * w[0] + I1[1, 1] * w[1] + I1[1, 2] * w[2],
           I1[2, 0] * w[0] + I1[2, 1] * w[1] + I1[2, 2] * w[2])
    Iw2 = (I2[0, 0] * w2[0] + I2[0, 1] * w2[1] + I2[0, 2] * w2[2],
           I2[1, 0] * w2[0] + I2[1, 1] * w2[1] + I2[1, 2] * w2[2],
           I2[2, 0] * w2[0] + I2[2, 1] * w2[1] + I2[2, 2] * w2[2])
    g1 = cross(w[0], w[1], w[2], Iw1[0], Iw1[1], Iw1[2])
    g2 = cross(w2[0], w2[1], w2[2], Iw2[0], Iw2[1], Iw2[2])
    F1 = np.empty(3)   # force on G1 (N) and torques on B1, B2 (N m), fixed components, from every active effect
    F2 = np.empty(3)
    T1 = np.empty(3)
    T2 = np.empty(3)
    for k in range(3):
        F1[k] = -m1 * a1[k]
        F2[k] = -m2 * a2[k]
        T1[k] = -h1[k] - g1[k]
        T2[k] = -h2[k] - g2[k]
        if ep[GRAVITY_ON] != 0.0:
            F1[k] += m1 * ep[GRAVITY + k]
            F2[k] += m2 * ep[GRAVITY + k]
        if ep[FORCE_ON] != 0.0:
            F2[k] += ep[FORCE + k]
        if ep[TORQUE1_ON] != 0.0:
            T1[k] += ep[TORQUE1 + k]
        if ep[TORQUE2_ON] != 0.0:
            T2[k] += ep[TORQUE2 + k]
    for i in range(12):
        s = 0.0
        for k in range(3):
            s += V1[k, i] * F1[k] + V2[k, i] * F2[k] + O1[k, i] * T1[k] + O2[k, i] * T2[k]
        f[i] = s
    o = 7 if case != 3 else 6
    for k in range(3):
        if ep[SPRING_ON] != 0.0:
            f[6 + k] -= ep[STIFFNESS + k] * (q[o + k] - ep[REST + k])
        if ep[DAMPING_ON] != 0.0:
            f[6 + k] -= ep[DAMPING + k] * u[6 + k]
    if ep[BALL_ON] != 0.0:
        what = mv(G, u[9], u[10], u[11])
        for j in range(3):
            f[9 + j] -= ep[BALL] * (G[j] * what[0] + G[3 + j] * what[1] + G[6 + j] * what[2])
    # body speeds nu = W u: [s1_dot, omega'_B1 = C1^T omega_B1, s2'_dot, omega_hat'_B2 = C2^T w_hat]
    wb = mv((C1[0], C1[3], C1[6], C1[1], C1[4], C1[7], C1[2], C1[5], C1[8]), w[0], w[1], w[2])
    hb = mv((C2[0], C2[3], C2[6], C2[1], C2[4], C2[7], C2[2], C2[5], C2[8]), wh[0], wh[1], wh[2])
    for k in range(3):
        nu[k], nu[3 + k], nu[6 + k], nu[9 + k] = u[k], wb[k], u[6 + k], hb[k]


if HAVE_NUMBA:

    @numba.njit(cache=True)
    def _eom_one(case, q, u, cp, ep):  # pragma: no cover - compiled
        M, f, nu = np.empty((12, 12)), np.empty(12), np.empty(12)
        _eom(case, q, u, cp, ep, M, f, nu)
        return M, f, nu

    @numba.njit(cache=True)
    def _rates_one(case, q, u, cp, ep):  # pragma: no cover - compiled
        M, f, nu = _eom_one(case, q, u, cp, ep)
        return nu, np.linalg.solve(M, f)

    @numba.njit(parallel=True, cache=True)
    def _eom_batch(case, q, u, cp, ep, M, f, nu):  # pragma: no cover - compiled
        for i in numba.prange(q.shape[0]):
            _eom(case, q[i], u[i], cp, ep, M[i], f[i], nu[i])


def equations_of_motion(chain, case, q, u, effects):
    """Kane's equations for validated float64 ``q (n, nq)``, ``u (n, 12)`` (see :mod:`relacc.dynamics`).

    Returns:
        ``M`` ``(n, 12, 12)`` (kg, kg m, kg m^2 blocks), ``f`` ``(n, 12)`` (N and
        N m per unit speed), both in the case's speeds, and the body speeds
        ``nu`` ``(n, 12)`` (Case 2's ``u``: m/s, rad/s).
    """
    n = q.shape[0]
    M, f, nu = np.empty((n, 12, 12)), np.empty((n, 12)), np.empty((n, 12))
    cp, ep = chain_params(chain), effect_params(effects)
    if fast.BACKEND == "numba":
        _eom_batch(int(case), np.ascontiguousarray(q), np.ascontiguousarray(u), cp, ep, M, f, nu)
    else:
        for i in range(n):
            _eom(int(case), q[i], u[i], cp, ep, M[i], f[i], nu[i])
    return M, f, nu


class Rates:
    """``(nu, udot)`` of one state for the integrators: body speeds (the tangent) and Kane's accelerations.

    Cases 1-2 integrate the quaternions with the body speeds ``nu``; case 3
    integrates the angles with ``u`` itself.
    """

    def __init__(self, chain, case, effects):
        self.case, self.cp, self.ep = int(case), chain_params(chain), effect_params(effects)

    def __call__(self, q, u):
        from relacc.errors import IntegrationError

        message = ("the integration diverged: the state or its equations of motion became non-finite or "
                   "singular; reduce the step (or, near case-3 gimbal lock, use quaternion coordinates)")
        if not (np.all(np.isfinite(q)) and np.all(np.isfinite(u))):
            raise IntegrationError(message)
        try:
            with np.errstate(over="ignore", invalid="ignore"):
                if fast.BACKEND == "numba":
                    nu, udot = _rates_one(self.case, q, u, self.cp, self.ep)
                else:
                    M, f, nu = np.empty((12, 12)), np.empty(12), np.empty(12)
                    _eom(self.case, q, u, self.cp, self.ep, M, f, nu)
                    udot = np.linalg.solve(M, f)
        except np.linalg.LinAlgError:
            raise IntegrationError(message) from None
        return (u if self.case == 3 else nu), udot


@jitable
def exp_mul(q, phi):
    """``q (x) Exp(phi)`` for a unit quaternion ``q`` (w, x, y, z) and a rotation vector ``phi`` (body)."""
    th2 = phi[0] * phi[0] + phi[1] * phi[1] + phi[2] * phi[2]
    if th2 < 1e-8:
        w, k = 1 - th2 / 8 + th2 * th2 / 384, 0.5 - th2 / 48 + th2 * th2 / 3840
    else:
        th = np.sqrt(th2)
        w, k = np.cos(th / 2), np.sin(th / 2) / th
    x, y, z = k * phi[0], k * phi[1], k * phi[2]
    return (q[0] * w - q[1] * x - q[2] * y - q[3] * z, q[0] * x + q[1] * w + q[2] * z - q[3] * y,
            q[0] * y - q[1] * z + q[2] * w + q[3] * x, q[0] * z + q[1] * y - q[2] * x + q[3] * w)


@jitable
def so3_dexpinv(phi, w):
    """``J_r^-1(phi) w`` (see :func:`relacc.dynamics.integrate.so3_dexpinv_body`)."""
    th2 = phi[0] * phi[0] + phi[1] * phi[1] + phi[2] * phi[2]
    if th2 < 1e-4:
        beta = 1 / 12 + th2 / 720 + th2 * th2 / 30240
    else:
        th = np.sqrt(th2)
        beta = 1 / th2 - (1 + np.cos(th)) / (2 * th * np.sin(th))
    c = cross(phi[0], phi[1], phi[2], w[0], w[1], w[2])
    cc = cross(phi[0], phi[1], phi[2], c[0], c[1], c[2])
    return w[0] + 0.5 * c[0] + beta * cc[0], w[1] + 0.5 * c[1] + beta * cc[1], w[2] + 0.5 * c[2] + beta * cc[2]


if HAVE_NUMBA:

    @numba.njit(cache=True)
    def integrate_q14(q, delta):  # pragma: no cover - compiled
        out = q.copy()
        for k in range(3):
            out[k] += delta[k]
            out[7 + k] += delta[6 + k]
        out[3:7] = exp_mul(q[3:7], delta[3:6])
        out[10:14] = exp_mul(q[10:14], delta[9:12])
        return out

    @numba.njit(cache=True)
    def dexpinv_q14(delta, w):  # pragma: no cover - compiled
        out = w.copy()
        out[3:6] = so3_dexpinv(delta[3:6], w[3:6])
        out[9:12] = so3_dexpinv(delta[9:12], w[9:12])
        return out
