"""Kane's equations: against Pinocchio and MuJoCo, energy balance, superposition, the fused kernel."""

import numpy as np
import pytest

import relacc
from relacc import dynamics
from relacc.core.derivatives import along_motion
from relacc.core.scales import dynamics_scales
from relacc.core.states import random_states
from relacc.core.tolerances import EPS, ROUNDING_FACTOR, assert_normalized_error
from relacc.dynamics.effects import NONE, Effects
from relacc.engines import CHAIN_ENGINES as ENGINES
from relacc.engines import load_engine
from relacc.kernels import dynamics as fastdyn

from .chain_engine import equations_of_motion as engine_equations
from .conftest import seed_for

ALL = Effects(gravity=[0.3, -0.5, -9.81], spring_stiffness=[40, 50, 60], spring_rest=[0.01, -0.02, 0.03],
              spring_damping=0.7, ball_damping=0.05, force_G2=[1, -2, 0.5], torque_B1=[0.1, 0.2, -0.3],
              torque_B2=[-0.2, 0.05, 0.1])
NAMES = ALL.active()


def _states(case, offset, n=200):
    s = random_states(case, n, seed_for(case, offset))
    if case == 3:  # keep away from gimbal lock, where case 3's M is singular
        s.q[:, [4, 10]] = np.clip(s.q[:, [4, 10]], -1.3, 1.3)
    return s


@pytest.fixture(scope="module")
def engines(fixture):
    return {name: load_engine(name, fixture) for name in ENGINES}


@pytest.mark.parametrize("engine", ENGINES)
def test_kane_equals_engine_through_speed_maps(fixture, engines, engine, case):
    """M = E^T M_e E and f = E^T (f_e - M_e Edot u) with every effect on, 200 states."""
    s = _states(case, 40)
    M, f = dynamics.equations_of_motion(fixture.chain, case, s.q, s.u, ALL)
    Me, fe = engine_equations(engines[engine], case, s.q, s.u, ALL)
    sM, sf = dynamics_scales(fixture.chain, case, s.q, s.u, ALL)
    assert_normalized_error(Me, M, sM, what=f"{engine} M", seed=s.seed)
    assert_normalized_error(fe, f, sf, what=f"{engine} f", seed=s.seed)


def test_mass_matrix_is_symmetric_positive_definite(fixture, case):
    """M is symmetric to rounding and positive definite away from gimbal lock."""
    s = _states(case, 41)
    M, _ = dynamics.equations_of_motion(fixture.chain, case, s.q, s.u)
    sM, _ = dynamics_scales(fixture.chain, case, s.q, s.u)
    assert_normalized_error(M, np.swapaxes(M, 1, 2), sM, what="M - M^T", seed=s.seed)
    assert np.all(np.linalg.eigvalsh(M)[:, 0] > 0)


@pytest.mark.parametrize("name", NAMES)
def test_superposition_each_effect_adds_its_generalized_force(fixture, engines, case, name):
    """f(all) - f(all but one effect) equals that effect's Q alone, in relacc and in both engines."""
    s = _states(case, 42, n=50)
    chain = fixture.chain
    others = ALL.without(name)
    only = Effects(**{k: getattr(ALL, k) for k in (name,) + (("spring_rest",) if name == "spring_stiffness" else ())})
    Q = dynamics.generalized_forces(chain, case, s.q, s.u, only)
    _, sf = dynamics_scales(chain, case, s.q, s.u, ALL)
    assert np.max(np.abs(Q)) > 1e-3, "the effect contributes nothing: a test that cannot fail"
    diff = dynamics.equations_of_motion(chain, case, s.q, s.u, ALL)[1] - \
        dynamics.equations_of_motion(chain, case, s.q, s.u, others)[1]
    assert_normalized_error(diff, Q, sf, what=f"relacc {name}", seed=s.seed)
    for engine, e in engines.items():
        diff = engine_equations(e, case, s.q, s.u, ALL)[1] - engine_equations(e, case, s.q, s.u, others)[1]
        assert_normalized_error(diff, Q, sf, what=f"{engine} {name}", seed=s.seed)


@pytest.mark.parametrize("effects", [NONE, Effects(gravity=[0, 0, -9.81], spring_stiffness=30, spring_rest=[0, 0, .1]),
                                     ALL], ids=["none", "conservative", "all"])
def test_energy_rate_is_the_power_of_non_conservative_forces(fixture, case, effects):
    """dE/dt along the motion (complex step, udot from Kane) equals Q_nc . u; zero when conservative."""
    s = _states(case, 43, n=100)
    chain = fixture.chain
    udot = dynamics.accelerations(chain, case, s.q, s.u, effects)
    rate = along_motion(case, s.q, s.u, udot, lambda q, u: dynamics.energy(chain, case, q, u, effects))
    nc = Effects(**{k: getattr(effects, k) for k in ("spring_damping", "ball_damping", "force_G2", "torque_B1",
                                                       "torque_B2") if getattr(effects, k) is not None})
    power = np.einsum("ni,ni->n", dynamics.generalized_forces(chain, case, s.q, s.u, nc), s.u)
    _, sf = dynamics_scales(chain, case, s.q, s.u, effects)
    speed = np.linalg.norm(s.u, axis=1)
    assert_normalized_error(rate, power, sf * speed, what="dE/dt", seed=s.seed, factor=4 * ROUNDING_FACTOR)


def test_kinetic_energy_and_momenta_equal_pinocchio(fixture, engines):
    """relacc's kinetic energy and centroidal momentum equal Pinocchio's on Case 2 states."""
    import pinocchio as pin

    e = engines["pinocchio"]
    m, d = e.routes["quaternion"].model, e.routes["quaternion"].data
    s = _states(2, 44, n=50)
    x = e.engine_input("quaternion", relacc.Case(2), s.q, s.u, None)
    E = dynamics.energy(fixture.chain, 2, s.q, s.u)
    p, H = dynamics.momenta(fixture.chain, 2, s.q, s.u)
    for i in range(50):
        assert pin.computeKineticEnergy(m, d, x.q[i], x.v[i]) == pytest.approx(E[i], rel=64 * EPS)
        pin.computeCentroidalMomentum(m, d, x.q[i], x.v[i])
        c = pin.centerOfMass(m, d, x.q[i])
        h_about_origin = d.hg.angular + np.cross(c, d.hg.linear)
        assert np.allclose(d.hg.linear, p[i], rtol=0, atol=64 * EPS * np.abs(p[i]).max())
        assert np.allclose(h_about_origin, H[i], rtol=0, atol=256 * EPS * (np.abs(H[i]).max() + 1))


def test_fused_accelerations_satisfy_kanes_equations(fixture, case):
    """The Newton-Euler kernel's udot solves Kane's M udot = f to rounding (backward error <= c eps), every effect on.

    A different derivation (each body alone, no linear solve) held to the reference equations; its distance
    from numpy's solve of them is within c eps kappa(M), the solve's own error bound.
    """
    s = _states(case, 45)
    M, f = dynamics.equations_of_motion(fixture.chain, case, s.q, s.u, ALL)
    a = dynamics.accelerations(fixture.chain, case, s.q, s.u, ALL)
    residual = np.linalg.norm(np.einsum("nij,nj->ni", M, a) - f, axis=1)
    size = np.linalg.norm(M, axis=(1, 2)) * np.linalg.norm(a, axis=1) + np.linalg.norm(f, axis=1)
    assert_normalized_error(residual, 0 * residual, size, what="M udot - f", seed=s.seed)
    ref = dynamics.accelerations(fixture.chain, case, s.q, s.u, ALL, backend="reference")
    kappa = np.linalg.cond(M)
    assert_normalized_error(a, ref, np.linalg.norm(ref, axis=1) * kappa, what="udot", seed=s.seed)


def test_fused_tangent_is_the_body_speeds(fixture, case):
    """The kernel's tangent (what the integrators move along) is Case 2's body speeds W u (case 3: u itself)."""
    s = _states(case, 46, n=50)
    tangent = np.array([fastdyn.rates_one(case, q, u, fastdyn.chain_params(fixture.chain),
                                          fastdyn.effect_params(ALL))[0] for q, u in zip(s.q, s.u)])
    _, nu, _ = relacc.core.speeds.to_body_speeds(case, s.q, s.u)
    assert_normalized_error(tangent, s.u if case == 3 else nu, np.linalg.norm(s.u, axis=1), what="tangent", seed=s.seed,
                 factor=8)


def test_accelerations_take_an_out_buffer(fixture):
    """accelerations(out=...) writes into the buffer and returns it; a wrong buffer is an InputError."""
    s = _states(2, 47, n=10)
    out = np.empty((10, 12))
    assert dynamics.accelerations(fixture.chain, 2, s.q, s.u, ALL, out=out) is out
    assert np.array_equal(out, dynamics.accelerations(fixture.chain, 2, s.q, s.u, ALL))
    with pytest.raises(relacc.InputError, match="out"):
        dynamics.accelerations(fixture.chain, 2, s.q, s.u, ALL, out=np.empty((10, 12), dtype=np.float32))


def test_effects_reject_bad_values():
    """Negative stiffness, NaN gravity and wrong lengths are InputErrors."""
    for kwargs in ({"spring_stiffness": -1}, {"gravity": [0, np.nan, 0]}, {"force_G2": [1, 2]},
                   {"ball_damping": [1, 2, 3]}, {"torque_B1": "up"}):
        with pytest.raises(relacc.InputError):
            Effects(**kwargs)


def test_equations_of_motion_take_out_buffers(fixture):
    """equations_of_motion(out=(M, f)) writes Kane's M and f into the caller's arrays and returns them."""
    s = _states(1, 48, n=7)
    M, f = dynamics.equations_of_motion(fixture.chain, 1, s.q, s.u, ALL)
    out = (np.empty((7, 12, 12)), np.empty((7, 12)))
    Mo, fo = dynamics.equations_of_motion(fixture.chain, 1, s.q, s.u, ALL, out=out)
    assert Mo is out[0] and fo is out[1] and np.array_equal(Mo, M) and np.array_equal(fo, f)
