"""Configuration quantities shared by the three cases.

Names follow the note: ``R_B1_T`` is ``[R_B1]^T`` (B1 -> fixed components),
``R_B2B1`` is ``[^{B2}R_{B1}]`` (B2 -> B1 components), a trailing ``_p`` is the
note's prime (body components), ``_dot`` a time derivative.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from relacc.core.cases import Case, layout
from relacc.core.rotations import matrix_from_123, matrix_from_quaternion


def mv(A, x):
    """Batched matrix-vector product ``A x``: ``(..., m, n) x (..., n) -> (..., m)``."""
    return np.einsum("...ij,...j->...i", A, x)


def T(A):
    """Batched transpose of ``(..., m, n)`` matrices."""
    return np.swapaxes(A, -1, -2)


@dataclass(frozen=True)
class Configuration:
    """The configuration of the chain, in the note's symbols.

    Attributes:
        s1: ``{s1}``, B1's origin, fixed components, ``(..., 3)``, m.
        s2_p: ``{s2'}``, prismatic offset, B1 components, ``(..., 3)``, m.
        q2_p: ``{q2'}``, B1 components, ``(3,)``, m.
        r2_p: ``{r2'}``, B2 components, ``(3,)``, m.
        R_B1_T: ``[R_B1]^T``, B1 -> fixed components, ``(..., 3, 3)``.
        R_B2B1: ``[^{B2}R_{B1}]``, B2 -> B1 components, ``(..., 3, 3)``.
        R_B2_T: ``[R_B2]^T = [R_B1]^T [^{B2}R_{B1}]``, B2 -> fixed, ``(..., 3, 3)``.
        q2, s2, r2: ``{q2}``, ``{s2}``, ``{r2}``, fixed components, ``(..., 3)``, m.
        theta_B1, theta_B2: 1-2-3 angles (case 3 only, else None), ``(..., 3)``, rad.
    """

    s1: np.ndarray
    s2_p: np.ndarray
    q2_p: np.ndarray
    r2_p: np.ndarray
    R_B1_T: np.ndarray
    R_B2B1: np.ndarray
    R_B2_T: np.ndarray
    q2: np.ndarray
    s2: np.ndarray
    r2: np.ndarray
    theta_B1: np.ndarray | None = None
    theta_B2: np.ndarray | None = None


def configuration(chain, case, q) -> Configuration:
    """Unpack a case's coordinates ``q`` into the note's configuration symbols.

    ``q`` must already be validated (:func:`relacc.core.cases.check_q`).
    """
    lay = layout(case)
    s1, s2_p = q[..., lay.s1], q[..., lay.s2_p]
    if lay.quaternions:
        R_B1_T = matrix_from_quaternion(q[..., lay.B1])
        R_B2B1 = matrix_from_quaternion(q[..., lay.B2])
        th1 = th2 = None
    else:
        th1, th2 = q[..., lay.B1], q[..., lay.B2]
        R_B1_T, R_B2B1 = matrix_from_123(th1), matrix_from_123(th2)
    R_B2_T = R_B1_T @ R_B2B1
    return Configuration(
        s1=s1,
        s2_p=s2_p,
        q2_p=chain.q2,
        r2_p=chain.r2,
        R_B1_T=R_B1_T,
        R_B2B1=R_B2B1,
        R_B2_T=R_B2_T,
        q2=mv(R_B1_T, chain.q2),
        s2=mv(R_B1_T, s2_p),
        r2=mv(R_B2_T, chain.r2),
        theta_B1=th1,
        theta_B2=th2,
    )


def position(cfg: Configuration):
    """``{r_G2} = {s1} + {q2} + {s2} + {r2}``: G2's position, fixed components, ``(..., 3)``, m."""
    return cfg.s1 + cfg.q2 + cfg.s2 + cfg.r2


def split(u):
    """The four 3-blocks of a speed vector ``(..., 12)`` in the note's order."""
    return u[..., 0:3], u[..., 3:6], u[..., 6:9], u[..., 9:12]


def assemble(blocks):
    """Place four ``(..., 3, 3)`` blocks side by side: ``(..., 3, 12)``."""
    shape = np.broadcast_shapes(*(b.shape for b in blocks))
    return np.concatenate([np.broadcast_to(b, shape) for b in blocks], axis=-1)


def chain_rule(V, Vdot, u, udot):
    """``sum_k [V_k]{udot_k} + [Vdot_k]{u_k}`` over the four blocks: ``(..., 3)``.

    The acceleration formulas eq4, eq11 and eq12 all have this form: the time
    derivative of ``{v} = sum_k [V_k]{u_k}``.

    Args:
        V, Vdot: four ``(..., 3, 3)`` blocks each.
        u, udot: ``(..., 12)`` speeds and their time derivatives.
    """
    acc = 0
    for Vk, Vdk, uk, udk in zip(V, Vdot, split(u), split(udot)):
        acc = acc + mv(Vk, udk) + mv(Vdk, uk)
    return acc


def identity_like(cfg: Configuration):
    """``[v_{G2,s1_dot}]``: the 3x3 identity, broadcast to the batch, ``(..., 3, 3)``."""
    return np.broadcast_to(np.eye(3, dtype=cfg.R_B1_T.dtype), cfg.R_B1_T.shape)


def zeros_like(cfg: Configuration):
    """``[v_dot_{G2,s1_dot}]``: zeros, ``(..., 3, 3)``."""
    return np.zeros_like(cfg.R_B1_T)


CASES = (Case.FIXED_FRAME, Case.BODY_FRAME, Case.ANGLE_RATES)
