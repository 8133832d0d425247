"""The three choices of generalized speeds, their coordinate layouts and input checks.

=====  ===========================================  =============================================
case   q (generalized coordinates)                  u (generalized speeds, 12)
=====  ===========================================  =============================================
1      ``[s1, quat_B1, s2', quat_B2/B1]`` (14)      ``[s1_dot, omega_B1, s2'_dot, omega_hat_B2]``
2      ``[s1, quat_B1, s2', quat_B2/B1]`` (14)      ``[s1_dot, omega'_B1, s2'_dot, omega_hat'_B2]``
3      ``[s1, theta_B1, s2', theta_B2]`` (12)       ``[s1_dot, theta_B1_dot, s2'_dot, theta_B2_dot]``
=====  ===========================================  =============================================

``s1``, ``s1_dot``: B1's origin, fixed components (m, m/s). ``s2'``, ``s2'_dot``:
offset of B2's joint point from ``q2'``, B1 components. ``omega_B1``: angular
velocity of B1 in the fixed frame R, fixed components; ``omega'_B1`` the same
vector in B1 components. ``omega_hat_B2``: angular velocity of B2 in B1, B1
components; ``omega_hat'_B2`` the same vector in B2 components (rad/s).
"""

from __future__ import annotations

import contextlib
import contextvars
import enum
import math
from dataclasses import dataclass

import numpy as np

from relacc.core.tolerances import QUATERNION_NORM_TOLERANCE
from relacc.errors import CaseError, InputError


class Case(enum.IntEnum):
    """Choice of generalized speeds, numbered as in the note."""

    FIXED_FRAME = 1
    """Fixed-frame angular velocity components (note's Case 1)."""
    BODY_FRAME = 2
    """Body-frame angular velocity components (note's Case 2)."""
    ANGLE_RATES = 3
    """1-2-3 orientation angle rates (note's Case 3)."""


def as_case(case) -> Case:
    """Convert ``1``, ``2``, ``3`` or a :class:`Case` to a :class:`Case`.

    Raises:
        CaseError: for anything else.
    """
    if isinstance(case, bool) or not isinstance(case, (int, np.integer, Case)):
        raise CaseError(f"unknown case {case!r}: accepted cases are 1, 2 and 3 (or relacc.Case)")
    try:
        return Case(int(case))
    except ValueError:
        raise CaseError(
            f"unknown case {case!r}: accepted cases are 1, 2 and 3 (or relacc.Case)"
        ) from None


@dataclass(frozen=True)
class Layout:
    """Where each named block sits in a case's ``q``; ``u`` is the same for all cases."""

    nq: int
    s1: slice
    B1: slice  # quat_B1 (4) or theta_B1 (3)
    s2_p: slice
    B2: slice  # quat_B2/B1 (4) or theta_B2 (3)
    quaternions: bool


_QUAT = Layout(14, slice(0, 3), slice(3, 7), slice(7, 10), slice(10, 14), True)
_ANGLES = Layout(12, slice(0, 3), slice(3, 6), slice(6, 9), slice(9, 12), False)

NU = 12
"""Number of generalized speeds in every case."""

U_BLOCKS = {"s1_dot": slice(0, 3), "B1": slice(3, 6), "s2_p_dot": slice(6, 9), "B2": slice(9, 12)}
"""Slices of the four 3-blocks of ``u`` (and ``udot``) in the note's order."""


def layout(case) -> Layout:
    """The coordinate layout of ``q`` for a case."""
    return _ANGLES if as_case(case) is Case.ANGLE_RATES else _QUAT


def _holds_bool(value) -> bool:
    """Whether nested lists or tuples hold a Python or numpy boolean (numpy would turn it into 0 or 1)."""
    stack = [value]
    while stack:
        item = stack.pop()
        if isinstance(item, (bool, np.bool_)):
            return True
        if isinstance(item, (list, tuple)):
            stack.extend(item)
    return False


def as_numbers(name: str, value, length: int, what, values: bool = True, offset: int = 0) -> np.ndarray:
    """``value`` as an array of numbers ``(..., length)``: lists and arrays alike, integers made float.

    ``what`` (what is accepted, for messages) is a string or a function returning one, called only for a message.

    Booleans, strings and objects are rejected; with ``values`` so are NaN and inf.
    ``offset`` is added to the leading batch index in messages (a chunk's
    position in a longer batch).

    Raises:
        InputError: naming ``name``, what was wrong and ``what`` is accepted.
    """
    if (isinstance(value, np.ndarray) and value.dtype == np.float64 and value.ndim and value.shape[-1] == length
            and (not values or np.isfinite(value).all())):
        return value  # the common case, without building a message
    if callable(what):
        what = what()
    if isinstance(value, (list, tuple)) and _holds_bool(value):
        raise InputError(f"{name}: expected numbers ({what}), got a boolean in {value!r:.80}")
    try:
        arr = np.asarray(value)
    except Exception as exc:  # ragged lists and the like
        raise InputError(f"{name}: cannot be read as an array ({exc}); expected {what}") from None
    if arr.dtype.kind not in "iufc":
        raise InputError(f"{name}: expected numbers ({what}), got dtype {arr.dtype}")
    if arr.ndim == 0 or arr.shape[-1] != length:
        raise InputError(f"{name}: expected shape (..., {length}) ({what}), got shape {arr.shape}")
    if arr.dtype.kind in "iu":
        arr = arr.astype(np.float64)
    if values and not np.all(np.isfinite(arr)):
        bad = np.argwhere(~np.isfinite(arr))[0]
        at = tuple(int(i) + (offset if k == 0 and arr.ndim > 1 else 0) for k, i in enumerate(bad))
        raise InputError(
            f"{name}: non-finite value {arr[tuple(bad)]} at index {at}; "
            "every entry must be a finite number"
        )
    return arr


_COMPLEX_STEP_POINTS = contextvars.ContextVar("relacc_complex_step_points", default=False)


def fixed_vector(owner: str, name: str, value, n: int = 3) -> np.ndarray:
    """``value`` as a read-only float ``(n,)`` of finite numbers: a model's or an effect's fixed vector (a position,
    an axis, a quaternion, gravity), as given, never normalized.

    Raises:
        InputError: naming ``owner`` and ``name``, what was given and what is accepted.
    """
    try:
        kind = np.asarray(value).dtype.kind
        arr = np.array(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError(f"{owner}: {name} must be {n} real numbers, got {value!r:.80}") from None
    if kind not in "iuf":  # strings, booleans, objects: not numbers, even where numpy would convert them
        raise InputError(f"{owner}: {name} must be {n} real numbers, got {np.asarray(value).tolist()!r:.80}")
    if arr.shape != (n,) or not np.all(np.isfinite(arr)):
        raise InputError(f"{owner}: {name} must be {n} finite numbers, got {np.asarray(value).tolist()!r:.80}")
    arr.setflags(write=False)
    return arr


@contextlib.contextmanager
def complex_step_points():
    """Inside the block, complex quaternions are judged as points of a complex step: by ``q . q = 1``.

    A complex step evaluates a formula at ``q(i h)``, the analytic
    continuation of a path of unit quaternions: there ``q . q = 1`` holds
    exactly while ``|q|^2 = 1 + O(h^2)``. Only relacc's own complex-step
    derivatives (:mod:`relacc.core.derivatives`) open this block; everywhere
    else a complex quaternion is judged by its true size, ``|q|^2``.
    """
    token = _COMPLEX_STEP_POINTS.set(True)
    try:
        yield
    finally:
        _COMPLEX_STEP_POINTS.reset(token)


def quaternion_norm_deviation(quat) -> np.ndarray:
    """``| |q|^2 - 1 |`` per quaternion ``(..., 4)``, ``|q|^2 = sum |q_i|^2`` (also for complex ``q``).

    Inside :func:`complex_step_points`, complex quaternions are judged by
    ``|q . q - 1|`` instead. Overflow gives ``inf``, not a warning.
    """
    with np.errstate(over="ignore", invalid="ignore"):
        if np.iscomplexobj(quat) and _COMPLEX_STEP_POINTS.get():
            return np.abs(np.einsum("...i,...i->...", quat, quat) - 1)
        return np.abs(np.sum(np.real(quat) ** 2 + np.imag(quat) ** 2, axis=-1) - 1)


def check_q(case, q, values: bool = True, offset: int = 0) -> np.ndarray:
    """Validate a case's coordinates; return them as a float (or complex) array.

    Quaternions must be unit to ``QUATERNION_NORM_TOLERANCE``; they are never
    normalized here. With ``values=False`` only the type and shape are
    checked (the fused kernels check the values themselves, see
    :mod:`relacc.kernels.kinematics`, and call back here to report what they find).

    ``offset`` shifts the leading batch index in messages (see :func:`as_numbers`).

    Raises:
        InputError: wrong length, non-finite entries or non-unit quaternions.
    """
    c = as_case(case)
    lay = layout(c)
    what = (
        "[s1 (3), quat_B1 (4, w first), s2' (3), quat_B2/B1 (4, w first)]"
        if lay.quaternions
        else "[s1 (3), theta_B1 (3), s2' (3), theta_B2 (3)]"
    )
    arr = as_numbers(f"q for case {int(c)}", q, lay.nq, what, values, offset)
    if values and lay.quaternions:
        for label, sl in (("quat_B1", lay.B1), ("quat_B2/B1", lay.B2)):
            dev = quaternion_norm_deviation(arr[..., sl])
            if np.any(dev > QUATERNION_NORM_TOLERANCE):
                idx = np.unravel_index(np.argmax(dev), dev.shape) if dev.ndim else ()
                at = f" at batch index {tuple(int(i) + (offset if k == 0 else 0) for k, i in enumerate(idx))}" \
                    if idx else ""
                with np.errstate(over="ignore", invalid="ignore"):
                    norm2 = float(np.sum(np.abs(arr[..., sl][idx]) ** 2))
                raise InputError(
                    f"q for case {int(c)}: {label}{at} has squared norm "
                    f"{norm2:.17g}, off 1 by "
                    f"{float(dev[idx]):.3g} > {QUATERNION_NORM_TOLERANCE:g}; pass unit "
                    "quaternions (w, x, y, z): relacc does not normalize them"
                )
    return arr


def check_u(name: str, u, values: bool = True, offset: int = 0) -> np.ndarray:
    """Validate generalized speeds (or their derivatives), shape ``(..., 12)``.

    Raises:
        InputError: wrong length or (with ``values``) non-finite entries.
    """
    return as_numbers(name, u, NU, "[s1 (3), B1 angular (3), s2' (3), B2 angular (3)] rates", values, offset)


def check_int(name: str, value, minimum: int | None = None) -> int:
    """Validate an integer argument (a count or a seed).

    Raises:
        InputError: not an integer, or below ``minimum``.
    """
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise InputError(f"{name}: expected an integer, got {value!r}")
    if minimum is not None and value < minimum:
        raise InputError(f"{name}: must be at least {minimum}, got {value}")
    return int(value)


def batch_rows(a, batch: tuple[int, ...], width: int, dtype=None) -> np.ndarray:
    """``a`` broadcast to ``batch + (width,)`` as a C-contiguous ``(n, width)`` array (of ``dtype`` if given): a view
    where ``a`` already is one (the kernels only read their inputs), else a copy."""
    n = math.prod(batch)  # explicit: a width of 0 (a tree where nothing moves) leaves -1 undefined
    if (isinstance(a, np.ndarray) and a.shape == batch + (width,) and a.flags.c_contiguous
            and (dtype is None or a.dtype == dtype)):
        return a.reshape(n, width)
    return np.ascontiguousarray(np.broadcast_to(a, batch + (width,)).reshape(n, width), dtype=dtype)
