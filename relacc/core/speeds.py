"""Maps between the three cases' generalized speeds (engine-free).

Every case is mapped to the *body speeds* of Case 2,

    nu = [s1_dot (fixed), omega'_B1 (B1 comps), s2'_dot (B1 comps), omega_hat'_B2 (B2 comps)],

with quaternion coordinates ``[s1, quat_B1, s2', quat_B2/B1]``. The map is
linear in the speeds, ``nu = [W(q)] u``, and its rate along the motion is
``nu_dot = [W] udot + [W_dot] u``. Engine adapters start from these body
speeds and apply their own conventions on top.

Block by block (the translational blocks are identities):

* case 1: ``omega'_B1 = [R_B1] omega_B1``, ``omega_hat'_B2 = [^{B2}R_{B1}]^T omega_hat_B2``;
* case 2: identity;
* case 3: ``omega'_B1 = [R_B1] W(theta_B1) theta_B1_dot``,
  ``omega_hat'_B2 = [^{B2}R_{B1}]^T W(theta_B2) theta_B2_dot``.

Each rotational block is ``[R] P`` where ``P`` maps the case's speeds to the
angular velocity in the reference frame's components and ``[R]`` maps those
components into the body's; hence ``d/dt([R] P) = -[R][omega~] P + [R] P_dot``
with ``omega = P u_block``.
"""

from __future__ import annotations

import numpy as np

from relacc.core.cases import Case, as_case, check_q, check_u, layout
from relacc.core.note.common import T, mv
from relacc.core.rotations import (
    matrix_from_123,
    matrix_from_quaternion,
    omega_partials_123,
    omega_partials_123_dot,
    quaternion_from_123,
    tilde,
)


def quaternion_coordinates(case, q):
    """The configuration in quaternion coordinates ``[s1, quat_B1, s2', quat_B2/B1]``.

    Cases 1 and 2 are returned as they are; case 3 angles become the unit
    quaternions of ``Rx Ry Rz`` (well conditioned everywhere).

    Returns:
        ``(..., 14)``; ``s1`` fixed components, ``s2'`` B1 components (m).
    """
    c = as_case(case)
    q = check_q(c, q)
    if c is not Case.ANGLE_RATES:
        return q
    lay = layout(c)
    return np.concatenate(
        [q[..., lay.s1], quaternion_from_123(q[..., lay.B1]), q[..., lay.s2_p], quaternion_from_123(q[..., lay.B2])],
        axis=-1,
    )


def _rotations(c, q):
    lay = layout(c)
    if lay.quaternions:
        return matrix_from_quaternion(q[..., lay.B1]), matrix_from_quaternion(q[..., lay.B2])
    return matrix_from_123(q[..., lay.B1]), matrix_from_123(q[..., lay.B2])


def _block_maps(c, q, u):
    """``(R, P, P_dot)`` for B1 and B2: body-from-reference rotation and case partials."""
    R_B1_T, R_B2B1 = _rotations(c, q)
    R1, R2 = T(R_B1_T), T(R_B2B1)  # [R_B1]: fixed -> B1; [^{B2}R_{B1}]^T: B1 -> B2
    batch = R1.shape[:-2]
    eye = np.broadcast_to(np.eye(3), batch + (3, 3))
    zero = np.zeros(batch + (3, 3))
    if c is Case.FIXED_FRAME:
        return (R1, eye, zero), (R2, eye, zero)
    if c is Case.BODY_FRAME:
        return (R1, R_B1_T, None), (R2, R_B2B1, None)
    lay = layout(c)
    th1, th2 = q[..., lay.B1], q[..., lay.B2]
    P1, P2 = omega_partials_123(th1), omega_partials_123(th2)
    if u is None:
        return (R1, P1, None), (R2, P2, None)
    return (
        (R1, P1, omega_partials_123_dot(th1, u[..., 3:6])),
        (R2, P2, omega_partials_123_dot(th2, u[..., 9:12])),
    )


def body_speed_map(case, q, u=None):
    """``[W(q)]`` with ``nu = [W] u`` and, if ``u`` is given, ``[W_dot]`` along the motion.

    Args:
        case: 1, 2 or 3.
        q: the case's coordinates ``(..., 14)`` or ``(..., 12)``.
        u: the case's speeds ``(..., 12)``, needed for ``W_dot`` only.

    Returns:
        ``W`` ``(..., 12, 12)`` (dimensionless) or ``(W, W_dot)`` with
        ``W_dot`` in 1/s. Rows are the body speeds ``nu``, columns the case's
        speeds.
    """
    c = as_case(case)
    q = check_q(c, q)
    if u is not None:
        u = check_u(f"u for case {int(c)}", u)
    blocks = _block_maps(c, q, u)
    batch = np.broadcast_shapes(q.shape[:-1], () if u is None else u.shape[:-1])
    W = np.zeros(batch + (12, 12), dtype=np.result_type(q, u if u is not None else q))
    W[..., 0:3, 0:3] = np.eye(3)
    W[..., 6:9, 6:9] = np.eye(3)
    for (R, P, _), sl in zip(blocks, (slice(3, 6), slice(9, 12))):
        W[..., sl, sl] = np.eye(3) if c is Case.BODY_FRAME else R @ P
    if u is None:
        return W
    W_dot = np.zeros_like(W)
    if c is not Case.BODY_FRAME:
        for (R, P, P_dot), sl in zip(blocks, (slice(3, 6), slice(9, 12))):
            omega = mv(P, u[..., sl])  # reference-frame components
            W_dot[..., sl, sl] = -R @ tilde(omega) @ P + R @ P_dot
    return W, W_dot


def to_body_speeds(case, q, u, udot=None):
    """A case's state in Case 2 form: ``(q14, nu, nu_dot)``.

    Args:
        case: 1, 2 or 3.
        q: ``(..., 14)`` or ``(..., 12)`` coordinates; u, udot: ``(..., 12)``.

    Returns:
        ``q14`` ``(..., 14)`` (see :func:`quaternion_coordinates`), ``nu``
        ``(..., 12)`` body speeds (m/s and rad/s), ``nu_dot`` ``(..., 12)``
        their rates (None without ``udot``).
    """
    W, W_dot = body_speed_map(case, q, u)
    u = np.asarray(u)
    nu = mv(W, u)
    nu_dot = None if udot is None else mv(W, check_u("udot", udot)) + mv(W_dot, u)
    return quaternion_coordinates(case, q), nu, nu_dot


def _condition_123(theta2):
    """2-norm condition number of ``W(theta)``: ``(1 + |sin theta2|) / |cos theta2|``.

    ``W^T W`` has eigenvalues 1 and ``1 +- |sin theta2|`` (unit columns, only
    the first and third not orthogonal), hence singular values
    ``sqrt(1 +- |sin theta2|)``.
    """
    s, c = np.abs(np.sin(theta2)), np.abs(np.cos(theta2))
    return np.divide(1 + s, c, out=np.full_like(c, np.inf, dtype=float), where=c > 0)


def inverse_condition(case, q):
    """Condition number of the speed map ``[W(q)]`` per state (its inverse's error amplification).

    1 for cases 1 and 2 (rotations); for case 3 the larger of B1's and B2's
    ``(1 + |sin theta2|) / |cos theta2|``, which grows like ``2 / delta`` at a
    distance ``delta`` from gimbal lock. The forward map (rates to angular
    velocity) is well conditioned everywhere; only its inverse suffers.

    Returns:
        ``(...)`` array >= 1, dimensionless.
    """
    c = as_case(case)
    q = check_q(c, q)
    if c is not Case.ANGLE_RATES:
        return np.ones(q.shape[:-1])
    lay = layout(c)
    return np.maximum(_condition_123(np.real(q[..., lay.B1][..., 1])), _condition_123(np.real(q[..., lay.B2][..., 1])))


def check_invertible(case, q, max_condition=None):
    """Raise :class:`relacc.SingularityError` where the case's speed map is too ill-conditioned.

    Args:
        max_condition: largest accepted condition number (default
            ``relacc.core.tolerances.MAX_CONDITION`` = 1e8).

    Raises:
        SingularityError: naming the body, the angle, its distance from gimbal
            lock and the condition number.
    """
    from relacc.core.tolerances import MAX_CONDITION
    from relacc.errors import SingularityError

    limit = MAX_CONDITION if max_condition is None else float(max_condition)
    c = as_case(case)
    q = check_q(c, q)
    if c is not Case.ANGLE_RATES:
        return
    lay = layout(c)
    for label, sl in (("theta_B1", lay.B1), ("theta_B2", lay.B2)):
        theta2 = np.real(q[..., sl][..., 1])
        cond = _condition_123(theta2)
        if np.any(cond > limit):
            idx = np.unravel_index(np.argmax(cond), cond.shape) if cond.ndim else ()
            t = float(theta2[idx])
            distance = float(np.arctan2(abs(np.cos(t)), abs(np.sin(t))))
            lock = "+pi/2" if np.sin(t) > 0 else "-pi/2"
            at = f" at batch index {tuple(int(i) for i in idx)}" if idx else ""
            raise SingularityError(
                f"{label}[1] = {t!r} rad{at} is {distance:.3g} rad from the 1-2-3 gimbal lock at {lock} "
                f"(mod pi): the map from angular velocity to 1-2-3 rates has condition number "
                f"{float(cond[idx]):.3g} > {limit:g}, so the rates are not defined to useful accuracy; "
                "use case 1 or 2 speeds there"
            )


def case_speeds(case, q, nu, nu_dot=None, *, max_condition=None):
    """Inverse of :func:`to_body_speeds`: the case's ``(u, udot)`` from body speeds.

    Args:
        case: 1, 2 or 3. q: the case's coordinates.
        nu: ``(..., 12)`` body speeds (Case 2 speeds). nu_dot: their rates or None.
        max_condition: see :func:`check_invertible`.

    Returns:
        ``u`` ``(..., 12)`` (m/s and rad/s, in the components of the case's
        speeds, see :mod:`relacc.core.cases`) and ``udot`` ``(..., 12)`` (their rates,
        m/s^2 and rad/s^2; None without ``nu_dot``).

    Raises:
        SingularityError: case 3 within the gimbal-lock limit.
    """
    c = as_case(case)
    check_invertible(c, q, max_condition)
    nu = check_u("nu (body speeds)", nu)
    W = body_speed_map(c, q)
    u = np.linalg.solve(W, nu[..., None])[..., 0]
    if nu_dot is None:
        return u, None
    _, W_dot = body_speed_map(c, q, u)
    udot = np.linalg.solve(W, (check_u("nu_dot", nu_dot) - mv(W_dot, u))[..., None])[..., 0]
    return u, udot
