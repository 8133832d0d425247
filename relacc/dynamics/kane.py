"""Kane's equations of the two-body chain: the chain's tree's (:func:`relacc.core.tree.model.chain_tree`,
:mod:`relacc.dynamics.tree`), in the chain's names, and its compiled form.

The chain is one tree above the note's formulas: B1 on a free joint, B2 on three slides and a ball, G2 B2's mass
centre (:meth:`relacc.Tree.from_chain`), with the chain's case-1/2/3 coordinates and speeds in the same order. Its
:class:`relacc.dynamics.effects.Effects` are that tree's :class:`relacc.dynamics.tree_effects.TreeEffects`
(:meth:`Effects.for_tree`). So ``M``, ``f``, the effects' generalized forces, the energy and the momenta are the
tree's, every body's partial velocities from :mod:`relacc.core.tree.walk`:

    M = sum_b m_b [V_b]^T [V_b] + [Omega_b]^T [I_b] [Omega_b],
    f = sum_b [V_b]^T (m_b g + F_b - m_b [Vdot_b]{u}) + [Omega_b]^T (T_b - [I_b][Omegadot_b]{u} - omega_b x I_b omega_b)
        + the slides' springs and dampers and the ball's damper,

``[I_b]`` about the mass centre in fixed components. What stays the chain's own is the compiled form of this tree
(:mod:`relacc.kernels.dynamics`, Newton-Euler block by block, ``backend="fast"``): 6 to 7 times faster per step than
the general tree kernels on this tree (``benchmarks/chain_form.py``), held to Kane's equations to rounding
(``tests/test_dynamics.py``).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from relacc.core.cases import Case, as_case, batch_rows, check_q, check_u
from relacc.core.chain import TwoBodyChain
from relacc.core.kinematics import check_finite_result, check_out
from relacc.core.speeds import check_invertible
from relacc.core.tree.model import chain_tree
from relacc.dynamics.effects import NONE, Effects
from relacc.dynamics.tree import generalized_forces as tree_forces
from relacc.dynamics.tree import tree_accelerations, tree_dynamics
from relacc.dynamics.tree_energy import tree_energy, tree_momenta
from relacc.errors import InputError


def _checked(chain, effects, case, q, u, values: bool = True) -> tuple[Case, np.ndarray, np.ndarray]:
    """The chain's inputs checked with the chain's messages: ``(case, q, u)``; with ``values``, finite and unit."""
    if not isinstance(chain, TwoBodyChain):
        raise InputError(f"chain: expected a relacc.TwoBodyChain, got {type(chain).__name__}")
    if not isinstance(effects, Effects):
        raise InputError(f"effects: expected relacc.dynamics.Effects, got {type(effects).__name__}")
    c = as_case(case)
    return c, check_q(c, q, values=values), check_u(f"u for case {int(c)}", u, values=values)


def _rows(q: np.ndarray, u: np.ndarray) -> tuple[tuple[int, ...], np.ndarray, np.ndarray]:
    """``(batch, q (n, nq), u (n, 12))``: checked states broadcast against each other, one state a row."""
    try:
        batch = np.broadcast_shapes(q.shape[:-1], u.shape[:-1])
    except ValueError:
        raise InputError(f"batch shapes of q {q.shape} and u {u.shape} do not broadcast") from None
    qf = np.broadcast_to(q, batch + q.shape[-1:]).reshape(-1, q.shape[-1])
    uf = np.broadcast_to(u, batch + u.shape[-1:]).reshape(-1, u.shape[-1])
    return batch, qf, uf


def generalized_forces(chain: TwoBodyChain, case: int, q: ArrayLike, u: ArrayLike, effects: Effects) -> np.ndarray:
    """``{Q}`` ``(..., 12)`` of the active effects only (N, or N m per unit angular speed), conjugate to the case's
    speeds: the chain's tree's (:func:`relacc.dynamics.tree.generalized_forces`); an absent effect adds nothing."""
    c, q, u = _checked(chain, effects, case, q, u)
    return np.array(tree_forces(chain_tree(chain), int(c), q, u, effects=effects.for_tree()))


def equations_of_motion(chain: TwoBodyChain, case: int, q: ArrayLike, u: ArrayLike, effects: Effects = NONE, *,
                        out: tuple | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Kane's equations ``[M] udot = {f}`` of the chain in a case's speeds: the chain's tree's
    (:func:`relacc.tree_dynamics`).

    Args:
        chain: :class:`relacc.TwoBodyChain` with masses and inertias.
        case: 1, 2 or 3. q: the case's coordinates ``(..., 14)`` or ``(..., 12)``.
        u: ``(..., 12)`` speeds. effects: :class:`relacc.dynamics.effects.Effects` (default: none).
        out: numpy's ``out`` convention: ``(M, f)`` writable C-contiguous float64 arrays
            ``batch + (12, 12)`` and ``batch + (12,)`` to write into; returned.

    Returns:
        ``M`` ``(..., 12, 12)`` (symmetric, positive definite away from gimbal
        lock in case 3; kg, kg m, kg m^2 blocks) and ``f`` ``(..., 12)``
        (N and N m per unit speed). Real or complex, as the inputs.

    Raises:
        InputError: as :func:`relacc.g2_kinematics`; effects not an Effects; a bad ``out``.

    Warns:
        AccuracyWarning: case 3 near the gimbal lock (``M`` in the rates is conditioned as the square of the rate map).
    """
    c, q, u = _checked(chain, effects, case, q, u)
    d = tree_dynamics(chain_tree(chain), int(c), q, u, effects=effects.for_tree())  # refuses non-finite results
    M, f = np.array(d.M), np.array(d.f)
    if out is None:
        return M, f
    if not isinstance(out, (tuple, list)) or len(out) != 2:
        raise InputError(f"out: expected (M, f) arrays, got {type(out).__name__}")
    Mo = check_out(out[0], M.shape, "out M")
    fo = check_out(out[1], f.shape, "out f")
    Mo[...], fo[...] = M, f
    return Mo, fo


def accelerations(chain: TwoBodyChain, case: int, q: ArrayLike, u: ArrayLike, effects: Effects = NONE, *,
                  backend: str = "auto", out: np.ndarray | None = None) -> np.ndarray:
    """The case's ``udot`` ``(..., 12)``: the rates of its speeds under exactly ``effects``.

    m/s^2 for the translational blocks, rad/s^2 for the angular ones, in the
    components the case's speeds use.

    Args:
        backend: ``"auto"`` (default: the compiled Newton-Euler kernel of
            :mod:`relacc.kernels.dynamics`, the compiled form of the chain's tree, for real inputs), ``"fast"``, or
            ``"reference"`` (the chain's tree, :func:`relacc.tree_accelerations`: Kane's ``M`` and ``f`` solved by
            Cholesky, by LU for complex inputs; case 3 in the body speeds of case 2, then mapped to the rates, so
            that the error grows as the rate map's condition number, not its square). The two satisfy Kane's
            equations to rounding.
        out: a float64 C-contiguous array ``(..., 12)`` to write into (numpy's ``out``
            convention); returned. When an error is raised its contents are unspecified.

    Raises:
        SingularityError: case 3 within ``MAX_CONDITION`` of gimbal lock, where
            the angle rates' accelerations are not defined to useful accuracy
            (:func:`relacc.core.speeds.check_invertible`).
        InputError: as :func:`relacc.g2_kinematics`; a bad ``out``.
    """
    if backend not in ("auto", "fast", "reference"):
        raise InputError(f"unknown backend {backend!r}: accepted are auto, fast, reference")
    c, q, u = _checked(chain, effects, case, q, u, values=False)

    def check_values():  # raises, naming the bad entry
        check_q(c, q), check_u(f"u for case {int(c)}", u)
        check_invertible(c, q)

    try:
        batch = np.broadcast_shapes(q.shape[:-1], u.shape[:-1])
    except ValueError:
        raise InputError(f"batch shapes of q {q.shape} and u {u.shape} do not broadcast") from None
    real = q.dtype.kind == "f" and u.dtype.kind == "f"
    if backend == "fast" and not real:
        raise InputError("backend 'fast' takes real inputs only; use backend 'reference' for complex ones")
    out = check_out(out, batch + (12,), "out")
    if backend == "reference" or not real:
        check_values()
        # the chain's tree (Kane's equations of any tree, case 3 solved in case-2 speeds and mapped)
        udot = np.array(tree_accelerations(chain_tree(chain), int(c), q, u, effects=effects.for_tree(),
                                           backend="reference"))
        if out is None:
            return udot
        out[...] = udot
        return out
    from relacc.kernels import dynamics as kernel

    target = out.reshape(-1, 12) if out is not None else np.empty((math.prod(batch), 12))
    with np.errstate(all="ignore"):
        bad, suspect = kernel.accelerations(int(c), batch_rows(q, batch, q.shape[-1], np.float64),
                                            batch_rows(u, batch, 12, np.float64),
                                            kernel.chain_params(chain), kernel.effect_params(effects), target)
    if suspect:
        check_values()
    if bad:
        check_finite_result((target,), q, u)
    return out if out is not None else target.reshape(batch + (12,))


def energy_terms(chain: TwoBodyChain, case: int, q: ArrayLike, u: ArrayLike, effects: Effects = NONE
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The terms of the energy, J, each ``(...)``: ``(kinetic, gravity, spring)``: the chain's tree's
    (:func:`relacc.dynamics.tree_energy.tree_energy`, real or complex).

    Gravity's potential ``-sum m_i g . r_Gi`` (0 when gravity is off), the
    spring's ``1/2 sum k (s2' - rest)^2`` (0 when off). Their sum is
    :func:`energy`; ``kinetic + |gravity| + spring`` is the magnitude of the
    terms, the scale energy drift is normalized by.
    """
    c, q, u = _checked(chain, effects, case, q, u)
    batch, qf, uf = _rows(q, u)
    terms = tree_energy(chain_tree(chain), qf, uf, effects.for_tree(), int(c))
    return tuple(t.reshape(batch) for t in terms)  # type: ignore[return-value]


def energy(chain: TwoBodyChain, case: int, q: ArrayLike, u: ArrayLike, effects: Effects = NONE) -> np.ndarray:
    """Kinetic plus potential energy of the active conservative effects, J, ``(...)`` (:func:`energy_terms`)."""
    T, gravity, spring = energy_terms(chain, case, q, u, effects)
    return T + gravity + spring


def momenta(chain: TwoBodyChain, case: int, q: ArrayLike, u: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Linear momentum ``(..., 3)`` (kg m/s) and angular momentum about R's origin ``(..., 3)`` (kg m^2/s), fixed
    components: the chain's tree's (:func:`relacc.dynamics.tree_energy.tree_momenta`)."""
    c, q, u = _checked(chain, NONE, case, q, u)
    batch, qf, uf = _rows(q, u)
    p, H = tree_momenta(chain_tree(chain), qf, uf, int(c))
    return p.reshape(batch + (3,)), H.reshape(batch + (3,))
