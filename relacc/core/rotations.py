"""Building blocks of the note: tilde matrices, rotation matrices, 1-2-3 partials.

Conventions (binding, see ``docs/conventions.md``):

* ``[R_B]`` maps fixed-frame components to B components, ``{v'} = [R_B]{v}``;
  its transpose ``[R_B]^T`` maps B components to fixed-frame components.
* Quaternions are scalar-first ``(w, x, y, z)``. The matrix of a quaternion is
  the *active* rotation it represents; for ``quat_B1`` that matrix is
  ``[R_B1]^T`` (B1 -> fixed components).
* Body-fixed 1-2-3 angles: ``[R_B]^T = Rx(theta1) Ry(theta2) Rz(theta3)``.

Every function takes arrays with any leading batch dimensions and is analytic
in its inputs (only polynomials, sin, cos and sqrt), so complex inputs are
accepted: the complex-step derivative checks rely on that.
"""

from __future__ import annotations

import numpy as np


def tilde(v):
    """Skew-symmetric matrix ``[v~]`` with ``[v~]{w} = {v} x {w}``.

    Args:
        v: vector, shape ``(..., 3)``, any frame's components, any units.

    Returns:
        ``(..., 3, 3)`` matrix in the same frame's components and units as ``v``.
    """
    v = np.asarray(v)
    x, y, z = v[..., 0], v[..., 1], v[..., 2]
    out = np.zeros(v.shape[:-1] + (3, 3), dtype=np.result_type(v, 0.0))
    out[..., 0, 1], out[..., 0, 2] = -z, y
    out[..., 1, 0], out[..., 1, 2] = z, -x
    out[..., 2, 0], out[..., 2, 1] = -y, x
    return out


def untilde(m):
    """Inverse of :func:`tilde`: the vector ``(..., 3)`` of a skew matrix ``(..., 3, 3)``."""
    m = np.asarray(m)
    return np.stack([m[..., 2, 1], m[..., 0, 2], m[..., 1, 0]], -1)


def matrix_from_quaternion(quat):
    """Rotation matrix of a unit quaternion ``(w, x, y, z)``.

    For ``quat_B1`` the result is ``[R_B1]^T`` (B1 -> fixed components); for
    ``quat_B2/B1`` it is ``[^{B2}R_{B1}]`` (B2 -> B1 components).

    Args:
        quat: ``(..., 4)`` unit quaternion, scalar first.

    Returns:
        ``(..., 3, 3)`` dimensionless rotation matrix.
    """
    q = np.asarray(quat)
    if q.size == 4 and q.dtype == np.float64:  # one rotation (a stepper's stage): the same arithmetic on floats
        w, x, y, z = q.ravel().tolist()
        xx, yy, zz = x * x, y * y, z * z
        xy, xz, yz = x * y, x * z, y * z
        wx, wy, wz = w * x, w * y, w * z
        return np.array([1 - 2 * (yy + zz), 2 * (xy - wz), 2 * (xz + wy), 2 * (xy + wz), 1 - 2 * (xx + zz),
                         2 * (yz - wx), 2 * (xz - wy), 2 * (yz + wx), 1 - 2 * (xx + yy)]).reshape(q.shape[:-1] + (3, 3))
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    xx, yy, zz = x * x, y * y, z * z
    xy, xz, yz = x * y, x * z, y * z
    wx, wy, wz = w * x, w * y, w * z
    out = np.empty(q.shape[:-1] + (3, 3), dtype=np.result_type(q, 0.0))  # filled entry by entry: no stacking
    out[..., 0, 0], out[..., 0, 1], out[..., 0, 2] = 1 - 2 * (yy + zz), 2 * (xy - wz), 2 * (xz + wy)
    out[..., 1, 0], out[..., 1, 1], out[..., 1, 2] = 2 * (xy + wz), 1 - 2 * (xx + zz), 2 * (yz - wx)
    out[..., 2, 0], out[..., 2, 1], out[..., 2, 2] = 2 * (xz - wy), 2 * (yz + wx), 1 - 2 * (xx + yy)
    return out


def matrix_from_123(theta):
    """``Rx(theta1) Ry(theta2) Rz(theta3)``: body-fixed 1-2-3 rotation matrix.

    For ``theta_B1`` the result is ``[R_B1]^T`` (B1 -> fixed components); for
    ``theta_B2`` it is ``[^{B2}R_{B1}]`` (B2 -> B1 components).

    Args:
        theta: ``(..., 3)`` angles in radians.

    Returns:
        ``(..., 3, 3)`` dimensionless rotation matrix.
    """
    t = np.asarray(theta)
    c1, c2, c3 = np.cos(t[..., 0]), np.cos(t[..., 1]), np.cos(t[..., 2])
    s1, s2, s3 = np.sin(t[..., 0]), np.sin(t[..., 1]), np.sin(t[..., 2])
    return np.stack(
        [
            np.stack([c2 * c3, -c2 * s3, s2], -1),
            np.stack([c1 * s3 + s1 * s2 * c3, c1 * c3 - s1 * s2 * s3, -s1 * c2], -1),
            np.stack([s1 * s3 - c1 * s2 * c3, s1 * c3 + c1 * s2 * s3, c1 * c2], -1),
        ],
        -2,
    )


def omega_partials_123(theta):
    """Partial angular velocity matrix ``[omega_{B,theta_dot}]`` of a 1-2-3 sequence.

    ``{omega} = [omega_{B,theta_dot}] {theta_dot}`` where ``omega`` is the angular
    velocity of B relative to its reference frame, in the *reference frame's*
    components (fixed components for B1; B1 components for B2 relative to B1).
    Its columns are ``e_x``, ``Rx e_y`` and ``Rx Ry e_z``.

    Args:
        theta: ``(..., 3)`` angles in radians.

    Returns:
        ``(..., 3, 3)`` dimensionless matrix.
    """
    t = np.asarray(theta)
    c1, c2 = np.cos(t[..., 0]), np.cos(t[..., 1])
    s1, s2 = np.sin(t[..., 0]), np.sin(t[..., 1])
    o, i = np.zeros_like(c1), np.ones_like(c1)
    return np.stack(
        [
            np.stack([i, o, s2], -1),
            np.stack([o, c1, -s1 * c2], -1),
            np.stack([o, s1, c1 * c2], -1),
        ],
        -2,
    )


def omega_partials_123_dot(theta, theta_dot):
    """Time derivative ``[omega_dot_{B,theta_dot}]`` of :func:`omega_partials_123`.

    Args:
        theta: ``(..., 3)`` angles in radians.
        theta_dot: ``(..., 3)`` angle rates in rad/s.

    Returns:
        ``(..., 3, 3)`` matrix in 1/s, same components as :func:`omega_partials_123`.
    """
    t, td = np.asarray(theta), np.asarray(theta_dot)
    c1, c2 = np.cos(t[..., 0]), np.cos(t[..., 1])
    s1, s2 = np.sin(t[..., 0]), np.sin(t[..., 1])
    d1, d2 = td[..., 0], td[..., 1]
    o = np.zeros_like(c1 * d1)
    return np.stack(
        [
            np.stack([o, o, c2 * d2], -1),
            np.stack([o, -s1 * d1, -c1 * c2 * d1 + s1 * s2 * d2], -1),
            np.stack([o, c1 * d1, -s1 * c2 * d1 - c1 * s2 * d2], -1),
        ],
        -2,
    )


def angles_123_from_matrix(R):
    """1-2-3 angles ``theta`` with ``Rx(theta1) Ry(theta2) Rz(theta3) = R``, theta2 in [-pi/2, pi/2].

    The inverse of :func:`matrix_from_123` away from gimbal lock
    (``cos(theta2) = 0``), where theta1 and theta3 are not separately defined
    and their sensitivity to ``R`` grows like ``1 / cos(theta2)``.

    Args:
        R: ``(..., 3, 3)`` rotation matrix (real).

    Returns:
        ``(..., 3)`` angles in radians, theta1 and theta3 in (-pi, pi].
    """
    R = np.asarray(R)
    theta2 = np.arctan2(R[..., 0, 2], np.hypot(R[..., 1, 2], R[..., 2, 2]))
    theta1 = np.arctan2(-R[..., 1, 2], R[..., 2, 2])
    theta3 = np.arctan2(-R[..., 0, 1], R[..., 0, 0])
    return np.stack([theta1, theta2, theta3], -1)


def quaternion_from_matrix(R):
    """The unit quaternion ``(w, x, y, z)``, ``w >= 0``, of rotation matrices ``R (..., 3, 3)`` (real, orthogonal to
    rounding): the inverse of :func:`matrix_from_quaternion` up to the sign it leaves free.

    Shepperd's method: of ``4 w^2 - 1 = trace`` and ``4 x^2 - 1 = 2 R_xx - trace`` (and y, z), the largest gives
    the component divided by (at least 1/2 before normalization), so no square root of a small difference is taken
    and every rotation, the half turns included, is within a few ulps; the result is normalized.
    """
    R = np.asarray(R, dtype=float)
    d = np.stack([R[..., 0, 0], R[..., 1, 1], R[..., 2, 2]], -1)
    t = d.sum(-1)
    q = np.stack([1 + t, R[..., 2, 1] - R[..., 1, 2], R[..., 0, 2] - R[..., 2, 0], R[..., 1, 0] - R[..., 0, 1]], -1)
    for i in range(3):
        j, k = (i + 1) % 3, (i + 2) % 3
        v = np.empty_like(q)
        v[..., 0] = R[..., k, j] - R[..., j, k]
        v[..., 1 + i] = 1 - t + 2 * R[..., i, i]
        v[..., 1 + j] = R[..., j, i] + R[..., i, j]
        v[..., 1 + k] = R[..., k, i] + R[..., i, k]
        pick = (d[..., i] > t) & np.all(d[..., i:i + 1] >= d, axis=-1)
        q = np.where(pick[..., None], v, q)
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    return np.where(q[..., :1] < 0, -q, q)


def quaternion_multiply(p, q):
    """Hamilton product ``p (x) q`` of scalar-first quaternions, shape ``(..., 4)``.

    The matrix of the product is ``matrix(p) @ matrix(q)``.
    """
    p, q = np.asarray(p), np.asarray(q)
    pw, px, py, pz = p[..., 0], p[..., 1], p[..., 2], p[..., 3]
    qw, qx, qy, qz = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    return np.stack(
        [
            pw * qw - px * qx - py * qy - pz * qz,
            pw * qx + px * qw + py * qz - pz * qy,
            pw * qy - px * qz + py * qw + pz * qx,
            pw * qz + px * qy - py * qx + pz * qw,
        ],
        -1,
    )


def quaternion_exp(phi):
    """Unit quaternion ``(w, x, y, z)`` of the rotation vector ``phi``.

    ``matrix_from_quaternion(quaternion_exp(phi)) == expm([phi~])``. Analytic in
    ``phi`` (the angle enters through ``phi . phi``, not ``|phi|``), so a
    complex ``phi`` gives the analytic continuation used by complex steps.

    Args:
        phi: ``(..., 3)`` rotation vector (axis times angle), radians.

    Returns:
        ``(..., 4)`` quaternion, scalar first.
    """
    phi = np.asarray(phi)
    angle2 = np.sum(phi * phi, axis=-1)
    small = np.abs(angle2) < 1e-8
    safe2 = np.where(small, 1.0, angle2)
    angle = np.sqrt(safe2)
    # Series of cos(a/2) and sin(a/2)/a in a^2, exact to rounding below 1e-8.
    w = np.where(small, 1 - angle2 / 8 + angle2**2 / 384, np.cos(angle / 2))
    k = np.where(small, 0.5 - angle2 / 48 + angle2**2 / 3840, np.sin(angle / 2) / angle)
    return np.concatenate([w[..., None], k[..., None] * phi], -1)


def quaternion_from_123(theta):
    """Unit quaternion ``(w, x, y, z)`` of ``Rx(theta1) Ry(theta2) Rz(theta3)``.

    Args:
        theta: ``(..., 3)`` body-fixed 1-2-3 angles in radians.

    Returns:
        ``(..., 4)`` quaternion with ``w >= 0`` for angles in ``(-pi, pi)``.
    """
    t = np.asarray(theta) / 2
    c, s = np.cos(t), np.sin(t)
    o = np.zeros_like(c[..., 0])
    qx = np.stack([c[..., 0], s[..., 0], o, o], -1)
    qy = np.stack([c[..., 1], o, s[..., 1], o], -1)
    qz = np.stack([c[..., 2], o, o, s[..., 2]], -1)
    return quaternion_multiply(quaternion_multiply(qx, qy), qz)


def quaternion_to_xyzw(quat):
    """Reorder a scalar-first quaternion ``(..., 4)`` to scalar-last ``(x, y, z, w)``."""
    q = np.asarray(quat)
    return np.concatenate([q[..., 1:], q[..., :1]], -1)


def quaternion_from_xyzw(quat):
    """Reorder a scalar-last quaternion ``(..., 4)`` to scalar-first ``(w, x, y, z)``."""
    q = np.asarray(quat)
    return np.concatenate([q[..., 3:], q[..., :3]], -1)
