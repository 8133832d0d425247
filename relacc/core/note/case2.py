"""Case 2: body-frame angular velocity components as generalized speeds.

``u = [s1_dot, omega'_B1, s2'_dot, omega_hat'_B2]``: ``omega'_B1`` in B1
components, ``omega_hat'_B2`` (angular velocity of B2 in B1) in B2 components.
Every result is in fixed-frame components.

Equation ids: ``eq2`` (velocity), ``eq10`` (partial velocities), ``eq11``
(acceleration: announced by the note, not printed; derived here),
``case2-a.1`` and ``case2-a.2`` (the two printed forms of a), ``case2-b``,
``case2-c``.

``[^{B2}R_{B1}]`` maps B2 to B1 components (``R_B2B1``); its transpose, the
note's ``[^{B1}R_{B2}]``, maps B1 to B2 components.
"""

from __future__ import annotations

from relacc.core.note.common import T, chain_rule, identity_like, mv, split, zeros_like
from relacc.core.rotations import tilde


def angular_velocities(cfg, u):
    """``(omega'_B1, omega_hat'_B2, omega'_B2)``, each ``(..., 3)``, rad/s.

    ``omega'_B1``: B1's angular velocity in R, B1 components.
    ``omega_hat'_B2``: B2's angular velocity in B1, B2 components.
    ``omega'_B2 = [^{B1}R_{B2}] omega'_B1 + omega_hat'_B2``: B2's angular
    velocity in R, B2 components (the note's undefined ``omega'_B2``).
    """
    _, omega_B1_p, _, omega_hat_B2_p = split(u)
    return omega_B1_p, omega_hat_B2_p, mv(T(cfg.R_B2B1), omega_B1_p) + omega_hat_B2_p


def eq2_velocity(cfg, u):
    """eq2: ``{v_G2} = {s1_dot} - [R_B1]^T([q2'~] + [s2'~]){omega'_B1}
    - [R_B2]^T[r2'~][^{B2}R_{B1}]^T{omega'_B1} + [R_B1]^T{s2'_dot}
    - [R_B2]^T[r2'~]{omega_hat'_B2}``.

    Returns:
        G2's velocity in R, fixed components, ``(..., 3)``, m/s.
    """
    s1_dot, omega_B1_p, s2_p_dot, omega_hat_B2_p = split(u)
    lever_p = tilde(cfg.q2_p) + tilde(cfg.s2_p)
    r_t = tilde(cfg.r2_p)
    return (
        s1_dot
        - mv(cfg.R_B1_T @ lever_p, omega_B1_p)
        - mv(cfg.R_B2_T @ r_t @ T(cfg.R_B2B1), omega_B1_p)
        + mv(cfg.R_B1_T, s2_p_dot)
        - mv(cfg.R_B2_T @ r_t, omega_hat_B2_p)
    )


def eq10_partials(cfg):
    """eq10: partial velocity blocks of G2, fixed components, each ``(..., 3, 3)``.

    * ``[v_{G2,s1_dot}] = I``
    * ``[v_{G2,omega'_B1}] = -[R_B1]^T([q2'~] + [s2'~]) - [R_B2]^T[r2'~][^{B2}R_{B1}]^T`` (m)
    * ``[v_{G2,s2'_dot}] = [R_B1]^T``
    * ``[v_{G2,omega_hat'_B2}] = -[R_B2]^T[r2'~]`` (m)
    """
    r_t = tilde(cfg.r2_p)
    return (
        identity_like(cfg),
        -cfg.R_B1_T @ (tilde(cfg.q2_p) + tilde(cfg.s2_p)) - cfg.R_B2_T @ r_t @ T(cfg.R_B2B1),
        cfg.R_B1_T,
        -cfg.R_B2_T @ r_t,
    )


def case2_a(cfg, u, form="corrected"):
    """case2-a: ``[v_dot_{G2,omega'_B1}]``, fixed components, ``(..., 3, 3)``, m/s.

    * ``case2-a.1`` (printed first line, right):
      ``-[R_B1]^T[s2'_dot~] - [R_B1_dot]^T([q2'~]+[s2'~]) - [R_B2_dot]^T[r2'~][^{B2}R_{B1}]^T
      - [R_B2]^T[r2'~][^{B1}R_{B2}]_dot``, each derivative of a rotation
      evaluated by the product rule.
    * ``case2-a.2`` (printed expansion, wrong): the last term printed as
      ``-[R_B2]^T[r2'~][omega'_B2~][^{B1}R_{B2}]``.
    * corrected: ``d/dt [^{B1}R_{B2}] = -[omega_hat'_B2~][^{B1}R_{B2}]`` (relative
      angular velocity, and a minus sign), so the last term is
      ``+[R_B2]^T[r2'~][omega_hat'_B2~][^{B1}R_{B2}]``. The printed form has
      the sign flipped and the absolute ``omega'_B2`` where the relative
      ``omega_hat'_B2`` belongs.

    Args:
        form: ``"corrected"``, ``"case2-a.1"`` or ``"case2-a.2"``.
    """
    omega_B1_p, omega_hat_B2_p, omega_B2_p = angular_velocities(cfg, u)
    s2_p_dot = u[..., 6:9]
    lever_p = tilde(cfg.q2_p) + tilde(cfg.s2_p)
    r_t = tilde(cfg.r2_p)
    R_B1B2 = T(cfg.R_B2B1)  # the note's [^{B1}R_{B2}]: B1 -> B2 components
    first = -cfg.R_B1_T @ tilde(s2_p_dot)
    if form == "case2-a.1":
        R_B1_T_dot = cfg.R_B1_T @ tilde(omega_B1_p)
        R_B2_T_dot = cfg.R_B2_T @ tilde(omega_B2_p)
        # [^{B1}R_{B2}] = [R_B2][R_B1]^T, differentiated by the product rule.
        R_B1B2_dot = T(R_B2_T_dot) @ cfg.R_B1_T + T(cfg.R_B2_T) @ R_B1_T_dot
        return (
            first
            - R_B1_T_dot @ lever_p
            - R_B2_T_dot @ r_t @ R_B1B2
            - cfg.R_B2_T @ r_t @ R_B1B2_dot
        )
    common = (
        first
        - cfg.R_B1_T @ tilde(omega_B1_p) @ lever_p
        - cfg.R_B2_T @ tilde(omega_B2_p) @ r_t @ R_B1B2
    )
    if form == "case2-a.2":
        return common - cfg.R_B2_T @ r_t @ tilde(omega_B2_p) @ R_B1B2
    return common + cfg.R_B2_T @ r_t @ tilde(omega_hat_B2_p) @ R_B1B2


def case2_b(cfg, omega_B1_p):
    """case2-b: ``[v_dot_{G2,s2'_dot}] = [R_B1_dot]^T = [R_B1]^T[omega'_B1~]``, (..., 3, 3), 1/s.

    (The note's subscript reads ``s2'_ddot``; a typesetting slip.)
    """
    return cfg.R_B1_T @ tilde(omega_B1_p)


def case2_c(cfg, omega_B2_p):
    """case2-c: ``[v_dot_{G2,omega_hat'_B2}] = -[R_B2_dot]^T[r2'~] = -[R_B2]^T[omega'_B2~][r2'~]``.

    ``omega'_B2`` is B2's angular velocity in R, B2 components. Returns
    ``(..., 3, 3)``, m/s.
    """
    return -cfg.R_B2_T @ tilde(omega_B2_p) @ tilde(cfg.r2_p)


def partials_dot(cfg, u, printed=frozenset()):
    """Time derivatives of the eq10 blocks along the motion: ``(0, case2-a, case2-b, case2-c)``.

    ``printed`` may hold ``"case2-a.1"`` or ``"case2-a.2"``.
    """
    omega_B1_p, _, omega_B2_p = angular_velocities(cfg, u)
    form = (
        "case2-a.2" if "case2-a.2" in printed else "case2-a.1" if "case2-a.1" in printed else "corrected"
    )
    return (zeros_like(cfg), case2_a(cfg, u, form), case2_b(cfg, omega_B1_p), case2_c(cfg, omega_B2_p))


def eq11_acceleration(V, Vdot, u, udot):
    """eq11 (missing from the note, derived): G2's acceleration in R, fixed comps, m/s^2.

    ``{a_G2} = [v_{G2,s1_dot}]{s1_ddot} + [v_{G2,omega'_B1}]{omega'_B1_dot}
    + [v_dot_{G2,omega'_B1}]{omega'_B1} + [v_{G2,s2'_dot}]{s2'_ddot}
    + [v_dot_{G2,s2'_dot}]{s2'_dot} + [v_{G2,omega_hat'_B2}]{omega_hat'_B2_dot}
    + [v_dot_{G2,omega_hat'_B2}]{omega_hat'_B2}``, the derivative of eq10.
    ``omega'_B1_dot`` is the derivative of the B1 components (equal to the B1
    components of B1's angular acceleration).
    """
    return chain_rule(V, Vdot, u, udot)
