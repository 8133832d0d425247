"""SO(3) as a typed group: unit quaternions with ``exp``, ``log``, composition and the 1-2-3 rate maps.

One toolkit for every rotation relacc moves (the tree's joints, the integrators), written in the
style of mink's ``SO3``: an immutable value holding batched unit quaternions ``(..., 4)``, scalar
first ``(w, x, y, z)``. ``SO3(q).as_matrix()`` is the *active* rotation of ``q``: for a body's
orientation it maps body components to fixed components (``[R_B]^T`` in the note).

Functions of the tangent space:

* :func:`jr_inv` -- the inverse right Jacobian ``J_r^-1(phi)``: the rate of ``phi`` for
  ``R = R0 Exp(phi)`` moving with body angular velocity ``w`` is ``J_r^-1(phi) w``;
* :func:`w123`, :func:`w123_dot` -- the note's partial angular velocity matrix of a 1-2-3 sequence,
  ``{omega} = [W(theta)] {theta_dot}`` (reference-frame components), and its rate.

Everything is analytic in its inputs (polynomials, sin, cos, sqrt of a square), so complex inputs
give the analytic continuation the complex-step checks use. Nothing normalizes: a quaternion is
taken as given (callers check norms where inputs enter, :mod:`relacc.core.cases`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from relacc.core.rotations import (
    matrix_from_123,
    matrix_from_quaternion,
    omega_partials_123,
    omega_partials_123_dot,
    quaternion_exp,
    quaternion_from_123,
    quaternion_multiply,
    tilde,
)


@dataclass(frozen=True)
class SO3:
    """A batch of rotations as unit quaternions.

    Attributes:
        wxyz: ``(..., 4)`` unit quaternions, scalar first (dimensionless).
    """

    wxyz: np.ndarray

    @classmethod
    def identity(cls, batch=()) -> "SO3":
        """The identity rotation, broadcast to ``batch``."""
        q = np.zeros(tuple(batch) + (4,))
        q[..., 0] = 1.0
        return cls(q)

    @classmethod
    def exp(cls, phi) -> "SO3":
        """``Exp(phi)``: the rotation by the rotation vector ``phi (..., 3)`` (axis times angle, rad)."""
        return cls(quaternion_exp(phi))

    @classmethod
    def from_123(cls, theta) -> "SO3":
        """``Rx(theta1) Ry(theta2) Rz(theta3)``, body-fixed 1-2-3 angles ``(..., 3)`` (rad)."""
        return cls(quaternion_from_123(theta))

    @classmethod
    def from_matrix(cls, R) -> "SO3":
        """The quaternion of a rotation matrix ``(..., 3, 3)`` (Shepperd's method: the largest pivot), ``w >= 0``."""
        R = np.asarray(R, dtype=float)
        tr = np.trace(R, axis1=-2, axis2=-1)
        diag = np.stack([R[..., 0, 0], R[..., 1, 1], R[..., 2, 2]], -1)
        pivot = np.argmax(np.concatenate([tr[..., None], diag], -1), axis=-1)
        q = np.empty(R.shape[:-2] + (4,))
        for k in range(4):
            sel = pivot == k
            r = R[sel]
            if k == 0:
                s = 2 * np.sqrt(1 + np.trace(r, axis1=-2, axis2=-1))
                cand = np.stack([s / 4, (r[:, 2, 1] - r[:, 1, 2]) / s, (r[:, 0, 2] - r[:, 2, 0]) / s,
                                 (r[:, 1, 0] - r[:, 0, 1]) / s], -1)
            else:
                i, j, m = k - 1, k % 3, (k + 1) % 3
                s = 2 * np.sqrt(1 + r[:, i, i] - r[:, j, j] - r[:, m, m])
                cand = np.empty((r.shape[0], 4))
                cand[:, 0] = (r[:, m, j] - r[:, j, m]) / s
                cand[:, 1 + i] = s / 4
                cand[:, 1 + j] = (r[:, j, i] + r[:, i, j]) / s
                cand[:, 1 + m] = (r[:, m, i] + r[:, i, m]) / s
            q[sel] = cand
        return cls(np.where(q[..., :1] < 0, -q, q))

    def as_matrix(self) -> np.ndarray:
        """``(..., 3, 3)`` the active rotation matrix (body components to reference-frame components)."""
        return matrix_from_quaternion(self.wxyz)

    def inverse(self) -> "SO3":
        """The inverse rotation (the conjugate quaternion)."""
        return SO3(self.wxyz * np.array([1.0, -1.0, -1.0, -1.0]))

    def __matmul__(self, other: "SO3") -> "SO3":
        """Composition ``self (x) other``: its matrix is ``self.as_matrix() @ other.as_matrix()``."""
        return SO3(quaternion_multiply(self.wxyz, other.wxyz))

    def log(self) -> np.ndarray:
        """``Log(R)``: the rotation vector ``(..., 3)`` (rad) of angle in ``[0, pi]``, the inverse of :meth:`exp`."""
        q = np.asarray(self.wxyz, dtype=float)
        q = np.where(q[..., :1] < 0, -q, q)  # the same rotation, angle <= pi
        w, xyz = q[..., 0], q[..., 1:]
        s = np.linalg.norm(xyz, axis=-1)
        angle = 2 * np.arctan2(s, w)
        # angle / s, with its series 2 / w (1 - s^2 / (3 w^2)) where s is tiny (no 0/0; w is then near 1)
        small = s < 1e-8
        ws, ss = np.where(small, w, 1.0), np.where(small, 1.0, s)
        k = np.where(small, 2 / ws * (1 - s * s / (3 * ws * ws)), angle / ss)
        return k[..., None] * xyz


def jr_inv(phi, w):
    """``J_r^-1(phi) w``: the rate of ``phi`` for ``R = R0 Exp(phi)`` moving with body angular velocity ``w``.

    ``J_r^-1 = I + 1/2 [phi~] + beta [phi~]^2``, ``beta = 1/theta^2 - (1 + cos theta) / (2 theta sin theta)``,
    with the series ``beta = 1/12 + theta^2/720 + theta^4/30240`` below theta = 1e-2 (its truncation,
    theta^6/1209600, is below eps there).

    Args:
        phi: ``(..., 3)`` rotation vector (rad). w: ``(..., 3)`` body angular velocity (rad/s).

    Returns:
        ``(..., 3)`` rad/s.
    """
    phi, w = np.asarray(phi, dtype=float), np.asarray(w, dtype=float)
    theta2 = np.sum(phi * phi, axis=-1)
    small = theta2 < 1e-4
    th = np.sqrt(np.where(small, 1.0, theta2))
    beta = np.where(small, 1 / 12 + theta2 / 720 + theta2 * theta2 / 30240,
                    1 / np.where(small, 1.0, theta2) - (1 + np.cos(th)) / (2 * th * np.sin(th)))
    pw = np.cross(phi, w)
    return w + 0.5 * pw + beta[..., None] * np.cross(phi, pw)


def w123(theta):
    """``[W(theta)]``: ``{omega} = [W]{theta_dot}`` for 1-2-3 angles ``(..., 3)``, reference-frame components.

    Its columns are ``e_x``, ``Rx e_y`` and ``Rx Ry e_z`` (dimensionless, ``(..., 3, 3)``).
    """
    return omega_partials_123(theta)


def w123_dot(theta, theta_dot):
    """``d[W(theta)]/dt`` along ``theta_dot`` (rad/s): ``(..., 3, 3)`` in 1/s."""
    return omega_partials_123_dot(theta, theta_dot)


def w123_body(theta, theta_dot=None):
    """``[W_b(theta)] = [R]^T [W(theta)]``: ``{omega} = [W_b]{theta_dot}`` in the *turned* frame's components.

    ``[R] = Rx Ry Rz`` (the turned frame in the frame it turns from): the rates' map to a ball's or free joint's
    case-2 speeds (MuJoCo's ``qvel``), well conditioned as ``W`` is (the same singular values). With
    ``theta_dot``, also its rate along the motion, ``d[W_b]/dt = -[R]^T [omega~] [W] + [R]^T [W_dot]`` with
    ``omega = [W] theta_dot`` (``d[R]^T/dt = -[R]^T [omega~]``).

    Args:
        theta: ``(..., 3)`` 1-2-3 angles (rad). theta_dot: ``(..., 3)`` their rates (rad/s) or None.

    Returns:
        ``W_b`` ``(..., 3, 3)`` (dimensionless), or ``(W_b, W_b_dot)`` with ``W_b_dot`` in 1/s.
    """
    theta = np.asarray(theta)
    Rt = np.swapaxes(matrix_from_123(theta), -1, -2)
    W = omega_partials_123(theta)
    if theta_dot is None:
        return Rt @ W
    omega = (W @ np.asarray(theta_dot)[..., None])[..., 0]
    return Rt @ W, Rt @ (omega_partials_123_dot(theta, theta_dot) - tilde(omega) @ W)


def condition_123(theta2):
    """2-norm condition number of ``W(theta)``: ``(1 + |sin theta2|) / |cos theta2|`` (inf at gimbal lock).

    ``W^T W`` has eigenvalues 1 and ``1 +- |sin theta2|`` (unit columns, only the first and third not
    orthogonal), hence singular values ``sqrt(1 +- |sin theta2|)``.
    """
    s, c = np.abs(np.sin(theta2)), np.abs(np.cos(theta2))
    return np.divide(1 + s, c, out=np.full_like(c, np.inf, dtype=float), where=c > 0)


__all__ = ["SO3", "condition_123", "jr_inv", "matrix_from_123", "tilde", "w123", "w123_body", "w123_dot"]
