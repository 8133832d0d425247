"""G2's position, velocity, acceleration and partial velocity matrices, by the note.

Entry point: :func:`g2_kinematics`.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from relacc.core.cases import Case, as_case, batch_rows, check_q, check_u
from relacc.core.chain import TwoBodyChain
from relacc.core.note import case1, case2, case3
from relacc.core.note.common import assemble, configuration, position
from relacc.core.note.equations import BY_ID, IDS
from relacc.errors import InputError, VariantError
from relacc.limits import require_memory


@dataclass(frozen=True, eq=False)
class G2Kinematics:
    """Kinematics of G2, B2's mass center, in the fixed frame R. Immutable.

    Every array is in **fixed-frame components** and carries the batch shape
    ``...`` of the inputs.

    Attributes:
        position: ``{r_G2}``, G2 from R's origin, ``(..., 3)``, m.
        velocity: ``{v_G2}``, G2's velocity in R, ``(..., 3)``, m/s.
        acceleration: ``{a_G2}``, G2's classical acceleration in R (second
            time derivative of ``position``; not a spatial acceleration),
            ``(..., 3)``, m/s^2; None when no ``udot`` was given.
        V: partial velocity matrix, ``{v_G2} = [V]{u}``, ``(..., 3, 12)``;
            columns in m/s per unit of the case's speed (1 for translational
            speeds, m for angular ones).
        Vdot: ``d[V]/dt`` along the motion, ``{a_G2} = [V]{udot} + [Vdot]{u}``,
            ``(..., 3, 12)``, the units of ``V`` per second.
        case: the choice of generalized speeds.
        variant: ``"corrected"``, ``"printed"`` or the sorted printed ids.
    """

    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray | None
    V: np.ndarray
    Vdot: np.ndarray
    case: Case
    variant: str
    owns: bool = field(default=True, repr=False)
    """False when the arrays are the caller's ``out`` buffers: then they stay writable, for reuse."""

    def __post_init__(self):
        if not self.owns:
            return
        for name in ("position", "velocity", "acceleration", "V", "Vdot"):
            value = getattr(self, name)
            if isinstance(value, np.ndarray):
                value.setflags(write=False)


def resolve_variant(variant) -> frozenset:
    """The set of equation ids to take in their printed form.

    Args:
        variant: ``"corrected"`` (none), ``"printed"`` (all; where the note
            prints two forms, ``eq9.2`` and ``case2-a.2`` win), or an iterable
            of equation ids.

    Raises:
        VariantError: unknown variant name or equation id.
    """
    if isinstance(variant, str):
        if variant == "corrected":
            return frozenset()
        if variant == "printed":
            return frozenset(IDS)
        raise VariantError(
            f"unknown variant {variant!r}: accepted are 'corrected', 'printed' or a set of "
            f"equation ids ({', '.join(IDS)})"
        )
    try:
        ids = frozenset(variant)
    except TypeError:
        raise VariantError(
            f"unknown variant {variant!r}: accepted are 'corrected', 'printed' or a set of equation ids"
        ) from None
    unknown = sorted(str(i) for i in ids if i not in BY_ID)
    if unknown:
        raise VariantError(f"unknown equation ids {unknown}: accepted are {', '.join(IDS)}")
    return ids


def check_finite_result(arrays, q, u, udot=None, model=None) -> None:
    """Raise :class:`InputError` if finite inputs produced a non-finite result (float64 overflow).

    relacc never returns inf or NaN: results beyond about 1e308 mean the
    inputs are out of float64's range for these formulas. ``model``: ``(what, largest magnitude)`` of the model's
    own numbers (masses, inertias), named too.
    """
    for a in arrays:
        if a is not None and not np.all(np.isfinite(a)):
            big = max(float(np.max(np.abs(x), initial=0.0)) for x in (q, u, udot) if x is not None)
            own = "" if model is None else f" and {model[0]} {model[1]:.3g}"
            raise InputError(
                f"the result overflowed float64 (largest input magnitude {big:.3g}{own}); accelerations grow "
                "with the square of the speeds and forces with the masses: keep |u| below about 1e150, positions "
                "below 1e300 and the products of masses and squared speeds within float64's range"
            )


def check_out(out, shape, name: str):
    """An ``out=`` buffer: None, or a writable C-contiguous float64 array of exactly ``shape``.

    Raises:
        InputError: anything else, naming the shape and dtype expected.
    """
    if out is None:
        return None
    if not (isinstance(out, np.ndarray) and out.dtype == np.float64 and out.shape == tuple(shape)
            and out.flags.c_contiguous and out.flags.writeable):
        got = f"{type(out).__name__} {getattr(out, 'shape', '')} {getattr(out, 'dtype', '')}".strip()
        if isinstance(out, np.ndarray):
            got += "".join(note for ok, note in ((out.flags.c_contiguous, ", not C-contiguous"),
                                                 (out.flags.writeable, ", read-only (relacc's results are)"))
                           if not ok)
        raise InputError(f"{name}: expected a writable C-contiguous float64 array of shape {tuple(shape)}, got {got}")
    return out


def _variant_label(variant, printed) -> str:
    if isinstance(variant, str):
        return variant
    return ",".join(sorted(printed)) if printed else "corrected"


BACKENDS = ("auto", "fast", "reference")


def _check_backend(backend, printed, *arrays) -> str:
    """Resolve ``backend`` to ``"fast"`` or ``"reference"``."""
    if backend not in BACKENDS:
        raise InputError(f"unknown backend {backend!r}: accepted are {', '.join(BACKENDS)}")
    real = all(a is None or a.dtype.kind == "f" for a in arrays)
    if backend == "fast" and (printed or not real):
        raise InputError("backend 'fast' evaluates the corrected variant on real inputs only; "
                         "use backend 'reference' for printed variants or complex inputs")
    if backend == "auto":
        return "fast" if (real and not printed) else "reference"
    return backend


def check_values(case, q, u, udot=None, offset: int = 0) -> None:
    """The value checks of :func:`check_q` and :func:`check_u` (finite, unit quaternions).

    ``offset``: the position of this batch in a longer one, added to the state index in messages.

    Raises:
        InputError: naming the first bad entry.
    """
    c = as_case(case)
    check_q(c, q, offset=offset)
    check_u(f"u for case {int(c)}", u, offset=offset)
    if udot is not None:
        check_u(f"udot for case {int(c)}", udot, offset=offset)


def _kernels():
    """The fused kernels, imported (and numba loaded) at the first batched call, not with the core."""
    from relacc.kernels import kinematics

    return kinematics


def g2_kinematics(chain: TwoBodyChain, case: int, q: ArrayLike, u: ArrayLike, udot: ArrayLike | None = None, *,
                  variant: str | Iterable[str] = "corrected", backend: str = "auto", out: Sequence | None = None
                  ) -> G2Kinematics:
    """Position, velocity, acceleration, V and Vdot of G2 by the note's formulas.

    Args:
        chain: :class:`relacc.TwoBodyChain` (``q2'``, ``r2'``).
        case: 1, 2, 3 or :class:`relacc.Case`.
        q: coordinates of the case, ``(..., 14)`` for cases 1-2
            ``[s1, quat_B1 (w,x,y,z), s2', quat_B2/B1]``, ``(..., 12)`` for
            case 3 ``[s1, theta_B1, s2', theta_B2]``.
        u: ``(..., 12)`` generalized speeds of the case (see :mod:`relacc.core.cases`).
        udot: ``(..., 12)`` their time derivatives, or None to skip the
            acceleration.
        variant: ``"corrected"`` (default), ``"printed"`` (the note's printed
            formulas where they differ) or a set of equation ids to take as
            printed (see :mod:`relacc.core.note.equations`).
        backend: ``"auto"`` (default: the fused kernels of :mod:`relacc.kernels.kinematics`
            for the corrected variant on real inputs, else the reference),
            ``"fast"`` or ``"reference"`` (the note's formulas one by one, as
            labelled in :mod:`relacc.core.note`; the two agree to a few ulps).
        out: numpy's ``out`` convention: ``(position, velocity, acceleration, V, Vdot)``,
            writable C-contiguous float64 arrays of shapes ``batch + (3,)`` (three times) and
            ``batch + (3, 12)`` (twice), ``acceleration`` None when ``udot`` is; the results are
            written there (no new output memory) and the returned :class:`G2Kinematics` holds
            them, still writable for the next call.

    Batch dimensions of ``q``, ``u`` and ``udot`` broadcast against each
    other. Complex inputs are accepted (every formula is analytic), which the
    complex-step derivative checks use.

    Returns:
        :class:`G2Kinematics`, every array in fixed-frame components.

    Raises:
        InputError: bad shapes, non-finite values, non-unit quaternions or a
            chain that is not a :class:`TwoBodyChain`.
        CaseError: unknown case. VariantError: unknown variant.
    """
    printed = resolve_variant(variant)
    c, q, u, udot, path, batch = _inputs(chain, case, q, u, udot, printed, backend, out=out)
    buffers = _kinematics_out(out, batch, udot is not None)
    with np.errstate(over="ignore", invalid="ignore"):  # overflow is reported below, as an InputError
        if path == "fast":
            flat = [batch_rows(q, batch, q.shape[-1], np.float64), batch_rows(u, batch, 12, np.float64),
                    None if udot is None else batch_rows(udot, batch, 12, np.float64)]
            views = None if buffers is None else tuple(
                None if b is None else b.reshape((-1,) + b.shape[len(batch):]) for b in buffers)
            (pos, vel, acc, V, Vdot), bad, bad_in = _kernels().kinematics(int(c), *flat, chain.q2, chain.r2,
                                                                          out=views)
            if bad_in:
                check_values(c, q, u, udot)  # raises, naming the bad entry
            if bad:
                check_finite_result((pos, vel, acc, V, Vdot), q, u, udot)
            if buffers is not None:
                return G2Kinematics(*buffers, c, _variant_label(variant, printed), owns=False)
            shape = lambda a, tail: a.reshape(batch + tail)  # noqa: E731
            return G2Kinematics(shape(pos, (3,)), shape(vel, (3,)), None if acc is None else shape(acc, (3,)),
                                shape(V, (3, 12)), shape(Vdot, (3, 12)), c, _variant_label(variant, printed))
        k = _evaluate(chain, c, q, u, udot, printed, batch, variant)
    if buffers is None:
        return k
    for target, name in zip(buffers, ("position", "velocity", "acceleration", "V", "Vdot")):
        if target is not None:
            target[...] = getattr(k, name)
    return G2Kinematics(*buffers, c, k.variant, owns=False)


def _kinematics_out(out, batch, with_acc) -> tuple[Any, Any, Any, Any, Any] | None:
    """Check ``g2_kinematics``'s ``out`` (None, or 5 buffers of the batch's shapes)."""
    if out is None:
        return None
    if not isinstance(out, (tuple, list)) or len(out) != 5:
        raise InputError("out: expected (position, velocity, acceleration, V, Vdot) arrays (acceleration None "
                         f"without udot), got {type(out).__name__}")
    names = ("position", "velocity", "acceleration", "V", "Vdot")
    tails = ((3,), (3,), (3,), (3, 12), (3, 12))
    if (out[2] is None) == with_acc:
        raise InputError("out: give an acceleration buffer exactly when udot is given")
    p, v, a, V, Vd = (None if (name == "acceleration" and not with_acc) else check_out(b, batch + tail, f"out {name}")
                      for b, name, tail in zip(out, names, tails))
    return p, v, a, V, Vd


def g2_acceleration(chain: TwoBodyChain, case: int, q: ArrayLike, u: ArrayLike, udot: ArrayLike, *,
                    backend: str = "auto", out: np.ndarray | None = None) -> np.ndarray:
    """G2's classical acceleration alone (corrected formulas), the fastest path.

    Same arguments and checks as :func:`g2_kinematics`, without V, Vdot; ``out``:
    a writable C-contiguous float64 ``batch + (3,)`` array to write into (returned).

    Returns:
        ``(..., 3)`` acceleration of G2 in R (second time derivative of its
        position), fixed-frame components, m/s^2.
    """
    c, q, u, udot, path, batch = _inputs(chain, case, q, u, udot, frozenset(), backend, need_udot=True, out=out)
    out = check_out(out, batch + (3,), "out")
    with np.errstate(over="ignore", invalid="ignore"):
        if path == "fast":
            flat = (batch_rows(q, batch, q.shape[-1], np.float64), batch_rows(u, batch, 12, np.float64),
                    batch_rows(udot, batch, 12, np.float64))
            acc, bad, bad_in = _kernels().acceleration(int(c), *flat, chain.q2, chain.r2,
                                                       out=None if out is None else out.reshape(-1, 3))
            if bad_in:
                check_values(c, q, u, udot)  # raises, naming the bad entry
            acc = acc.reshape(batch + (3,))
            if bad:
                check_finite_result((acc,), q, u, udot)
        else:
            acc = _evaluate(chain, c, q, u, udot, frozenset(), batch, "corrected").acceleration
            if out is not None:
                out[...] = acc
                acc = out
    if out is not None:
        return out
    if isinstance(acc, np.ndarray):
        acc.setflags(write=False)
    return acc


def _inputs(chain, case, q, u, udot, printed, backend, need_udot=False, out=None
            ) -> tuple[Case, np.ndarray, np.ndarray, Any, str, tuple[int, ...]]:
    """The checks both entry points share: ``(case, q, u, udot, path, batch)``.

    Types and shapes here; values (finite, unit quaternions) here on the
    reference path or, on the fast path, in the kernel.
    """
    if not isinstance(chain, TwoBodyChain):
        raise InputError(f"chain: expected a relacc.TwoBodyChain, got {type(chain).__name__}")
    c = as_case(case)
    q = check_q(c, q, values=False)
    u = check_u(f"u for case {int(c)}", u, values=False)
    if udot is not None or need_udot:
        udot = check_u(f"udot for case {int(c)}", udot, values=False)
    path = _check_backend(backend, printed, q, u, udot)
    if path == "reference":
        check_values(c, q, u, udot)
    shapes = [q.shape[:-1], u.shape[:-1]] + ([udot.shape[:-1]] if udot is not None else [])
    try:
        batch = np.broadcast_shapes(*shapes)
    except ValueError:
        raise InputError(
            f"batch shapes of q, u, udot do not broadcast: {shapes}; give equal leading shapes"
        ) from None
    per_state = (41 if need_udot else 120) * (1 if path == "fast" else 20)  # doubles: outputs, copies, temporaries
    if out is not None and path == "fast":
        per_state = 38  # the outputs are the caller's: only the inputs' contiguous copies, at most
    n = math.prod(batch)
    require_memory(8 * per_state * float(n), f"evaluating {n} states at once",
                   "stream them with relacc.core.stream.iter_g2_kinematics")
    return c, q, u, udot, path, batch


def _evaluate(chain, c, q, u, udot, printed, batch, variant) -> G2Kinematics:
    cfg = configuration(chain, c, q)
    if c is Case.FIXED_FRAME:
        velocity = case1.eq1_velocity(cfg, u)
        V = case1.eq3_partials(cfg)
        Vdot = case1.partials_dot(cfg, u, printed)
        acc = None if udot is None else case1.eq4_acceleration(cfg, u, udot, V, Vdot, printed)
    elif c is Case.BODY_FRAME:
        velocity = case2.eq2_velocity(cfg, u)
        V = case2.eq10_partials(cfg)
        Vdot = case2.partials_dot(cfg, u, printed)
        acc = None if udot is None else case2.eq11_acceleration(V, Vdot, u, udot)
    else:
        velocity = case3.velocity(cfg, u, printed)
        V = case3.partials(cfg, printed)
        Vdot = case3.partials_dot(cfg, u, printed)
        acc = None if udot is None else case3.eq12_acceleration(V, Vdot, u, udot)

    check_finite_result((position(cfg), velocity, acc, assemble(V), assemble(Vdot)), q, u, udot)
    bvec = lambda a: np.ascontiguousarray(np.broadcast_to(a, batch + (3,)))  # noqa: E731
    bmat = lambda blocks: np.ascontiguousarray(np.broadcast_to(assemble(blocks), batch + (3, 12)))  # noqa: E731
    return G2Kinematics(
        position=bvec(position(cfg)),
        velocity=bvec(velocity),
        acceleration=None if acc is None else bvec(acc),
        V=bmat(V),
        Vdot=bmat(Vdot),
        case=c,
        variant=_variant_label(variant, printed),
    )
