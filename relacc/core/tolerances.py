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
1e8 the rates carry relative errors up to about 1e8 eps = 2e-8, and their accelerations that times the mass
matrix's condition number in case-2 speeds (forward dynamics in case 3 is solved in case-2 speeds and mapped, so
the condition number enters once, not squared). Beyond it
(within about 2e-8 rad of gimbal lock) relacc raises instead of answering.
"""

CONDITION_WARNING = 1e6
"""Condition number of a case-3 rate map above which an answer in 1-2-3 rates comes with a
:class:`relacc.AccuracyWarning` naming the joint, its ``theta2``, the distance to the lock and the error to expect.

Rates from angular velocities lose ``log10(cond)`` digits (relative errors up to about ``cond eps``, times the mass
matrix's condition number for accelerations, :func:`relacc.tree_accelerations`); above 1e6, ten or fewer of the
sixteen remain. Between this and :data:`MAX_CONDITION` relacc answers and warns; above, it raises.
"""

PIVOT_FLOOR = ROUNDING_FACTOR * EPS
"""Smallest accepted ratio of a pivot of the mass matrix's factorization (any elimination order: the compiled kernels'
``L^T D L`` and articulated-body pivots, numpy's Cholesky) to the matrix's scale at that speed: its diagonal entry
before elimination plus the mean of the diagonal entries (the articulated-body kernels: of those met so far, over
the number of speeds).

``lambda_min(M) <= d_k`` and both the diagonal entry and the mean are at most ``lambda_max(M)``, so a ratio below
the floor proves ``kappa(M) > 1 / (2 c eps)``: the accelerations' bound ``c eps kappa(M)``
(:mod:`relacc.validation.robots.agreement`) then exceeds 1/2, and no digit of them is certain. Such a matrix is
singular to working precision (two ball joints on one body, a speed that moves no inertia): relacc raises
:class:`relacc.SingularityError` naming the speeds instead of answering. The mean is what catches a speed whose own
diagonal entry is nothing but rounding residue: a point mass on a ball joint, turning about its lever, has a diagonal
entry of a few eps times the mass times the lever squared in case 2 (the state's rotation rounds), and its pivot
passed a test against that entry alone (issue 49: three kernels answered 46.88, 46.84 and -58.36). Exactly singular
matrices leave pivots of a few eps times the diagonal in cases 1 and 3 too (their speed maps round), so a test for
pivots ``<= 0`` alone misses them.
"""

MASS_CONDITION_WARNING = 1e10
"""A lower bound on the mass matrix's condition number (a pivot's ratio to the scale, as :data:`PIVOT_FLOOR`'s test
reads it) above which forward dynamics answer with a :class:`relacc.AccuracyWarning`: the accelerations then carry
relative errors up to ``eps kappa(M)``, above 2e-6, fewer than six certain digits (two hinges on one body, the
second tilted 3e-7 rad from the first: kappa 8.9e13, and one state 0.90 off relative between two correct methods)."""

ILL_FLOOR = 1.0 / MASS_CONDITION_WARNING
"""The pivot ratio below which :data:`MASS_CONDITION_WARNING` applies (compared as :data:`PIVOT_FLOOR` is)."""

TRIG_ULPS = 2
"""Largest difference, in ulps of the result, between :func:`relacc.kernels.trig.sincos` and libm's ``sin``/``cos``.

Each is within 1 ulp of the exact value (fdlibm's bound for the former; the
platform libm's documented bound, glibc's here, for the latter), so they
differ by at most 2 ulps. The fused kernels' case-3 results therefore differ
from the reference's by a few more roundings than the factor-8 agreement of
``tests/test_fast.py`` already allows for: a sine or cosine enters each term
through at most three factors.
"""

MUJOCO_EIG_EPS = 1e-12
"""kg m^2: the accuracy of an inertia tensor MuJoCo's compiler stores on principal axes. Its Jacobi iteration
(``mju_eig3``) stops once the largest off-diagonal entry of the rotated tensor is below ``eigEPS = 1e-12``
(absolute), and the principal moments it keeps drop those entries, so the tensor rebuilt from ``body_inertia`` and
``body_iquat`` differs from the file's by up to that much (measured on the chain: 6e-16)."""

BULLET_JACOBI_THRESHOLD = 1e-6
"""Relative to an inertia's trace: how far from the file's a URDF inertia with products of inertia may come back from
PyBullet. Its URDF importer (``BulletURDFImporter::getMassAndInertia2``) diagonalizes such a tensor with
``btMatrix3x3::diagonalize(rot, threshold = 1e-6, 30)``, a Jacobi iteration that makes one more rotation once the
largest off-diagonal entry is at most ``threshold`` times the trace and then keeps the diagonal, so an off-diagonal
entry up to that is dropped (measured on a tensor with all three products: 2.5e-11 of its trace, far inside)."""

MJMINVAL = 1e-15
"""MuJoCo's ``mjMINVAL``: the floor of the divisors in its springdamper computation, and the smallest mesh volume or
area its compiler accepts (relacc's reading follows both, :mod:`relacc.reading.mjcf`, :mod:`relacc.reading.mesh`)."""

VERTEX_ROUNDING = 4 * float(np.finfo(np.float32).eps)
"""Relative to a mesh geom's largest inertia entry: what single precision vertices (every mesh format's) allow the
inertia computed from them, as a written inertia's digits allow its value: each coordinate is within eps_f32 / 2 of
the one meant, and the inertia, a sum of products of two coordinates, within twice that of its largest entry; four
eps_f32 with the mass centre's shift. Added to the body's ``written`` (the physical checks' allowance)."""

COMPLEX_STEP = 1e-20
"""Step ``h`` of the complex-step derivative ``Im f(x + i h) / h``.

Its truncation error is ``h^2 |f'''| / 6``, below 1e-40 relative here; it has no
subtractive cancellation, so the derivative is exact to rounding.
"""


def moment_tolerance(moments, written: float = 0.0) -> float:
    """kg m^2: how far principal moments ``(3,)`` may be from a rigid body's conditions for rounding alone: the
    eigen-decomposition's ``ROUNDING_FACTOR * eps`` of the largest moment, plus what the file's own digits allow.
    ``written``: the Frobenius norm of the rounding of the tensor's entries as written (half a unit in each entry's
    last digit, :func:`relacc.reading.xml.rounding`); a symmetric perturbation of that norm moves each eigenvalue by
    at most that much (Weyl), and a sum of three of them by three times it."""
    big = float(np.abs(np.asarray(moments, dtype=float)).max(initial=0.0))
    return ROUNDING_FACTOR * EPS * big + 3.0 * float(written)


def triangle_violation(moments, written: float = 0.0) -> str:
    """The first triangle inequality a rigid body's principal moments ``(3,)`` (kg m^2) break, as text (the sums,
    and by how much relative to ``C`` against what rounding allows), or ``""``: ``A + B >= C`` for every ordering, to
    :func:`moment_tolerance` (the eigen-decomposition's rounding and the file's written digits, ``written``)."""
    m = np.sort(np.asarray(moments, dtype=float))
    tol = moment_tolerance(m, written)
    short = m[2] - (m[0] + m[1])
    if short > tol:
        return (f"A + B = {m[0] + m[1]:.12g} < C = {m[2]:.12g}, short by {short / m[2]:.2g} of C (rounding and the "
                f"file's digits allow {tol / m[2]:.2g})")
    return ""


PRINTED_DIGITS = 6
"""Significant digits a description file is assumed to print its numbers with (MuJoCo's saved XML, most exporters):
``relacc diff`` counts a difference between two files only beyond what printing to that many digits can change."""

PRINTED_RTOL = 0.5 * 10.0 ** (1 - PRINTED_DIGITS)
"""5e-6: half a unit in the :data:`PRINTED_DIGITS`-th significant digit, relative to the number printed (at most; a
number whose leading digit is 9 is printed 10 times closer)."""

PRINTED_ANGLE = PRINTED_RTOL * np.pi
"""rad: the largest rotation one printed orientation may be off by: an angle up to pi printed to
:data:`PRINTED_DIGITS` digits (a URDF's ``rpy``; a quaternion's unit components are off by less)."""


def printed_tolerance(scale, rtol: float = PRINTED_RTOL) -> float:
    """How far two files' numbers for one quantity may be apart from printing alone: each file's ``rtol`` of the
    magnitude of the written terms the quantity is formed from (``scale``, in the quantity's units, see
    :mod:`relacc.validation.diff` for each quantity's), plus the float64 rounding of forming it
    (``ROUNDING_FACTOR * eps``)."""
    return (2.0 * float(rtol) + ROUNDING_FACTOR * EPS) * float(scale)


def rounding_tolerance(factor: float = ROUNDING_FACTOR) -> float:
    """Tolerance on a normalized error that comes from rounding only: ``factor * eps``."""
    return factor * EPS


def robot_tolerance(n_links: int) -> float:
    """Tolerance on a normalized error between two engines' readings of one robot model (``relacc compare``).

    ``ROUNDING_FACTOR * eps * n_links``: each engine forms a link's quantities through a chain of
    transforms and sums over the links, each link adding at most the roundings that
    ``ROUNDING_FACTOR`` covers for the two-body chain. Solves with the mass matrix carry their
    condition number in the scale they are normalized by (:mod:`relacc.validation.robots.agreement`).
    """
    return ROUNDING_FACTOR * EPS * max(int(n_links), 1)


def inverse_diagonal_sensitivity(Minv: np.ndarray, moves: np.ndarray, rotational: np.ndarray, masses: np.ndarray,
                                  inertias: np.ndarray, length: float) -> np.ndarray:
    """``(nv,)``: how much the mass matrix's rounding moves each diagonal entry of its inverse, relatively, per unit of
    :func:`robot_tolerance` (MuJoCo's ``dof_invweight0``, from which its compiler derives a ``springdamper`` joint's
    stiffness and damping).

    First order, ``d(M^-1)_ii = -x^T dM x`` with ``x = M^-1 e_i``. Each entry of ``M`` is a sum over the bodies both
    speeds move of ``m_b g_k g_l`` (lever arms: ``g`` = ``length``, the model's extent from the world origin, for a
    rotational speed, 1 for a translational one) and ``|I_b|`` (rotational pairs), each rounded to ``robot_tolerance``
    of its magnitude; so ``|x^T dM x| <= tol sum_b m_b (sum_k g_k |x_k|)^2 + |I_b| (sum_k rot_k |x_k|)^2`` over the
    speeds ``k`` that move ``b``, and the relative change is that over ``(M^-1)_ii``.

    Args:
        Minv: ``(nv, nv)`` the inverse mass matrix. moves: ``(nb, nv)`` bool, the speeds that move each body.
        rotational: ``(nv,)`` bool. masses: ``(nb,)`` kg. inertias: ``(nb,)`` the 2-norm of each body's inertia
            (kg m^2). length: m.
    """
    g = np.where(rotational, length, 1.0)
    A = np.abs(Minv)
    lever = (moves * g) @ A
    turn = (moves * rotational) @ A
    return (masses @ lever**2 + inertias @ turn**2) / np.diag(Minv)


def central_difference_bound(h: float, third_derivative_scale, value_scale):
    """Error bound of the central difference ``(f(x + h) - f(x - h)) / 2h``.

    Truncation ``h^2 |f'''| / 6`` plus rounding ``eps |f| / h``; scales may be arrays.
    """
    return h**2 / 6 * third_derivative_scale + EPS / h * value_scale


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


def assert_normalized_error(x, ref, scale, *, what: str, seed=None, factor: float = ROUNDING_FACTOR,
                            truncation: float = 0.0):
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
