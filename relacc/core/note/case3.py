"""Case 3: 1-2-3 orientation angle rates as generalized speeds.

``u = [s1_dot, theta_B1_dot, s2'_dot, theta_B2_dot]``; ``theta_B1`` orients B1
in R, ``theta_B2`` orients B2 in B1, both body-fixed 1-2-3. Every result is
in fixed-frame components.

Equation ids: ``case3-partials`` (the velocity expression and its partial
velocity matrices), ``eq12`` (acceleration), ``case3-rates`` (the derivatives
of the partial velocity matrices).

The note writes ``[omega_{B2,theta_B2_dot}]`` where Eq. 1 has
``[R_B1]^T {omega_hat_B2}`` and defers the matrix to "previous notes for a
1-2-3 rotation sequence". That matrix gives B2's angular velocity relative
to its reference body B1 in *B1* components, so read literally (the printed
variant) the formula misses a factor ``[R_B1]^T``. Read as the partial of
B2's angular velocity in R in *fixed* components,
``[omega_{B2,theta_B2_dot}] = [R_B1]^T [W(theta_B2)]``, it is right: the
corrected variant uses that reading.
"""

from __future__ import annotations

from relacc.core.note.case1 import eq5_q2_dot, eq6_s2_dot, eq7_r2_dot
from relacc.core.note.common import chain_rule, identity_like, mv, split, zeros_like
from relacc.core.rotations import omega_partials_123, omega_partials_123_dot, tilde


def omega_partials(cfg, printed=frozenset()):
    """``([omega_{B1,theta_B1_dot}], [omega_{B2,theta_B2_dot}])``, fixed components, (..., 3, 3).

    The first is ``W(theta_B1)``; the second ``[R_B1]^T W(theta_B2)`` (corrected)
    or ``W(theta_B2)`` (``"case3-partials"`` printed, literal reading).
    """
    W1 = omega_partials_123(cfg.theta_B1)
    W2 = omega_partials_123(cfg.theta_B2)
    return W1, (W2 if "case3-partials" in printed else cfg.R_B1_T @ W2)


def omega_partials_dot(cfg, u, printed=frozenset()):
    """Time derivatives of :func:`omega_partials`, fixed components, (..., 3, 3), 1/s.

    ``d/dt([R_B1]^T W(theta_B2)) = [omega_B1~][R_B1]^T W(theta_B2) + [R_B1]^T W_dot(theta_B2)``
    (corrected); ``W_dot(theta_B2)`` alone for ``"case3-rates"`` printed.
    """
    _, th1_dot, _, th2_dot = split(u)
    W1_dot = omega_partials_123_dot(cfg.theta_B1, th1_dot)
    W2_dot = omega_partials_123_dot(cfg.theta_B2, th2_dot)
    if "case3-rates" in printed:
        return W1_dot, W2_dot
    omega_B1 = mv(omega_partials_123(cfg.theta_B1), th1_dot)
    W2 = omega_partials_123(cfg.theta_B2)
    return W1_dot, tilde(omega_B1) @ cfg.R_B1_T @ W2 + cfg.R_B1_T @ W2_dot


def angular_velocities(cfg, u):
    """``(omega_B1, omega_hat_B2 in fixed components, omega_B2)``, (..., 3), rad/s.

    ``omega_B1 = W(theta_B1) theta_B1_dot``; B2's angular velocity in B1 is
    ``[R_B1]^T W(theta_B2) theta_B2_dot`` in fixed components, and
    ``omega_B2 = omega_B1 +`` that.
    """
    _, th1_dot, _, th2_dot = split(u)
    omega_B1 = mv(omega_partials_123(cfg.theta_B1), th1_dot)
    w_hat = mv(cfg.R_B1_T @ omega_partials_123(cfg.theta_B2), th2_dot)
    return omega_B1, w_hat, omega_B1 + w_hat


def velocity(cfg, u, printed=frozenset()):
    """case3-partials (velocity line): G2's velocity in R, fixed components, (..., 3), m/s.

    ``{v_G2} = {s1_dot} - ([q2~]+[s2~]+[r2~])[omega_{B1,theta_B1_dot}]{theta_B1_dot}
    + [R_B1]^T{s2'_dot} - [r2~][omega_{B2,theta_B2_dot}]{theta_B2_dot}``
    """
    s1_dot, th1_dot, s2_p_dot, th2_dot = split(u)
    P1, P2 = omega_partials(cfg, printed)
    lever = tilde(cfg.q2) + tilde(cfg.s2) + tilde(cfg.r2)
    return s1_dot - mv(lever @ P1, th1_dot) + mv(cfg.R_B1_T, s2_p_dot) - mv(tilde(cfg.r2) @ P2, th2_dot)


def partials(cfg, printed=frozenset()):
    """case3-partials: partial velocity blocks of G2, fixed components, (..., 3, 3).

    * ``[v_{G2,s1_dot}] = I``
    * ``[v_{G2,theta_B1_dot}] = -([q2~]+[s2~]+[r2~])[omega_{B1,theta_B1_dot}]`` (m/rad)
    * ``[v_{G2,s2'_dot}] = [R_B1]^T``
    * ``[v_{G2,theta_B2_dot}] = -[r2~][omega_{B2,theta_B2_dot}]`` (m/rad)
    """
    P1, P2 = omega_partials(cfg, printed)
    return (
        identity_like(cfg),
        -(tilde(cfg.q2) + tilde(cfg.s2) + tilde(cfg.r2)) @ P1,
        cfg.R_B1_T,
        -tilde(cfg.r2) @ P2,
    )


def partials_dot(cfg, u, printed=frozenset()):
    """case3-rates: time derivatives of the case3-partials blocks, (..., 3, 3).

    * ``[v_dot_{G2,theta_B1_dot}] = -([q2_dot~]+[s2_dot~]+[r2_dot~])[omega_{B1,theta_B1_dot}]
      - ([q2~]+[s2~]+[r2~])[omega_dot_{B1,theta_B1_dot}]``
    * ``[v_dot_{G2,s2'_dot}] = [omega_B1~][R_B1]^T``
    * ``[v_dot_{G2,theta_B2_dot}] = -[r2_dot~][omega_{B2,theta_B2_dot}] - [r2~][omega_dot_{B2,theta_B2_dot}]``

    ``q2_dot``, ``s2_dot``, ``r2_dot`` come from eq5-eq7 with the angular
    velocities of :func:`angular_velocities`. ``printed`` may hold
    ``"case3-partials"`` (literal ``[omega_{B2,theta_B2_dot}]``) and
    ``"case3-rates"`` (literal derivative).
    """
    omega_B1, _, omega_B2 = angular_velocities(cfg, u)
    q2_dot = eq5_q2_dot(cfg, omega_B1)
    s2_dot = eq6_s2_dot(cfg, omega_B1, u[..., 6:9])
    r2_dot = eq7_r2_dot(cfg, omega_B2)
    P1, P2 = omega_partials(cfg, printed)
    P1_dot, P2_dot = omega_partials_dot(cfg, u, printed)
    lever = tilde(cfg.q2) + tilde(cfg.s2) + tilde(cfg.r2)
    lever_dot = tilde(q2_dot) + tilde(s2_dot) + tilde(r2_dot)
    return (
        zeros_like(cfg),
        -lever_dot @ P1 - lever @ P1_dot,
        tilde(omega_B1) @ cfg.R_B1_T,
        -tilde(r2_dot) @ P2 - tilde(cfg.r2) @ P2_dot,
    )


def eq12_acceleration(V, Vdot, u, udot):
    """eq12: G2's acceleration in R, fixed components, (..., 3), m/s^2.

    ``{a_G2} = [v_{G2,s1_dot}]{s1_ddot} + [v_{G2,theta_B1_dot}]{theta_B1_ddot}
    + [v_dot_{G2,theta_B1_dot}]{theta_B1_dot} + [v_{G2,s2'_dot}]{s2'_ddot}
    + [v_dot_{G2,s2'_dot}]{s2'_dot} + [v_{G2,theta_B2_dot}]{theta_B2_ddot}
    + [v_dot_{G2,theta_B2_dot}]{theta_B2_dot}``
    """
    return chain_rule(V, Vdot, u, udot)
