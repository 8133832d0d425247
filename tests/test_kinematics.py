"""The core's G2 formulas against derivatives along the motion and hand-derived states.

References are independent of the formulas under test: complex-step time
derivatives of the core's own *position* (and of V), computed on the moved
configuration, and closed-form motions worked out by hand.
"""

import numpy as np
import pytest

import relacc
from relacc.core import speeds
from relacc.core.derivatives import along_motion
from relacc.core.note.equations import EQUATIONS
from relacc.core.scales import term_scales
from relacc.core.states import random_states
from relacc.core.tolerances import assert_normalized_error, normalized_error, richardson_bound, rounding_tolerance

from .conftest import N_STATES, seed_for


def _states(case, offset=0, n=N_STATES):
    return random_states(case, n, seed_for(case, offset))


def _field(chain, case, name, variant="corrected"):
    return lambda q, u: getattr(relacc.g2_kinematics(chain, case, q, u, variant=variant), name)


def test_velocity_is_time_derivative_of_position(chain, case):
    """v_G2 equals d/dt r_G2 along the motion (complex step), 1000 states."""
    s = _states(case)
    k = relacc.g2_kinematics(chain, case, s.q, s.u)
    ref = along_motion(case, s.q, s.u, None, _field(chain, case, "position"))
    assert_normalized_error(k.velocity, ref, term_scales(chain, case, s.q, s.u).velocity, what="velocity", seed=s.seed)


def test_V_is_the_linear_map_from_speeds_to_velocity(chain, case):
    """[V]{u} equals the velocity formula, and V is independent of u, 1000 states."""
    s = _states(case, 1)
    k = relacc.g2_kinematics(chain, case, s.q, s.u)
    sc = term_scales(chain, case, s.q, s.u)
    assert_normalized_error(np.einsum("nij,nj->ni", k.V, s.u), k.velocity, sc.velocity, what="V u", seed=s.seed)
    other = relacc.g2_kinematics(chain, case, s.q, 2 * s.u + 1)
    assert np.array_equal(other.V, k.V)


def test_acceleration_is_time_derivative_of_velocity(chain, case):
    """a_G2 equals d/dt v_G2 along the motion with u moving at udot, 1000 states."""
    s = _states(case, 2)
    k = relacc.g2_kinematics(chain, case, s.q, s.u, s.udot)
    ref = along_motion(case, s.q, s.u, s.udot, _field(chain, case, "velocity"))
    sc = term_scales(chain, case, s.q, s.u, s.udot)
    assert_normalized_error(k.acceleration, ref, sc.acceleration, what="acceleration", seed=s.seed)


def test_Vdot_is_time_derivative_of_V(chain, case):
    """Vdot equals d/dt V along the motion on the moved configuration, 1000 states."""
    s = _states(case, 3)
    k = relacc.g2_kinematics(chain, case, s.q, s.u)
    ref = along_motion(case, s.q, s.u, None, _field(chain, case, "V"))
    assert_normalized_error(k.Vdot, ref, term_scales(chain, case, s.q, s.u).Vdot, what="Vdot", seed=s.seed)


def test_acceleration_is_V_udot_plus_Vdot_u(chain, case):
    """a = V udot + Vdot u, 1000 states: the reference path's V and Vdot against the fused kernel's acceleration.

    Not a tautology: the reference path forms its acceleration by that very chain rule, but the kernel behind
    :func:`relacc.g2_acceleration` sums the angular accelerations' terms (``perstate.acc_from``) and never forms
    V or Vdot."""
    s = _states(case, 4)
    k = relacc.g2_kinematics(chain, case, s.q, s.u, s.udot, backend="reference")
    ref = np.einsum("nij,nj->ni", k.V, s.udot) + np.einsum("nij,nj->ni", k.Vdot, s.u)
    fast = relacc.g2_acceleration(chain, case, s.q, s.u, s.udot, backend="fast")
    sc = term_scales(chain, case, s.q, s.u, s.udot)
    assert_normalized_error(fast, ref, sc.acceleration, what="V udot + Vdot u", seed=s.seed)


def test_richardson_agrees_within_its_truncation_bound(chain, case):
    """A real-step method (Richardson, h = 1e-3 s) agrees within its O(h^4) + eps/h error model."""
    s = _states(case, 5, n=200)
    h = 1e-3
    k = relacc.g2_kinematics(chain, case, s.q, s.u, s.udot)
    ref = along_motion(case, s.q, s.u, s.udot, _field(chain, case, "velocity"), method="richardson", h=h)
    sc = term_scales(chain, case, s.q, s.u, s.udot)
    # |v^(5)| <= (|u| + |udot| + 1)^5 times the terms' magnitude (speeds ~ N(0, 1)); |v| <= its term scale.
    speed = np.linalg.norm(s.u, axis=-1) + np.linalg.norm(s.udot, axis=-1) + 1
    bound = richardson_bound(h, speed**5 * (sc.acceleration + sc.velocity), sc.velocity + sc.position)
    err = np.abs(k.acceleration - ref).max(axis=-1)
    assert np.all(err <= bound), f"Richardson error above its bound (seed {s.seed})"


def test_pure_spin_about_z_matches_hand_derivation(chain, case):
    """Identity orientations, B1 spinning at w about z: v = w e_z x L, a = -w^2 L_xy (by hand)."""
    w = 2.5
    lever = chain.q2 + chain.r2  # s2' = 0, all frames aligned
    if case == 3:
        q = np.zeros(12)
    else:
        q = np.zeros(14)
        q[3] = q[10] = 1.0
    u = np.zeros(12)
    u[5] = w  # omega_B1 = w e_z in every case at the identity orientation
    k = relacc.g2_kinematics(chain, case, q, u, np.zeros(12))
    v_ref = np.array([-w * lever[1], w * lever[0], 0.0])
    a_ref = np.array([-(w**2) * lever[0], -(w**2) * lever[1], 0.0])
    sc = term_scales(chain, case, q, u, np.zeros(12))
    assert_normalized_error(k.velocity, v_ref, sc.velocity, what="spin velocity")
    assert_normalized_error(k.acceleration, a_ref, sc.acceleration, what="spin acceleration")


def test_prismatic_slide_only_is_rigid_translation(chain, case):
    """Only s2' moving: G2's velocity is [R_B1]^T s2'_dot and its acceleration [R_B1]^T s2'_ddot."""
    s = _states(case, 6, n=100)
    u = np.zeros_like(s.u)
    udot = np.zeros_like(s.udot)
    u[:, 6:9], udot[:, 6:9] = s.u[:, 6:9], s.udot[:, 6:9]
    k = relacc.g2_kinematics(chain, case, s.q, u, udot)
    R = k.V[:, :, 6:9]  # [R_B1]^T, checked orthonormal below
    assert_normalized_error(R @ np.swapaxes(R, 1, 2), np.eye(3), np.ones(100), what="R R^T", factor=8)
    sc = term_scales(chain, case, s.q, u, udot)
    assert_normalized_error(k.velocity, np.einsum("nij,nj->ni", R, u[:, 6:9]), sc.velocity, what="slide v")
    assert_normalized_error(k.acceleration, np.einsum("nij,nj->ni", R, udot[:, 6:9]), sc.acceleration, what="slide a")


def test_same_motion_gives_same_kinematics_in_every_case(chain):
    """A case-3 state mapped to cases 1 and 2 gives the same r, v, a; V and Vdot map through W."""
    s = _states(3, 7)
    k3 = relacc.g2_kinematics(chain, 3, s.q, s.u, s.udot)
    q14, nu, nu_dot = speeds.to_body_speeds(3, s.q, s.u, s.udot)
    k2 = relacc.g2_kinematics(chain, 2, q14, nu, nu_dot)
    # Case 1 speeds from body speeds: omega_B1 = [R_B1]^T omega'_B1, omega_hat_B2 = [^{B2}R_{B1}] omega_hat'_B2.
    W1, W1_dot = speeds.body_speed_map(1, q14, np.zeros_like(nu))
    u1 = np.linalg.solve(W1, nu[..., None])[..., 0]
    W1, W1_dot = speeds.body_speed_map(1, q14, u1)
    u1_dot = np.linalg.solve(W1, (nu_dot - np.einsum("nij,nj->ni", W1_dot, u1))[..., None])[..., 0]
    k1 = relacc.g2_kinematics(chain, 1, q14, u1, u1_dot)
    sc = term_scales(chain, 3, s.q, s.u, s.udot)
    for other in (k1, k2):
        assert_normalized_error(other.position, k3.position, sc.position, what="position", seed=s.seed)
        assert_normalized_error(other.velocity, k3.velocity, sc.velocity, what="velocity", seed=s.seed)
        assert_normalized_error(other.acceleration, k3.acceleration, sc.acceleration, what="acceleration", seed=s.seed)
    W3, W3_dot = speeds.body_speed_map(3, s.q, s.u)
    assert_normalized_error(k2.V @ W3, k3.V, sc.V, what="V2 W = V3", seed=s.seed)
    assert_normalized_error(k2.Vdot @ W3 + k2.V @ W3_dot, k3.Vdot, sc.Vdot, what="Vdot map", seed=s.seed)


def test_body_speed_map_rate_is_time_derivative(case):
    """W_dot equals the complex-step derivative of W along the motion."""
    s = _states(case, 8, n=300)
    W, W_dot = speeds.body_speed_map(case, s.q, s.u)
    ref = along_motion(case, s.q, s.u, None, lambda q, u: speeds.body_speed_map(case, q))
    assert_normalized_error(W_dot, ref, np.linalg.norm(s.u, axis=-1), what="W_dot", seed=s.seed, factor=16)


def test_batched_equals_single_state(chain, case):
    """Each state of a batch equals its own single-state evaluation to a few ulps."""
    s = _states(case, 9, n=25)
    k = relacc.g2_kinematics(chain, case, s.q, s.u, s.udot)
    sc = term_scales(chain, case, s.q, s.u, s.udot)
    for i in range(len(s)):
        one = relacc.g2_kinematics(chain, case, s.q[i], s.u[i], s.udot[i])
        for name in ("position", "velocity", "acceleration", "V", "Vdot"):
            assert_normalized_error(getattr(one, name), getattr(k, name)[i], sc.of(name)[i],
                                    what=name, seed=s.seed, factor=4)


def test_batch_shapes_broadcast(chain, case):
    """A (2, 5) batch of q with one shared u gives (2, 5, ...) results."""
    s = _states(case, 10, n=10)
    q = s.q.reshape(2, 5, -1)
    k = relacc.g2_kinematics(chain, case, q, s.u[0], s.udot[0])
    assert k.position.shape == (2, 5, 3) and k.V.shape == (2, 5, 3, 12)
    assert k.acceleration.shape == (2, 5, 3) and k.Vdot.shape == (2, 5, 3, 12)
    flat = relacc.g2_kinematics(chain, case, s.q, np.broadcast_to(s.u[0], (10, 12)),
                                np.broadcast_to(s.udot[0], (10, 12)))
    assert np.array_equal(k.acceleration.reshape(10, 3), flat.acceleration)


def test_results_are_immutable(chain):
    """G2Kinematics arrays cannot be written to."""
    s = _states(1, 11, n=2)
    k = relacc.g2_kinematics(chain, 1, s.q, s.u, s.udot)
    with pytest.raises(ValueError):
        k.velocity[0, 0] = 1.0
    with pytest.raises(AttributeError):
        k.velocity = None


def _measured(chain, equation, s):
    """(value, independent reference, scale) of the output an equation id is measured through."""
    case = equation.case
    k = relacc.g2_kinematics(chain, case, s.q, s.u, s.udot, variant={equation.id})
    sc = term_scales(chain, case, s.q, s.u, s.udot)
    d = lambda name, udot=None: along_motion(case, s.q, s.u, udot, _field(chain, case, name))  # noqa: E731
    if equation.quantity == "velocity":
        return k.velocity, d("position"), sc.velocity
    if equation.quantity == "V":  # through V u: a wrong block gives a wrong product
        return np.einsum("nij,nj->ni", k.V, s.u), d("position"), sc.velocity
    if equation.quantity == "Vdot":
        return k.Vdot, d("V"), sc.Vdot
    return k.acceleration, d("velocity", s.udot), sc.acceleration


@pytest.mark.parametrize("equation", EQUATIONS, ids=lambda e: e.id)
def test_printed_forms_against_derivatives(chain, equation):
    """Each id's printed form: equal to the corrected one when they coincide, off by O(1) when they differ."""
    s = _states(equation.case, 12, n=200)
    err = normalized_error(*_measured(chain, equation, s))
    if equation.differs:
        assert np.median(err) > 1e-3, f"{equation.id}: printed form unexpectedly agrees (seed {s.seed})"
    else:
        assert err.max() <= rounding_tolerance(), f"{equation.id}: {err.max():.3g} (seed {s.seed})"


def test_printed_variant_changes_only_the_wrong_blocks(chain):
    """variant='printed' in Case 1 changes Vdot's omega_hat_B2 block and the acceleration, nothing else."""
    s = _states(1, 13, n=50)
    kc = relacc.g2_kinematics(chain, 1, s.q, s.u, s.udot, backend="reference")
    kp = relacc.g2_kinematics(chain, 1, s.q, s.u, s.udot, variant="printed")
    assert np.array_equal(kc.position, kp.position) and np.array_equal(kc.V, kp.V)
    assert np.array_equal(kc.Vdot[..., :9], kp.Vdot[..., :9])
    # every state's printed block differs by far more than rounding (measured: at least 0.095 here, against
    # rounding_tolerance() ~ 1e-13), so the printed form is a different formula, not a rounding of the same one
    gap = np.abs(kc.Vdot[..., 9:] - kp.Vdot[..., 9:]).reshape(len(s), -1).max(axis=1)
    assert gap.min() > 1e6 * rounding_tolerance(), f"seed {s.seed}: {gap.min():.3g}"
    assert kp.variant == "printed"
