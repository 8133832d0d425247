"""relacc's tree against MuJoCo, independent checks of each case's speeds, the chain as one instance.

References are MuJoCo's own numbers (``tests/trees.py``: ``xipos``, ``mj_jac``, ``mj_jacDot``, the acceleration
routine's ``cacc``, ``mj_fullM``, ``qfrc_bias``, ``mj_forward``'s ``qacc``), scipy's Euler angles, and central
differences along MuJoCo's own motion. Tolerances: relacc's error model for trees
(:mod:`relacc.core.tree.scales`: ``c eps depth`` on the terms' magnitude along each body's path).
"""

from pathlib import Path

import mujoco
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import relacc
from relacc.core.tolerances import EPS, ROUNDING_FACTOR
from relacc.core.tree import convert, random_states, reference_q
from relacc.core.tree.scales import tree_scales, tree_tolerance
from relacc.engines.mujoco_.spec import read_tree, tree_of
from tests.trees import jacdot_exact, mujoco_reference, passive_off, random_mjcf

MODELS = Path(relacc.__file__).resolve().parents[1] / "models"
PHYSICAL = ("position", "velocity", "acceleration", "omega", "alpha")


def _tree_file(tmp_path, seed, nb, **kw):
    path = tmp_path / f"random{seed}.xml"
    path.write_text(random_mjcf(seed, nb, **kw))
    return path


def _assert_bodies(tree, got, ref, scale, what, seed, mask=None):
    """Every body's normalized error within its tolerance; the message names the body, state, error and seed."""
    err = np.abs(got - ref).reshape(got.shape[:2] + (-1,)).max(-1) / np.maximum(scale, np.finfo(float).tiny)
    tol = tree_tolerance(tree)
    ratio = err / tol
    if mask is not None:
        ratio = ratio[:, mask]
    i, b = np.unravel_index(np.argmax(ratio), ratio.shape)
    body = np.flatnonzero(mask)[b] if mask is not None else b
    assert ratio.max() <= 1, (f"{what}: body {tree.body_names[body]!r} state {i}: normalized error "
                              f"{err[i, body]:.3g} ({err[i, body] / EPS:.1f} eps) > {tol[body]:.3g} (seed {seed})")


@pytest.mark.parametrize("seed", range(12))
def test_random_trees_agree_with_mujoco_in_every_case(tmp_path, seed):
    """Random trees of 3-12 bodies (free root; ball, hinge, slide and stacked joints; random placements, anchors,
    inertial frames): every body's position, velocity, acceleration, omega and alpha agree with MuJoCo in cases 1-3."""
    path = _tree_file(tmp_path, seed, 3 + seed % 10)
    _agrees_with_mujoco_in_every_case(path, 16, seed)


def _agrees_with_mujoco_in_every_case(path, n, seed):
    """Every body's physical quantities of relacc's tree of ``path`` against MuJoCo's, at ``n`` random states
    (``seed``) in cases 1-3; returns the tree."""
    tree, model = read_tree(path), mujoco.MjModel.from_xml_path(str(path))
    st = random_states(tree, 2, n, seed)
    ref = mujoco_reference(model, st.q, st.u, st.udot)
    for case in (1, 2, 3):
        q, u, udot = convert(tree, st.q, st.u, st.udot, source=2, target=case)
        k = relacc.tree_kinematics(tree, case, q, u, udot)
        sc = tree_scales(tree, case, q, u, udot)
        for name in PHYSICAL:
            _assert_bodies(tree, getattr(k, name), ref[name], sc.of(name), f"case {case} {name}", seed)
    return tree


@pytest.mark.parametrize("seed", range(12, 20))
def test_random_trees_partials_and_dynamics_agree_with_mujoco(tmp_path, seed):
    """Case 2 (MuJoCo's speeds): V, Omega against mj_jac; Vdot, Omegadot against mj_jacDot where it is exact;
    Kane's M and f against mj_fullM and -qfrc_bias; forward dynamics against mj_forward's qacc."""
    path = _tree_file(tmp_path, seed, 3 + seed % 10)
    tree, model = read_tree(path), mujoco.MjModel.from_xml_path(str(path))
    st = random_states(tree, 2, 12, seed)
    ref = mujoco_reference(model, st.q, st.u, st.udot)
    k = relacc.tree_kinematics(tree, 2, st.q, st.u, st.udot)
    sc = tree_scales(tree, 2, st.q, st.u, st.udot)
    _assert_bodies(tree, k.V, ref["J"], sc.V, "V", seed)
    _assert_bodies(tree, k.Omega, ref["Jr"], sc.Omega, "Omega", seed)
    exact = jacdot_exact(model)
    _assert_bodies(tree, k.Vdot, ref["Jdot"], sc.Vdot, "Vdot", seed, exact)
    _assert_bodies(tree, k.Omegadot, ref["Jrdot"], sc.Omegadot, "Omegadot", seed, exact)
    dyn = relacc.tree_dynamics(tree, 2, st.q, st.u)
    # M's entries are sums over bodies of m |V|^2 + |Omega|^2 |I|;
    # f's of m |V| (|g| + |Vdot| |u|) and |I| |Omega| (|Omegadot| |u| + |Omega|^2 |u|^2)
    Vn, Vdn = np.linalg.norm(k.V, axis=(2, 3)), np.linalg.norm(k.Vdot, axis=(2, 3))
    On, Odn = np.linalg.norm(k.Omega, axis=(2, 3)), np.linalg.norm(k.Omegadot, axis=(2, 3))
    mass = np.array([b.mass for b in tree.bodies])
    inertia = np.array([np.linalg.norm(b.inertia) for b in tree.bodies])
    un = np.linalg.norm(st.u, axis=1)[:, None]
    M_scale = (mass * Vn**2 + inertia * On**2).sum(1) + max(np.abs(j.armature).max(initial=0) for _, j in tree.joints)
    f_scale = (mass * Vn * (np.linalg.norm(tree.gravity) + Vdn * un) + inertia * On * (Odn * un + On**2 * un**2)).sum(1)
    tol = ROUNDING_FACTOR * EPS * max(tree.depth)
    np.testing.assert_array_less(np.abs(dyn.M - ref["M"]).max((1, 2)) / M_scale, tol, err_msg=f"M (seed {seed})")
    np.testing.assert_array_less(np.abs(dyn.f + ref["bias"]).max(1) / f_scale, tol, err_msg=f"f (seed {seed})")
    acc = relacc.tree_accelerations(tree, 2, st.q, st.u)
    data = mujoco.MjData(model)
    model.opt.disableflags |= (mujoco.mjtDisableBit.mjDSBL_CONSTRAINT | mujoco.mjtDisableBit.mjDSBL_ACTUATION
                               | passive_off())
    for i in range(len(st.q)):
        data.qpos[:], data.qvel[:] = st.q[i], st.u[i]
        mujoco.mj_forward(model, data)
        # the perturbation bound of a solve: ||M^-1|| (||M|| |a| + |f| terms) c eps depth
        bound = np.linalg.norm(np.linalg.inv(ref["M"][i]), 2) * (np.linalg.norm(ref["M"][i], 2) * np.abs(acc[i]).max()
                                                                 + f_scale[i]) * tol
        np.testing.assert_allclose(acc[i], data.qacc, rtol=0, atol=bound, err_msg=f"forward dynamics, state {i} "
                                                                                  f"(seed {seed})")


@pytest.mark.parametrize("stack", [("slide",), ("slide", "slide")])
def test_mujoco_jacdot_after_a_ball_and_a_slide(stack):
    """A finding: MuJoCo's mj_jacDot takes a ball's columns from the velocity of the whole body, so a slide after a ball
    on the same body adds ``v_slide x omega_ball`` to ``J_dot v``. Central differences of MuJoCo's own velocities along
    its own motion side with relacc; MuJoCo's acceleration routine (cacc) agrees with relacc too."""
    joints = '<joint name="ball" type="ball" pos="0.1 0.2 -0.1"/>' + "".join(
        f'<joint name="s{i}" type="slide" axis="{a}"/>' for i, a in enumerate(("0.6 0 0.8", "0 1 0")[:len(stack)]))
    xml = (f'<mujoco><worldbody><body name="a" pos="0.3 0 0"><freejoint/><inertial pos="0.1 0 0" mass="1" '
           f'diaginertia=".1 .2 .25"/><body name="b" pos="0 0.4 0">{joints}<inertial pos="0.2 0.1 0" mass="1" '
           f'diaginertia=".1 .2 .25"/></body></body></worldbody></mujoco>')
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    tree = tree_of(model, "ball-slide")
    st = random_states(tree, 2, 4, 5)
    k = relacc.tree_kinematics(tree, 2, st.q, st.u, st.udot)
    ref = mujoco_reference(model, st.q, st.u, st.udot)
    for i in range(4):
        q0, u0, a0 = st.q[i], st.u[i], st.udot[i]

        def velocity(t, n=64):
            q = q0.copy()
            for s in range(n):  # midpoint steps along qvel(t) = u0 + a0 t
                mujoco.mj_integratePos(model, q, u0 + a0 * (s + 0.5) * t / n, t / n)
            data.qpos[:], data.qvel[:] = q, u0 + a0 * t
            mujoco.mj_kinematics(model, data)
            mujoco.mj_comPos(model, data)
            J = np.zeros((3, model.nv))
            mujoco.mj_jac(model, data, J, None, data.xipos[2], 2)
            return J @ (u0 + a0 * t)

        h = 1e-4
        fd = (velocity(h) - velocity(-h)) / (2 * h)
        # central difference: truncation h^2 |v'''| / 6 (|v'''| ~ 1e3 here) plus the midpoint path's h^2 error
        np.testing.assert_allclose(k.acceleration[i, 1], fd, rtol=0, atol=1e-5)
        mujoco_jdot_v = ref["Jdot"][i, 1] @ u0
        ball = ref["Jr"][i, 1][:, 6:9] @ u0[6:9]  # the ball's relative angular velocity
        slide = ref["J"][i, 1][:, 9:] @ u0[9:]  # the slides' velocity
        np.testing.assert_allclose(mujoco_jdot_v - k.Vdot[i, 1] @ u0, np.cross(slide, ball), rtol=0, atol=1e-12)
        np.testing.assert_allclose(ref["acceleration"][i, 1], k.acceleration[i, 1], rtol=0, atol=1e-12)


def test_case_speeds_mean_what_the_docs_say(tmp_path):
    """Case 1: a free joint's angular velocity in world components, a ball's relative one in the parent body's
    (from MuJoCo's xmat and cvel); case 3: scipy's intrinsic XYZ angles of the same rotation, their rates by central
    differences along MuJoCo's motion."""
    seed = 3
    path = _tree_file(tmp_path, seed, 6)
    tree, model = read_tree(path), mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    st = random_states(tree, 2, 3, seed)
    q1, u1, _ = convert(tree, st.q, st.u, source=2, target=1)
    q3, u3, _ = convert(tree, st.q, st.u, source=2, target=3)
    # balls that are their body's only rotating joint: the frame they turn from is the body's placement
    rot = [(k, j) for k, (b, j) in enumerate(tree.joints) if j.type == "free" or (
        j.type == "ball" and [x.type for x in tree.bodies[b].joints if x.type != "slide"] == ["ball"])]
    assert any(j.type == "ball" for _, j in rot), "the seed's tree needs a ball"

    def frames(q, v):
        data.qpos[:], data.qvel[:] = q, v
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)
        mujoco.mj_comVel(model, data)
        return data.xmat.reshape(-1, 3, 3).copy(), data.cvel[:, :3].copy()

    for i in range(3):
        R, w = frames(st.q[i], st.u[i])
        for k, j in rot:
            b = tree.joints[k][0] + 1
            parent = int(model.body_parentid[b])
            d = tree.dofadr[k] + (3 if j.type == "free" else 0)
            want = w[b] if j.type == "free" else R[parent].T @ (w[b] - w[parent])
            np.testing.assert_allclose(u1[i, d:d + 3], want, rtol=0, atol=64 * EPS * (1 + np.abs(want).max()))
            # case 3: the joint's rotation (world, or relative to the body's placement in its parent) as XYZ angles
            placed = R[parent] @ mujoco_quat_matrix(model.body_quat[b]) if j.type == "ball" else np.eye(3)
            rel = placed.T @ R[b]
            a3 = tree.qadr(3)[k] + (3 if j.type == "free" else 0)
            # angles of one rotation by two routes (relacc's from the quaternion, scipy's from the matrix): the
            # rounding bound of angles up to pi, times the 1/cos of the middle angle the drawn states keep below ~3
            np.testing.assert_allclose(q3[i, a3:a3 + 3], Rotation.from_matrix(rel).as_euler("XYZ"), rtol=0,
                                       atol=ROUNDING_FACTOR * EPS * np.pi * 3)
            h = 1e-6
            angles = []
            for t in (h, -h):
                qt = st.q[i].copy()
                mujoco.mj_integratePos(model, qt, st.u[i], t)
                Rt, _ = frames(qt, st.u[i])
                placed_t = Rt[parent] @ mujoco_quat_matrix(model.body_quat[b]) if j.type == "ball" else np.eye(3)
                angles.append(Rotation.from_matrix(placed_t.T @ Rt[b]).as_euler("XYZ"))
            # central difference of angles: truncation h^2 |theta'''|/6 < 1e-10, rounding eps / h ~ 2e-10
            np.testing.assert_allclose(u3[i, d:d + 3], (angles[0] - angles[1]) / (2 * h), rtol=0, atol=1e-8)


def mujoco_quat_matrix(quat):
    m = np.zeros(9)
    mujoco.mju_quat2Mat(m, np.asarray(quat, dtype=float))
    return m.reshape(3, 3)


@pytest.mark.parametrize("case", [1, 2, 3])
def test_the_chain_is_one_instance(case):
    """The two-body chain as a tree gives g2_kinematics' G2 (body 2's mass centre) to the chain's own tolerance."""
    from relacc.core.scales import term_scales
    from relacc.core.states import random_states as chain_states

    chain = relacc.fixtures.load().chain
    tree = relacc.Tree.from_chain(chain)
    s = chain_states(case, 500, 11)
    g = relacc.g2_kinematics(chain, case, s.q, s.u, s.udot, backend="reference")
    k = relacc.tree_kinematics(tree, case, s.q, s.u, s.udot)
    sc = term_scales(chain, case, s.q, s.u, s.udot)
    for name in ("position", "velocity", "acceleration", "V", "Vdot"):
        relacc.core.tolerances.assert_normalized_error(getattr(k, name)[:, 1], getattr(g, name), sc.of(name),
                                                       what=f"case {case} {name}", seed=11)


@pytest.mark.parametrize("case", [1, 2, 3])
def test_the_error_models_magnitudes_at_g2_are_the_notes_levers(case):
    """The tree's error model at the chain's B2 (which ``term_scales`` is) is the chain's, written here from the note's
    vectors: the lever ``l = |q2'| + |s2'| + |r2'|`` (``s2'`` one vector, its three slides orthogonal), ``W`` and
    ``A`` the two angular blocks' norms. Only ``position`` sums its terms in another order (one rounding of the
    magnitude, 2 eps relative)."""
    from relacc.core.cases import layout
    from relacc.core.scales import term_scales
    from relacc.core.states import random_states as chain_states

    chain = relacc.fixtures.load().chain
    s = chain_states(case, 200, 12)
    lay, n = layout(case), lambda a: np.linalg.norm(a, axis=-1)
    lever = n(chain.q2) + n(s.q[:, lay.s2_p]) + n(chain.r2)
    w, a = n(s.u[:, 3:6]) + n(s.u[:, 9:12]), n(s.udot[:, 3:6]) + n(s.udot[:, 9:12])
    sd2 = n(s.u[:, 6:9])
    expected = {"position": n(s.q[:, lay.s1]) + lever, "V": 1 + lever, "velocity": n(s.u[:, 0:3]) + sd2 + lever * w,
                "Vdot": w * (1 + lever) + sd2,
                "acceleration": n(s.udot[:, 0:3]) + n(s.udot[:, 6:9]) + lever * a + w * (w * lever + 2 * sd2)}
    tree_sc = tree_scales(relacc.Tree.from_chain(chain), case, s.q, s.u, s.udot)
    chain_sc = term_scales(chain, case, s.q, s.u, s.udot)
    for name, ref in expected.items():
        for got in (tree_sc.of(name)[:, 1], chain_sc.of(name)):
            np.testing.assert_allclose(got, ref, rtol=2 * EPS, atol=0, err_msg=f"case {case} {name}, seed 12")


def test_slides_that_are_not_orthogonal_add_their_magnitudes():
    """Two slides at 45 degrees can cancel (``s e1 - s e2`` is short when ``s`` is long): their terms' magnitudes
    add, ``|s1| + |s2|``; two orthogonal ones are one vector, ``sqrt(s1^2 + s2^2)``."""
    r = np.sqrt(0.5)
    for axes, combine in ((([1, 0, 0], [r, r, 0])), lambda a, b: abs(a) + abs(b)), \
            ((([1, 0, 0], [0, 0, 1])), lambda a, b: np.hypot(a, b)):
        body = relacc.Body("b", -1, joints=tuple(relacc.Joint.slide(f"s{i}", ax) for i, ax in enumerate(axes)),
                           mass=1.0, com=np.zeros(3), inertia=np.eye(3))
        tree = relacc.Tree("slides", (body,))
        q, u = np.array([3.0, -2.0]), np.array([0.5, 4.0])
        sc = tree_scales(tree, 2, q, u)
        assert sc.position[0] == combine(3.0, -2.0) and sc.velocity[0] == combine(0.5, 4.0)


def test_the_chain_toml_and_its_mjcf_are_the_same_tree():
    """Tree.from_file reads the chain's TOML directly and its MJCF by relacc's own reading: the same geometry and
    inertia, bit for bit (the reading keeps a ``fullinertia`` as written, where MuJoCo's compiler would store it on
    principal axes, :data:`relacc.core.tolerances.MUJOCO_EIG_EPS`)."""
    a = relacc.Tree.from_file(MODELS / "two_body.toml")
    b = relacc.Tree.from_file(MODELS / "two_body.xml")
    assert a.joint_names == b.joint_names and a.body_names == b.body_names
    for x, y in zip(a.bodies, b.bodies):
        np.testing.assert_array_equal(x.inertia, y.inertia)
        np.testing.assert_array_equal(x.com, y.com)
        np.testing.assert_array_equal(x.pos, y.pos)
        assert x.mass == y.mass
    np.testing.assert_array_equal(reference_q(a, 2), reference_q(b, 2))


@pytest.mark.parametrize("case", [1, 3])
def test_case_rates_are_the_time_derivatives_of_the_case_speeds(tmp_path, case):
    """``udot`` of a case (what tree_kinematics and tree_accelerations take) is the time derivative of its speeds along
    MuJoCo's motion: central differences of the converted speeds (checked above against MuJoCo and scipy), not the
    conversion's own rate formula."""
    seed = 7
    path = _tree_file(tmp_path, seed, 7)
    tree, model = read_tree(path), mujoco.MjModel.from_xml_path(str(path))
    st = random_states(tree, 2, 4, seed)
    _, _, udot = convert(tree, st.q, st.u, st.udot, source=2, target=case)
    h = 1e-5
    for i in range(4):
        ends = []
        for t in (h, -h):
            q = st.q[i].copy()
            for s in range(8):  # midpoint steps along qvel(t) = u + udot t
                mujoco.mj_integratePos(model, q, st.u[i] + st.udot[i] * (s + 0.5) * t / 8, t / 8)
            ends.append(convert(tree, q, st.u[i] + st.udot[i] * t, source=2, target=case)[1])
        # truncation h^2 |u'''| / 6 ~ 1e-10 |u'''|, rounding eps |u| / h ~ 1e-10
        np.testing.assert_allclose(udot[i], (ends[0] - ends[1]) / (2 * h), rtol=0, atol=1e-7,
                                   err_msg=f"state {i} (seed {seed})")


def test_a_tree_without_speeds_converts_and_answers_in_every_case():
    """robosuite's mounts and null bases, example-robot-data's quadrotor_base: bodies welded to the world, no speed.
    Before: ``convert`` raised numpy's "cannot reshape array of size 0" (a batch's rows inferred from width 0)."""
    tree = relacc.Tree("mount", [relacc.Body("base", mass=2.0, com=(0.0, 0.0, 0.1), inertia=np.eye(3) * 0.1)])
    assert tree.nv == 0
    q, u = np.zeros((3, 0)), np.zeros((3, 0))
    for case in (1, 2, 3):
        qt, ut, udt = convert(tree, q, u, u, source=2, target=case)
        assert qt.shape == ut.shape == udt.shape == (3, 0)
        assert relacc.tree_accelerations(tree, case, q, u).shape == (3, 0)
        k = relacc.tree_kinematics(tree, case, q, u, u)
        np.testing.assert_allclose(k.position[:, 0], np.tile([0.0, 0.0, 0.1], (3, 1)), rtol=0, atol=0)
