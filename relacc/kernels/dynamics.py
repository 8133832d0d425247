"""Fused forward dynamics and integration: the throughput path of :mod:`relacc.dynamics` and simulations.

The chain's joint between B1 and B2 is three slides and a ball: six degrees
of freedom, so the two bodies are free of each other and Kane's ``12 x 12``
mass matrix is, in the bodies' absolute accelerations, block diagonal: two
6 x 6 blocks, ``diag(m_i I, I_Gi)``. The forward dynamics of one state is
therefore, without any linear solve:

1. the bodies' angular velocities from the case's speeds (fixed components:
   ``omega_B1``, ``omega_hat_B2``, ``omega_B2 = omega_B1 + omega_hat_B2``);
2. every active effect as a force and a torque on each body (gravity
   ``m_i g``; the spring and damper on ``s2'`` as equal and opposite forces at
   B2's joint point; ball damping ``-c omega_hat_B2`` on B2 and its reaction on
   B1; the force at G2; the torques);
3. Newton-Euler for each body: ``a_Gi = F_i / m_i``,
   ``alpha_i = I_i^-1 (T_i - omega_i x I_i omega_i)`` (body components);
4. the case's ``udot`` from the absolute accelerations, by differentiating
   the relative coordinates twice: ``s1_ddot`` from ``a_G1``; ``s2'_ddot`` from
   ``a_G2`` minus everything else in ``d^2/dt^2 (s1 + [R_B1]^T (q2' + s2') + r2)``;
   the angular rates as the derivatives of the case's components of
   ``omega_B1`` and ``omega_hat_B2`` (case 3: through ``W(theta)^-1``).

It is a different derivation from Kane's equations (:mod:`relacc.dynamics.kane`):
``tests/test_dynamics.py`` holds its ``udot`` to satisfy them, ``M udot = f``,
to rounding (backward error ``<= c eps``).

The integrators (RKMK4 on SO(3) for cases 1-2, RK4 on the angles for case 3,
semi-implicit Euler) run here as compiled loops over steps (:func:`advance`,
:func:`record`) and over the members of an ensemble (:func:`ensemble`), the
same algorithms as :mod:`relacc.dynamics.integrate`.
"""

from __future__ import annotations

import weakref

import numpy as np

from relacc.core.tolerances import MAX_CONDITION
from relacc.kernels.jit import leaf, unfused
from relacc.kernels.perstate import HAVE_NUMBA, bad_inputs, jitable, numba
from relacc.kernels.so3 import cross, exp_mul, jr_inv, mv, quat_matrix, r123, w123_dot_mv, w123_mv, w123_solve
from relacc.kernels.trig import LIMIT, sincos

# Offsets into the chain parameters ``cp`` (:func:`chain_params`), all in the chain's own components.
Q2, R2, R1 = 0, 3, 6          # q2' (B1), r2' (B2), r1' (B1): 3 each, m
M1, M2 = 9, 10                # masses, kg
INERTIA_B1, INERTIA_B2 = 11, 20  # inertias about G1 (B1 comps), G2 (B2 comps): 9 each, row-major, kg m^2
INVERSE_B1, INVERSE_B2 = 29, 38  # their inverses, 1/(kg m^2)
N_CHAIN = 47

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

INTEGRATORS = {"rk4": 0, "euler": 1}
"""relacc's integrators by scene name, and their codes in the compiled loops."""


_PARAMS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
"""Each chain's and each effects' parameter array, made once: both are frozen, with read-only arrays."""


def _once(key, make) -> np.ndarray:
    got = _PARAMS.get(key)
    if got is None:
        got = _PARAMS[key] = make(key)
    return got


def chain_params(chain) -> np.ndarray:
    """The chain's constants as one float array laid out by ``Q2`` ... ``INVERSE_B2`` (``N_CHAIN`` values); made once
    a chain and shared by its callers, which never write to it (a single state's call spent 11 us making it)."""
    return _once(chain, _chain_params)


def effect_params(effects) -> np.ndarray:
    """Flags and values of :class:`relacc.dynamics.Effects`, laid out by ``GRAVITY_ON`` ... ``TORQUE2``; made once
    an effects and shared as :func:`chain_params`."""
    return _once(effects, _effect_params)


def _chain_params(chain) -> np.ndarray:
    out = np.empty(N_CHAIN)
    out[Q2:Q2 + 3], out[R2:R2 + 3], out[R1:R1 + 3] = chain.q2, chain.r2, chain.r1
    out[M1], out[M2] = chain.m1, chain.m2
    out[INERTIA_B1:INERTIA_B1 + 9], out[INERTIA_B2:INERTIA_B2 + 9] = chain.I1.ravel(), chain.I2.ravel()
    out[INVERSE_B1:INVERSE_B1 + 9] = np.linalg.inv(chain.I1).ravel()
    out[INVERSE_B2:INVERSE_B2 + 9] = np.linalg.inv(chain.I2).ravel()
    return out


def _effect_params(effects) -> np.ndarray:
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
def _mtv(A, x0, x1, x2):
    """``A^T x`` for a row-major 3x3 tuple ``A``."""
    return (A[0] * x0 + A[3] * x1 + A[6] * x2, A[1] * x0 + A[4] * x1 + A[7] * x2,
            A[2] * x0 + A[5] * x1 + A[8] * x2)


@jitable
def _cp3(cp, at):
    return cp[at], cp[at + 1], cp[at + 2]


@jitable
def _cp9(cp, at):
    return (cp[at], cp[at + 1], cp[at + 2], cp[at + 3], cp[at + 4], cp[at + 5], cp[at + 6], cp[at + 7],
            cp[at + 8])


@jitable
def _add(a, b):
    return a[0] + b[0], a[1] + b[1], a[2] + b[2]


@jitable
def _sub(a, b):
    return a[0] - b[0], a[1] - b[1], a[2] - b[2]


@jitable
def _scale(s, a):
    return s * a[0], s * a[1], s * a[2]


@jitable
def _x(a, b):
    return cross(a[0], a[1], a[2], b[0], b[1], b[2])


@jitable
def _angle_trig(x):
    """``(cos x, sin x)`` of one angle (rad): :func:`relacc.kernels.trig.sincos`, libm beyond its range."""
    if abs(x) <= LIMIT:
        s, c = sincos(x)
        return c, s
    return np.cos(x), np.sin(x)


@jitable
def _trig3(q, k):
    """``(c1, c2, c3, s1, s2, s3)`` of the 1-2-3 angles ``q[k:k + 3]``."""
    c1, s1 = _angle_trig(q[k])
    c2, s2 = _angle_trig(q[k + 1])
    c3, s3 = _angle_trig(q[k + 2])
    return c1, c2, c3, s1, s2, s3


@jitable(inline=True)
def _w_solve(t, b):
    """``W(theta)^-1 b`` for the cosines and sines ``t`` (:func:`_trig3`)."""
    return w123_solve(t[0], t[1], t[3], t[4], b[0], b[1], b[2])


@jitable
def _newton_euler(m, I, Iinv, C, F, T, w):
    """Absolute accelerations of one body: ``a_G = F / m``, ``alpha = C I^-1 (C^T T - w' x I w')`` (fixed comps)."""
    wb = _mtv(C, w[0], w[1], w[2])
    Iw = mv(I, wb[0], wb[1], wb[2])
    Tb = _mtv(C, T[0], T[1], T[2])
    g = _sub(Tb, _x(wb, Iw))
    ab = mv(Iinv, g[0], g[1], g[2])
    return _scale(1.0 / m, F), mv(C, ab[0], ab[1], ab[2])


@leaf
def rates(case, q, u, cp, ep):
    """One state's ``(tangent, udot)``, 12-tuples: what the integrators move along, and the speeds' rates.

    ``tangent``: cases 1-2 the body speeds ``[s1_dot, omega'_B1, s2'_dot, omega_hat'_B2]`` (the
    quaternions move by ``quat (x) Exp(omega' dt)``); case 3 ``u`` itself. ``udot``: the case's
    speeds' rates by Newton-Euler (module docstring), m/s^2 and rad/s^2 in the case's components.
    """
    t1 = t2 = (1.0, 1.0, 1.0, 0.0, 0.0, 0.0)  # the angles' trigonometry (case 3 only)
    if case == 3:
        t1, t2 = _trig3(q, 3), _trig3(q, 9)
        C1, Mr = r123(t1[0], t1[1], t1[2], t1[3], t1[4], t1[5]), r123(t2[0], t2[1], t2[2], t2[3], t2[4], t2[5])
        o = 6
    else:
        C1, Mr = quat_matrix(q[3], q[4], q[5], q[6]), quat_matrix(q[10], q[11], q[12], q[13])
        o = 7
    C2 = (C1[0] * Mr[0] + C1[1] * Mr[3] + C1[2] * Mr[6], C1[0] * Mr[1] + C1[1] * Mr[4] + C1[2] * Mr[7],
          C1[0] * Mr[2] + C1[1] * Mr[5] + C1[2] * Mr[8], C1[3] * Mr[0] + C1[4] * Mr[3] + C1[5] * Mr[6],
          C1[3] * Mr[1] + C1[4] * Mr[4] + C1[5] * Mr[7], C1[3] * Mr[2] + C1[4] * Mr[5] + C1[5] * Mr[8],
          C1[6] * Mr[0] + C1[7] * Mr[3] + C1[8] * Mr[6], C1[6] * Mr[1] + C1[7] * Mr[4] + C1[8] * Mr[7],
          C1[6] * Mr[2] + C1[7] * Mr[5] + C1[8] * Mr[8])
    ua, ub = (u[3], u[4], u[5]), (u[9], u[10], u[11])
    # 1. angular velocities, fixed components
    if case == 1:
        w1, wh = ua, mv(C1, ub[0], ub[1], ub[2])
    elif case == 2:
        w1, wh = mv(C1, ua[0], ua[1], ua[2]), mv(C2, ub[0], ub[1], ub[2])
    else:
        w1 = w123_mv(t1[0], t1[1], t1[3], t1[4], ua[0], ua[1], ua[2])
        hb = w123_mv(t2[0], t2[1], t2[3], t2[4], ub[0], ub[1], ub[2])
        wh = mv(C1, hb[0], hb[1], hb[2])
    w2 = _add(w1, wh)
    # geometry, fixed components: G1 from B1's origin, the joint point from B1's origin, G2 from it
    r1 = mv(C1, cp[R1], cp[R1 + 1], cp[R1 + 2])
    L = mv(C1, cp[Q2] + q[o], cp[Q2 + 1] + q[o + 1], cp[Q2 + 2] + q[o + 2])
    r2 = mv(C2, cp[R2], cp[R2 + 1], cp[R2 + 2])
    sd = mv(C1, u[6], u[7], u[8])
    m1, m2 = cp[M1], cp[M2]
    # 2. forces on G1, G2 and torques about them, fixed components, from the active effects only
    F1, F2, T1, T2 = (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
    if ep[GRAVITY_ON] != 0.0:
        g = _cp3(ep, GRAVITY)
        F1, F2 = _scale(m1, g), _scale(m2, g)
    if ep[SPRING_ON] != 0.0 or ep[DAMPING_ON] != 0.0:
        f0, f1, f2 = 0.0, 0.0, 0.0
        if ep[SPRING_ON] != 0.0:
            f0 -= ep[STIFFNESS] * (q[o] - ep[REST])
            f1 -= ep[STIFFNESS + 1] * (q[o + 1] - ep[REST + 1])
            f2 -= ep[STIFFNESS + 2] * (q[o + 2] - ep[REST + 2])
        if ep[DAMPING_ON] != 0.0:
            f0 -= ep[DAMPING] * u[6]
            f1 -= ep[DAMPING + 1] * u[7]
            f2 -= ep[DAMPING + 2] * u[8]
        fs = mv(C1, f0, f1, f2)  # on B2 at the joint point; its reaction on B1 at the same point
        F2, F1 = _add(F2, fs), _sub(F1, fs)
        T2 = _add(T2, _x(_scale(-1.0, r2), fs))
        T1 = _add(T1, _x(_sub(L, r1), _scale(-1.0, fs)))
    if ep[BALL_ON] != 0.0:
        tb = _scale(-ep[BALL], wh)  # on B2; its reaction on B1
        T2, T1 = _add(T2, tb), _sub(T1, tb)
    if ep[FORCE_ON] != 0.0:
        F2 = _add(F2, _cp3(ep, FORCE))
    if ep[TORQUE1_ON] != 0.0:
        T1 = _add(T1, _cp3(ep, TORQUE1))
    if ep[TORQUE2_ON] != 0.0:
        T2 = _add(T2, _cp3(ep, TORQUE2))
    # 3. Newton-Euler, each body alone
    a1, al1 = _newton_euler(m1, _cp9(cp, INERTIA_B1), _cp9(cp, INVERSE_B1), C1, F1, T1, w1)
    a2, al2 = _newton_euler(m2, _cp9(cp, INERTIA_B2), _cp9(cp, INVERSE_B2), C2, F2, T2, w2)
    # 4. the case's udot from the absolute accelerations
    s1dd = _sub(_sub(a1, _x(al1, r1)), _x(w1, _x(w1, r1)))
    rest = _add(_add(_add(s1dd, _x(al1, L)), _x(w1, _x(w1, L))), _scale(2.0, _x(w1, sd)))
    rest = _add(_add(rest, _x(al2, r2)), _x(w2, _x(w2, r2)))
    s2dd = _mtv(C1, a2[0] - rest[0], a2[1] - rest[1], a2[2] - rest[2])
    hd = _sub(_sub(al2, al1), _x(w1, wh))  # d/dt of omega_hat_B2's B1 components, in fixed components
    if case == 1:
        ang1, ang2 = al1, _mtv(C1, hd[0], hd[1], hd[2])
        tan1, tan2 = _mtv(C1, w1[0], w1[1], w1[2]), _mtv(C2, wh[0], wh[1], wh[2])
    elif case == 2:
        ang1 = _mtv(C1, al1[0], al1[1], al1[2])
        h2 = _sub(_sub(al2, al1), _x(w2, wh))
        ang2 = _mtv(C2, h2[0], h2[1], h2[2])
        tan1, tan2 = ua, ub
    else:
        ang1 = _w_solve(t1, _sub(al1, w123_dot_mv(t1[0], t1[1], t1[3], t1[4], u[3], u[4], ua[1], ua[2])))
        hb1 = _mtv(C1, hd[0], hd[1], hd[2])
        ang2 = _w_solve(t2, _sub(hb1, w123_dot_mv(t2[0], t2[1], t2[3], t2[4], u[9], u[10], ub[1], ub[2])))
        tan1, tan2 = ua, ub
    udot = (s1dd[0], s1dd[1], s1dd[2], ang1[0], ang1[1], ang1[2], s2dd[0], s2dd[1], s2dd[2],
            ang2[0], ang2[1], ang2[2])
    tangent = (u[0], u[1], u[2], tan1[0], tan1[1], tan1[2], u[6], u[7], u[8], tan2[0], tan2[1], tan2[2])
    return tangent, udot


@leaf
def move(case, q, delta, out):
    """``out = q`` moved by the tangent vector ``delta`` (cases 1-2: ``quat (x) Exp``; case 3: ``q + delta``)."""
    if case == 3:
        for k in range(12):
            out[k] = q[k] + delta[k]
        return
    for k in range(3):
        out[k] = q[k] + delta[k]
        out[7 + k] = q[7 + k] + delta[6 + k]
    exp_mul(q, 3, delta[3], delta[4], delta[5], out)
    exp_mul(q, 10, delta[9], delta[10], delta[11], out)


@jitable
def _dexp_tangent(case, delta, w, out):
    """The local-coordinate rate whose move of ``delta`` has velocity ``w`` (identity in case 3)."""
    for k in range(12):
        out[k] = w[k]
    if case != 3:
        a = jr_inv(delta[3], delta[4], delta[5], w[3], w[4], w[5])
        b = jr_inv(delta[9], delta[10], delta[11], w[9], w[10], w[11])
        out[3], out[4], out[5], out[9], out[10], out[11] = a[0], a[1], a[2], b[0], b[1], b[2]


@jitable
def step(case, method, q, u, dt, cp, ep, s):
    """One step of ``dt`` seconds, in place on ``q``, ``u``; ``s`` a (10, 14) scratch.

    ``method`` 0: RKMK4 (RK4 in local coordinates around the step's start, so cases 1-2 stay on
    SO(3) at order 4); 1: semi-implicit Euler (``u`` first, then ``q`` moves with the new ``u``).
    """
    nq = q.shape[0]
    if method == 1:
        _, a = rates(case, q, u, cp, ep)
        for k in range(12):
            u[k] += dt * a[k]
        w, _ = rates(case, q, u, cp, ep)
        for k in range(12):
            s[0, k] = dt * w[k]
        move(case, q, s[0], s[1])
        q[:] = s[1, :nq]
        return
    d, x, v, kk, acc = s[0], s[1], s[2], s[3], s[4]  # local coordinates, moved q, u, stage slope, sum
    w1, a1 = rates(case, q, u, cp, ep)
    for k in range(12):
        kk[k] = w1[k]
        acc[k] = w1[k]
        s[5, k] = a1[k]
    for stage in range(3):
        h = 0.5 * dt if stage < 2 else dt
        for k in range(12):
            d[k] = h * kk[k]
            v[k] = u[k] + h * (a1[k] if stage == 0 else s[5 + stage, k])
        move(case, q, d, x)
        wn, an = rates(case, x[:nq], v[:12], cp, ep)
        for k in range(12):
            s[6 + stage, k] = an[k]
            s[9, k] = wn[k]
        _dexp_tangent(case, d, s[9], kk)
        for k in range(12):
            acc[k] += (2.0 if stage < 2 else 1.0) * kk[k]
    for k in range(12):
        d[k] = dt / 6 * acc[k]
        u[k] += dt / 6 * (s[5, k] + 2 * s[6, k] + 2 * s[7, k] + s[8, k])
    move(case, q, d, x)
    q[:] = x[:nq]


@jitable
def _finite_state(q, u):
    z = 0.0
    for k in range(q.shape[0]):
        z += q[k] * 0.0
    for k in range(12):
        z += u[k] * 0.0
    return z == 0.0


@jitable
def record(case, method, q, u, dt, gaps, cp, ep, Q, U):
    """From ``(q, u)``, take ``gaps[j]`` steps then store the state in ``Q[j]``, ``U[j]``, for every ``j``.

    Returns:
        The number of records stored: ``len(gaps)``, or the index of the first record whose state
        became non-finite (the run diverged there; the records before it are valid).
    """
    s = np.empty((10, 14))
    for j in range(gaps.shape[0]):
        for _ in range(gaps[j]):
            step(case, method, q, u, dt, cp, ep, s)
        if not _finite_state(q, u):
            return j
        Q[j, :] = q
        U[j, :] = u
    return gaps.shape[0]


@jitable
def suspect_input(case, q, u):
    """1 when a state may fail the input checks of :func:`relacc.dynamics.accelerations`, else 0.

    Non-finite entries and quaternions off unit norm (the rule of
    :func:`relacc.kernels.perstate.bad_inputs`), and, for case 3, an angle
    ``theta_2`` with ``|cos theta_2| < 4 / MAX_CONDITION``, which every speed map
    of condition number ``(1 + |sin|) / |cos|`` above ``MAX_CONDITION / 2`` has:
    a superset of what the checks reject, so that they only run, and decide,
    when a state is suspect.
    """
    if bad_inputs(case, q, u, u):
        return 1
    if case == 3:  # (1 + |sin|) / |cos| > MAX_CONDITION / 2 needs |cos| < 4 / MAX_CONDITION
        for k in (4, 10):
            if abs(np.cos(q[k])) * MAX_CONDITION < 4.0:
                return 1
    return 0


if HAVE_NUMBA:

    @unfused
    def _accelerations(case, q, u, cp, ep, out, start, stop):  # pragma: no cover - compiled
        """States ``start .. stop - 1``' ``udot`` into ``out`` ``(n, 12)``; returns ``(non-finite results, suspect
        inputs)`` (:func:`accelerations`)."""
        bad, bad_in = 0, 0
        for i in range(start, stop):
            bad_in += suspect_input(case, q[i], u[i])
            _, a = rates(case, q[i], u[i], cp, ep)
            nb = 0
            for k in range(12):
                out[i, k] = a[k]
                nb += 0 if (a[k] == a[k] and abs(a[k]) < np.inf) else 1
            bad += nb
        return bad, bad_in

    @numba.njit(cache=True)
    def advance(case, method, q, u, dt, k, cp, ep):  # pragma: no cover - compiled
        """``k`` steps from ``(q, u)`` (copies); returns the new ``(q, u)``."""
        q, u = q.copy(), u.copy()
        s = np.empty((10, 14))
        for _ in range(k):
            step(case, method, q, u, dt, cp, ep, s)
        return q, u

    @numba.njit(cache=True)
    def record_run(case, method, q, u, dt, gaps, cp, ep, Q, U):  # pragma: no cover - compiled
        """:func:`record` on copies of ``q``, ``u``."""
        return record(case, method, q.copy(), u.copy(), dt, gaps, cp, ep, Q, U)

    @numba.njit(parallel=True, cache=True)
    def ensemble(case, method, Q0, U0, dt, gaps, cp, ep, Q, U, done):  # pragma: no cover - compiled
        """:func:`record` for every member in parallel: ``Q0 (N, nq)``, ``U0 (N, 12)`` -> ``Q (N, m, nq)``,
        ``U (N, m, 12)``; ``done[i]`` the records member ``i`` stored."""
        for i in numba.prange(Q0.shape[0]):
            done[i] = record(case, method, Q0[i].copy(), U0[i].copy(), dt, gaps, cp, ep, Q[i], U[i])

    @numba.njit(cache=True)
    def rates_one(case, q, u, cp, ep):  # pragma: no cover - compiled
        """:func:`rates` of one state as two arrays, for Python callers (``solve_ivp``)."""
        w, a = rates(case, q, u, cp, ep)
        return np.array(w), np.array(a)

    @numba.njit(cache=True)
    def move_one(case, q, delta):  # pragma: no cover - compiled
        out = np.empty(q.shape[0])
        move(case, q, delta, out)
        return out

    @numba.njit(cache=True)
    def dexp_one(case, delta, w):  # pragma: no cover - compiled
        out = np.empty(12)
        _dexp_tangent(case, delta, w, out)
        return out

else:  # pragma: no cover - exercised only without numba

    def _accelerations(case, q, u, cp, ep, out, start, stop):
        bad, bad_in = 0, 0
        for i in range(start, stop):
            bad_in += suspect_input(case, q[i], u[i])
            out[i] = rates(case, q[i], u[i], cp, ep)[1]
            bad += int(np.count_nonzero(~np.isfinite(out[i])))
        return bad, bad_in

    def advance(case, method, q, u, dt, k, cp, ep):
        q, u, s = q.copy(), u.copy(), np.empty((10, 14))
        for _ in range(k):
            step(case, method, q, u, dt, cp, ep, s)
        return q, u

    def record_run(case, method, q, u, dt, gaps, cp, ep, Q, U):
        return record(case, method, q.copy(), u.copy(), dt, gaps, cp, ep, Q, U)

    def ensemble(case, method, Q0, U0, dt, gaps, cp, ep, Q, U, done):
        for i in range(Q0.shape[0]):
            done[i] = record(case, method, Q0[i].copy(), U0[i].copy(), dt, gaps, cp, ep, Q[i], U[i])

    def rates_one(case, q, u, cp, ep):
        w, a = rates(case, q, u, cp, ep)
        return np.array(w), np.array(a)

    def move_one(case, q, delta):
        out = np.empty(q.shape[0])
        move(case, q, delta, out)
        return out

    def dexp_one(case, delta, w):
        out = np.empty(12)
        _dexp_tangent(case, delta, w, out)
        return out


US_PER_STATE = 0.15
"""Microseconds of :func:`accelerations`' work a state on one thread, what :func:`relacc.kernels.jit.parallel_pays`
weighs: 0.063-0.153 over a batch in ``chain-form-2026-11-29-run2`` to ``run4``, the slowest case."""


def accelerations(case, q, u, cp, ep, out) -> tuple[int, int]:
    """Every state's ``udot`` into ``out`` ``(n, 12)``; returns ``(non-finite results, suspect inputs)``.

    Suspect inputs (:func:`suspect_input`) send the caller to the full Python checks, which decide. The states run on
    the calling thread, or split over numba's threads where that pays (:func:`relacc.kernels.jit.parallel_pays`; a
    state's bits are the same either way): a parallel loop's start alone costs more than a few thousand states."""
    from relacc.kernels.jit import parallel_pays, split

    args, n = (case, q, u, cp, ep, out), q.shape[0]
    return split(_accelerations, args, n, 1) if parallel_pays(n, US_PER_STATE, 1) else _accelerations(*args, 0, n)


class Rates:
    """``(tangent, udot)`` of one state as arrays, for Python integrators (``solve_ivp`` on SO(3) charts).

    Raises :class:`relacc.IntegrationError` when the state or its rates are non-finite.
    """

    def __init__(self, chain, case, effects):
        self.case, self.cp, self.ep = int(case), chain_params(chain), effect_params(effects)

    def __call__(self, q, u, t=0.0):
        """The chain's effects are constant: ``t`` (s) is accepted and unused."""
        from relacc.errors import IntegrationError

        with np.errstate(all="ignore"):
            w, a = rates_one(self.case, np.ascontiguousarray(q, dtype=float), np.ascontiguousarray(u, dtype=float),
                             self.cp, self.ep)
        if not (np.all(np.isfinite(w)) and np.all(np.isfinite(a))):
            raise IntegrationError("the integration diverged: the state or its rates became non-finite; reduce "
                                   "the step (or, near case-3 gimbal lock, use quaternion coordinates)")
        return w, a
