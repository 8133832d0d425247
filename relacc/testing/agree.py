"""``assert_agrees``: relacc's error model in anyone's tests, with a message that says where it went wrong."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from relacc.core.cases import U_BLOCKS
from relacc.core.tolerances import EPS, normalized_error, rounding_tolerance
from relacc.errors import InputError
from relacc.limits import require_memory

if TYPE_CHECKING:
    from relacc.testing.expected import Expected

SPEED_NAMES = {
    1: ("s1_dot", "omega_B1", "s2'_dot", "omega_hat_B2"),
    2: ("s1_dot", "omega'_B1", "s2'_dot", "omega_hat'_B2"),
    3: ("s1_dot", "theta_B1_dot", "s2'_dot", "theta_B2_dot"),
}
"""The four blocks of each case's generalized speeds, as the note names them (the columns of V and Vdot)."""

COMPONENTS = ("x", "y", "z")


def column_errors(actual, expected, scale, case) -> dict:
    """``{block name: largest normalized error in V's (or Vdot's) columns of that block}``, ``(n, 3, 12)`` inputs."""
    return {name: float(np.max(normalized_error(actual[..., sl], expected[..., sl], scale)))
            for name, sl in zip(SPEED_NAMES[int(case)], U_BLOCKS.values())}


def assert_agrees(actual: ArrayLike, expected: "Expected | ArrayLike", *, scale: ArrayLike | None = None,
                  what: str = "", tolerance: float | None = None) -> np.ndarray:
    """Assert that ``actual`` agrees with ``expected`` within relacc's error model; return the per-state errors.

    The error of a state is ``max |actual - expected| / scale`` (the magnitude of the terms,
    :func:`relacc.core.scales.term_scales`); it must not exceed ``c eps`` (64 eps, the rounding of
    an evaluation like relacc's own) plus the reference's own bound.

    Args:
        actual: ``(n, 3)`` or ``(n, 3, 12)`` (or one state without the leading axis).
        expected: an :class:`relacc.testing.Expected` (from ``relacc_truth``/:func:`relacc.testing.truth`),
            which carries the scale, the reference's bound, the case and the seed; or a plain array of
            the same shape, judged against ``scale`` or, without one, against the largest entry of
            each expected state (a value-relative model, weaker than the terms' magnitude).
        scale: ``(n,)`` magnitudes overriding the expected's.
        what: a label for the message.
        tolerance: the rounding allowance; default ``c eps`` (:func:`relacc.core.tolerances.rounding_tolerance`).

    Raises:
        AssertionError: naming the worst state's index and seed, its component, the normalized error
            against the tolerance and, for V and Vdot, the generalized-speed columns that disagree.
        InputError: shapes that differ.
    """
    from relacc.testing.expected import Expected

    ref = expected.values if isinstance(expected, Expected) else np.asarray(expected)
    act = np.asarray(actual)
    for label, arr in (("actual", act), ("expected", ref)):
        if arr.dtype.kind not in "iufc" or arr.dtype.kind == "b":
            raise InputError(f"{what or label}: expected numbers, got {arr.dtype} values")
    if act.shape != ref.shape:
        if act.shape == ref.shape[1:] and ref.shape[0] == 1:
            act = act[None]
        else:
            raise InputError(f"{what or 'actual'}: shape {act.shape} differs from the expected {ref.shape}")
    if ref.ndim == 1 or (ref.ndim == 2 and ref.shape[-1] == 12):  # one state: (3,) or V's (3, 12)
        act, ref = act[None], ref[None]
    require_memory(8.0 * 6 * act.size, f"{what or 'actual'}: {act.size} values", "compare fewer states at a time")
    if scale is None:
        if isinstance(expected, Expected):
            scale = expected.scale
        else:
            scale = np.max(np.abs(ref.reshape(ref.shape[0], -1)), axis=1) if ref.ndim > 1 else np.max(np.abs(ref))
    scale = np.asarray(scale, dtype=float)
    bound = expected.bound if isinstance(expected, Expected) else 0.0
    tol = (rounding_tolerance() if tolerance is None else tolerance) + np.asarray(bound)
    errors = np.atleast_1d(normalized_error(act, ref, scale))
    ok = np.all(errors <= tol) and np.all(np.isfinite(act))
    if ok:
        return errors
    ratio = np.where(np.isfinite(errors), errors / np.broadcast_to(tol, errors.shape), np.inf)
    if not np.all(np.isfinite(act)):
        finite = np.all(np.isfinite(act.reshape(errors.shape + (-1,))), axis=-1)
        ratio = np.where(finite, ratio, np.inf)
    known = expected if isinstance(expected, Expected) else None
    if known is not None and known.labels:  # a model's bodies: judge (state, body) pairs, name the body
        labels = known.labels
        flat = ratio.reshape(-1)
        i, body = (int(x) for x in np.unravel_index(int(np.argmax(flat)), ratio.shape))
        diff = np.abs(act[i, body] - ref[i, body])
        row = int(np.unravel_index(np.nanargmax(np.where(np.isnan(diff), np.inf, diff)), diff.shape)[0])
        tol_i = float(np.broadcast_to(tol, errors.shape)[i, body])
        label = what or known.quantity
        raise AssertionError(f"{label} against {known.source}: normalized error {float(errors[i, body]):.3g} "
                             f"({float(errors[i, body]) / EPS:.3g} eps) > tolerance {tol_i:.3g} ({tol_i / EPS:.3g} "
                             f"eps) at state {int(i)} of seed {known.seed!r}, body {labels[body]}, component "
                             f"{COMPONENTS[row]}")
    i = int(np.argmax(ratio))
    diff = np.abs(act[i] - ref[i])
    row = int(np.unravel_index(np.nanargmax(np.where(np.isnan(diff), np.inf, diff)), diff.shape)[0])
    quantity = expected.quantity if isinstance(expected, Expected) else ""
    label = what or quantity or "value"
    seed = f" of seed {expected.seed!r}" if isinstance(expected, Expected) else ""
    source = f" against {expected.source}" if isinstance(expected, Expected) else ""
    tol_i = float(np.broadcast_to(tol, errors.shape)[i])
    msg = (f"{label}{source}: normalized error {float(errors[i]):.3g} ({float(errors[i]) / EPS:.3g} eps) > "
           f"tolerance {tol_i:.3g} ({tol_i / EPS:.3g} eps) at state {i}{seed}, component {COMPONENTS[row]}")
    if act.ndim == 3 and act.shape[-1] == 12:
        case = expected.case if isinstance(expected, Expected) else 1
        per = column_errors(act[i:i + 1], ref[i:i + 1], scale[i:i + 1] if scale.ndim else scale, case)
        bad = [name for name, e in per.items() if e > tol_i]
        msg += f"; the columns that disagree: {', '.join(bad) or 'none alone'}"
    raise AssertionError(msg)
