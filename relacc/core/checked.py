"""The building blocks that ``relacc`` exports, with the input checks of :func:`relacc.g2_kinematics`.

:mod:`relacc.core.rotations` holds the bare functions, which relacc itself
calls on inputs it has already checked (complex-step perturbations
included). The versions here check first: numbers only (lists welcome,
booleans and strings not), the right trailing shape, finite values, and unit
quaternions to :data:`relacc.core.tolerances.QUATERNION_NORM_TOLERANCE`
(never normalized). Complex inputs are accepted, as by the core.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from relacc.core import rotations
from relacc.core.cases import as_numbers, quaternion_norm_deviation
from relacc.core.tolerances import QUATERNION_NORM_TOLERANCE
from relacc.errors import InputError
from relacc.limits import require_memory

WORK = 64
"""Floats of output and temporaries per input row that the building blocks need at most (a 3x3 matrix and its
intermediate products): the budget checked against the memory available before any work."""


def _numbers(name, value, length, what):
    """``as_numbers`` in the order that allocates nothing large unchecked: shape, then cost, then values."""
    arr = as_numbers(name, value, length, what, values=False)
    rows = arr.size // length
    require_memory(8.0 * WORK * rows, f"{name}: {rows} rows", "pass fewer at a time")
    return as_numbers(name, arr, length, what)


def _unit_quaternion(name, value):
    quat = _numbers(name, value, 4, "unit quaternions (w, x, y, z)")
    dev = quaternion_norm_deviation(quat)
    if np.any(dev > QUATERNION_NORM_TOLERANCE):
        idx = np.unravel_index(np.argmax(dev), dev.shape) if dev.ndim else ()
        at = f" at batch index {tuple(int(i) for i in idx)}" if idx else ""
        raise InputError(f"{name}{at}: squared norm off 1 by {float(dev[idx]):.3g} > {QUATERNION_NORM_TOLERANCE:g}; "
                         "pass unit quaternions (w, x, y, z): relacc does not normalize them")
    return quat


def _broadcast(name, *arrays):
    try:
        batch = np.broadcast_shapes(*(a.shape[:-1] for a in arrays))
    except ValueError:
        raise InputError(f"{name}: batch shapes {[a.shape[:-1] for a in arrays]} do not broadcast") from None
    rows = float(np.prod(batch, dtype=float))
    require_memory(8.0 * WORK * rows, f"{name}: {int(rows)} rows, broadcast", "pass fewer at a time")


def tilde(v: ArrayLike) -> np.ndarray:
    """Skew-symmetric ``[v~]`` ``(..., 3, 3)`` of ``v`` ``(..., 3)`` (:func:`relacc.core.rotations.tilde`), checked."""
    return rotations.tilde(_numbers("v", v, 3, "3-vectors"))


def matrix_from_quaternion(quat: ArrayLike) -> np.ndarray:
    """Rotation matrix ``(..., 3, 3)`` of a unit quaternion ``(..., 4)``, w first, checked.

    For ``quat_B1`` this is ``[R_B1]^T`` (B1 -> fixed components), dimensionless.
    """
    return rotations.matrix_from_quaternion(_unit_quaternion("quat", quat))


def matrix_from_123(theta: ArrayLike) -> np.ndarray:
    """``Rx(theta1) Ry(theta2) Rz(theta3)`` ``(..., 3, 3)`` of 1-2-3 angles ``(..., 3)`` in rad, checked."""
    return rotations.matrix_from_123(_numbers("theta", theta, 3, "1-2-3 angles in rad"))


def omega_partials_123(theta: ArrayLike) -> np.ndarray:
    """``[omega_{B,theta_dot}]`` ``(..., 3, 3)`` of 1-2-3 angles ``(..., 3)`` (rad), checked.

    Maps angle rates to the angular velocity in the reference frame's components.
    """
    return rotations.omega_partials_123(_numbers("theta", theta, 3, "1-2-3 angles in rad"))


def omega_partials_123_dot(theta: ArrayLike, theta_dot: ArrayLike) -> np.ndarray:
    """Time derivative ``(..., 3, 3)`` (1/s) of :func:`omega_partials_123`, checked."""
    theta = _numbers("theta", theta, 3, "1-2-3 angles in rad")
    theta_dot = _numbers("theta_dot", theta_dot, 3, "1-2-3 angle rates in rad/s")
    _broadcast("theta, theta_dot", theta, theta_dot)
    return rotations.omega_partials_123_dot(theta, theta_dot)


def quaternion_exp(phi: ArrayLike) -> np.ndarray:
    """Unit quaternion ``(..., 4)`` (w first) of the rotation vector ``phi`` ``(..., 3)`` in rad, checked."""
    return rotations.quaternion_exp(_numbers("phi", phi, 3, "rotation vectors in rad"))


def quaternion_from_123(theta: ArrayLike) -> np.ndarray:
    """Unit quaternion ``(..., 4)`` (w first) of ``Rx Ry Rz`` for 1-2-3 angles ``(..., 3)`` in rad, checked."""
    return rotations.quaternion_from_123(_numbers("theta", theta, 3, "1-2-3 angles in rad"))


def quaternion_multiply(p: ArrayLike, q: ArrayLike) -> np.ndarray:
    """Hamilton product ``p (x) q`` ``(..., 4)`` of unit quaternions (w first), checked."""
    p, q = _unit_quaternion("p", p), _unit_quaternion("q", q)
    _broadcast("p, q", p, q)
    return rotations.quaternion_multiply(p, q)
