"""Time derivatives along the motion, by methods whose error is known.

The configuration is moved on its manifold, never by adding to quaternion
components: :func:`advance` follows the motion with the case's speeds held
fixed, using the exponential map for the quaternions. The path is analytic
in time, so it accepts a complex time and supports the complex step.

A derivative of ``f`` along the motion is ``d/dt f(advance(q, u, t), u + t udot)``
at ``t = 0``. Only the path's first derivative matters, so holding the speeds'
rates fixed over the step is exact for this purpose.
"""

from __future__ import annotations

import numpy as np

from relacc.core.cases import Case, as_case, check_q, check_u, complex_step_points, layout
from relacc.core.rotations import quaternion_exp, quaternion_multiply
from relacc.core.tolerances import COMPLEX_STEP
from relacc.errors import InputError


def advance(case, q, u, t):
    """Coordinates reached from ``q`` after time ``t`` moving with the speeds ``u``.

    * ``s1 += t s1_dot``, ``s2' += t s2'_dot``;
    * case 1: ``quat_B1 <- exp(t omega_B1) (x) quat_B1`` (fixed components act on
      the left), ``quat_B2/B1 <- exp(t omega_hat_B2) (x) quat_B2/B1`` (B1 components);
    * case 2: ``quat_B1 <- quat_B1 (x) exp(t omega'_B1)`` (body components act on
      the right), ``quat_B2/B1 <- quat_B2/B1 (x) exp(t omega_hat'_B2)``;
    * case 3: ``theta += t theta_dot``.

    The quaternions stay unit (also for complex ``t``, where ``q . q = 1``
    analytically).

    Args:
        case: 1, 2 or 3.
        q: ``(..., 14)`` or ``(..., 12)`` coordinates.
        u: ``(..., 12)`` speeds.
        t: time step (s), real or complex scalar.

    Returns:
        Coordinates of the same layout, ``(..., nq)``; complex if ``t`` is.
    """
    c = as_case(case)
    lay = layout(c)
    q = check_q(c, q)
    u = check_u("u", u)
    if not isinstance(t, (int, float, complex, np.number)) or isinstance(t, bool) or not np.isfinite(t):
        raise InputError(f"t: expected a finite real or complex time step in seconds, got {t!r}")
    batch = np.broadcast_shapes(q.shape[:-1], u.shape[:-1])
    q = np.broadcast_to(q, batch + q.shape[-1:])
    u = np.broadcast_to(u, batch + (12,))
    out = np.array(q, dtype=np.result_type(q, u, t), copy=True)
    out[..., lay.s1] = q[..., lay.s1] + t * u[..., 0:3]
    out[..., lay.s2_p] = q[..., lay.s2_p] + t * u[..., 6:9]
    if c is Case.ANGLE_RATES:
        out[..., lay.B1] = q[..., lay.B1] + t * u[..., 3:6]
        out[..., lay.B2] = q[..., lay.B2] + t * u[..., 9:12]
    elif c is Case.FIXED_FRAME:
        out[..., lay.B1] = quaternion_multiply(quaternion_exp(t * u[..., 3:6]), q[..., lay.B1])
        out[..., lay.B2] = quaternion_multiply(quaternion_exp(t * u[..., 9:12]), q[..., lay.B2])
    else:
        out[..., lay.B1] = quaternion_multiply(q[..., lay.B1], quaternion_exp(t * u[..., 3:6]))
        out[..., lay.B2] = quaternion_multiply(q[..., lay.B2], quaternion_exp(t * u[..., 9:12]))
    return out


def complex_step(f, h: float = COMPLEX_STEP):
    """``Im f(i h) / h``: the derivative at 0 of an analytic, real-on-reals ``f``.

    ``f`` is evaluated inside :func:`relacc.core.cases.complex_step_points`,
    so the complexified quaternions of the path are accepted.

    Truncation error ``h^2 |f'''| / 6``; no cancellation, so exact to rounding
    for the default ``h = 1e-20``.
    """
    with complex_step_points():
        return np.imag(f(1j * h)) / h


def central_difference(f, h: float):
    """``(f(h) - f(-h)) / 2h``; truncation ``h^2 |f'''| / 6``, rounding ``~eps |f| / h``."""
    return (f(h) - f(-h)) / (2 * h)


def richardson(f, h: float):
    """Richardson extrapolation of two central differences: ``(4 D(h/2) - D(h)) / 3``.

    Truncation ``O(h^4)``: ``h^4 |f^(5)| / 480``; rounding about ``1.5 eps |f| / h``.
    """
    return (4 * central_difference(f, h / 2) - central_difference(f, h)) / 3


def along_motion(case, q, u, udot, function, method="complex", h=None):
    """``d/dt function(advance(q, u, t), u + t udot)`` at ``t = 0``.

    Args:
        function: ``(q, u) -> array``; must accept complex input for the
            complex step.
        method: ``"complex"`` (default, exact to rounding), ``"central"`` or
            ``"richardson"``.
        h: step (s); defaults to ``COMPLEX_STEP`` for complex, else required.
    """
    udot = np.zeros_like(np.asarray(u, dtype=float)) if udot is None else np.asarray(udot)
    g = lambda t: function(advance(case, q, u, t), np.asarray(u) + t * udot)  # noqa: E731
    if method == "complex":
        return complex_step(g, COMPLEX_STEP if h is None else h)
    if h is None:
        raise InputError("a real-step derivative needs an explicit step h (seconds)")
    if method == "central":
        return central_difference(g, h)
    if method == "richardson":
        return richardson(g, h)
    raise InputError(f"unknown derivative method {method!r}: accepted are 'complex', 'central', 'richardson'")
