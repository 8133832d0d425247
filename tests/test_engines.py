"""Engine adapters: coordinate round trips and the rebuilt Pinocchio model."""

import numpy as np
import pinocchio as pin
import pytest

from relacc.core.cases import as_case
from relacc.core.states import random_states
from relacc.core.tolerances import EPS, ROUNDING_FACTOR, assert_normalized_error
from relacc.engines import CHAIN_ENGINES as ENGINES
from relacc.engines import load_engine
from relacc.engines.pinocchio_.adapter import LWA
from relacc.errors import EngineError
from relacc.validation.compare import routes_for

from .chain_engine import note_state
from .conftest import seed_for


@pytest.fixture(scope="module")
def engines(fixture):
    return {name: load_engine(name, fixture) for name in ENGINES}


@pytest.mark.parametrize("engine", ENGINES)
def test_round_trip_note_engine_note(engines, engine, case):
    """note -> engine -> note returns the same q, u and udot (angles away from gimbal lock)."""
    s = random_states(case, 200, seed_for(case, 20))
    q = s.q.copy()
    if case == 3:  # keep theta2 inside (-pi/2, pi/2), where 1-2-3 angles are unique
        q[:, [4, 10]] = np.clip(q[:, [4, 10]] / 2, -1.4, 1.4)
    e = engines[engine]
    for route in routes_for(case):
        x = e.engine_input(route, as_case(case), q, s.u, s.udot)
        q2, u2, udot2 = note_state(e, route, case, x)
        scale = np.ones(len(q))
        assert_normalized_error(q2, q, scale, what=f"{engine}/{route} q", seed=s.seed, factor=16)
        assert_normalized_error(u2, s.u, np.linalg.norm(s.u, axis=-1), what="u", seed=s.seed, factor=16)
        ref = np.linalg.norm(s.udot, axis=-1) + np.linalg.norm(s.u, axis=-1) ** 2
        assert_normalized_error(udot2, s.udot, ref, what="udot", seed=s.seed, factor=16)



def close(x):
    """Two evaluations of one quantity by products in another order: the error model's rounding bound, c eps times
    the magnitude (at least 1: coordinates of order one enter every product)."""
    return ROUNDING_FACTOR * EPS * max(1.0, float(np.abs(x).max()))


def test_split_pinocchio_model_matches_loaded(engines):
    """The composite-free model gives the loaded model's frames, velocities, accelerations, J and M."""
    e = engines["pinocchio"]
    loaded, split = e.routes["quaternion"].composite_model, e.routes["quaternion"].model
    assert (loaded.nq, loaded.nv) == (split.nq, split.nv)
    dl, ds = loaded.createData(), split.createData()
    rng = np.random.default_rng(seed_for(1, 21))
    for _ in range(50):
        q = pin.randomConfiguration(loaded, -np.ones(loaded.nq), np.ones(loaded.nq))
        v, a = rng.normal(size=(2, loaded.nv))
        for m, d in ((loaded, dl), (split, ds)):
            pin.forwardKinematics(m, d, q, v, a)
            pin.updateFramePlacements(m, d)
            pin.computeJointJacobians(m, d, q)
            pin.crba(m, d, q)
        for name in ("G2", "B1", "B2"):
            fl, fs = loaded.getFrameId(name), split.getFrameId(name)
            # one kinematics through two joint compositions: products in another order, rounding of the magnitudes
            placed = ds.oMf[fs].homogeneous
            assert np.allclose(dl.oMf[fl].homogeneous, placed, rtol=0, atol=close(placed))
            for get in (pin.getFrameVelocity, pin.getFrameClassicalAcceleration):
                want = get(split, ds, fs, LWA).vector
                assert np.allclose(get(loaded, dl, fl, LWA).vector, want, rtol=0, atol=close(want))
            J_loaded, J_split = pin.getFrameJacobian(loaded, dl, fl, LWA), pin.getFrameJacobian(split, ds, fs, LWA)
            assert np.allclose(J_loaded, J_split, rtol=0, atol=close(J_split))
        Ml, Ms = np.triu(dl.M), np.triu(ds.M)
        assert np.allclose(Ml, Ms, rtol=0, atol=close(Ms))


def test_split_model_time_variation_matches_classical_acceleration(engines):
    """On the rebuilt model, J a + Jdot v is Pinocchio's own classical acceleration of G2."""
    r = engines["pinocchio"].routes["quaternion"]
    m, d = r.model, r.data
    f = m.getFrameId("G2")
    rng = np.random.default_rng(seed_for(1, 22))
    for _ in range(50):
        q = pin.randomConfiguration(m, -np.ones(m.nq), np.ones(m.nq))
        v, a = rng.normal(size=(2, m.nv))
        pin.forwardKinematics(m, d, q, v, a)
        pin.updateFramePlacements(m, d)
        acc = pin.getFrameClassicalAcceleration(m, d, f, LWA).linear
        pin.computeJointJacobians(m, d)
        pin.computeJointJacobiansTimeVariation(m, d, q, v)
        J = pin.getFrameJacobian(m, d, f, LWA)[:3]
        Jd = pin.getFrameJacobianTimeVariation(m, d, f, LWA)[:3]
        scale = np.abs(J) @ np.abs(a) + np.abs(Jd) @ np.abs(v)
        assert np.all(np.abs(J @ a + Jd @ v - acc) <= 64 * np.finfo(float).eps * scale.max())


def test_euler_route_rejects_cases_1_and_2(engines):
    """The Euler fixtures hold case-3 coordinates only: asking for case 1 there is an EngineError."""
    s = random_states(1, 2, 0)
    with pytest.raises(EngineError, match="case 3"):
        engines["mujoco"].g2_kinematics(1, s.q, s.u, route="euler")
    with pytest.raises(EngineError, match="unknown route"):
        engines["mujoco"].g2_kinematics(1, s.q, s.u, route="spatial")


def test_unknown_engine_is_an_engine_error():
    """load_engine names the accepted engines."""
    with pytest.raises(EngineError, match="pinocchio, mujoco"):
        load_engine("bullet")
