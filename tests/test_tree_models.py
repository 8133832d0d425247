"""relacc's tree on models nobody here wrote, on hard cases, with effects, and with bad input.

Shipped models: gymnasium's MuJoCo assets and MuJoCo's own test model, against MuJoCo (``tests/trees.py``).
Tolerances: relacc's error model for trees (:mod:`relacc.core.tree.scales`).
"""

import importlib.util
from pathlib import Path

import gymnasium
import mujoco
import numpy as np
import pytest

import relacc
from relacc.core.tolerances import EPS
from relacc.core.tree import convert, random_states
from relacc.core.tree.scales import tree_scales, tree_tolerance
from relacc.engines.mujoco_.adapter import full_inertia
from relacc.engines.mujoco_.spec import read_tree
from relacc.errors import InputError, ModelError, SingularityError
from tests.test_tree import PHYSICAL, _agrees_with_mujoco_in_every_case, _assert_bodies, _tree_file
from tests.trees import jacdot_exact, mujoco_reference, passive_off

ASSETS = sorted((Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets").glob("*.xml"))
MUJOCO_TESTDATA = Path(importlib.util.find_spec("mujoco").origin).parent / "testdata"


@pytest.mark.parametrize("path", ASSETS + [MUJOCO_TESTDATA / "model.xml"], ids=lambda p: p.name)
def test_shipped_models_agree_with_mujoco(path):
    """Every gymnasium asset and MuJoCo's own test model: every body in cases 1-3, V and Omega (and Vdot where
    mj_jacDot is exact) in case 2, and every site's position and partial velocities."""
    tree, model = read_tree(path), mujoco.MjModel.from_xml_path(str(path))
    st = random_states(tree, 2, 6, 0)
    ref = mujoco_reference(model, st.q, st.u, st.udot)
    for case in (1, 2, 3):
        q, u, udot = convert(tree, st.q, st.u, st.udot, source=2, target=case)
        k = relacc.tree_kinematics(tree, case, q, u, udot, points="all" if case == 2 else None)
        sc = tree_scales(tree, case, q, u, udot)
        for name in PHYSICAL:
            _assert_bodies(tree, getattr(k, name), ref[name], sc.of(name), f"{path.name} case {case} {name}", 0)
    k = relacc.tree_kinematics(tree, 2, st.q, st.u, st.udot, points="all")
    sc = tree_scales(tree, 2, st.q, st.u, st.udot)
    _assert_bodies(tree, k.V, ref["J"], sc.V, f"{path.name} V", 0)
    _assert_bodies(tree, k.Omega, ref["Jr"], sc.Omega, f"{path.name} Omega", 0)
    _assert_bodies(tree, k.Vdot, ref["Jdot"], sc.Vdot, f"{path.name} Vdot", 0, jacdot_exact(model))
    sites = [p for p in tree.points if p.name in {model.site(s).name for s in range(model.nsite)}]
    data = mujoco.MjData(model)
    for i in range(len(st.q)):
        data.qpos[:], data.qvel[:] = st.q[i], st.u[i]
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)
        for p in sites:
            s = model.site(p.name).id
            J = np.zeros((3, model.nv))
            mujoco.mj_jacSite(model, data, J, None, s)
            j = k.points.names.index(p.name)
            body = max(p.body, 0)
            scale = sc.position[i, body] + np.linalg.norm(p.pos)
            np.testing.assert_allclose(k.points.position[i, j], data.site_xpos[s], rtol=0,
                                       atol=tree_tolerance(tree)[body] * scale, err_msg=f"site {p.name}")
            np.testing.assert_allclose(k.points.V[i, j], J, rtol=0,
                                       atol=tree_tolerance(tree)[body] * (sc.V[i, body] + np.linalg.norm(p.pos)),
                                       err_msg=f"site {p.name}")


def test_a_model_without_bodies_is_refused():
    """MuJoCo's mesh test model has no body besides the world: one line naming the file."""
    with pytest.raises(ModelError, match="msh.xml: the MJCF has no <body> in its <worldbody>"):
        relacc.Tree.from_file(MUJOCO_TESTDATA / "msh.xml")


URDF = """<robot name="arm">
  <link name="base"><inertial><mass value="2"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/>
  </inertial></link>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/><origin xyz="0 0 0.3" rpy="0.1 0 0"/>
    <axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <link name="upper"><inertial><origin xyz="0 0 0.2"/><mass value="1"/>
    <inertia ixx="0.02" iyy="0.02" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="tool_mount" type="fixed"><parent link="upper"/><child link="tool"/>
    <origin xyz="0.05 0 0.4" rpy="0 0.3 0"/></joint>
  <link name="tool"><inertial><mass value="0.1"/><inertia ixx="1e-4" iyy="1e-4" izz="1e-4" ixy="0" ixz="0" iyz="0"/>
  </inertial></link>
</robot>
"""


def test_urdf_fixed_links_are_welded_bodies(tmp_path):
    """A URDF's fixed link, which MuJoCo's compiler fuses away, is a body of relacc's reading without joints, moving
    with its parent: its position and velocity are those of the unfused model's body (MuJoCo with fusestatic off)."""
    path = tmp_path / "arm.urdf"
    path.write_text(URDF)
    tree = relacc.Tree.from_file(path)
    assert "tool" in tree.body_names and not tree.bodies[tree.body("tool")].joints
    spec = mujoco.MjSpec.from_file(str(path))
    spec.compiler.fusestatic = False
    full = spec.compile()
    data = mujoco.MjData(full)
    rng = np.random.default_rng(3)
    q, u = rng.uniform(-1, 1, (5, tree.nv)), rng.standard_normal((5, tree.nv))
    k = relacc.tree_kinematics(tree, 2, q, u)
    b, tool = tree.body("tool"), full.body("tool").id
    for i in range(5):
        data.qpos[:], data.qvel[:] = q[i], u[i]
        mujoco.mj_kinematics(full, data)
        mujoco.mj_comPos(full, data)
        J = np.zeros((3, full.nv))
        mujoco.mj_jac(full, data, J, None, data.xpos[tool], tool)
        np.testing.assert_allclose(k.position[i, b], data.xpos[tool], rtol=0, atol=64 * EPS)  # massless: its origin
        np.testing.assert_allclose(k.velocity[i, b], J @ u[i], rtol=0, atol=64 * EPS * (1 + np.abs(u[i]).sum()))


def test_effects_agree_with_mujoco(tmp_path):
    """Springs and dampers on a hinge, a slide and a ball (MuJoCo's passive forces) and loads on bodies (MuJoCo's
    xfrc_applied, at the mass centre): relacc's forward dynamics with exactly those effects is MuJoCo's."""
    xml = """<mujoco><compiler angle="radian"/><option gravity="0 0 -9.81"/><worldbody>
      <body name="a" pos="0 0 1"><freejoint name="root"/><inertial pos="0.1 0 0" mass="2" diaginertia=".1 .2 .25"/>
        <body name="b" pos="0.3 0 0"><joint name="h" type="hinge" axis="0 0.6 0.8" stiffness="3" springref="0.2"
          damping="0.4"/><inertial pos="0.2 0.05 0" mass="1" diaginertia=".05 .06 .07"/>
          <body name="c" pos="0.4 0 0"><joint name="s" type="slide" axis="1 0 0" stiffness="20" springref="-0.1"
            damping="0.7"/><joint name="ball" type="ball" stiffness="1.5" damping="0.3"/>
            <inertial pos="0.1 0.1 0" mass="0.5" diaginertia=".01 .02 .025"/></body></body></body>
    </worldbody></mujoco>"""
    path = tmp_path / "effects.xml"
    path.write_text(xml)
    tree, model = read_tree(path), mujoco.MjModel.from_xml_path(str(path))
    model.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT | mujoco.mjtDisableBit.mjDSBL_CONSTRAINT
    data = mujoco.MjData(model)
    loads = {"b": relacc.BodyLoad(force=(1.0, -2.0, 0.5), torque=(0.1, 0.2, -0.3)),
             "c": relacc.BodyLoad(force=(0.0, 3.0, 0.0), frequency=2.0, phase=0.3)}
    effects = relacc.TreeEffects(joints={"h": relacc.JointEffect(3, 0.4, 0.2), "s": relacc.JointEffect(20, 0.7, -0.1),
                                         "ball": relacc.JointEffect(1.5, 0.3)}, bodies=loads)
    st = random_states(tree, 2, 5, 2)
    t = 0.37
    acc = relacc.tree_accelerations(tree, 2, st.q, st.u, effects=effects, t=t)
    for i in range(5):
        data.qpos[:], data.qvel[:] = st.q[i], st.u[i]
        data.xfrc_applied[:] = 0
        for name, load in loads.items():
            s = np.sin(2 * np.pi * load.frequency * t + load.phase) if load.frequency else 1.0
            data.xfrc_applied[model.body(name).id] = np.concatenate([load.force, load.torque]) * s
        mujoco.mj_forward(model, data)
        M = np.zeros((model.nv, model.nv))
        full_inertia(model, data, M)
        # relacc's accelerations in MuJoCo's equations: the residual on the magnitude of the terms summed
        terms = (np.linalg.norm(M, 2) * np.abs(acc[i]).max() + np.abs(data.qfrc_passive).max()
                 + np.abs(data.qfrc_applied).max() + np.abs(data.qfrc_bias).max())
        np.testing.assert_allclose(M @ (acc[i] - data.qacc), 0, rtol=0, atol=64 * EPS * max(tree.depth) * terms,
                                   err_msg=f"state {i}")
    for i in range(5):  # and with no effects, nothing but gravity acts (MuJoCo with passive forces off)
        model.opt.disableflags |= passive_off()
        data.qpos[:], data.qvel[:], data.xfrc_applied[:] = st.q[i], st.u[i], 0
        mujoco.mj_forward(model, data)
        M = np.zeros((model.nv, model.nv))
        full_inertia(model, data, M)
        terms = np.linalg.norm(M, 2) * np.abs(data.qacc).max() + np.abs(data.qfrc_bias).max()
        np.testing.assert_allclose(M @ (relacc.tree_accelerations(tree, 2, st.q[i], st.u[i]) - data.qacc), 0, rtol=0,
                                   atol=64 * EPS * max(tree.depth) * terms)


def test_joint_forces_are_mujocos_passive_forces(tmp_path):
    """relacc's springs and dampers alone (:func:`relacc.dynamics.tree.joint_forces`, the forces every engine's
    stepper is given at every stage) against MuJoCo's ``qfrc_passive`` of the same stiffness, rest and damping on a
    hinge, a slide, a ball and a damped free joint; the hinge and the slide are computed together (one index
    operation), the ball on its own. Tolerance: each force is a product of at most three terms, ``64 eps`` times the
    sum of the terms' magnitudes."""
    from relacc.dynamics.tree import joint_forces

    xml = """<mujoco><compiler angle="radian"/><option gravity="0 0 0"/><worldbody>
      <body name="a" pos="0 0 1"><freejoint name="root"/><inertial pos="0.1 0 0" mass="2" diaginertia=".1 .2 .25"/>
        <body name="b" pos="0.3 0 0"><joint name="h" type="hinge" axis="0 0.6 0.8" stiffness="3" springref="0.2"
          damping="0.4"/><inertial pos="0.2 0.05 0" mass="1" diaginertia=".05 .06 .07"/>
          <body name="c" pos="0.4 0 0"><joint name="d" type="hinge" axis="1 0 0" damping="0.25"/>
            <joint name="s" type="slide" axis="1 0 0" stiffness="20" springref="-0.1" damping="0.7"/>
            <joint name="ball" type="ball" stiffness="1.5" damping="0.3"/>
            <inertial pos="0.1 0.1 0" mass="0.5" diaginertia=".01 .02 .025"/></body></body></body>
    </worldbody></mujoco>"""
    path = tmp_path / "springs.xml"
    path.write_text(xml)
    tree, model = read_tree(path), mujoco.MjModel.from_xml_path(str(path))
    model.dof_damping[:6] = 0.15  # the free joint's damper (MuJoCo's <freejoint> takes no damping attribute)
    data = mujoco.MjData(model)
    effects = relacc.TreeEffects(joints={"root": relacc.JointEffect(0, 0.15), "h": relacc.JointEffect(3, 0.4, 0.2),
                                         "s": relacc.JointEffect(20, 0.7, -0.1), "ball": relacc.JointEffect(1.5, 0.3),
                                         "d": relacc.JointEffect(0, 0.25)})
    seed = 12
    st = random_states(tree, 2, 7, seed)
    f = joint_forces(tree, st.q, st.u, effects)
    for i in range(7):
        data.qpos[:], data.qvel[:] = st.q[i], st.u[i]
        mujoco.mj_forward(model, data)
        scale = 20 * (np.abs(st.q[i]).max() + 1) + np.abs(st.u[i]).max()  # the largest stiffness and damping: 20, 0.7
        np.testing.assert_allclose(f[i], data.qfrc_passive, rtol=0, atol=64 * EPS * scale, err_msg=f"seed {seed}")


def test_case_1_forward_dynamics_with_a_balls_and_a_free_joints_dampers_is_mujocos_in_the_compiled_path(tmp_path):
    """A damped free root and a sprung, damped ball first to turn its (rotated) body: relacc's case-1 forward
    dynamics (the kernel, the springs and dampers evaluated in case-2 speeds and carried back by ``[B]^T``, no longer
    Kane's equations in Python) mapped to MuJoCo's speeds by relacc's conversion, against MuJoCo's ``qacc`` with the
    same passive forces and gravity. Tolerance: ``M (udot - qacc)`` within ``64 eps depth`` times the terms, as the
    test above; the conversion's own rounding is within it."""
    from relacc.dynamics import tree as tree_dynamics_module

    xml = """<mujoco><compiler angle="radian"/><option gravity="0 0 -9.81"/><worldbody>
      <body name="a" pos="0 0 1"><freejoint name="root"/><inertial pos="0.1 0 0" mass="2" diaginertia=".1 .2 .25"/>
        <body name="b" pos="0.3 0 0" quat="0.8 0.36 0.48 0"><joint name="ball" type="ball" stiffness="1.5"
          damping="0.3"/><inertial pos="0.2 0.05 0" mass="1" diaginertia=".05 .06 .07"/>
          <body name="c" pos="0.4 0 0"><joint name="h" type="hinge" axis="0 0.6 0.8" damping="0.4"/>
            <inertial pos="0.1 0.1 0" mass="0.5" diaginertia=".01 .02 .025"/></body></body></body>
    </worldbody></mujoco>"""
    path = tmp_path / "dampers.xml"
    path.write_text(xml)
    tree, model = read_tree(path), mujoco.MjModel.from_xml_path(str(path))
    model.dof_damping[:6] = 0.15
    data = mujoco.MjData(model)
    effects = relacc.TreeEffects(gravity=(0, 0, -9.81), joints={"root": relacc.JointEffect(0, 0.15),
                                                                "ball": relacc.JointEffect(1.5, 0.3),
                                                                "h": relacc.JointEffect(0, 0.4)})
    seed = 21
    st = random_states(tree, 1, 9, seed)
    assert tree_dynamics_module._effect_forces(tree, 1, st.q, st.u, effects, 0.0) is not None, "not compiled"
    a1 = relacc.tree_accelerations(tree, 1, st.q, st.u, effects=effects)
    q2, u2, a2 = convert(tree, st.q, st.u, a1, source=1, target=2)
    for i in range(9):
        data.qpos[:], data.qvel[:] = q2[i], u2[i]
        mujoco.mj_forward(model, data)
        M = np.zeros((model.nv, model.nv))
        full_inertia(model, data, M)
        terms = np.linalg.norm(M, 2) * np.abs(data.qacc).max() + np.abs(data.qfrc_bias).max() + np.abs(
            data.qfrc_passive).max()
        np.testing.assert_allclose(M @ (a2[i] - data.qacc), 0, rtol=0, atol=64 * EPS * max(tree.depth) * terms,
                                   err_msg=f"seed {seed}, state {i}")


def test_a_three_link_arm_built_in_python():
    """A planar three-link arm with hinges about z, against its closed form: mass centre i at
    ``sum_{j<i} l_j e(phi_j) + c_i e(phi_i)`` with ``phi_i = q_1 + ... + q_i``, ``e(phi) = (cos phi, sin phi, 0)``."""
    lengths, coms = (0.5, 0.4, 0.3), (0.25, 0.2, 0.15)
    bodies = []
    for i, (length, c) in enumerate(zip(lengths, coms)):
        bodies.append(relacc.Body(f"link{i + 1}", parent=-1 if i == 0 else f"link{i}",
                                  pos=(0, 0, 0) if i == 0 else (lengths[i - 1], 0, 0),
                                  joints=[relacc.Joint.hinge(f"q{i + 1}", axis=(0, 0, 1))], mass=1.0 + i,
                                  com=(c, 0, 0), inertia=np.diag([0.01, 0.02, 0.02])))
    arm = relacc.Tree("three-link arm", bodies)
    rng = np.random.default_rng(1)
    q, u, udot = rng.uniform(-np.pi, np.pi, (20, 3)), rng.standard_normal((20, 3)), rng.standard_normal((20, 3))
    k = relacc.tree_kinematics(arm, 1, q, u, udot)
    phi, w, a = np.cumsum(q, 1), np.cumsum(u, 1), np.cumsum(udot, 1)
    e = lambda x: np.stack([np.cos(x), np.sin(x), np.zeros_like(x)], -1)  # noqa: E731
    n = lambda x: np.stack([-np.sin(x), np.cos(x), np.zeros_like(x)], -1)  # noqa: E731
    for i in range(3):
        levers = [(lengths[j] if j < i else coms[i], j) for j in range(i + 1)]
        pos = sum(length * e(phi[:, j]) for length, j in levers)
        vel = sum(length * w[:, j, None] * n(phi[:, j]) for length, j in levers)
        acc = sum(length * (a[:, j, None] * n(phi[:, j]) - w[:, j, None] ** 2 * e(phi[:, j])) for length, j in levers)
        for got, want in ((k.position, pos), (k.velocity, vel), (k.acceleration, acc)):
            np.testing.assert_allclose(got[:, i], want, rtol=0, atol=64 * EPS * 3 * (1 + np.abs(u).sum(1).max()) ** 2)
        np.testing.assert_allclose(k.omega[:, i, 2], w[:, i], rtol=0, atol=8 * EPS * np.abs(u).sum(1).max())


def test_a_fifty_link_chain_agrees_with_mujoco(tmp_path):
    """A 50-link chain of random joints (each body on the previous one) agrees with MuJoCo in all three cases,
    within ``c eps depth`` (depth up to 50 joints)."""
    from tests.trees import random_mjcf

    xml = random_mjcf(50, 50, chain=True)
    path = tmp_path / "chain50.xml"
    path.write_text(xml)
    tree = _agrees_with_mujoco_in_every_case(path, 4, 50)
    assert max(tree.depth) >= 50


def test_far_from_the_origin_relacc_loses_no_digits(tmp_path):
    """With the free root moved 1e8 m away, every velocity, acceleration and partial velocity is the one at the origin
    to rounding of the terms *without* |p| (relacc's levers are relative, never differences of world positions);
    positions move by exactly the offset, to rounding of |p|."""
    path = _tree_file(tmp_path, 4, 8)
    tree = read_tree(path)
    st = random_states(tree, 2, 20, 4)
    far = st.q.copy()
    far[:, 0:3] += 1e8
    for case in (1, 2, 3):
        q0, u, udot = convert(tree, st.q, st.u, st.udot, source=2, target=case)
        q1, _, _ = convert(tree, far, st.u, st.udot, source=2, target=case)
        k0, k1 = (relacc.tree_kinematics(tree, case, q, u, udot) for q in (q0, q1))
        sc = tree_scales(tree, case, q0, u, udot)
        for name in ("velocity", "acceleration", "V", "Vdot", "omega", "alpha"):
            _assert_bodies(tree, getattr(k1, name), getattr(k0, name), sc.of(name), f"far {name}", 4)
        _assert_bodies(tree, k1.position - 1e8, k0.position, tree_scales(tree, case, q1, u).position, "position", 4)


def test_gimbal_lock_at_any_ball_names_the_joint(tmp_path):
    """Case 3 at a ball's gimbal lock: kinematics answers (the forward map is fine), the inverse maps raise
    SingularityError naming the joint."""
    path = _tree_file(tmp_path, 1, 5)
    tree = read_tree(path)
    st = random_states(tree, 3, 3, 1)
    ball = next(k for k, (_, j) in enumerate(tree.joints) if j.type == "ball")
    q = st.q.copy()
    q[1, tree.qadr(3)[ball] + 1] = np.pi / 2
    relacc.tree_kinematics(tree, 3, q, st.u, st.udot)
    name = tree.joints[ball][1].name
    with pytest.raises(SingularityError, match=f"joint '{name}'.*gimbal lock"):
        relacc.tree_accelerations(tree, 3, q, st.u)
    q2, u2, _ = convert(tree, q, st.u, source=3, target=2)
    with pytest.raises(SingularityError, match=f"joint '{name}'"):
        convert(tree, q2, u2, source=2, target=3)


def test_nearly_massless_bodies(tmp_path):
    """Bodies of 1e-9 kg: MuJoCo and relacc still agree within the perturbation bound of the solve (its condition
    number grows as the masses shrink); an exactly massless body on a joint is a SingularityError naming its speed."""
    from tests.trees import random_mjcf

    path = tmp_path / "light.xml"
    path.write_text(random_mjcf(9, 6, light=1e-9))
    tree, model = read_tree(path), mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    model.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONSTRAINT
    st = random_states(tree, 2, 4, 9)
    acc = relacc.tree_accelerations(tree, 2, st.q, st.u)
    dyn = relacc.tree_dynamics(tree, 2, st.q, st.u)
    for i in range(4):
        data.qpos[:], data.qvel[:] = st.q[i], st.u[i]
        mujoco.mj_forward(model, data)
        M = np.asarray(dyn.M[i])
        scale = np.linalg.norm(M, 2) * np.abs(acc[i]).max() + np.abs(dyn.f[i]).max()
        bound = np.linalg.norm(np.linalg.inv(M), 2) * scale * 64 * EPS * max(tree.depth)
        np.testing.assert_allclose(acc[i], data.qacc, rtol=0, atol=bound)
    empty = relacc.Tree("empty", [relacc.Body("a", joints=[relacc.Joint.hinge("spin", (0, 0, 1))])])
    with pytest.raises(SingularityError, match="no inertia moves with spin"):
        relacc.tree_accelerations(empty, 2, [0.0], [1.0])


@pytest.mark.parametrize("build, match", [
    (lambda: relacc.Body("a", joints=[relacc.Joint.free("f"), relacc.Joint.hinge("h", (0, 0, 1))]), "only joint"),
    (lambda: relacc.Joint.hinge("h", (0, 0, 2)), "unit axis"),
    (lambda: relacc.Body("a", quat=(1, 1, 0, 0)), "unit quaternion"),
    (lambda: relacc.Tree("t", [relacc.Body("a", parent="nobody")]), "names parent 'nobody'"),
    (lambda: relacc.Tree("t", [relacc.Body("a"), relacc.Body("a")]), "two bodies are named 'a'"),
    (lambda: relacc.Body("a", mass=-1), "mass must be a finite number >= 0"),
    (lambda: relacc.Body("a", inertia=[[1, 2, 0], [0, 1, 0], [0, 0, 1]]), "symmetric"),
])
def test_bad_trees_say_what_is_wrong(build, match):
    with pytest.raises(InputError, match=match):
        build()


def test_bad_states_say_what_is_wrong():
    tree = relacc.Tree.from_chain(relacc.fixtures.load().chain)
    q = np.zeros(14)
    q[3] = q[10] = 1.0
    relacc.tree_kinematics(tree, 2, q, np.zeros(12))
    bad = q.copy()
    bad[10] = 1.1
    with pytest.raises(InputError, match="joint 'B2_ball'.*off unit"):
        relacc.tree_kinematics(tree, 2, bad, np.zeros(12))
    with pytest.raises(InputError, match=r"expected shape \(\.\.\., 12\)"):
        relacc.tree_kinematics(tree, 3, q, np.zeros(12))
    with pytest.raises(InputError, match="no point 'tip'"):
        relacc.tree_kinematics(tree, 2, q, np.zeros(12), points=["tip"])
    with pytest.raises(InputError, match="expected a relacc.Tree"):
        relacc.tree_kinematics(relacc.fixtures.load().chain, 2, q, np.zeros(12))
    k = relacc.tree_kinematics(tree, 2, [q.tolist()], [[0.0] * 12])  # lists are accepted wherever arrays are
    assert k.position.shape == (1, 2, 3)
