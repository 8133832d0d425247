"""The magnitudes the error model normalizes by, and the conditions of global-coordinate evaluations.

Part of the one error model (:mod:`relacc.core.tolerances` holds the
tolerances): a normalized error is ``max |x - x_ref| / scale`` with
``scale`` the magnitude of the terms summed to form ``x``
(:func:`term_scales` for G2's kinematics, :func:`dynamics_scales` for
Kane's ``M`` and ``f``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from relacc.core.cases import layout
from relacc.core.conventions import QUANTITIES
from relacc.core.tree.model import chain_tree
from relacc.core.tree.scales import tree_scales


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
    s1 = np.linalg.norm(np.real(np.asarray(q)[..., layout(case).s1]), axis=-1)
    return 1 + s1 * ratio


def velocity_condition(quantity: str, chain, case, q, u, udot=None):
    """What an engine loses forming a quantity from world-frame spatial velocities, relative to the terms'
    magnitude, one value per state (0 for quantities other than ``Vdot`` and ``acceleration``).

    Such an engine (Pinocchio's frame Jacobians' time variation and classical acceleration, MuJoCo's ``cacc`` and
    ``mj_jacDot``, Drake's ``Jdot v``) carries the absolute translational velocity of B1's origin, ``s1_dot``, in
    terms that cancel in G2's classical ``V̇`` (``ω × (ṡ1 + ...)`` against ``ṡ1 × ω``) and acceleration: it rounds
    at ``eps |s1_dot|`` in every term of ``V̇`` and ``eps W |s1_dot|`` in the acceleration (``W`` as in
    :func:`term_scales`), which the note's scales, built from relative velocities, do not contain. Measured
    (issue 49): with ``|s1_dot|`` from 0 to 1000 m/s the three engines' ``V̇`` errors grew from 9 to 1.2e5 eps of the
    note's scale and stayed within 7 eps of this one; the report's Hypothesis search had found Pinocchio's ``V̇`` at
    173 eps against a bound of 66 at ``|s1_dot|`` = 16 m/s.

    Returns:
        ``(...)`` array ``>= 0``: ``|s1_dot| / scale`` for ``Vdot``, ``W |s1_dot| / scale`` for the acceleration.
    """
    u = np.asarray(u)
    sd = np.linalg.norm(np.real(u[..., 0:3]), axis=-1)
    if quantity not in ("Vdot", "acceleration"):
        return np.zeros_like(sd)
    sc = term_scales(chain, case, q, u, udot).of(quantity)
    sensitivity = lever_sensitivity("Vdot", case, q, u, udot) if quantity == "acceleration" else 1.0
    return sd * sensitivity / np.maximum(sc, np.finfo(np.float64).tiny)


def offset_error(lost: float, quantity: str, chain, case, q, u, udot=None):
    """Normalized error of a model that puts G2 ``lost`` metres off (an engine's compile-time rounding).

    ``lost * lever_sensitivity / scale``, one value per state; 0 when nothing is lost.
    """
    return lost * per_metre_of_lever(quantity, chain, case, q, u, udot)


def term_scales(chain, case, q, u, udot=None) -> TermScales:
    """Magnitudes of the terms of position, velocity, acceleration, V and Vdot: the tree's error model
    (:func:`relacc.core.tree.scales.tree_scales`) of the chain's tree (:func:`relacc.core.tree.model.chain_tree`)
    at B2's mass centre, which for this tree is

    with ``l = |q2'| + |s2'| + |r2'|`` (lever from B1's origin to G2),
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
    sc = tree_scales(chain_tree(chain), case, q, u, udot)
    return TermScales(**{name: sc.of(name)[..., 1] for name in QUANTITIES})


def dynamics_scales(chain, case, q, u, effects=None):
    """Magnitudes of the terms of Kane's ``M`` and ``f``, one value per state.

    With ``m = m1 + m2``, ``J = |I1| + |I2|`` (Frobenius), ``l``, ``W`` as in
    :func:`term_scales` and ``l1 = |r1'|``:

    * ``M``: ``m (1 + l + l1)^2 + J`` (kg m^2; the translational blocks are smaller);
    * ``f``: ``m (1 + l + l1) (W^2 (l + l1) + 2 W |s2'_dot| + |g|) + J W^2`` plus
      every active effect's size (``|K| |s2' - rest| + |C| |s2'_dot| + c W
      + |F| (1 + l) + |T1| + |T2|``).
    """
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
            g = float(np.linalg.norm(effects.gravity))
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
