"""Drake as the third engine: faithful to the model source, self-consistent, conventions converted once."""

import json

import numpy as np
import pytest
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import JacobianWrtVariable

import relacc
from relacc import simulate
from relacc.cli import main
from relacc.core.rotations import matrix_from_quaternion, quaternion_from_xyzw
from relacc.core.states import random_states
from relacc.core.tolerances import EPS, assert_normalized_error
from relacc.engines import load_engine
from relacc.errors import EngineError, FixtureError, InputError
from relacc.fixtures import shipped
from relacc.simulate import scenes
from tests.trees import rk4_as_textbook

from .conftest import seed_for


@pytest.fixture(scope="module")
def drake(fixture):
    return load_engine("drake", fixture)


def _parsed(path):
    plant = MultibodyPlant(0.0)
    Parser(plant).AddModels(str(path))
    plant.Finalize()
    return plant


@pytest.mark.parametrize("filename", ["two_body.xml", "two_body_euler.urdf"])
def test_drakes_parsers_read_the_toml_masses_and_inertias(fixture, filename):
    """Drake's MJCF and URDF parsers give B1 and B2 the TOML's masses, mass centers and central inertias."""
    plant = _parsed(fixture.path(filename))
    context = plant.CreateDefaultContext()
    c = fixture.chain
    for name, mass, com, inertia in (("B1", c.m1, c.r1, c.I1), ("B2", c.m2, c.r2, c.I2)):
        body = plant.GetBodyByName(name)
        M = body.CalcSpatialInertiaInBodyFrame(context)
        assert M.get_mass() == pytest.approx(mass, rel=1e-15)
        # the mass centre as read (a decimal's rounding); the central inertia shifted there and back: a few roundings
        # of the inertia and of the parallel-axis term m |c|^2
        assert np.allclose(M.get_com(), com, rtol=0, atol=4 * EPS * np.abs(com).max())
        central = M.Shift(M.get_com()).CalcRotationalInertia().CopyToFullMatrix3()
        assert np.allclose(central, inertia, rtol=0, atol=8 * EPS * (np.abs(inertia).max() + mass * (com @ com)))


def test_drakes_mjcf_parser_builds_the_same_chain_with_a_roll_pitch_yaw_ball(fixture, drake):
    """Drake's MJCF reading of two_body.xml places B2 where relacc's plant does; its ball is a BallRpyJoint.

    Why the adapter builds its own plant: the parsed ball has roll-pitch-yaw positions (singular at pitch
    +-pi/2) and Drake ignores MJCF sites, so G2 is not in the parsed model.
    """
    plant = _parsed(fixture.path("two_body.xml"))
    assert plant.GetJointByName("B2_ball").type_name() == "ball_rpy" and not plant.HasFrameNamed("G2")
    ours = drake.routes["quaternion"].plant
    s = random_states(1, 50, seed_for(1, 90))
    cp, co = plant.CreateDefaultContext(), ours.CreateDefaultContext()
    from pydrake.math import RollPitchYaw, RotationMatrix

    for q in s.q:
        ours.SetPositions(co, np.r_[q[3:7], q[0:3], q[10:14], q[7:10]])
        rpy = RollPitchYaw(RotationMatrix(matrix_from_quaternion(q[10:14]))).vector()
        plant.SetPositions(cp, np.r_[q[3:7], q[0:3], q[7:10], rpy])
        for body in ("B1", "B2"):
            Xa = plant.EvalBodyPoseInWorld(cp, plant.GetBodyByName(body)).GetAsMatrix4()
            Xb = ours.EvalBodyPoseInWorld(co, ours.GetBodyByName(body)).GetAsMatrix4()
            assert np.allclose(Xa, Xb, rtol=0, atol=32 * EPS * (1 + np.abs(q[:3]).max()))


def test_drakes_jdot_from_autodiff_equals_its_bias(drake, case):
    """J_dot (Drake's automatic differentiation) times v equals Drake's own bias term, on both routes."""
    from relacc.validation.compare import routes_for

    s = random_states(case, 100, seed_for(case, 91))
    for route in routes_for(case):
        r = drake.routes[route]
        x = drake.engine_input(route, relacc.Case(case), s.q, s.u, s.udot)
        pts = drake.points(route, x.q, x.v, x.a)
        bias = np.empty((len(s), 3))
        for i in range(len(s)):
            r.plant.SetPositions(r.context, x.q[i])
            r.plant.SetVelocities(r.context, x.v[i])
            bias[i] = r.plant.CalcBiasTranslationalAcceleration(r.context, JacobianWrtVariable.kV,
                                                                r.plant.GetFrameByName("G2"), np.zeros(3),
                                                                r.plant.world_frame(), r.plant.world_frame())[:, 0]
        scale = np.linalg.norm(pts.J_dot, axis=(1, 2)) * np.linalg.norm(x.v, axis=1)
        assert_normalized_error(np.einsum("nij,nj->ni", pts.J_dot, x.v), bias, scale,
                                what=f"{route} J_dot v", seed=s.seed)
        # the acceleration kinematics agree with J a + J_dot v too (two Drake routines, one answer)
        ref = np.einsum("nij,nj->ni", pts.J, x.a) + bias
        scale = scale + np.linalg.norm(pts.J, axis=(1, 2)) * np.linalg.norm(x.a, axis=1)
        assert_normalized_error(pts.acceleration, ref, scale, what=f"{route} acceleration", seed=s.seed)


def test_drakes_velocities_are_case_1_speeds_reordered(drake):
    """On the quaternion route Drake's v is [omega_B1, s1_dot, omega_hat_B2, s2'_dot]: Case 1's u, reordered."""
    s = random_states(1, 20, seed_for(1, 92))
    x = drake.engine_input("quaternion", relacc.Case(1), s.q, s.u, s.udot)
    order = [3, 4, 5, 0, 1, 2, 9, 10, 11, 6, 7, 8]
    assert_normalized_error(x.v, s.u[:, order], np.linalg.norm(s.u, axis=1), what="v", seed=s.seed, factor=4)
    assert_normalized_error(x.a, s.udot[:, order], np.linalg.norm(s.udot, axis=1) + np.linalg.norm(s.u, axis=1) ** 2,
                 what="a", seed=s.seed, factor=8)
    assert np.array_equal(x.q[:, :4], s.q[:, 3:7]) and np.array_equal(quaternion_from_xyzw(
        np.c_[x.q[:, 8:11], x.q[:, 7]]), s.q[:, 10:14])


def test_check_with_drake_alone_passes(capsys, fixture):
    """`relacc check --engines drake --json` passes in all three cases and five quantities."""
    assert main(["check", "--engines", "drake", "--states", "200", "--quiet", "--json",
                 "--model", str(fixture.source)]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["passed"] and {(c["case"], c["quantity"]) for c in out["comparisons"]} == {
        (c, q) for c in (1, 2, 3) for q in ("position", "velocity", "acceleration", "V", "Vdot")}
    assert {c["engine"] for c in out["comparisons"]} == {"drake"} and out["versions"]["drake"]


@rk4_as_textbook()
def test_scenes_name_drakes_integrator(tmp_path):
    """A scene with Drake and rk4 but no [simulate.drake] is refused; an error-controlled Drake run works."""
    path = shipped.scene_path("tumbling")
    text = path.read_text()
    bad = tmp_path / "bad.toml"
    bad.write_text(text[:text.index("[simulate.drake]")])
    with pytest.raises(FixtureError, match=r"field \[simulate\]\.integrator: Drake has no 'rk4' integrator"):
        scenes.load(bad)
    base = scenes.load(path)
    with pytest.raises(InputError, match="Drake has no 'rk4' integrator"):
        base.replace(drake_integrator=None)
    ctrl = simulate.run(base.replace(duration=0.2, engines=("mujoco", "drake"), drake_integrator="runge_kutta3",
                                     drake_accuracy=1e-9))
    assert ctrl.differences()[0] < 1e-8
    assert "error-controlled" in ctrl.trajectories["drake"].applied["integrator"]
    with pytest.raises(EngineError, match="fixed-step integrators only"):
        load_engine("mujoco").adapter.stepper(base.engine_effects, 1e-3, "rk4", accuracy=1e-9)
