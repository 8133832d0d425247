"""Kane's equations of the two-body chain from the partial velocities of each case.

For a case's speeds ``u``, with fixed-frame components throughout:

* ``v_G2 = [V_G2] u`` from the note (:func:`relacc.g2_kinematics`);
* ``v_G1 = [V_G1] u`` with ``[V_G1] = [I, -[r1~][P1], 0, 0]``, ``r1 = [R_B1]^T r1'``;
* ``omega_B1 = [Om1] u``, ``[Om1] = [0, P1, 0, 0]``;
* ``omega_B2 = [Om2] u``, ``[Om2] = [0, P1, 0, G]``;

where ``[P1] = [R_B1]^T [W11]`` maps the case's B1 speeds to B1's angular
velocity and ``[G] = [R_B2]^T [W22]`` maps its B2 speeds to B2's angular
velocity in B1 (``W11``, ``W22``: the blocks of :func:`relacc.core.speeds.body_speed_map`).
Kane's equations ``sum_i [V_Gi]^T (F_i - m_i a_Gi) + [Om_i]^T (T_i - I_i alpha_i - omega_i x I_i omega_i) = 0``
give ``[M] udot = {f}`` with

    M = sum_i m_i V_Gi^T V_Gi + Om_i^T I_i Om_i,
    f = Q - sum_i m_i V_Gi^T Vdot_Gi u + Om_i^T (I_i Omdot_i u + omega_i x I_i omega_i),

``I_i`` the inertia about G_i in fixed components and ``Q`` the generalized
forces of the active effects only (:mod:`relacc.dynamics.effects`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from relacc.core.cases import Case, as_case, check_q, check_u, layout
from relacc.core.chain import TwoBodyChain
from relacc.core.kinematics import check_finite_result, check_out, g2_kinematics
from relacc.core.note.common import T, configuration, mv
from relacc.core.rotations import tilde
from relacc.core.speeds import body_speed_map, check_invertible
from relacc.dynamics.effects import NONE, Effects
from relacc.errors import InputError


@dataclass(frozen=True, eq=False)
class BodyPartials:
    """Partial velocities and angular velocities of both bodies, fixed components, per state.

    Attributes:
        V1, V1dot: ``(..., 3, 12)`` of G1 (m/s per unit speed) and rates.
        V2, V2dot: ``(..., 3, 12)`` of G2.
        Om1, Om1dot, Om2, Om2dot: ``(..., 3, 12)`` of B1, B2 (rad/s per unit speed).
        R1, R2: ``[R_B1]^T``, ``[R_B2]^T`` ``(..., 3, 3)``; r1, r2: ``{r1}``, ``{r2}`` (fixed, m).
        rG1, rG2: positions of G1, G2 (fixed, m).
    """

    V1: np.ndarray
    V1dot: np.ndarray
    V2: np.ndarray
    V2dot: np.ndarray
    Om1: np.ndarray
    Om1dot: np.ndarray
    Om2: np.ndarray
    Om2dot: np.ndarray
    R1: np.ndarray
    R2: np.ndarray
    rG1: np.ndarray
    rG2: np.ndarray


def body_partials(chain: TwoBodyChain, case: int, q: ArrayLike, u: ArrayLike) -> BodyPartials:
    """Partial velocity and angular velocity matrices of G1, G2, B1, B2 (see the module docstring).

    Raises:
        InputError: bad shapes or values of ``q``, ``u`` (lists and tuples are accepted).
    """
    c = as_case(case)
    q, u = check_q(c, q), check_u(f"u for case {int(c)}", u)
    cfg = configuration(chain, c, q)
    k = g2_kinematics(chain, c, q, u)
    W, Wd = body_speed_map(c, q, u)
    batch = k.V.shape[:-2]
    R1, R2 = np.broadcast_to(cfg.R_B1_T, batch + (3, 3)), np.broadcast_to(cfg.R_B2_T, batch + (3, 3))
    P1 = R1 @ W[..., 3:6, 3:6]
    G = R2 @ W[..., 9:12, 9:12]
    w1 = mv(P1, u[..., 3:6])
    w2 = w1 + mv(G, u[..., 9:12])
    P1d = tilde(w1) @ P1 + R1 @ Wd[..., 3:6, 3:6]
    Gd = tilde(w2) @ G + R2 @ Wd[..., 9:12, 9:12]
    r1 = mv(R1, chain.r1)
    zero = np.zeros(batch + (3, 12), dtype=np.result_type(P1, Gd, r1))

    def blocks(*pairs):
        out = zero.copy()
        for col, mat in pairs:
            out[..., :, col:col + 3] = mat
        return out

    eye = np.broadcast_to(np.eye(3), batch + (3, 3))
    V1 = blocks((0, eye), (3, -tilde(r1) @ P1))
    V1dot = blocks((3, -tilde(np.cross(w1, r1)) @ P1 - tilde(r1) @ P1d))
    return BodyPartials(
        V1=V1, V1dot=V1dot, V2=k.V, V2dot=k.Vdot,
        Om1=blocks((3, P1)), Om1dot=blocks((3, P1d)),
        Om2=blocks((3, P1), (9, G)), Om2dot=blocks((3, P1d), (9, Gd)),
        R1=R1, R2=R2, rG1=np.broadcast_to(cfg.s1, batch + (3,)) + r1, rG2=k.position,
    )


def _inertia_fixed(R, I_body):
    return R @ I_body @ T(R)


def generalized_forces(chain: TwoBodyChain, case: int, q: ArrayLike, u: ArrayLike, effects: Effects,
                       bp: BodyPartials | None = None) -> np.ndarray:
    """``{Q}`` ``(..., 12)`` of the active effects only (N, or N m per unit angular speed).

    Each absent effect is skipped, not computed as zero.
    """
    c = as_case(case)
    q, u = check_q(c, q), check_u(f"u for case {int(c)}", u)
    bp = bp if bp is not None else body_partials(chain, c, q, u)
    batch = bp.V2.shape[:-2]
    Q = np.zeros(batch + (12,), dtype=np.result_type(bp.V2, q, u))
    if effects.gravity is not None:
        Q += chain.m1 * mv(T(bp.V1), effects.gravity) + chain.m2 * mv(T(bp.V2), effects.gravity)
    lay = layout(c)
    if effects.spring_stiffness is not None:
        Q[..., 6:9] -= effects.spring_stiffness * (q[..., lay.s2_p] - effects.spring_rest)
    if effects.spring_damping is not None:
        Q[..., 6:9] -= effects.spring_damping * u[..., 6:9]
    if effects.ball_damping is not None:
        G = bp.Om2[..., :, 9:12]
        w_hat = mv(G, u[..., 9:12])  # B2's angular velocity in B1, fixed components
        Q[..., 9:12] -= effects.ball_damping * mv(T(G), w_hat)
    if effects.force_G2 is not None:
        Q += mv(T(bp.V2), effects.force_G2)
    if effects.torque_B1 is not None:
        Q += mv(T(bp.Om1), effects.torque_B1)
    if effects.torque_B2 is not None:
        Q += mv(T(bp.Om2), effects.torque_B2)
    return Q


def equations_of_motion(chain: TwoBodyChain, case: int, q: ArrayLike, u: ArrayLike, effects: Effects = NONE, *,
                        out: tuple | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Kane's equations ``[M] udot = {f}`` of the chain in a case's speeds.

    Args:
        chain: :class:`relacc.TwoBodyChain` with masses and inertias.
        case: 1, 2 or 3. q: the case's coordinates ``(..., 14)`` or ``(..., 12)``.
        u: ``(..., 12)`` speeds. effects: :class:`relacc.dynamics.effects.Effects` (default: none).

    Returns:
        ``M`` ``(..., 12, 12)`` (symmetric, positive definite away from gimbal
        lock in case 3; kg, kg m, kg m^2 blocks) and ``f`` ``(..., 12)``
        (N and N m per unit speed).

    Args:
        out: numpy's ``out`` convention: ``(M, f)`` writable C-contiguous float64 arrays
            ``batch + (12, 12)`` and ``batch + (12,)`` to write into; returned.

    Raises:
        InputError: as :func:`relacc.g2_kinematics`; effects not an Effects; a bad ``out``.
    """
    if not isinstance(chain, TwoBodyChain):
        raise InputError(f"chain: expected a relacc.TwoBodyChain, got {type(chain).__name__}")
    if not isinstance(effects, Effects):
        raise InputError(f"effects: expected relacc.dynamics.effects.Effects, got {type(effects).__name__}")
    c = as_case(case)
    q, u = check_q(c, q), check_u(f"u for case {int(c)}", u)
    bp = body_partials(chain, c, q, u)
    I1, I2 = _inertia_fixed(bp.R1, chain.I1), _inertia_fixed(bp.R2, chain.I2)
    M = (chain.m1 * T(bp.V1) @ bp.V1 + chain.m2 * T(bp.V2) @ bp.V2
         + T(bp.Om1) @ I1 @ bp.Om1 + T(bp.Om2) @ I2 @ bp.Om2)
    f = generalized_forces(chain, c, q, u, effects, bp)
    f = f - chain.m1 * mv(T(bp.V1), mv(bp.V1dot, u)) - chain.m2 * mv(T(bp.V2), mv(bp.V2dot, u))
    for Om, Omd, I in ((bp.Om1, bp.Om1dot, I1), (bp.Om2, bp.Om2dot, I2)):
        w = mv(Om, u)
        f = f - mv(T(Om), mv(I, mv(Omd, u)) + np.cross(w, mv(I, w)))
    check_finite_result((M, f), q, u)
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
            :mod:`relacc.kernels.dynamics` for real inputs), ``"fast"``, or
            ``"reference"`` (Kane's ``M`` and ``f``, :func:`equations_of_motion`,
            solved by ``numpy.linalg.solve``; case 3 in the body speeds of case 2, then mapped to the rates, so
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
    if not isinstance(chain, TwoBodyChain):
        raise InputError(f"chain: expected a relacc.TwoBodyChain, got {type(chain).__name__}")
    if not isinstance(effects, Effects):
        raise InputError(f"effects: expected relacc.dynamics.Effects, got {type(effects).__name__}")
    if backend not in ("auto", "fast", "reference"):
        raise InputError(f"unknown backend {backend!r}: accepted are auto, fast, reference")
    c = as_case(case)
    q, u = check_q(c, q, values=False), check_u(f"u for case {int(c)}", u, values=False)

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
        # solved in body speeds (case 2), mapped: M3 = W^T M2 W would square W's condition number
        if c == Case.ANGLE_RATES:
            from relacc.core.speeds import body_speed_map, quaternion_coordinates

            W, W_dot = body_speed_map(c, q, u)
            M, f = equations_of_motion(chain, 2, quaternion_coordinates(c, q), mv(W, u), effects)
            nu_dot = np.linalg.solve(M, f[..., None])[..., 0]
            udot = np.linalg.solve(W, (nu_dot - mv(W_dot, u))[..., None])[..., 0]
        else:
            M, f = equations_of_motion(chain, c, q, u, effects)
            udot = np.linalg.solve(M, f[..., None])[..., 0]
        if out is None:
            return udot
        out[...] = udot
        return out
    from relacc.kernels import dynamics as kernel

    flat = lambda a, w: np.ascontiguousarray(np.broadcast_to(a, batch + (w,)).reshape(-1, w))  # noqa: E731
    target = out.reshape(-1, 12) if out is not None else np.empty((int(np.prod(batch)), 12))
    with np.errstate(all="ignore"):
        bad, suspect = kernel.accelerations(int(c), flat(q, q.shape[-1]), flat(u, 12), kernel.chain_params(chain),
                                            kernel.effect_params(effects), target)
    if suspect:
        check_values()
    if bad:
        check_finite_result((target,), q, u)
    return out if out is not None else target.reshape(batch + (12,))


def energy_terms(chain: TwoBodyChain, case: int, q: ArrayLike, u: ArrayLike, effects: Effects = NONE
                 ) -> tuple[np.ndarray | float, np.ndarray, np.ndarray]:
    """The terms of the energy, J, each ``(...)``: ``(kinetic, gravity, spring)``.

    Gravity's potential ``-sum m_i g . r_Gi`` (0 when gravity is off), the
    spring's ``1/2 sum k (s2' - rest)^2`` (0 when off). Their sum is
    :func:`energy`; ``kinetic + |gravity| + spring`` is the magnitude of the
    terms, the scale energy drift is normalized by.
    """
    c = as_case(case)
    q, u = check_q(c, q), check_u("u", u)
    bp = body_partials(chain, c, q, u)
    T = 0.0
    for m, V, Om, R, I in ((chain.m1, bp.V1, bp.Om1, bp.R1, chain.I1), (chain.m2, bp.V2, bp.Om2, bp.R2, chain.I2)):
        v, w = mv(V, u), mv(Om, u)
        T = T + 0.5 * m * np.sum(v * v, -1) + 0.5 * np.sum(w * mv(_inertia_fixed(R, I), w), -1)
    zero = np.zeros_like(np.real(T))
    gravity = zero
    if effects.gravity is not None:
        gravity = -chain.m1 * bp.rG1 @ effects.gravity - chain.m2 * bp.rG2 @ effects.gravity
    return T, gravity, effects.spring_energy(q[..., layout(c).s2_p])


def energy(chain: TwoBodyChain, case: int, q: ArrayLike, u: ArrayLike, effects: Effects = NONE) -> np.ndarray | float:
    """Kinetic plus potential energy of the active conservative effects, J, ``(...)`` (:func:`energy_terms`)."""
    T, gravity, spring = energy_terms(chain, case, q, u, effects)
    return T + gravity + spring


def momenta(chain: TwoBodyChain, case: int, q: ArrayLike, u: ArrayLike
            ) -> tuple[np.ndarray | float, np.ndarray | float]:
    """Linear momentum ``(..., 3)`` (kg m/s) and angular momentum about R's origin ``(..., 3)`` (kg m^2/s).

    Both in fixed-frame components.
    """
    c = as_case(case)
    q, u = check_q(c, q), check_u("u", u)
    bp = body_partials(chain, c, q, u)
    p, H = 0.0, 0.0
    for m, V, Om, R, I, rG in ((chain.m1, bp.V1, bp.Om1, bp.R1, chain.I1, bp.rG1),
                               (chain.m2, bp.V2, bp.Om2, bp.R2, chain.I2, bp.rG2)):
        v, w = mv(V, u), mv(Om, u)
        p = p + m * v
        H = H + np.cross(rG, m * v) + mv(_inertia_fixed(R, I), w)
    return p, H
