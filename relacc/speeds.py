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

from relacc.cases import Case, as_case, check_q, check_u, layout
from relacc.note.common import T, mv
from relacc.rotations import (
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
