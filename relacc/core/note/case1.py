"""Case 1: fixed-frame angular velocity components as generalized speeds.

``u = [s1_dot, omega_B1, s2'_dot, omega_hat_B2]``: ``omega_B1`` in fixed
components, ``omega_hat_B2`` (angular velocity of B2 in B1) in B1 components.
Every vector and matrix returned here is in fixed-frame components.

Equation ids: ``eq1`` (velocity), ``eq3`` (partial velocities), ``eq4``
(acceleration), ``case1-a`` (the unnumbered derivative a), ``eq5``-``eq7``
(its ingredients), ``eq8`` (b), ``eq9.1`` and ``eq9.2`` (the two printed
forms of c).
"""

from __future__ import annotations

import numpy as np

from relacc.core.note.common import T, chain_rule, identity_like, mv, split, zeros_like
from relacc.core.rotations import tilde


def angular_velocities(cfg, u):
    """``(omega_B1, omega_hat_B2 in fixed components, omega_B2)``, each ``(..., 3)``, rad/s.

    ``omega_B2 = omega_B1 + [R_B1]^T omega_hat_B2`` is B2's angular velocity in
    R, fixed components (the note's unhatted ``omega_B2`` of Eq. 7).
    """
    _, omega_B1, _, omega_hat_B2 = split(u)
    w_hat = mv(cfg.R_B1_T, omega_hat_B2)
    return omega_B1, w_hat, omega_B1 + w_hat


def eq1_velocity(cfg, u):
    """eq1: ``{v_G2} = {s1_dot} - ([q2~] + [s2~] + [r2~]) {omega_B1} + [R_B1]^T {s2'_dot}
    - [r2~] [R_B1]^T {omega_hat_B2}``.

    Returns:
        G2's velocity in R, fixed components, ``(..., 3)``, m/s.
    """
    s1_dot, omega_B1, s2_p_dot, omega_hat_B2 = split(u)
    lever = tilde(cfg.q2) + tilde(cfg.s2) + tilde(cfg.r2)
    return (
        s1_dot
        - mv(lever, omega_B1)
        + mv(cfg.R_B1_T, s2_p_dot)
        - mv(tilde(cfg.r2) @ cfg.R_B1_T, omega_hat_B2)
    )


def eq3_partials(cfg):
    """eq3: partial velocity blocks of G2, fixed components, each ``(..., 3, 3)``.

    * ``[v_{G2,s1_dot}] = I``
    * ``[v_{G2,omega_B1}] = -([q2~] + [s2~] + [r2~])`` (m)
    * ``[v_{G2,s2'_dot}] = [R_B1]^T``
    * ``[v_{G2,omega_hat_B2}] = -[r2~] [R_B1]^T`` (m)

    The note prints the last subscript as ``omega_dot_B2``; it is the partial
    with respect to ``omega_hat_B2`` (a typesetting slip, numbers unaffected).
    """
    return (
        identity_like(cfg),
        -(tilde(cfg.q2) + tilde(cfg.s2) + tilde(cfg.r2)),
        cfg.R_B1_T,
        -tilde(cfg.r2) @ cfg.R_B1_T,
    )


def eq5_q2_dot(cfg, omega_B1):
    """eq5: ``{q2_dot} = [R_B1_dot]^T {q2'} = [omega_B1~] [R_B1]^T {q2'}``, fixed comps, m/s."""
    return mv(tilde(omega_B1) @ cfg.R_B1_T, cfg.q2_p)


def eq6_s2_dot(cfg, omega_B1, s2_p_dot):
    """eq6: ``{s2_dot} = [omega_B1~] [R_B1]^T {s2'} + [R_B1]^T {s2'_dot}``, fixed comps, m/s."""
    return mv(tilde(omega_B1) @ cfg.R_B1_T, cfg.s2_p) + mv(cfg.R_B1_T, s2_p_dot)


def eq7_r2_dot(cfg, omega_B2):
    """eq7: ``{r2_dot} = [R_B2_dot]^T {r2'} = [omega_B2~] [R_B2]^T {r2'}``, fixed comps, m/s.

    ``omega_B2`` is B2's angular velocity in R (fixed components); the note
    uses the symbol without defining it, and only this reading is right.
    """
    return mv(tilde(omega_B2) @ cfg.R_B2_T, cfg.r2_p)


def rates(cfg, u):
    """``({q2_dot}, {s2_dot}, {r2_dot})`` by eq5-eq7, fixed components, m/s."""
    omega_B1, _, omega_B2 = angular_velocities(cfg, u)
    return (
        eq5_q2_dot(cfg, omega_B1),
        eq6_s2_dot(cfg, omega_B1, u[..., 6:9]),
        eq7_r2_dot(cfg, omega_B2),
    )


def case1_a(q2_dot, s2_dot, r2_dot):
    """case1-a: ``[v_dot_{G2,omega_B1}] = -([q2_dot~] + [s2_dot~] + [r2_dot~])``, (..., 3, 3), m/s."""
    return -(tilde(q2_dot) + tilde(s2_dot) + tilde(r2_dot))


def eq8(cfg, omega_B1):
    """eq8: ``[v_dot_{G2,s2'_dot}] = [R_B1_dot]^T = [omega_B1~] [R_B1]^T``, (..., 3, 3), 1/s."""
    return tilde(omega_B1) @ cfg.R_B1_T


def eq9(cfg, omega_B1, r2_dot, form="corrected"):
    """eq9: ``[v_dot_{G2,omega_hat_B2}]``, fixed components, ``(..., 3, 3)``, m/s.

    * ``eq9.1`` (printed, first form, right):
      ``-[r2_dot~] [R_B1]^T - [r2~] [R_B1_dot]^T`` with ``[R_B1_dot]^T`` from eq8.
    * ``eq9.2`` (printed, final form, wrong): ``-[r2_dot~] [R_B1]^T - [r2~] [omega_B1~]^T``.
      It replaces ``[R_B1_dot]^T = [omega_B1~][R_B1]^T`` by ``[omega_B1~]^T``:
      the factor ``[R_B1]^T`` is dropped and the skew matrix transposed.
    * corrected: ``-[r2_dot~] [R_B1]^T - [r2~] [omega_B1~] [R_B1]^T``.

    Args:
        form: ``"corrected"``, ``"eq9.1"`` or ``"eq9.2"``.
    """
    first = -tilde(r2_dot) @ cfg.R_B1_T
    if form == "eq9.2":
        return first - tilde(cfg.r2) @ T(tilde(omega_B1))
    if form == "eq9.1":
        return first - tilde(cfg.r2) @ eq8(cfg, omega_B1)
    return first - tilde(cfg.r2) @ tilde(omega_B1) @ cfg.R_B1_T


def partials_dot(cfg, u, printed=frozenset()):
    """Time derivatives of the eq3 blocks along the motion, each ``(..., 3, 3)``.

    ``(0, case1-a, eq8, eq9)``; ``printed`` may hold ``"eq9.1"`` or ``"eq9.2"``.
    """
    omega_B1, _, _ = angular_velocities(cfg, u)
    q2_dot, s2_dot, r2_dot = rates(cfg, u)
    form = "eq9.2" if "eq9.2" in printed else "eq9.1" if "eq9.1" in printed else "corrected"
    return (
        zeros_like(cfg),
        case1_a(q2_dot, s2_dot, r2_dot),
        eq8(cfg, omega_B1),
        eq9(cfg, omega_B1, r2_dot, form),
    )


def eq4_acceleration(cfg, u, udot, V, Vdot, printed=frozenset()):
    """eq4: G2's acceleration in R, fixed components, ``(..., 3)``, m/s^2.

    ``{a_G2} = [v_{G2,s1_dot}]{s1_ddot} + [v_{G2,omega_B1}]{omega_B1_dot}
    + [v_dot_{G2,omega_B1}]{omega_B1} + [v_{G2,s2'_dot}]{s2'_ddot}
    + [v_dot_{G2,s2'_dot}]{s2'_dot} + [v_{G2,omega_hat_B2}]{omega_hat_B2_dot}
    + [v_dot_{G2,omega_hat_B2}]{X}``

    The note prints ``X`` as ``omega_dot_B2``. Read literally (``"eq4"`` in
    ``printed``) that is B2's angular acceleration in R, fixed components,
    ``omega_B1_dot + [omega_B1~][R_B1]^T omega_hat_B2 + [R_B1]^T omega_hat_B2_dot``,
    and the result is wrong. Read as the note's own subscripts read the same
    glyph, ``X = omega_hat_B2``, and this is the chain rule of eq3: corrected.

    Args:
        V, Vdot: the four blocks of eq3 and of their derivatives.
    """
    if "eq4" not in printed:
        return chain_rule(V, Vdot, u, udot)
    _, omega_B1, _, omega_hat_B2 = split(u)
    omega_B2_dot = (
        udot[..., 3:6]
        + mv(tilde(omega_B1) @ cfg.R_B1_T, omega_hat_B2)
        + mv(cfg.R_B1_T, udot[..., 9:12])
    )
    head = np.broadcast_to(u[..., :9], omega_B2_dot.shape[:-1] + (9,))
    return chain_rule(V, Vdot, np.concatenate([head, omega_B2_dot], -1), udot)
