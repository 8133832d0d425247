"""SO(3) and 3-vector algebra of the compiled kernels, written once for the chain's and the trees' kernels.

The compiled twin of :mod:`relacc.core.so3` (which the reference paths and the Python integrators use): plain
arithmetic on scalars and row-major 9-tuples, so every function runs as Python on whole numpy columns (the numpy
backend) and compiles under numba when called from jitted code (:func:`relacc.kernels.jit.jitable`). The small ones
also come as twins inlined at numba's level (``cross_inline``, ``mm_inline``, ...: the same code): the tree kernels'
hot loops call those (non-inlined calls made cached code 45% slower there), the chain's kernels the plain ones
(inlining them made their first compilation 50% longer for no speed). Tests hold them to :mod:`relacc.core.so3` and
:mod:`relacc.core.rotations`.

* :func:`quat_matrix`, :func:`r123`: the active rotation of a unit quaternion ``(w, x, y, z)``, of 1-2-3 angles
  (``Rx Ry Rz`` from their cosines and sines);
* :func:`w123`, :func:`w123_mv`, :func:`w123_dot_mv`, :func:`w123_solve`: the 1-2-3 rate map ``W(theta)``
  (``omega = W theta_dot``, reference-frame components), its rate, products and inverse;
* :func:`exp_mul`: ``q (x) Exp(phi)`` (a quaternion moved by a body rotation vector); :func:`jr_inv`: the inverse
  right Jacobian ``J_r^-1(phi) w``, the rate of ``phi`` for body angular velocity ``w``;
* :func:`cross`, :func:`mm`, :func:`mv`, :func:`cross_cols`.
"""

from __future__ import annotations

import numpy as np

from relacc.kernels.jit import inline_twin, jitable


@jitable
def cross(a0, a1, a2, b0, b1, b2):
    return a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0


@jitable
def quat_matrix(w, x, y, z):
    """The active rotation (row-major 9-tuple) of a unit quaternion, scalar first."""
    return (1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
            2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
            2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y))


@jitable
def r123(c1, c2, c3, s1, s2, s3):
    """``Rx Ry Rz`` from the cosines and sines of the three angles."""
    return (c2 * c3, -c2 * s3, s2,
            c1 * s3 + s1 * s2 * c3, c1 * c3 - s1 * s2 * s3, -s1 * c2,
            s1 * s3 - c1 * s2 * c3, s1 * c3 + c1 * s2 * s3, c1 * c2)


@jitable
def mm(A, B):
    """``A B`` of row-major 9-tuples."""
    return (A[0] * B[0] + A[1] * B[3] + A[2] * B[6], A[0] * B[1] + A[1] * B[4] + A[2] * B[7],
            A[0] * B[2] + A[1] * B[5] + A[2] * B[8],
            A[3] * B[0] + A[4] * B[3] + A[5] * B[6], A[3] * B[1] + A[4] * B[4] + A[5] * B[7],
            A[3] * B[2] + A[4] * B[5] + A[5] * B[8],
            A[6] * B[0] + A[7] * B[3] + A[8] * B[6], A[6] * B[1] + A[7] * B[4] + A[8] * B[7],
            A[6] * B[2] + A[7] * B[5] + A[8] * B[8])


@jitable
def mv(A, x0, x1, x2):
    """``A x`` for a row-major 9-tuple ``A``."""
    return (A[0] * x0 + A[1] * x1 + A[2] * x2, A[3] * x0 + A[4] * x1 + A[5] * x2,
            A[6] * x0 + A[7] * x1 + A[8] * x2)


@jitable
def cross_cols(w0, w1, w2, A):
    """The matrix whose column j is ``w x A[:, j]``, row-major."""
    c0 = cross(w0, w1, w2, A[0], A[3], A[6])
    c1 = cross(w0, w1, w2, A[1], A[4], A[7])
    c2 = cross(w0, w1, w2, A[2], A[5], A[8])
    return (c0[0], c1[0], c2[0], c0[1], c1[1], c2[1], c0[2], c1[2], c2[2])


@jitable
def w123(c1, c2, s1, s2, d1, d2):
    """``W(theta)`` and ``W_dot(theta, theta_dot)``, row-major 9-tuples, from cosines and sines of theta1, theta2 and
    the rates ``d1``, ``d2`` of theta1, theta2."""
    z = 0.0 * c1
    W = (1.0 + z, z, s2, z, c1, -s1 * c2, z, s1, c1 * c2)
    Wd = (z, z, c2 * d2, z, -s1 * d1, -c1 * c2 * d1 + s1 * s2 * d2, z, c1 * d1, -s1 * c2 * d1 - c1 * s2 * d2)
    return W, Wd


@jitable
def w123_mv(c1, c2, s1, s2, x0, x1, x2):
    """``W(theta) x`` written out (W has a unit entry and three zeros)."""
    return x0 + s2 * x2, c1 * x1 - s1 * c2 * x2, s1 * x1 + c1 * c2 * x2


@jitable
def w123_dot_mv(c1, c2, s1, s2, d1, d2, x1, x2):
    """``W_dot(theta, theta_dot) x`` written out (its first column is zero, so x0 drops out)."""
    return (c2 * d2 * x2,
            -s1 * d1 * x1 + (-c1 * c2 * d1 + s1 * s2 * d2) * x2,
            c1 * d1 * x1 + (-s1 * c2 * d1 - c1 * s2 * d2) * x2)


@jitable
def w123_solve(c1, c2, s1, s2, b0, b1, b2):
    """``W(theta)^-1 b`` (``det W = cos theta2``: inf or NaN at gimbal lock, caught by the callers)."""
    x2 = (c1 * b2 - s1 * b1) / c2
    return b0 - s2 * x2, c1 * b1 + s1 * b2, x2


@jitable
def exp_mul(q, at, phi0, phi1, phi2, out):
    """``out[at:at+4] = q[at:at+4] (x) Exp(phi)`` for a unit quaternion (w, x, y, z) and a body rotation vector."""
    th2 = phi0 * phi0 + phi1 * phi1 + phi2 * phi2
    if th2 < 1e-8:  # series of cos(a/2) and sin(a/2)/a, exact to rounding below 1e-8
        w, k = 1 - th2 / 8 + th2 * th2 / 384, 0.5 - th2 / 48 + th2 * th2 / 3840
    else:
        th = np.sqrt(th2)
        w, k = np.cos(th / 2), np.sin(th / 2) / th
    x, y, z = k * phi0, k * phi1, k * phi2
    a, b, c, d = q[at], q[at + 1], q[at + 2], q[at + 3]
    out[at] = a * w - b * x - c * y - d * z
    out[at + 1] = a * x + b * w + c * z - d * y
    out[at + 2] = a * y - b * z + c * w + d * x
    out[at + 3] = a * z + b * y - c * x + d * w


@jitable
def jr_inv(phi0, phi1, phi2, w0, w1, w2):
    """``J_r^-1(phi) w`` (:func:`relacc.core.so3.jr_inv`): ``w + 1/2 phi x w + beta phi x (phi x w)``."""
    th2 = phi0 * phi0 + phi1 * phi1 + phi2 * phi2
    if th2 < 1e-4:
        beta = 1 / 12 + th2 / 720 + th2 * th2 / 30240
    else:
        th = np.sqrt(th2)
        beta = 1 / th2 - (1 + np.cos(th)) / (2 * th * np.sin(th))
    c = cross(phi0, phi1, phi2, w0, w1, w2)
    cc = cross(phi0, phi1, phi2, c[0], c[1], c[2])
    return w0 + 0.5 * c[0] + beta * cc[0], w1 + 0.5 * c[1] + beta * cc[1], w2 + 0.5 * c[2] + beta * cc[2]


cross_inline, mm_inline, mv_inline, quat_matrix_inline, r123_inline = (
    inline_twin(f) for f in (cross, mm, mv, quat_matrix, r123))
