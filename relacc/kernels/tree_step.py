"""Compiled fixed-step integration of a tree in any case's coordinates, its effects evaluated inside the loop.

The same algorithms as :func:`relacc.dynamics.integrate.rkmk4_step` and :func:`~relacc.dynamics.integrate.euler_step`
on :class:`relacc.dynamics.integrate.TreeSpace` (cases 1-2: quaternions move as ``quat (x) Exp(phi)`` with body
rotation vectors, their stage rates through ``J_r^-1``, every other coordinate by its speed, the tangent being case-2
speeds: in case 1 ``B u`` from each stage's frames; case 3: every coordinate by its rate, the accelerations solved in
case-2 speeds and mapped to the rates), with the forward dynamics of
:mod:`relacc.kernels.tree_dynamics` (composite rigid bodies or articulated bodies, as the tree's plan chooses) at
every stage. The effects of a :class:`relacc.dynamics.tree_effects.TreeEffects` act as
:func:`relacc.tree_accelerations` applies them:

* gravity: the base's acceleration ``-g`` of the spatial pass;
* a joint's spring and damper (MuJoCo's passive force on its case-2 speeds): ``-d w`` on every speed, ``-k (x - x0)``
  on a hinge's or slide's coordinate, ``-k Log(q0^-1 q)`` on a ball's (child components);
* a load on a body (force ``F`` at its mass centre, torque ``T``, both fixed components, times ``sin(2 pi f t +
  phase)`` or 1): the spatial force ``(c x F + T, F)`` about the spatial pass's point ``O`` (``c`` the mass centre from
  ``O``) taken off the body's bias force, so that it works through every speed on the body's path.

One state's stage costs what one forward dynamics costs: nothing is allocated inside the loop, nothing returns to
Python between steps. A stage that fails (non-finite or non-unit input, a singular mass matrix, a non-finite result)
stops the member; the caller decides what it means (:func:`relacc.simulate.subjects.tree_stepper`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from relacc.core.tolerances import MAX_CONDITION, PIVOT_FLOOR
from relacc.kernels.jit import HAVE_NUMBA, jitable, leaf, numba
from relacc.kernels.so3 import cross_inline as cross
from relacc.kernels.so3 import exp_mul, jr_inv
from relacc.kernels.so3 import mv_inline as mv
from relacc.kernels.tree import BALL, FREE, HINGE, SLIDE, row9

OK, SINGULAR, BAD_INPUT, NON_FINITE = 0, 1, 2, 3
"""A member's status: stepped, a singular mass matrix, a non-finite or non-unit input to a stage, a non-finite rate."""

RK4, EULER = 0, 1
INTEGRATORS = {"rk4": RK4, "euler": EULER}


class EffectArrays(NamedTuple):
    """A tree's effects as flat arrays: joints ``jk (J,)`` with ``stiffness``, ``damping`` ``(J,)`` and ``rest (J, 4)``
    (a hinge's or slide's coordinate in ``[:, 0]``, a ball's quaternion ``(w, x, y, z)``); loads on bodies ``lb (L,)``
    with ``force``, ``torque`` ``(L, 3)`` (N, N m, fixed components), ``frequency`` (Hz) and ``phase`` (rad)
    ``(L,)``."""

    jk: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray
    rest: np.ndarray
    lb: np.ndarray
    force: np.ndarray
    torque: np.ndarray
    frequency: np.ndarray
    phase: np.ndarray


def effect_arrays(tree, effects) -> tuple[np.ndarray, EffectArrays]:
    """``(gravity (3,), EffectArrays)`` of ``effects`` on ``tree`` (names checked by ``effects.resolve``)."""
    gravity, joints, loads = effects.resolve(tree)
    rest = np.zeros((len(joints), 4))
    for r, (_, _, x0) in zip(rest, joints):
        x0 = np.asarray(x0, dtype=float).reshape(-1)
        r[:x0.size] = x0
    return np.array(gravity, dtype=float), EffectArrays(
        np.array([k for k, _, _ in joints], dtype=np.int64),
        np.array([e.stiffness for _, e, _ in joints], dtype=float),
        np.array([e.damping for _, e, _ in joints], dtype=float), rest,
        np.array([b for b, _ in loads], dtype=np.int64),
        np.array([ld.force for _, ld in loads], dtype=float).reshape(-1, 3),
        np.array([ld.torque for _, ld in loads], dtype=float).reshape(-1, 3),
        np.array([ld.frequency for _, ld in loads], dtype=float),
        np.array([ld.phase for _, ld in loads], dtype=float))


@jitable
def _joint_forces(T, qadr, E, q, u, tau, case):
    """The joints' springs and dampers into ``tau[0]`` (zeroed first, case-2 speeds), from ``q[0]`` (``case``'s
    coordinates: a ball's quaternion, or in case 3 its 1-2-3 angles) and ``u[0]`` (case-2 speeds)."""
    for c in range(tau.shape[1]):
        tau[0, c] = 0.0
    for j in range(E.jk.shape[0]):
        k = E.jk[j]
        kind, a, d = T.jtype[k], qadr[k], T.dofadr[k]
        k_s, k_d = E.stiffness[j], E.damping[j]
        nd = 6 if kind == FREE else (3 if kind == BALL else 1)
        for c in range(nd):
            tau[0, d + c] = -k_d * u[0, d + c]
        if k_s == 0.0:
            continue
        if kind == HINGE or kind == SLIDE:
            tau[0, d] -= k_s * (q[0, a] - E.rest[j, 0])
        elif kind == BALL:  # -k Log(rest^-1 q): rest's conjugate times q, angle in [0, pi]
            w0, x0, y0, z0 = E.rest[j, 0], -E.rest[j, 1], -E.rest[j, 2], -E.rest[j, 3]
            if case == 3:  # the quaternion of Rx Ry Rz: qx (x) qy (x) qz, half angles
                ca, sa = np.cos(0.5 * q[0, a]), np.sin(0.5 * q[0, a])
                cb, sb = np.cos(0.5 * q[0, a + 1]), np.sin(0.5 * q[0, a + 1])
                cc, sc = np.cos(0.5 * q[0, a + 2]), np.sin(0.5 * q[0, a + 2])
                w1, x1, y1, z1 = ca * cb, sa * cb, ca * sb, sa * sb  # qx (x) qy
                w1, x1, y1, z1 = w1 * cc - z1 * sc, x1 * cc + y1 * sc, y1 * cc - x1 * sc, z1 * cc + w1 * sc
            else:
                w1, x1, y1, z1 = q[0, a], q[0, a + 1], q[0, a + 2], q[0, a + 3]
            w = w0 * w1 - x0 * x1 - y0 * y1 - z0 * z1
            x = w0 * x1 + x0 * w1 + y0 * z1 - z0 * y1
            y = w0 * y1 - x0 * z1 + y0 * w1 + z0 * x1
            z = w0 * z1 + x0 * y1 - y0 * x1 + z0 * w1
            if w < 0.0:
                w, x, y, z = -w, -x, -y, -z
            s = np.sqrt(x * x + y * y + z * z)
            f = 2.0 / w * (1.0 - s * s / (3.0 * w * w)) if s < 1e-8 else 2.0 * np.arctan2(s, w) / s
            tau[0, d] -= k_s * f * x
            tau[0, d + 1] -= k_s * f * y
            tau[0, d + 2] -= k_s * f * z


@jitable
def _loads(E, t, com, o, R, pA):
    """Each load's spatial force ``(c x F + T, F)`` about ``O`` taken off its body's bias force ``pA``."""
    for j in range(E.lb.shape[0]):
        b = E.lb[j]
        s = 1.0 if E.frequency[j] == 0.0 else np.sin(2.0 * np.pi * E.frequency[j] * t + E.phase[j])
        f0, f1, f2 = s * E.force[j, 0], s * E.force[j, 1], s * E.force[j, 2]
        r0, r1, r2 = mv(row9(R, b), com[b, 0], com[b, 1], com[b, 2])
        m0, m1, m2 = cross(o[b, 0] + r0, o[b, 1] + r1, o[b, 2] + r2, f0, f1, f2)
        pA[b, 0] -= m0 + s * E.torque[j, 0]
        pA[b, 1] -= m1 + s * E.torque[j, 1]
        pA[b, 2] -= m2 + s * E.torque[j, 2]
        pA[b, 3] -= f0
        pA[b, 4] -= f1
        pA[b, 5] -= f2


@jitable
def _move(case, T, qadr, q, delta, out):
    """``out = q`` moved by the tangent vector ``delta``: in case 2 (case-2 speeds) quaternions ``(x) Exp``, the rest
    added; in case 3 (the rates) every coordinate added."""
    if case == 3:
        for c in range(q.shape[0]):
            out[c] = q[c] + delta[c]
        return
    for k in range(T.jtype.shape[0]):
        kind, a, d = T.jtype[k], qadr[k], T.dofadr[k]
        if kind == HINGE or kind == SLIDE:
            out[a] = q[a] + delta[d]
        elif kind == FREE:
            for c in range(3):
                out[a + c] = q[a + c] + delta[d + c]
            exp_mul(q, a + 3, delta[d + 3], delta[d + 4], delta[d + 5], out)
        else:
            exp_mul(q, a, delta[d], delta[d + 1], delta[d + 2], out)


@jitable
def _dexpinv(case, T, delta, w, out):
    """``out = w`` with (case 2) each rotation's part through ``J_r^-1(delta)``: the stage's rate in the step's
    chart; case 3's chart is the angles themselves."""
    for c in range(w.shape[0]):
        out[c] = w[c]
    if case == 3:
        return
    for k in range(T.jtype.shape[0]):
        kind, d = T.jtype[k], T.dofadr[k]
        if kind == BALL or kind == FREE:
            d = d + 3 if kind == FREE else d
            r = jr_inv(delta[d], delta[d + 1], delta[d + 2], w[d], w[d + 1], w[d + 2])
            out[d], out[d + 1], out[d + 2] = r[0], r[1], r[2]


@jitable
def _tangent(case, T, Bm, u, out):
    """``out``: the manifold's tangent of the speeds ``u``: the speeds themselves (cases 2 and 3), or (case 1) each
    ball's and free joint's case-2 angular speeds ``B u`` (``Bm[k]``: joint ``k``'s ``B``, row-major, from the
    stage's spatial pass), the rest unchanged."""
    for c in range(u.shape[0]):
        out[c] = u[c]
    if case != 1:
        return
    for k in range(T.jtype.shape[0]):
        kind = T.jtype[k]
        if kind == BALL or kind == FREE:
            d = T.dofadr[k] + (3 if kind == FREE else 0)
            x0, x1, x2 = u[d], u[d + 1], u[d + 2]
            out[d] = Bm[k, 0] * x0 + Bm[k, 1] * x1 + Bm[k, 2] * x2
            out[d + 1] = Bm[k, 3] * x0 + Bm[k, 4] * x1 + Bm[k, 5] * x2
            out[d + 2] = Bm[k, 6] * x0 + Bm[k, 7] * x1 + Bm[k, 8] * x2


if HAVE_NUMBA:
    from relacc.kernels.tree import ANGLES_CASE2
    from relacc.kernels.tree_aba import accelerate, backward
    from relacc.kernels.tree_crba import factor_solve, mass_matrix
    from relacc.kernels.tree_spatial import bad_inputs, forward, row_to_rates, row_to_speeds

    class Scratch(NamedTuple):
        """One member's work arrays (see :func:`scratch`)."""

        Q: np.ndarray
        U: np.ndarray
        tau: np.ndarray
        out: np.ndarray
        S: np.ndarray
        C: np.ndarray
        o: np.ndarray
        R: np.ndarray
        V: np.ndarray
        IA: np.ndarray
        pA: np.ndarray
        acc: np.ndarray
        Ub: np.ndarray
        uu: np.ndarray
        Dinv: np.ndarray
        tmp: np.ndarray
        Ic: np.ndarray
        cd: np.ndarray
        A: np.ndarray
        f: np.ndarray
        M: np.ndarray
        x: np.ndarray
        diag: np.ndarray
        stage: np.ndarray
        rates: np.ndarray
        zeros: np.ndarray
        tau2: np.ndarray
        a2: np.ndarray
        near: np.ndarray
        Bm: np.ndarray

    @numba.njit(cache=True)
    def scratch(nq, nv, nb, nj, width):  # pragma: no cover - compiled
        """Work arrays for one member: a stage's state ``Q (1, nq)``, ``U (1, nv)`` (case-2 speeds), its forces and
        rates, the spatial pass's and both algorithms' arrays, ``stage (12, max(nq, nv))`` for the steps' vectors;
        case 3's ``rates``, ``zeros``, ``tau2``, ``a2`` ``(1, nv)``, and ``near`` ``(1 + nq)``: the largest 1-2-3
        condition number a stage met and that stage's coordinates."""
        nj1 = max(nj, 1)
        return Scratch(np.empty((1, nq)), np.empty((1, nv)), np.empty((1, nv)), np.empty((1, nv)), np.empty((nv, 6)),
                       np.empty((nj1, 6)), np.empty((nb, 3)), np.empty((nb, 9)), np.empty((nb, 6)),
                       np.empty((nb, 21)), np.empty((nb, 6)), np.empty((nb, 6)), np.empty((nv, 6)), np.empty(nv),
                       np.empty((nj1, 36)), np.empty(60), np.empty((nb, 21)), np.empty(8), np.empty((nb, 6)),
                       np.empty((nb, 6)), np.zeros((nv, width + 1)), np.empty(nv), np.empty(nv),
                       np.empty((14, max(nq, nv, 1))), np.empty((1, nv)), np.zeros((1, nv)), np.empty((1, nv)),
                       np.empty((1, nv)), np.zeros(1 + nq), np.zeros((nj1, 9)))

    @leaf
    def _failed_stage(case, W, failed):  # pragma: no cover - compiled
        nq, nv = W.Q.shape[1], W.U.shape[1]
        failed[0] = W.stage[11, 0]
        for c in range(nq):
            failed[1 + c] = W.Q[0, c]
        for c in range(nv):
            failed[1 + nq + c] = W.rates[0, c] if case == 3 else W.U[0, c]  # the stage's speeds, of its case

    @leaf
    def rates(case, aba, q, u, t, T, qadr, anc, depth, mass, com, inertia, arm, free, g, E, W, a):  # pragma: no cover
        """``a = udot`` of the state ``(q, u)`` of ``case`` (2, or 3: solved in case-2 speeds on the angles and mapped
        to the rates, as :func:`relacc.kernels.tree_dynamics.accelerations`) at time ``t`` under the effects; returns
        the status."""
        nq, nv = q.shape[0], u.shape[0]
        W.stage[11, 0] = t  # the stage's time, for a caller that asks why a stage failed
        for c in range(nq):
            W.Q[0, c] = q[c]
        for c in range(nv):
            W.U[0, c] = u[c]
            W.rates[0, c] = u[c]  # case 3's speeds, kept for a caller that asks why a stage failed
        r0 = np.int64(0)  # the one row, as a variable: a literal 0 would compile each callee a second time
        if bad_inputs(case, W.Q, W.U, r0, T, qadr):
            return BAD_INPUT
        mode = case
        if case == 3:
            for k in range(T.jtype.shape[0]):
                kind = T.jtype[k]
                if kind == BALL or kind == FREE:
                    s2 = abs(np.sin(q[qadr[k] + (3 if kind == FREE else 0) + 1]))
                    c2 = abs(np.cos(q[qadr[k] + (3 if kind == FREE else 0) + 1]))
                    if not c2 * MAX_CONDITION > 1.0 + s2:
                        return SINGULAR
                    if 1.0 + s2 > W.near[0] * c2:
                        W.near[0] = (1.0 + s2) / c2
                        for c in range(nq):
                            W.near[1 + c] = q[c]
            row_to_speeds(W.Q, W.rates, W.zeros, r0, T, W.U, W.tau2, 0, W.Bm)  # Bm: case 1's, free here
            mode = ANGLES_CASE2
        forward(mode, W.Q, W.U, r0, T, qadr, mass, com, inertia, W.S, W.C, W.o, W.R, W.V, W.IA, W.pA)
        if case == 1:  # each rotation's B = R_after^T R_parent: the joint forces act on case-2 speeds B u
            for b in range(T.parent.shape[0]):
                p = T.parent[b]
                for k in range(T.jstart[b], T.jstart[b] + T.jnum[b]):
                    kind = T.jtype[k]
                    if kind != BALL and kind != FREE:
                        continue
                    for r in range(3):
                        for c in range(3):
                            acc_ = 0.0
                            for x in range(3):
                                rp = (1.0 if x == c else 0.0) if (p < 0 or kind == FREE) else W.R[p, 3 * x + c]
                                acc_ += W.R[b, 3 * x + r] * rp
                            W.Bm[k, 3 * r + c] = acc_
            _tangent(1, T, W.Bm, u, W.rates[0])
            _joint_forces(T, qadr, E, W.Q, W.rates, W.tau, 2)
            for k in range(T.jtype.shape[0]):  # back to case-1 forces: B^T tau2 on each rotation
                kind = T.jtype[k]
                if kind == BALL or kind == FREE:
                    d = T.dofadr[k] + (3 if kind == FREE else 0)
                    y0, y1, y2 = W.tau[0, d], W.tau[0, d + 1], W.tau[0, d + 2]
                    for r in range(3):
                        W.tau[0, d + r] = W.Bm[k, r] * y0 + W.Bm[k, 3 + r] * y1 + W.Bm[k, 6 + r] * y2
        else:
            _joint_forces(T, qadr, E, W.Q, W.U, W.tau, case)
        _loads(E, t, com, W.o, W.R, W.pA)
        if aba:
            for b in range(W.IA.shape[0]):
                for c in range(21):
                    W.Ic[b, c] = W.IA[b, c]
            if backward(mode, W.Q, W.U, W.tau, r0, T, qadr, arm, free, W.S, W.C, W.R, W.V, W.IA, W.pA, W.Ub, W.uu,
                        W.Dinv, W.tmp, W.Ic, W.cd, PIVOT_FLOOR) == 1:
                return SINGULAR
            accelerate(T, g, free, W.S, W.C, W.Ub, W.uu, W.Dinv, W.acc, r0, W.out)
            for c in range(nv):
                W.a2[0, c] = W.out[0, c]
        else:
            mass_matrix(mode, W.Q, W.U, W.tau, r0, T, qadr, anc, depth, arm, free, g, W.S, W.C, W.R, W.V, W.IA, W.pA,
                        W.A, W.f, W.M, W.x, W.tmp)
            if factor_solve(W.M, W.x, anc, depth, W.diag, PIVOT_FLOOR) == 1:
                return SINGULAR
            for c in range(nv):
                W.a2[0, c] = W.x[c]
        if case == 3:
            row_to_rates(W.Q, W.rates, r0, W.a2, 0, T, W.out, W.Bm)
            for c in range(nv):
                a[c] = W.out[0, c]
        else:
            for c in range(nv):
                a[c] = W.a2[0, c]
        for c in range(nv):
            if not abs(a[c]) < np.inf:
                return NON_FINITE
        return OK

    @leaf
    def step(case, method, aba, q, u, t, h, T, qadr, anc, depth, mass, com, inertia, arm, free, g, E,
             W):  # pragma: no cover - compiled
        """One step of ``h`` s from time ``t``, in place on ``q (nq,)``, ``u (nv,)``; returns the status (the state
        is unchanged unless it is OK)."""
        nv = u.shape[0]
        s = W.stage
        a1, a2, a3, a4, k2, k3, dlt, v = s[0, :nv], s[1, :nv], s[2, :nv], s[3, :nv], s[4, :nv], s[5, :nv], \
            s[6, :nv], s[7, :nv]
        x = s[8, :q.shape[0]]
        w1, w = s[12, :nv], s[13, :nv]  # the stages' tangents (case 1: B u; else the speeds)
        st = rates(case, aba, q, u, t, T, qadr, anc, depth, mass, com, inertia, arm, free, g, E, W, a1)
        if st:
            return st
        if method == EULER:
            for c in range(nv):
                v[c] = u[c] + h * a1[c]
            _tangent(case, T, W.Bm, v, w)  # B depends on q only: the first stage's
            for c in range(nv):
                dlt[c] = h * w[c]
            _move(case, T, qadr, q, dlt, x)
            for c in range(nv):
                u[c] = v[c]
            for c in range(q.shape[0]):
                q[c] = x[c]
            return OK
        _tangent(case, T, W.Bm, u, w1)
        for c in range(nv):  # stage 2
            dlt[c] = 0.5 * h * w1[c]
            v[c] = u[c] + 0.5 * h * a1[c]
        _move(case, T, qadr, q, dlt, x)
        st = rates(case, aba, x, v, t + 0.5 * h, T, qadr, anc, depth, mass, com, inertia, arm, free, g, E, W, a2)
        if st:
            return st
        _tangent(case, T, W.Bm, v, w)
        _dexpinv(case, T, dlt, w, k2)
        for c in range(nv):  # stage 3
            dlt[c] = 0.5 * h * k2[c]
            v[c] = u[c] + 0.5 * h * a2[c]
        _move(case, T, qadr, q, dlt, x)
        st = rates(case, aba, x, v, t + 0.5 * h, T, qadr, anc, depth, mass, com, inertia, arm, free, g, E, W, a3)
        if st:
            return st
        _tangent(case, T, W.Bm, v, w)
        _dexpinv(case, T, dlt, w, k3)
        for c in range(nv):  # stage 4
            dlt[c] = h * k3[c]
            v[c] = u[c] + h * a3[c]
        _move(case, T, qadr, q, dlt, x)
        st = rates(case, aba, x, v, t + h, T, qadr, anc, depth, mass, com, inertia, arm, free, g, E, W, a4)
        if st:
            return st
        k4 = s[9, :nv]
        _tangent(case, T, W.Bm, v, w)
        _dexpinv(case, T, dlt, w, k4)
        for c in range(nv):
            dlt[c] = h / 6 * (w1[c] + 2 * k2[c] + 2 * k3[c] + k4[c])
            u[c] = u[c] + h / 6 * (a1[c] + 2 * a2[c] + 2 * a3[c] + a4[c])
        _move(case, T, qadr, q, dlt, x)
        for c in range(q.shape[0]):
            q[c] = x[c]
        return OK

    @numba.njit(cache=True)
    def record(case, method, aba, q, u, t0, h, gaps, T, qadr, anc, depth, mass, com, inertia, arm, free, g, E, Q,
               U, width, failed, near):  # pragma: no cover - compiled
        """From ``(q, u)`` (copies) at ``t0``: ``gaps[j]`` steps, then record ``j`` into ``Q[j]``, ``U[j]``.
        Returns ``(records stored, status, steps taken)``: fewer records than gaps when a stage failed, and then
        ``failed`` holds that stage's time, coordinates and speeds (``(1 + nq + nv,)``); ``near`` ``(1 + nq)``: the
        largest 1-2-3 condition number a stage met in case 3 and that stage's coordinates (0 elsewhere)."""
        q, u = q.copy(), u.copy()
        W = scratch(q.shape[0], u.shape[0], T.parent.shape[0], T.jtype.shape[0], width)
        done = 0
        for j in range(gaps.shape[0]):
            for _ in range(gaps[j]):
                st = step(case, method, aba, q, u, t0 + done * h, h, T, qadr, anc, depth, mass, com, inertia, arm,
                          free, g, E, W)
                if st:
                    _failed_stage(case, W, failed)
                    for c in range(near.shape[0]):  # element by element: no shape check to compile
                        near[c] = W.near[c]
                    return j, st, done
                done += 1
            for c in range(q.shape[0]):
                Q[j, c] = q[c]
            for c in range(u.shape[0]):
                U[j, c] = u[c]
        for c in range(near.shape[0]):
            near[c] = W.near[c]
        return gaps.shape[0], OK, done

    @numba.njit(cache=True)
    def advance_range(case, method, aba, Q0, U0, t0, h, k, T, qadr, anc, depth, mass, com, inertia, arm, free, g,
                      E, width, status, failed, near, start, stop):  # pragma: no cover - compiled
        """``k`` steps of rows ``start .. stop - 1`` of ``Q0 (n, nq)``, ``U0 (n, nv)`` in place on the calling thread;
        ``status[i]`` the row's (a failed row is left where its last good step left it, ``failed[i]`` its failed
        stage as in :func:`record`, ``near[i]`` as :func:`record`'s)."""
        W = scratch(Q0.shape[1], U0.shape[1], T.parent.shape[0], T.jtype.shape[0], width)
        for i in range(start, stop):
            q, u = Q0[i], U0[i]
            status[i] = OK
            W.near[:] = 0.0
            for n in range(k):
                st = step(case, method, aba, q, u, t0 + n * h, h, T, qadr, anc, depth, mass, com, inertia, arm, free,
                          g, E, W)
                if st:
                    status[i] = st
                    _failed_stage(case, W, failed[i])
                    break
            for c in range(near.shape[1]):
                near[i, c] = W.near[c]

    @numba.njit(parallel=True, cache=True)
    def advance_rows(case, method, aba, Q0, U0, t0, h, k, T, qadr, anc, depth, mass, com, inertia, arm, free, g, E,
                     width, status, failed, near):  # pragma: no cover - compiled
        """:func:`advance_range` over every row, rows in parallel."""
        for i in numba.prange(Q0.shape[0]):
            advance_range(case, method, aba, Q0, U0, t0, h, k, T, qadr, anc, depth, mass, com, inertia, arm, free, g,
                          E, width, status, failed, near, np.int64(i), np.int64(i) + 1)  # int64, as from Python


__all__ = ["EULER", "INTEGRATORS", "RK4", "EffectArrays", "effect_arrays"]
