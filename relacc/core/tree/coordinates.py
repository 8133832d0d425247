"""A tree's coordinates and speeds in the note's three cases, their checks, and the maps between cases.

Per joint, in the tree's joint order:

==========  ================================  =============================================================
joint       q (cases 1-2 | case 3)            u: case 1 | case 2 (MuJoCo's ``qvel``) | case 3
==========  ================================  =============================================================
free        ``[p, quat]`` (7) | ``[p, theta]``   ``[p_dot, omega]``: omega in fixed | body | 1-2-3 rates
ball        ``quat`` (4) | ``theta`` (3)        relative angular velocity in the parent body's | the
                                               body's (the frame it turns) components | 1-2-3 rates
hinge       angle (rad)                        its rate, every case
slide       displacement (m)                   its rate, every case
==========  ================================  =============================================================

``p`` and ``p_dot`` are the body's origin and its velocity, fixed components. Quaternions are
``(w, x, y, z)``, unit to 1e-12 (never normalized). 1-2-3 angles describe the same rotation as the
quaternion: ``Rx(theta1) Ry(theta2) Rz(theta3)`` is the body frame in the world (free) or in the
frame the ball turns from. Cases 1-2 share ``q``: a MuJoCo state ``(qpos, qvel)`` is a case-2 state.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from relacc.core.cases import Case, as_case, as_numbers, check_int, quaternion_norm_deviation
from relacc.core.rotations import angles_123_from_matrix, matrix_from_quaternion, quaternion_from_123
from relacc.core.so3 import condition_123
from relacc.core.states import States
from relacc.core.tolerances import MAX_CONDITION, QUATERNION_NORM_TOLERANCE
from relacc.core.tree.walk import angular_map, mv, walk
from relacc.errors import InputError, SingularityError

if TYPE_CHECKING:
    from relacc.core.states import States
    from relacc.core.tree.model import Tree


def rotations(tree, case):
    """``[(joint index, kind, qadr, dofadr)]`` of the ball and free joints.

    ``qadr`` and ``dofadr`` are the rotation's first coordinate and first speed."""
    c = int(case)
    out = []
    for k, ((_, j), a, d) in enumerate(zip(tree.joints, tree.qadr(c), tree.dofadr)):
        if j.type == "free":
            out.append((k, "free", a + 3, d + 3))
        elif j.type == "ball":
            out.append((k, "ball", a, d))
    return out


def check_q(tree, case, q, values: bool = True) -> np.ndarray:
    """A case's coordinates ``(..., nq)`` as an array; with ``values``, finite and with unit quaternions.

    Raises:
        InputError: the wrong length, a non-finite entry, or a quaternion off unit by more than 1e-12,
            naming the joint.
    """
    c = as_case(case)
    arr = as_numbers(f"q for case {int(c)} of tree {tree.name!r}", q, tree.nq_in(c),
                     lambda: "the joints' coordinates in order: "
                     + ", ".join(f"{j.name} ({j.type})" for _, j in tree.joints),
                     values)
    if values and c != Case.ANGLE_RATES:
        for k, kind, a, _ in rotations(tree, c):
            dev = quaternion_norm_deviation(arr[..., a:a + 4])
            if np.any(dev > QUATERNION_NORM_TOLERANCE):
                idx = np.unravel_index(np.argmax(dev), dev.shape) if dev.ndim else ()
                raise InputError(f"q for case {int(c)}: joint {tree.joints[k][1].name!r}'s quaternion (q[{a}:{a + 4}])"
                                 f"{' at batch index ' + str(tuple(int(i) for i in idx)) if idx else ''} is off unit "
                                 f"by {float(dev[idx]):.3g} > {QUATERNION_NORM_TOLERANCE:g}; pass unit quaternions "
                                 "(w, x, y, z): relacc does not normalize them")
    return arr


def check_u(tree, name: str, u, values: bool = True) -> np.ndarray:
    """Speeds (or their rates) ``(..., nv)`` as an array, finite with ``values``."""
    return as_numbers(name, u, tree.nv, lambda: "the joints' speeds in order: " + ", ".join(tree.speed_names()), values)


def rate_map_conditions(tree, q3) -> np.ndarray:
    """``(n_rotations, ...)``: the condition number of each ball's and free joint's map from angular velocity to 1-2-3
    rates, ``(1 + |sin theta2|) / |cos theta2|`` (:func:`relacc.core.so3.condition_123`), at the case-3 coordinates
    ``q3 (..., nq)``, in the order of :func:`rotations`; 0 where ``theta2`` is not finite (the value checks judge
    that)."""
    out = []
    for _, _, a, _ in rotations(tree, 3):
        theta2 = np.real(q3[..., a + 1])
        with np.errstate(invalid="ignore"):
            out.append(np.where(np.isfinite(theta2), condition_123(theta2), 0.0))
    return np.array(out).reshape((len(out),) + np.shape(q3)[:-1])


def check_invertible(tree, q3):
    """Raise :class:`SingularityError` naming the joint whose 1-2-3 rate map is too ill-conditioned.

    ``q3``: case-3 coordinates. Angular velocity to rates amplifies errors by the condition number
    (:func:`rate_map_conditions`); above :data:`relacc.core.tolerances.MAX_CONDITION` the rates are not defined to
    useful accuracy.
    """
    for (k, _, a, _), cond in zip(rotations(tree, 3), rate_map_conditions(tree, q3)):
        if np.any(cond > MAX_CONDITION):
            theta2 = np.real(q3[..., a + 1])
            idx = np.unravel_index(np.argmax(cond), cond.shape) if cond.ndim else ()
            t = float(theta2[idx])
            raise SingularityError(
                f"joint {tree.joints[k][1].name!r}: theta2 = {t!r} rad"
                f"{' at batch index ' + str(tuple(int(i) for i in idx)) if idx else ''} is "
                f"{float(np.arctan2(abs(np.cos(t)), abs(np.sin(t)))):.3g} rad from the 1-2-3 gimbal lock: the map from "
                f"angular velocity to 1-2-3 rates has condition number {float(cond[idx]):.3g} > {MAX_CONDITION:g}; "
                "use case 1 or 2 speeds there")


def warn_near_lock(tree, q3, consequence: str, stacklevel: int = 2):
    """Warn (:class:`relacc.AccuracyWarning`) where a joint's 1-2-3 rate map is conditioned above
    :data:`relacc.core.tolerances.CONDITION_WARNING` (and within :data:`~relacc.core.tolerances.MAX_CONDITION`,
    which :func:`check_invertible` refuses beyond), naming the joint, ``theta2`` and the distance to the lock.

    ``stacklevel``: the frame the warning names, 1 this function's caller, 2 that one's caller (the default).
    ``consequence``: what that costs, formatted with ``cond`` (the condition number), ``cond2`` (its square) and
    ``err`` (``cond eps``)."""
    import warnings

    from relacc.core.tolerances import CONDITION_WARNING, EPS
    from relacc.errors import AccuracyWarning

    worst = None  # (cond, joint, theta2, batch index) of the worst-conditioned joint
    for k, _, a, _ in rotations(tree, 3):
        theta2 = np.real(q3[..., a + 1])
        with np.errstate(invalid="ignore"):
            cond = np.where(np.isfinite(theta2), condition_123(theta2), 0.0)
        if cond.size == 0:
            continue
        idx = np.unravel_index(np.argmax(cond), cond.shape) if cond.ndim else ()
        if cond[idx] > CONDITION_WARNING and (worst is None or cond[idx] > worst[0]):
            worst = (float(cond[idx]), k, float(theta2[idx]), idx)
    if worst is not None:
        c, k, t, idx = worst
        warnings.warn(
            f"joint {tree.joints[k][1].name!r}: theta2 = {t!r} rad"
            f"{' at batch index ' + str(tuple(int(i) for i in idx)) if idx else ''} is "
            f"{float(np.arctan2(abs(np.cos(t)), abs(np.sin(t)))):.3g} rad from the 1-2-3 gimbal lock, where its "
            f"rate map has condition number {c:.3g} > {CONDITION_WARNING:g}: "
            + consequence.format(cond=c, cond2=c * c, err=c * EPS), AccuracyWarning, stacklevel=stacklevel + 1)


def reference_q(tree: Tree, case: int) -> np.ndarray:
    """``(nq,)`` the tree as placed: free bodies where their placement puts them, balls at identity, hinges
    and slides at ``ref`` (MuJoCo's ``qpos0``)."""
    c = int(as_case(case))
    q = np.zeros(tree.nq_in(c))
    for (b, j), a in zip(tree.joints, tree.qadr(c)):
        if j.type == "free":
            body = tree.bodies[b]
            q[a:a + 3] = body.pos
            angles = c == Case.ANGLE_RATES
            q[a + 3:a + (6 if angles else 7)] = angles_123_from_matrix(matrix_from_quaternion(body.quat)) if angles \
                else body.quat
        elif j.type == "ball":
            q[a:a + (3 if c == Case.ANGLE_RATES else 4)] = 0.0 if c == Case.ANGLE_RATES else (1.0, 0.0, 0.0, 0.0)
        else:
            q[a] = j.ref
    return q


def q_in_case(tree, source: int, target: int, q):
    """``q`` of ``source`` in ``target``'s layout (quaternions <-> 1-2-3 angles; nothing else changes)."""
    if (source == 3) == (target == 3):
        return q.copy()
    out = np.empty(q.shape[:-1] + (tree.nq_in(target),), dtype=q.dtype)
    qs, qt = tree.qadr(source), tree.qadr(target)
    for (_, j), a, t in zip(tree.joints, qs, qt):
        lin = 3 if j.type == "free" else 0
        out[..., t:t + lin] = q[..., a:a + lin]
        if j.type in ("free", "ball"):
            if target == 3:
                quat = q[..., a + lin:a + lin + 4]
                out[..., t + lin:t + lin + 3] = angles_123_from_matrix(matrix_from_quaternion(quat))
            else:
                out[..., t + lin:t + lin + 4] = quaternion_from_123(q[..., a + lin:a + lin + 3])
        else:
            out[..., t] = q[..., a]
    return out


def convert(tree: Tree, q: ArrayLike, u: ArrayLike | None = None, udot: ArrayLike | None = None, *, source: int,
            target: int) -> tuple[np.ndarray, Any, Any]:
    """A state of case ``source`` in case ``target``: ``(q, u, udot)`` (each None where not given).

    The motion is the same: every body's pose, velocity and acceleration are unchanged. A ball's
    or free joint's speeds ``u_t = A_t^-1 A_s u_s`` and rates ``udot_t = A_t^-1 (A_s udot_s + A_dot_s u_s -
    A_dot_t u_t)`` (:func:`relacc.core.tree.walk.angular_map`); every other speed is unchanged.

    Raises:
        InputError: bad shapes or values. SingularityError: to case 3 within the gimbal-lock limit.
    """
    s, t = int(as_case(source)), int(as_case(target))
    q = check_q(tree, s, q)
    qt = q_in_case(tree, s, t, q)
    if t == 3:
        check_invertible(tree, qt)
    if u is None:
        return qt, None, None
    u = check_u(tree, f"u for case {s}", u)
    batch = np.broadcast_shapes(q.shape[:-1], u.shape[:-1])
    rows = int(np.prod(batch, dtype=np.int64))  # not -1: a tree without speeds has rows of width 0
    flat = lambda a, w: np.broadcast_to(a, batch + (w,)).reshape(rows, w)  # noqa: E731
    qf, uf, qtf = flat(q, q.shape[-1]), flat(u, tree.nv), flat(qt, qt.shape[-1])
    ud = None if udot is None else flat(check_u(tree, f"udot for case {s}", udot), tree.nv)
    ut = uf.copy()
    udt = None if ud is None else ud.copy()
    from relacc.limits import CONVERT_BYTES

    # the walk holds (chunk, 3, nv) arrays per body: a chunk of states at a time keeps it near CONVERT_BYTES
    chunk = max(1, CONVERT_BYTES // (8 * 12 * 3 * max(1, tree.nb) * max(1, tree.nv)))
    for start in range(0, len(qf), chunk):
        part = slice(start, start + chunk)
        _, joints = walk(tree, s, qf[part], uf[part])
        for k, kind, a, d in rotations(tree, t):
            jf = joints[k]
            u_j = uf[part, d:d + 3]
            rel = mv(jf.A, u_j)  # the joint's relative angular velocity, fixed components
            rec = {name: getattr(jf, name) for name in ("R_parent", "w_parent", "R_before", "w_before", "R_after",
                                                         "w_after")}
            theta = qtf[part, a:a + 3] if t == 3 else None
            A_t, _ = angular_map(t, kind, rec, theta, np.zeros_like(theta) if t == 3 else None)
            ut[part, d:d + 3] = np.linalg.solve(A_t, rel[..., None])[..., 0]
            if ud is not None and udt is not None:  # the rates were given, so converted
                _, A_dot_t = angular_map(t, kind, rec, theta, ut[part, d:d + 3] if t == 3 else None)
                rel_dot = mv(jf.A, ud[part, d:d + 3]) + mv(jf.A_dot, u_j)
                udt[part, d:d + 3] = np.linalg.solve(A_t, (rel_dot - mv(A_dot_t, ut[part, d:d + 3]))[..., None])[
                    ..., 0]
    shape = lambda a: None if a is None else a.reshape(batch + (tree.nv,))  # noqa: E731
    return np.broadcast_to(qt, batch + (qt.shape[-1],)).copy(), shape(ut), shape(udt)


def random_states(tree: Tree, case: int, n: int, seed: int, *, size: float | None = None,
                  ranges: dict | None = None) -> States:
    """``n`` random states (``numpy.random.default_rng(seed)``), drawn in case 2 and converted: a
    :class:`relacc.core.states.States` of ``tree``.

    Free joints: a position within ``size`` (default: the tree's extent, at least 1 m) of the origin and a
    uniformly random unit quaternion; balls: a random unit quaternion; hinges uniform in ``[-pi, pi]``;
    slides within ``size``; a hinge or slide named in ``ranges`` (``{joint name: (lower, upper)}``, a file's limits)
    uniform in its range. Speeds and rates: standard normals in case 2. States within the gimbal-lock
    limit of case 3 are drawn again.
    """
    from relacc.limits import require_memory, tree_states_bytes

    c = int(as_case(case))
    n = check_int("n", n, minimum=1)
    require_memory(tree_states_bytes(tree, n, c), f"{n} random states of {tree.name!r}", "ask for fewer states")
    rng = np.random.default_rng(seed)
    if size is None:
        size = max([1.0] + [float(np.linalg.norm(b.pos) + np.linalg.norm(b.com)) for b in tree.bodies])
    q = np.repeat(reference_q(tree, 2)[None], n, axis=0)
    for (_, j), a in zip(tree.joints, tree.qadr(2)):
        if j.type in ("free", "ball"):
            quat = rng.standard_normal((n, 4))
            quat /= np.linalg.norm(quat, axis=1, keepdims=True)
            if j.type == "free":
                q[:, a:a + 3] = rng.uniform(-size, size, (n, 3))
                a += 3
            q[:, a:a + 4] = quat
        elif ranges and j.name in ranges:
            lo, hi = ranges[j.name]
            q[:, a] = rng.uniform(lo, hi, n)
        else:
            q[:, a] = rng.uniform(-np.pi, np.pi, n) if j.type == "hinge" else rng.uniform(-size, size, n)
    u, udot = rng.standard_normal((n, tree.nv)), rng.standard_normal((n, tree.nv))
    if c == Case.ANGLE_RATES:  # away from gimbal lock: redraw those joints' quaternions at a safe angle
        for k, _, a, _ in rotations(tree, 2):
            theta = angles_123_from_matrix(matrix_from_quaternion(q[:, a:a + 4]))
            near = condition_123(theta[:, 1]) > 1e3
            theta[near, 1] *= 0.9
            q[near, a:a + 4] = quaternion_from_123(theta[near])
    if c != Case.BODY_FRAME:
        q, u, udot = convert(tree, q, u, udot, source=2, target=c)
    return States(as_case(c), q, u, udot, int(seed), tree)
