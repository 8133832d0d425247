"""The one error model of relacc: every tolerance in the project comes from here.

A computed quantity ``x`` is compared with a reference ``x_ref`` through its
*normalized error*

    err = max_i |x_i - x_ref_i| / scale,

where ``scale`` is the magnitude of the terms that are summed to form ``x``
(:func:`term_scales`). Two float64 evaluations of the same sum of products
differ by at most ``k * eps * scale`` where ``k`` is the number of dependent
roundings along the longest chain of operations. The comparison passes when

    err <= ROUNDING_FACTOR * eps + truncation,

with ``truncation`` the derivative method's own error, zero for exact methods.

``ROUNDING_FACTOR`` (c = 64) covers the longest chain in the formulas: a
quaternion -> matrix (4 roundings), a product of three 3x3 matrices (2 x 3
roundings each), a 3x3 times a vector (3), and a 12-term sum (12 in the worst
order), about 30 in all, doubled for the reference's own rounding. The
observed worst cases are written in ``docs/error-model.md``. ``c * eps`` is
1.4e-14, well inside the project's 1e-12 target.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

EPS = float(np.finfo(np.float64).eps)
"""Machine epsilon of float64, 2.22e-16."""

ROUNDING_FACTOR = 64
"""c: bound on the dependent roundings of one evaluation plus its reference."""

TARGET = 1e-12
"""Project target for normalized agreement; ``ROUNDING_FACTOR * EPS`` must stay below it."""

QUATERNION_NORM_TOLERANCE = 1e-12
"""Largest accepted ``|w^2 + x^2 + y^2 + z^2 - 1|``; relacc never normalizes.

A deviation ``d`` perturbs every vector rotated by the quaternion by at most
``d`` relative to its length, so accepted quaternions keep results within the
1e-12 target.
"""

MAX_CONDITION = 1e8
"""Largest condition number of the case-3 inverse speed map relacc accepts.

Mapping angular velocities back to 1-2-3 rates amplifies relative errors by
the condition number of ``W(theta)``, ``(1 + |sin theta2|) / |cos theta2|``; at
1e8 the rates carry relative errors up to about 1e8 eps = 2e-8. Beyond it
(within about 2e-8 rad of gimbal lock) relacc raises instead of answering.
"""

TRIG_ULPS = 2
"""Largest difference, in ulps of the result, between :func:`relacc.trig.sincos` and libm's ``sin``/``cos``.

Each is within 1 ulp of the exact value (fdlibm's bound for the former; the
platform libm's documented bound, glibc's here, for the latter), so they
differ by at most 2 ulps. The fused kernels' case-3 results therefore differ
from the reference's by a few more roundings than the factor-8 agreement of
``tests/test_fast.py`` already allows for: a sine or cosine enters each term
through at most three factors.
"""

COMPLEX_STEP = 1e-20
"""Step ``h`` of the complex-step derivative ``Im f(x + i h) / h``.

Its truncation error is ``h^2 |f'''| / 6``, below 1e-40 relative here; it has no
subtractive cancellation, so the derivative is exact to rounding.
"""


def rounding_tolerance(factor: float = ROUNDING_FACTOR) -> float:
    """Tolerance on a normalized error that comes from rounding only: ``factor * eps``."""
    return factor * EPS


def richardson_bound(h: float, fifth_derivative_scale, value_scale):
    """Error bound of Richardson extrapolation of central differences, ``(4 D(h/2) - D(h)) / 3``.

    Truncation ``h^4 |f^(5)| / 480`` plus rounding ``1.5 eps |f| / h`` (the
    differences amplify each value's rounding by ``1/h``); scales may be arrays.
    """
    return h**4 / 480 * fifth_derivative_scale + 1.5 * EPS / h * value_scale


def normalized_error(x, ref, scale):
    """``max |x - ref| / scale`` over the trailing (vector or matrix) axes.

    Args:
        x, ref: arrays of equal shape ``(..., 3)`` or ``(..., 3, 12)``.
        scale: ``(...)`` magnitude of the terms (same units as ``x``).

    Returns:
        ``(...)`` dimensionless normalized error; ``0`` where ``x == ref``
        exactly, even if ``scale`` is zero.
    """
    x, ref, scale = np.asarray(x), np.asarray(ref), np.asarray(scale, dtype=float)
    diff = np.abs(x - ref)
    extra = diff.ndim - scale.ndim
    diff = diff.reshape(diff.shape[: diff.ndim - extra] + (-1,)).max(axis=-1)
    tiny = np.finfo(np.float64).tiny
    return np.where(diff == 0, 0.0, diff / np.maximum(scale, tiny))


@dataclass(frozen=True)
class TermScales:
    """Magnitude of the terms summed in each quantity, one value per state.

    Every field has the leading batch shape of the state. Units: ``position``
    m, ``velocity`` m/s, ``acceleration`` m/s^2, ``V`` m per unit speed
    (1 or m), ``Vdot`` the same per second.
    """

    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    V: np.ndarray
    Vdot: np.ndarray

    def of(self, quantity: str) -> np.ndarray:
        """The scale of one quantity by name (``"position"``, ..., ``"Vdot"``)."""
        return getattr(self, quantity)


def lever_sensitivity(quantity: str, case, q, u, udot=None):
    """How much a quantity changes per metre of error in a lever arm, one value per state.

    ``1`` for position and V, ``W`` for velocity and Vdot, ``A + W^2`` for the
    acceleration (``W``, ``A`` as in :func:`term_scales`): a point misplaced
    by ``d`` metres on a body moves the quantity by at most ``d`` times this.
    """
    u = np.asarray(u)
    n = lambda a: np.linalg.norm(np.real(a), axis=-1)  # noqa: E731
    w = n(u[..., 3:6]) + n(u[..., 9:12])
    if quantity in ("position", "V"):
        return np.ones_like(w)
    if quantity in ("velocity", "Vdot"):
        return w
    alpha = 0.0 if udot is None else n(np.asarray(udot)[..., 3:6]) + n(np.asarray(udot)[..., 9:12])
    return alpha + w * w


def per_metre_of_lever(quantity: str, chain, case, q, u, udot=None):
    """Normalized change of a quantity per metre of lever-arm error, one value per state (1/m).

    ``lever_sensitivity / scale``, the scale from :func:`term_scales`.
    """
    sc = term_scales(chain, case, q, u, udot).of(quantity)
    return lever_sensitivity(quantity, case, q, u, udot) / np.maximum(sc, np.finfo(np.float64).tiny)


def global_condition(quantity: str, chain, case, q, u, udot=None):
    """Condition of a quantity computed in global coordinates, one value per state.

    An engine that forms lever arms as differences of world positions
    (MuJoCo's Jacobians and accelerations; Pinocchio's world-frame Jacobians)
    loses about ``eps |s1|`` in every lever arm, so relative to the terms'
    magnitude the condition is

        1 + |s1| lever_sensitivity / scale.

    Position is a sum whose scale already contains ``|s1|``: condition 1.

    Returns:
        ``(...)`` array >= 1.
    """
    ratio = per_metre_of_lever(quantity, chain, case, q, u, udot)
    if quantity == "position":
        return np.ones_like(ratio)
    from relacc.cases import layout

    s1 = np.linalg.norm(np.real(np.asarray(q)[..., layout(case).s1]), axis=-1)
    return 1 + s1 * ratio


def offset_error(lost: float, quantity: str, chain, case, q, u, udot=None):
    """Normalized error of a model that puts G2 ``lost`` metres off (an engine's compile-time rounding).

    ``lost * lever_sensitivity / scale``, one value per state; 0 when nothing is lost.
    """
    return lost * per_metre_of_lever(quantity, chain, case, q, u, udot)


def term_scales(chain, case, q, u, udot=None) -> TermScales:
    """Magnitudes of the terms of position, velocity, acceleration, V and Vdot.

    With ``l = |q2'| + |s2'| + |r2'|`` (lever from B1's origin to G2),
    ``W = |u_ang1| + |u_ang2|`` (angular speeds; the 1-2-3 partial matrices
    have unit columns, so their norm is at most sqrt(3), absorbed in c),
    ``A = |udot_ang1| + |udot_ang2|``:

    * position: ``|s1| + l``
    * V: ``1 + l``
    * velocity: ``|s1_dot| + |s2'_dot| + l W``
    * Vdot: ``W (1 + l) + |s2'_dot|``
    * acceleration: ``|s1_ddot| + |s2'_ddot| + l A + W (W l + 2 |s2'_dot|)``

    Args:
        chain: :class:`relacc.TwoBodyChain`.
        case: 1, 2 or 3.
        q: ``(..., 14)`` or ``(..., 12)`` coordinates of the case.
        u: ``(..., 12)`` speeds of the case.
        udot: ``(..., 12)`` speed derivatives, or None (acceleration scale 0).
    """
    from relacc.cases import layout  # local: cases imports this module

    lay = layout(case)
    q, u = np.asarray(q), np.asarray(u)
    n = lambda a: np.linalg.norm(np.real(a), axis=-1)  # noqa: E731
    lever = n(chain.q2) + n(q[..., lay.s2_p]) + n(chain.r2)
    s1 = n(q[..., lay.s1])
    sd1, sd2 = n(u[..., 0:3]), n(u[..., 6:9])
    w = n(u[..., 3:6]) + n(u[..., 9:12])
    if udot is None:
        acc = np.zeros_like(w)
    else:
        udot = np.asarray(udot)
        sdd = n(udot[..., 0:3]) + n(udot[..., 6:9])
        alpha = n(udot[..., 3:6]) + n(udot[..., 9:12])
        acc = sdd + lever * alpha + w * (w * lever + 2 * sd2)
    shape = np.broadcast_shapes(lever.shape, w.shape)
    b = lambda a: np.broadcast_to(a, shape)  # noqa: E731
    return TermScales(
        position=b(s1 + lever),
        velocity=b(sd1 + sd2 + lever * w),
        acceleration=b(acc),
        V=b(1 + lever),
        Vdot=b(w * (1 + lever) + sd2),
    )


def assert_agree(x, ref, scale, *, what: str, seed=None, factor: float = ROUNDING_FACTOR, truncation: float = 0.0):
    """Assert ``normalized_error(x, ref, scale) <= factor * eps + truncation`` everywhere.

    On failure the message names the quantity, the worst state's batch index,
    the error in units of eps, the tolerance and the seed.

    Returns:
        The ``(...)`` array of normalized errors, for reporting.
    """
    err = np.asarray(normalized_error(x, ref, scale))
    tol = factor * EPS + truncation
    if not np.all(err <= tol):
        idx = np.unravel_index(np.argmax(np.where(np.isnan(err), np.inf, err)), err.shape) if err.ndim else ()
        raise AssertionError(
            f"{what}: normalized error {float(err[idx]):.3g} ({float(err[idx]) / EPS:.1f} eps) > "
            f"tolerance {tol:.3g} at state {tuple(int(i) for i in idx)} (seed {seed})"
        )
    return err


def dynamics_scales(chain, case, q, u, effects=None):
    """Magnitudes of the terms of Kane's ``M`` and ``f``, one value per state.

    With ``m = m1 + m2``, ``J = |I1| + |I2|`` (Frobenius), ``l``, ``W`` as in
    :func:`term_scales` and ``l1 = |r1'|``:

    * ``M``: ``m (1 + l + l1)^2 + J`` (kg m^2; the translational blocks are smaller);
    * ``f``: ``m (1 + l + l1) (W^2 (l + l1) + 2 W |s2'_dot| + |g|) + J W^2`` plus
      every active effect's size (``|K| |s2' - rest| + |C| |s2'_dot| + c W
      + |F| (1 + l) + |T1| + |T2|``).
    """
    from relacc.cases import layout

    sc = term_scales(chain, case, q, u)
    q, u = np.asarray(q), np.asarray(u)
    n = lambda a: np.linalg.norm(np.real(a), axis=-1)  # noqa: E731
    lever = sc.V - 1 + np.linalg.norm(chain.r1)
    w = n(u[..., 3:6]) + n(u[..., 9:12])
    sd = n(u[..., 6:9])
    m = chain.m1 + chain.m2
    J = np.linalg.norm(chain.I1) + np.linalg.norm(chain.I2)
    M = m * (1 + lever) ** 2 + J
    g = 0.0
    extra = 0.0
    if effects is not None:
        s2 = q[..., layout(case).s2_p]
        if effects.gravity is not None:
            g = np.linalg.norm(effects.gravity)
        if effects.spring_stiffness is not None:
            extra = extra + n(effects.spring_stiffness) * n(s2 - effects.spring_rest)
        if effects.spring_damping is not None:
            extra = extra + n(effects.spring_damping) * sd
        if effects.ball_damping is not None:
            extra = extra + effects.ball_damping * w
        if effects.force_G2 is not None:
            extra = extra + n(effects.force_G2) * (1 + lever)
        for T in (effects.torque_B1, effects.torque_B2):
            if T is not None:
                extra = extra + n(T)
    f = m * (1 + lever) * (w * w * lever + 2 * w * sd + g) + J * w * w + extra
    return M, f
