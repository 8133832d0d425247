"""Kane's equations of any tree in any of the three cases: :func:`tree_dynamics`, :func:`tree_accelerations`.

From the partial velocities of every mass centre ``[V_b]`` and partial angular velocities
``[Omega_b]`` (:mod:`relacc.core.tree.walk`), with ``[I_b]`` about the mass centre in fixed components:

    M = sum_b m_b [V_b]^T [V_b] + [Omega_b]^T [I_b] [Omega_b]  (+ armature)
    f = sum_b [V_b]^T (m_b g + F_b - m_b [Vdot_b]{u})
        + [Omega_b]^T (T_b - [I_b][Omegadot_b]{u} - omega_b x [I_b] omega_b)
        + joint springs and dampers

so that ``M udot = f + tau`` with ``tau`` the generalized forces conjugate to ``u``. Armature ``D``
(MuJoCo's, diagonal in case-2 speeds ``u2 = [B] u``) adds ``[B]^T D [B]`` to ``M`` and
``-[B]^T D [B_dot] u`` to ``f``; joint springs and dampers act on case-2 speeds through ``[B]^T``.

Forward dynamics in case 3 (:func:`tree_accelerations`) is solved in case-2 speeds and mapped to the rates: Kane's
equations in the rates, ``M3 = [B]^T M2 [B]``, square ``[B]``'s condition number, which grows as ``2 / delta`` at a
distance ``delta`` from the 1-2-3 gimbal lock; mapped, the error grows as that number once (docs/hard-cases.md).
"""

from __future__ import annotations

import math
import threading
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from relacc.core.cases import Case, as_case, batch_rows
from relacc.core.kinematics import check_finite_result
from relacc.core.rotations import quaternion_from_123, tilde
from relacc.core.so3 import SO3
from relacc.core.tree.coordinates import check_invertible, rotations
from relacc.core.tree.kinematics import inputs
from relacc.core.tree.model import NQ, NQ_ANGLES, NV, Tree
from relacc.core.tree.walk import mv, walk
from relacc.dynamics.tree_effects import NO_EFFECTS, TreeEffects
from relacc.errors import InputError, SingularityError


@dataclass(frozen=True, eq=False)
class TreeDynamics:
    """``M udot = f + tau`` of a tree in a case's speeds.

    Attributes:
        M: ``(..., nv, nv)`` generalized mass matrix (kg, kg m or kg m^2 per pair of speeds).
        f: ``(..., nv)`` generalized forces of the effects minus the inertial (Coriolis, centrifugal)
            terms, conjugate to ``u`` (N or N m per speed).
        case: the choice of speeds.
    """

    M: np.ndarray
    f: np.ndarray
    case: int


def _speed_map(case, kind, jf, n):
    """``(B, B_dot)``: a ball's or free joint's MuJoCo (case 2) angular speeds are ``B u`` of the case's."""
    if case == Case.BODY_FRAME:
        eye = np.broadcast_to(np.eye(3), (n, 3, 3))
        return eye, np.zeros_like(eye)
    RaT = np.swapaxes(jf.R_after, -1, -2)
    return RaT @ jf.A, RaT @ jf.A_dot - RaT @ tilde(jf.w_after) @ jf.A


def _ball_quaternion(case, q, a):
    return quaternion_from_123(q[:, a:a + 3]) if case == Case.ANGLE_RATES else q[:, a:a + 4]


def equations(tree, case, q, u, effects=None, t=0.0, *, active_only: bool = False):
    """``(M (n, nv, nv), f (n, nv))`` for flat, checked ``q (n, nq)``, ``u (n, nv)`` (see the module docstring), real
    or complex (complex-step derivatives). ``active_only``: ``f`` is the generalized forces of the effects alone
    (gravity, body loads, joint springs and dampers; no inertial term, no armature) and ``M`` is zero."""
    effects = NO_EFFECTS if effects is None else effects
    if not isinstance(effects, TreeEffects):
        raise InputError(f"effects: expected a relacc.dynamics.tree_effects.TreeEffects, got {type(effects).__name__}")
    gravity, joint_effects, loads = effects.resolve(tree)
    n, nv = q.shape[0], tree.nv
    frames, joints = walk(tree, case, q, u)
    dtype = np.result_type(q, u, float)
    M = np.zeros((n, nv, nv), dtype=dtype)
    f = np.zeros((n, nv), dtype=dtype)
    load_at = {b: load for b, load in loads}
    for b, (fr, body) in enumerate(zip(frames, tree.bodies)):
        dofs = np.asarray(tree.path_dofs[b])
        if not dofs.size:
            continue
        r = mv(fr.R, np.broadcast_to(body.com, (n, 3)))
        V, Vdot = fr.point(r)
        V, Vdot = V[:, :, dofs], Vdot[:, :, dofs]
        Om, Omd = fr.Omega[:, :, dofs], fr.Omegadot[:, :, dofs]
        u_b = u[:, dofs]
        I_w = fr.R @ body.inertia @ np.swapaxes(fr.R, -1, -2)
        w = mv(Om, u_b)
        if active_only:
            F, T = np.broadcast_to(body.mass * gravity, (n, 3)), np.zeros((n, 3))
        else:
            F = body.mass * (gravity - mv(Vdot, u_b))
            T = -mv(I_w, mv(Omd, u_b)) - np.cross(w, mv(I_w, w))
        if b in load_at:
            s = np.broadcast_to(load_at[b].factor(t), (n,))[:, None]
            F, T = F + s * load_at[b].force, T + s * load_at[b].torque
        if not active_only:
            sub = (slice(None), dofs[:, None], dofs[None, :])
            M[sub] += body.mass * np.einsum("nia,nib->nab", V, V) + np.einsum("nia,nij,njb->nab", Om, I_w, Om)
        f[:, dofs] += np.einsum("nia,ni->na", V, F) + np.einsum("nia,ni->na", Om, T)
    _joint_terms(tree, case, q, u, joints, joint_effects, M, f, armature=not active_only)
    return M, f


def _passive(kind, eff, rest, x, w) -> np.ndarray:
    """MuJoCo's passive force of one joint's spring and damper on case-2 speeds ``w (n, k)`` (N, N m per speed):
    ``-damping w``, and for a hinge's or slide's spring ``-stiffness (x - rest)`` (``x (n, 1)`` its coordinate), for
    a ball's ``-stiffness log(rest^-1 x)`` (``x (n, 4)`` its quaternion ``(w, x, y, z)``); a free joint has none."""
    out = -eff.damping * w
    if eff.stiffness and kind in ("hinge", "slide"):
        out = out - eff.stiffness * (x - rest)
    elif eff.stiffness and kind == "ball":
        out = out - eff.stiffness * (SO3(np.broadcast_to(rest, (x.shape[0], 4))).inverse() @ SO3(x)).log()
    return out


def _joint_terms(tree, case, q, u, joints, joint_effects, M, f, armature: bool = True):
    """Armature (unless not ``armature``), springs and dampers: terms on case-2 speeds, mapped to the case's through
    ``[B]``."""
    effect_at = {k: (eff, rest) for k, eff, rest in joint_effects}
    rot = {k: (kind, a, d) for k, kind, a, d in rotations(tree, case)}
    for k, ((_, j), a, d) in enumerate(zip(tree.joints, tree.qadr(case), tree.dofadr)):
        eff, rest = effect_at.get(k, (None, None))
        arm = j.armature if armature else np.zeros_like(j.armature)
        if not (np.any(arm) or eff is not None):
            continue
        lin = 3 if j.type == "free" else (1 if j.type in ("hinge", "slide") else 0)
        for i in range(lin):  # hinge, slide, a free joint's translation: case-2 speeds in every case
            if arm[i]:
                M[:, d + i, d + i] += arm[i]
        if eff is not None and lin:
            f[:, d:d + lin] += _passive(j.type, eff, rest, q[:, a:a + lin], u[:, d:d + lin])
        if k not in rot:
            continue
        kind, qa, da = rot[k]
        B, B_dot = _speed_map(case, kind, joints[k], q.shape[0])
        u2 = mv(B, u[:, da:da + 3])
        arm_r = arm[lin:lin + 3]
        if np.any(arm_r):
            blk = (slice(None), slice(da, da + 3), slice(da, da + 3))
            M[blk] += np.swapaxes(B, -1, -2) @ (arm_r[:, None] * B)
        tau2 = -arm_r * mv(B_dot, u[:, da:da + 3])
        if eff is not None:
            x = _ball_quaternion(case, q, qa) if kind == "ball" and eff.stiffness else None
            tau2 = tau2 + _passive(kind, eff, rest, x, u2)
        f[:, da:da + 3] += mv(np.swapaxes(B, -1, -2), tau2)


def joint_forces(tree, q, v, effects, joint_effects=None, case: int = 2) -> np.ndarray:
    """``(n, nv)`` the generalized forces of ``effects``' joint springs and dampers alone at case-2 states
    ``q (n, nq)``, ``v (n, nv)`` (MuJoCo's ``qpos``, ``qvel``): what MuJoCo's passive force gives for them (N, N m
    per speed). Only the positions and speeds of joints with an effect are read. ``joint_effects``: the second
    item of ``effects.resolve(tree)`` when the caller has it already (a stepper calls this at every stage: it keeps
    :func:`joint_force_plan` instead). ``case`` 1 or 3: states of that case, the effects on hinges and slides only
    (their speeds are every case's)."""
    if joint_effects is None:
        _, joint_effects, _ = effects.resolve(tree)
    return joint_force_plan(tree, joint_effects, case)(q, v)


@dataclass(frozen=True)
class JointForcePlan:
    """:func:`joint_forces` for one tree, one list of resolved joint effects and one case, its indices found once:
    the hinges' and slides' dampers and springs as index arrays (one operation each for all of them, in
    :func:`_passive`'s order of operations, so the same bits), balls and free joints one by one. ``nq``, ``nv``: the
    tree's in the plan's case."""

    nq: int
    nv: int
    damped_v: np.ndarray
    damping: np.ndarray
    sprung_v: np.ndarray
    sprung_q: np.ndarray
    stiffness: np.ndarray
    rest: np.ndarray
    others: tuple

    def __call__(self, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """``(n, nv)`` the forces at states ``q (n, nq)``, ``v (n, nv)`` of the plan's case."""
        f = np.zeros((q.shape[0], self.nv))
        if self.damped_v.size:
            f[:, self.damped_v] = -self.damping * v[:, self.damped_v]
        if self.sprung_v.size:
            f[:, self.sprung_v] -= self.stiffness * (q[:, self.sprung_q] - self.rest)
        for kind, eff, rest, qs, vs in self.others:
            f[:, vs] = _passive(kind, eff, rest, q[:, qs], v[:, vs])
        return f


def joint_force_plan(tree, joint_effects, case: int = 2) -> JointForcePlan:
    """The :class:`JointForcePlan` of ``joint_effects`` (the second item of ``effects.resolve(tree)``) on ``tree`` in
    ``case``'s coordinates."""
    qadr, nq = tree.qadr(case), NQ_ANGLES if int(case) == 3 else NQ
    lin: list[tuple[int, int, float, float, Any]] = []
    others = []
    for k, eff, rest in joint_effects:
        kind, a, d = tree.joints[k][1].type, qadr[k], tree.dofadr[k]
        if kind in ("hinge", "slide"):
            lin.append((a, d, eff.damping, eff.stiffness, rest))
        else:
            others.append((kind, eff, rest, slice(a, a + nq[kind]), slice(d, d + NV[kind])))
    sprung = [x for x in lin if x[3]]

    def column(rows, i, dtype=float):
        return np.array([x[i] for x in rows], dtype=dtype)

    return JointForcePlan(tree.nq_in(case), tree.nv, column(lin, 1, np.intp), column(lin, 2),
                          column(sprung, 1, np.intp), column(sprung, 0, np.intp), column(sprung, 3),
                          column(sprung, 4), tuple(others))


def tree_dynamics(tree: Tree, case: int, q: ArrayLike, u: ArrayLike, *, effects: TreeEffects | None = None,
                 t: ArrayLike = 0.0) -> TreeDynamics:
    """Kane's ``M udot = f + tau`` of a tree in a case's speeds (see the module docstring).

    Args:
        tree: :class:`relacc.Tree`. case: 1, 2 or 3. q: ``(..., nq)``. u: ``(..., nv)``.
        effects: :class:`relacc.dynamics.tree_effects.TreeEffects`; default gravity of the tree only.
        t: time (s), for sinusoidal loads; a scalar or broadcast against the batch.

    Returns:
        :class:`TreeDynamics`.

    Warns:
        AccuracyWarning: case 3 near the 1-2-3 gimbal lock (a joint's rate map conditioned above
            :data:`relacc.core.tolerances.CONDITION_WARNING`): ``M`` in the rates is conditioned as the square of
            that map, and singular at the lock itself.
    """
    nb, nv = (tree.nb, tree.nv) if isinstance(tree, Tree) else (0, 0)
    c, q, u, _, batch = inputs(tree, case, q, u, bytes_per_state=8.0 * (nv * nv + 4 * nb * 3 * nv * 3),
                               what="Kane's equations of")
    if c == Case.ANGLE_RATES:
        from relacc.core.tree.coordinates import warn_near_lock

        warn_near_lock(tree, q, "the mass matrix in the rates, [W_b]^T M2 [W_b] with M2 the mass matrix in case-2 "
                       "speeds, has a condition number up to {cond2:.3g} times M2's and is singular at the lock "
                       "(relacc.tree_accelerations solves in case-2 speeds instead)")
    tt = _flat_time(t, batch)
    with np.errstate(over="ignore", invalid="ignore"):  # an overflow is refused below, in one sentence
        M, f = equations(tree, c, batch_rows(q, batch, q.shape[-1]), batch_rows(u, batch, tree.nv), effects, tt)
    check_finite_result((M, f), q, u, model=_model_magnitude(tree))
    M, f = M.reshape(batch + (tree.nv, tree.nv)), f.reshape(batch + (tree.nv,))
    M.setflags(write=False)
    f.setflags(write=False)
    return TreeDynamics(M, f, c)


def generalized_forces(tree: Tree, case: int, q: ArrayLike, u: ArrayLike, *, effects: TreeEffects | None = None,
                       t: ArrayLike = 0.0) -> np.ndarray:
    """``{Q}`` ``(..., nv)``: the generalized forces of the effects alone, conjugate to the case's speeds (N, or N m per
    unit angular speed): ``sum_b [V_b]^T (m_b g + F_b) + [Omega_b]^T T_b`` plus the joints' springs and dampers
    through ``[B]^T`` (module docstring), no inertial term. Real or complex inputs; arguments as
    :func:`tree_dynamics`."""
    nb, nv = (tree.nb, tree.nv) if isinstance(tree, Tree) else (0, 0)
    c, q, u, _, batch = inputs(tree, case, q, u, bytes_per_state=8.0 * (4 * nb * 3 * nv * 3), what="the forces of")
    tt = _flat_time(t, batch)
    _, f = equations(tree, c, batch_rows(q, batch, q.shape[-1]), batch_rows(u, batch, tree.nv), effects, tt,
                     active_only=True)
    return f.reshape(batch + (tree.nv,))


def _flat_time(t: ArrayLike, batch: tuple[int, ...]) -> np.ndarray | float:
    """The time ``t`` (s) for a flattened batch: ``(n,)`` when ``t`` has a shape (broadcast against ``batch``), the
    scalar itself otherwise."""
    t_arr = np.asarray(t, dtype=float)
    return np.broadcast_to(t_arr, batch).reshape(-1) if t_arr.ndim else float(t_arr)


def _model_magnitude(tree) -> tuple[str, float]:
    """``("largest mass or inertia", its magnitude)`` of a tree, for the overflow message."""
    return "largest mass or inertia", max(max(b.mass, float(np.abs(b.inertia).max())) for b in tree.bodies)


def tree_accelerations(tree: Tree, case: int, q: ArrayLike, u: ArrayLike, *, tau: ArrayLike | None = None,
                       effects: TreeEffects | None = None, t: ArrayLike = 0.0, backend: str = "auto",
                       out: np.ndarray | None = None) -> np.ndarray:
    """``udot`` with ``M udot = f + tau``: forward dynamics of a tree in a case's speeds.

    Args:
        tau: ``(..., nv)`` generalized forces conjugate to ``u`` (N or N m), default zero.
        backend: ``"auto"`` (the compiled kernel of :mod:`relacc.kernels.tree_dynamics`, with the generalized
            forces of ``effects``' joints and body loads evaluated apart and applied, a ball's or free joint's spring or
            damper in case 1 through its case-2 speeds; the reference path where such a ball follows a turning
            joint on its body), ``"fast"`` (the kernel, gravity only) or
            ``"reference"`` (Kane's equations of :func:`tree_dynamics`, solved by Cholesky); they agree to rounding.
            Complex ``q``, ``u`` or ``tau`` (complex-step derivatives) take the reference path whatever ``backend``
            says but ``"fast"``, which refuses them: every path that answers carries the imaginary parts.
        out: a writable C-contiguous float64 ``(..., nv)`` array to write into (fast backend), returned.
        (the others as in :func:`tree_dynamics`)

    Returns:
        ``(..., nv)`` the speeds' rates (m/s^2, rad/s^2).

    Case 3 is solved in case-2 speeds and mapped to the rates (:func:`_angle_rates`): its error is the rate map's
    condition number times case 2's, not that number squared as Kane's equations in the rates would give.

    Raises:
        SingularityError: ``M`` is singular (speeds that move no inertia, named) or case 3 is within
            the gimbal-lock limit at a joint (named, :data:`relacc.core.tolerances.MAX_CONDITION`).

    Warns:
        AccuracyWarning: case 3 near the lock (above :data:`relacc.core.tolerances.CONDITION_WARNING`), naming the
            joint, its ``theta2``, the distance to the lock and the relative error to expect.
    """
    if tau is None and effects is None and out is None and backend == "auto" and type(case) is int:
        ones = _KERNEL.SINGLE.get(tree) if _KERNEL is not None and type(tree) is Tree else None  # the single-state
        one = None if ones is None else ones.get((case, None, threading.get_ident()))  # lane, in two lookups
        res = one(q, u) if one is not None else _one_state(tree, case, q, u, None)
        if res is not None:
            return res
    if backend not in ("auto", "fast", "reference"):
        raise InputError(f"unknown backend {backend!r}: accepted are auto, fast, reference")
    if any(x is not None and np.iscomplexobj(x) for x in (q, u, tau)):  # complex steps: Kane's equations carry them
        if backend == "fast":
            raise InputError("complex q, u or tau: the compiled kernel takes real numbers; backend 'auto' or "
                             "'reference' carries complex ones (complex-step derivatives) through Kane's equations")
        backend = "reference"
    simple = effects is None or (isinstance(effects, TreeEffects) and not effects.joints and not effects.bodies)
    if backend == "fast" and not simple:
        raise InputError("backend 'fast' applies gravity only: joint and body effects take backend 'reference'")
    if isinstance(tree, Tree) and as_case(case) == 3:
        if backend == "reference" or not simple or not _kernel().HAVE_NUMBA:
            return _angle_rates(tree, q, u, tau, effects, t, backend, out)
        return _fast(tree, 3, q, u, tau, effects, out)  # the kernel maps the rates to case-2 speeds itself
    if backend == "fast" or (backend == "auto" and simple):
        return _fast(tree, case, q, u, tau, effects, out)
    if backend == "auto" and isinstance(effects, TreeEffects) and isinstance(tree, Tree):
        applied = _effect_forces(tree, case, q, u, effects, t)
        if applied is not None:  # the effects' forces as applied ones, the kernel for the rest
            return _fast(tree, case, q, u, applied if tau is None else np.add(tau, applied),
                         TreeEffects(gravity=effects.gravity), out)
    if out is not None:
        raise InputError("out= is for the fast backend")
    _, q, u, _, batch = inputs(tree, case, q, u, values=False)
    tau, _ = _tau(tree, tau, batch, q.shape[-1])
    d = tree_dynamics(tree, case, q, u, effects=effects, t=t)
    rhs = np.array(d.f)
    if tau is not None:
        rhs = rhs + tau
    if d.case == Case.ANGLE_RATES:
        check_invertible(tree, np.asarray(q, dtype=float))
    return solve(tree, d.M, rhs)


def _angle_rates(tree, q, u, tau, effects, t, backend, out):
    """Case 3's ``udot`` solved in case-2 speeds (module docstring): ``theta_ddot = [W_b]^-1 (u2_dot - [W_b_dot]
    theta_dot)`` per ball and free joint, ``u2 = [W_b] theta_dot`` (:func:`relacc.core.so3.w123_body`) and
    ``tau2 = [W_b]^-T tau``; every other speed is the same in both cases.

    Kane's equations in the rates themselves, ``[W_b]^T M2 [W_b]``, square the rate map's condition number; this way
    its error is ``cond(W_b)`` times case 2's, ``c eps kappa(M2)`` (docs/hard-cases.md)."""
    from relacc.core.kinematics import check_out
    from relacc.core.so3 import w123_body
    from relacc.core.tree.coordinates import q_in_case, warn_near_lock

    _, q, u, _, batch = inputs(tree, 3, q, u, bytes_per_state=8.0 * 4 * tree.nv, what="forward dynamics of")
    tau, batch = _tau(tree, tau, batch, q.shape[-1])
    out = check_out(out, batch + (tree.nv,), "out")
    if out is not None and backend == "reference":
        raise InputError("out= is for the fast backend")
    check_invertible(tree, np.real(q))
    warn_near_lock(tree, q, "its rates' accelerations carry relative errors up to about {err:.2g} times the mass "
                   "matrix's condition number", stacklevel=3)
    n = math.prod(batch)
    qf, uf = batch_rows(q, batch, q.shape[-1]), batch_rows(u, batch, tree.nv)
    u2 = np.array(uf)
    tau2 = None if tau is None else np.array(batch_rows(tau, batch, tree.nv))
    maps = []
    for _, _, a, d in rotations(tree, 3):
        W, W_dot = w123_body(qf[:, a:a + 3], uf[:, d:d + 3])
        u2[:, d:d + 3] = mv(W, uf[:, d:d + 3])
        if tau2 is not None:
            tau2[:, d:d + 3] = np.linalg.solve(np.swapaxes(W, -1, -2), tau2[:, d:d + 3, None])[..., 0]
        maps.append((d, W, W_dot))
    tt = _flat_time(t, batch)
    a2 = tree_accelerations(tree, 2, q_in_case(tree, 3, 2, qf), u2, tau=tau2, effects=effects, t=tt,
                            backend=backend)
    res = np.array(a2)
    for d, W, W_dot in maps:
        res[:, d:d + 3] = np.linalg.solve(W, (a2[:, d:d + 3] - mv(W_dot, uf[:, d:d + 3]))[..., None])[..., 0]
    if out is not None:
        out.reshape(n, tree.nv)[...] = res
        return out
    res = res.reshape(batch + (tree.nv,))
    res.setflags(write=False)
    return res


def _effect_forces(tree, case, q, u, effects, t):
    """``(..., nv)`` the generalized forces of ``effects``' joint springs and dampers and body loads in the case's
    speeds, evaluated apart for the compiled kernel (numpy, batched). A ball's or free joint's spring or damper in
    case 1 is evaluated at the case-2 speeds ``u2 = [B] u1`` and carried back by ``[B]^T`` (:func:`_case1_map`); None
    where that needs the walk's joint frames (a ball after a turning joint on its body; case 3, which
    :func:`tree_accelerations` solves in case-2 speeds).

    Loads act at the bodies' mass centres: ``[V_b]^T F + [Omega_b]^T T``, compiled
    (:func:`relacc.kernels.tree_loads.load_forces`); joints' as :func:`joint_forces` (a hinge's or slide's speed is
    the same in every case)."""
    c, q, u, _, batch = inputs(tree, case, q, u, values=False)
    _, joint_effects, loads = effects.resolve(tree)
    rotating = any(tree.joints[k][1].type in ("ball", "free") for k, _, _ in joint_effects)
    maps = _case1_maps(tree) if rotating and int(c) == 1 else None
    if rotating and int(c) != 2 and maps is None:
        return None
    n = math.prod(batch)
    qf, uf = batch_rows(q, batch, q.shape[-1]), batch_rows(u, batch, tree.nv)
    if maps is None:
        f = joint_forces(tree, qf, uf, effects, joint_effects, case=int(c))
    else:  # in case-2 speeds u2 = [B] u1, then f1 = [B]^T f2 (the power is the same)
        turns = [(d, _case1_map(qf[:, a:a + 4], Rb)) for d, a, Rb in maps]
        u2 = np.array(uf, dtype=float)
        for d, Bt in turns:
            u2[:, d:d + 3] = np.einsum("nji,nj->ni", Bt, uf[:, d:d + 3])
        f = joint_forces(tree, qf, u2, effects, joint_effects, case=2)
        for d, Bt in turns:
            f[:, d:d + 3] = np.einsum("nij,nj->ni", Bt, f[:, d:d + 3])
    if loads:
        from relacc.kernels.tree_loads import load_forces

        tt = _flat_time(t, batch)
        s = np.stack([np.broadcast_to(load.factor(tt), (n,)) for _, load in loads], axis=1)[..., None]  # (n, L, 1)
        force = s * np.array([load.force for _, load in loads])
        torque = s * np.array([load.torque for _, load in loads])
        f += load_forces(tree, int(c), qf, uf, [b for b, _ in loads], force, torque)
    return f.reshape(batch + (tree.nv,))


def _case1_maps(tree) -> list | None:
    """``[(dofadr, qadr, Rb)]`` of every ball's and free joint's rotation for :func:`_case1_map` (``Rb`` the ball's
    body's fixed orientation in its parent, None for a free joint); None where a ball follows a hinge or a ball on its
    body (the frame it turns from then moves with that joint: the walk's reference path handles it)."""
    from relacc.core.rotations import matrix_from_quaternion

    out = []
    for k, kind, a, d in rotations(tree, 1):
        if kind == "free":
            out.append((d, a, None))
            continue
        b = tree.joints[k][0]
        before = tree.body_joints[b][:tree.body_joints[b].index(k)]
        if any(tree.joints[j][1].type != "slide" for j in before):
            return None
        out.append((d, a, matrix_from_quaternion(tree.bodies[b].quat)))
    return out


def _case1_map(quat, Rb) -> np.ndarray:
    """``[B]^T (n, 3, 3)`` of a ball's or free joint's rotation, ``u2 = [B] u1`` (:func:`relacc.core.tree.walk.
    angular_map`: ``A1 u1 = A2 u2`` with ``A1 = [R_parent]``, ``A2 = [R_after] = [R_parent][Rb][R_j]`` for a ball
    first to turn its body, ``A1 = I``, ``A2 = [R_j]`` for a free joint): ``[B]^T = [Rb][R_j]``, or ``[R_j]``."""
    from relacc.core.rotations import matrix_from_quaternion

    Rj = matrix_from_quaternion(quat)
    return Rj if Rb is None else Rb @ Rj


def _tau(tree, tau, batch, nq) -> tuple[Any, tuple[int, ...]]:
    """``(tau, batch)``: the applied generalized forces checked (shape, then their batch's cost against the memory
    available, then values) and the batch they broadcast to with the states'; ``tau`` None stays None."""
    from relacc.core.tree.coordinates import check_u
    from relacc.limits import require_memory

    if tau is None:
        return None, batch
    tau = check_u(tree, "tau", tau, values=False)
    try:
        batch = np.broadcast_shapes(batch, tau.shape[:-1])
    except ValueError:
        raise InputError(f"tau's batch shape {tau.shape[:-1]} does not broadcast with the states' {batch}") from None
    n = float(math.prod(batch))
    require_memory(8.0 * n * (nq + 5 * tree.nv), f"forward dynamics of {int(n)} states of {tree.name!r}",
                   "pass fewer states at a time")
    return check_u(tree, "tau", tau), batch


def _fast(tree, case, q, u, tau, effects, out):
    """The compiled kernel's answer, with every check of the reference path."""
    from relacc.core.kinematics import check_out
    from relacc.kernels import tree_dynamics as kernel

    if tau is None and out is None:
        one = _one_state(tree, case, q, u, effects)
        if one is not None:
            return one
    nv = tree.nv if isinstance(tree, Tree) else 0
    # the kernel's outputs and its per-state work: a few rows of nv (the factorization lives per thread)
    c, q, u, _, batch = inputs(tree, case, q, u, values=False, bytes_per_state=8.0 * 4 * nv,
                               what="forward dynamics of")
    tau, batch = _tau(tree, tau, batch, q.shape[-1])
    if tau is None:
        tau = np.zeros(batch + (tree.nv,))
    if c == Case.ANGLE_RATES:
        from relacc.core.tree.coordinates import warn_near_lock

        check_invertible(tree, np.real(q))
        warn_near_lock(tree, q, "its rates' accelerations carry relative errors up to about {err:.2g} times the mass "
                       "matrix's condition number", stacklevel=3)
    out = check_out(out, batch + (tree.nv,), "out")
    gravity = tree.gravity if effects is None or effects.gravity is None else effects.gravity
    n = math.prod(batch)
    flat_out = None if out is None else out.reshape(n, tree.nv)
    res, bad_in, singular, ill = kernel.accelerations(tree, c, batch_rows(q, batch, q.shape[-1]),
                                                      batch_rows(u, batch, tree.nv), batch_rows(tau, batch, tree.nv),
                                                      np.asarray(gravity, dtype=float), flat_out)
    if bad_in:
        inputs(tree, c, q, u)  # raises, naming the bad entry
    if ill:
        warn_ill_conditioned(ill, n, stacklevel=3)
    bad = () if np.isfinite(res).all() else np.flatnonzero(~np.all(np.isfinite(res), axis=1))
    if len(bad):  # a non-positive pivot (NaN rows) or an overflow: the reference path says which, or answers
        qs, us, ts = batch_rows(q, batch, q.shape[-1]), batch_rows(u, batch, tree.nv), batch_rows(tau, batch, tree.nv)
        d = tree_dynamics(tree, c, qs[bad], us[bad], effects=effects)
        res[bad] = solve(tree, d.M, np.array(d.f) + ts[bad])  # raises SingularityError naming the speeds
        check_finite_result((res,), q, u, model=_model_magnitude(tree))
    if out is not None:
        return out
    res = res.reshape(batch + (tree.nv,))
    res.setflags(write=False)
    return res


def _one_state(tree, case, q, u, effects):
    """One state's answer by the kernel's single-state lane (:func:`relacc.kernels.tree_dynamics.single`), or None
    for anything but one plain, valid state in case 1 or 2 whose equations are regular (the general path then decides,
    and says what is wrong). The lane of the tree's own gravity is kept in
    :data:`relacc.kernels.tree_dynamics.SINGLE`, where :func:`tree_accelerations` finds it first."""
    if not (isinstance(tree, Tree) and type(case) is int and case in (1, 2)):
        return None
    gravity = tree.gravity if effects is None or effects.gravity is None else effects.gravity
    return _kernel().single(tree, case, gravity)(q, u)


def _kernel():
    """:mod:`relacc.kernels.tree_dynamics`, imported on first use (it loads numba)."""
    global _KERNEL
    if _KERNEL is None:
        from relacc.kernels import tree_dynamics

        _KERNEL = tree_dynamics
    return _KERNEL


_KERNEL: Any = None


def warn_ill_conditioned(n_ill: int, n: int, stacklevel: int = 2) -> None:
    """An :class:`relacc.AccuracyWarning` that ``n_ill`` of ``n`` states were answered with a mass matrix whose
    factorization had a pivot at most :data:`relacc.core.tolerances.ILL_FLOOR` of its scale (kappa(M) above
    :data:`relacc.core.tolerances.MASS_CONDITION_WARNING`), and the error to expect."""
    import warnings

    from relacc.core.tolerances import EPS, MASS_CONDITION_WARNING
    from relacc.errors import AccuracyWarning

    bound, err = MASS_CONDITION_WARNING, EPS * MASS_CONDITION_WARNING
    warnings.warn(f"{n_ill} of {n} states: the mass matrix is ill-conditioned, kappa(M) > {bound:.0e} (a pivot of its "
                  f"factorization at most {1 / bound:.0e} of its scale), so their accelerations carry relative errors "
                  f"up to eps kappa(M), more than {err:.1g}: two joints that nearly move the same inertia (nearly "
                  "parallel axes on one body), or a speed that moves almost none", AccuracyWarning,
                  stacklevel=stacklevel + 1)


def solve(tree, M, rhs):
    """``M^-1 rhs`` by Cholesky, batched; SingularityError naming the speeds where ``M`` is singular to working
    precision: not positive definite, a pivot at most :data:`relacc.core.tolerances.PIVOT_FLOOR` times its scale
    (its diagonal entry plus the mean diagonal entry), or its smallest eigenvalue at most that times the mean diagonal
    entry (then ``kappa(M) > 1 / (2 c eps)`` and no digit of the answer is certain). Warns
    (:func:`warn_ill_conditioned`) where either is at most :data:`relacc.core.tolerances.ILL_FLOOR` times it."""
    from relacc.core.tolerances import ILL_FLOOR, PIVOT_FLOOR

    flatM = M.reshape(-1, tree.nv, tree.nv)
    if np.iscomplexobj(M) or np.iscomplexobj(rhs):  # complex steps: M is complex symmetric, not Hermitian (no Cholesky)
        out = np.linalg.solve(M, rhs[..., None])[..., 0]
        out.setflags(write=False)
        return out
    names = tree.speed_names()
    try:
        L = np.linalg.cholesky(M)
        pivots = np.diagonal(L, axis1=-2, axis2=-1).reshape(-1, tree.nv) ** 2
        diagonal = np.diagonal(flatM, axis1=-2, axis2=-1)
        scale = diagonal + diagonal.mean(axis=-1, keepdims=True)
        # the smallest eigenvalue against the mean diagonal entry, whatever the speeds' order (the pivots' test alone
        # depends on it: a point mass on a ball joint leaves its last pivot large); both prove kappa(M) large
        least = np.linalg.eigvalsh(flatM)[:, :1] if tree.nv else np.ones((len(flatM), 1))
        mean = diagonal.mean(axis=-1, keepdims=True) if tree.nv else np.ones((len(flatM), 1))
        low = (pivots <= PIVOT_FLOOR * scale) | (least <= PIVOT_FLOOR * mean)
        ill = int(np.sum((np.any(pivots <= ILL_FLOOR * scale, axis=-1) | (least[:, 0] <= ILL_FLOOR * mean[:, 0]))
                         & ~np.any(low, axis=-1)))
    except np.linalg.LinAlgError:
        L, low, ill = None, np.ones((len(flatM), 1), dtype=bool), 0
    if low.any():
        for state, Mi in enumerate(flatM):
            dependent = _dependent_speeds(Mi, PIVOT_FLOOR) if L is None or low[state].any() else []
            if dependent:
                break
        else:
            state, dependent = 0, list(range(tree.nv))  # not positive definite with every pivot above the floor
        speeds = ", ".join(names[i] for i in dependent)
        dead = [names[i] for i in dependent if not np.any(flatM[state, i])]
        raise SingularityError(
            f"the mass matrix is singular to working precision (state {state}): "
            + (f"no inertia moves with {', '.join(dead)}" if dead else
               f"the speeds {speeds} move no inertia that the speeds before them do not already move")
            + f" (a pivot of its factorization at most {PIVOT_FLOOR:.1e} of its scale, its diagonal entry plus the "
            "mean diagonal entry, so kappa(M) > 1/(2 c eps) and no digit of the accelerations is certain); lock or "
            "remove those joints, or give their bodies mass or inertia") from None
    if ill:
        warn_ill_conditioned(ill, len(flatM), stacklevel=3)
    factor: np.ndarray = L  # type: ignore[assignment]  # not None: a failed factorization raised above
    y = np.linalg.solve(factor, rhs[..., None])
    out = np.linalg.solve(np.swapaxes(factor, -1, -2), y)[..., 0]
    out.setflags(write=False)
    return out


def _dependent_speeds(M, floor) -> list[int]:
    """The speeds of one ``(nv, nv)`` mass matrix whose pivot, eliminating the speeds before them in order (a
    dependent one skipped), is at most ``floor`` times its scale (its diagonal entry plus the mean diagonal entry):
    those that move no inertia the earlier ones do not already move."""
    A = np.array(M, dtype=float)
    mean = float(np.mean(np.diagonal(A))) if len(A) else 0.0
    out = []
    for k in range(len(A)):
        if not A[k, k] > floor * (M[k, k] + mean) or M[k, k] <= 0:
            out.append(k)
            continue
        A[k + 1:, k + 1:] -= np.outer(A[k + 1:, k], A[k, k + 1:]) / A[k, k]
    return out


__all__ = ["TreeDynamics", "TreeEffects", "equations", "generalized_forces", "solve", "tree_accelerations",
           "tree_dynamics"]
