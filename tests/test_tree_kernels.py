"""The fused tree kernel (relacc.kernels.tree) against the reference walk (relacc.core.tree.walk).

Both evaluate the same sums in a different order (the kernel merges a joint's two lever moves and skips
zero levers), so they agree to rounding: within the tree error model's tolerance on the terms' magnitude.
"""

import numpy as np
import pytest

import relacc
from relacc.core.tolerances import EPS, ROUNDING_FACTOR
from relacc.core.tree import convert, random_states
from relacc.core.tree.scales import tree_scales
from relacc.engines.mujoco_.spec import read_tree
from relacc.errors import InputError
from relacc.fixtures.shipped import models_dir
from tests.test_tree import _assert_bodies, _tree_file

FIELDS = ("position", "velocity", "acceleration", "omega", "alpha", "V", "Vdot", "Omega", "Omegadot")


@pytest.mark.parametrize("seed", [0, 3, 7, 11])
@pytest.mark.parametrize("case", [1, 2, 3])
def test_the_kernel_is_the_reference_walk(tmp_path, seed, case):
    """Random trees (ball-then-slide stacks included) in every case: every field and every point."""
    tree = read_tree(_tree_file(tmp_path, seed, 4 + seed))
    st = random_states(tree, 2, 70, seed)  # 70 states: a partial last block of the parallel loop
    q, u, udot = convert(tree, st.q, st.u, st.udot, source=2, target=case)
    fast = relacc.tree_kinematics(tree, case, q, u, udot, backend="fast")
    ref = relacc.tree_kinematics(tree, case, q, u, udot, backend="reference")
    sc = tree_scales(tree, case, q, u, udot)
    for name in FIELDS:
        _assert_bodies(tree, getattr(fast, name), getattr(ref, name), sc.of(name), f"case {case} {name}", seed)
    # rotations composed along each path in another order: the rounding bound per composition, times the depth
    np.testing.assert_allclose(fast.rotation, ref.rotation, rtol=0, atol=ROUNDING_FACTOR * EPS * max(tree.depth))


@pytest.mark.parametrize("seed", [0, 5, 8])
@pytest.mark.parametrize("case", [1, 2, 3])
def test_kinematics_without_partials_is_the_reference_walk(tmp_path, seed, case):
    """``partials=False`` (spatial velocities and accelerations root to leaves, no partial velocity formed) against the
    reference walk (which sums partial velocities times speeds): the same physical quantities, within the tree error
    model's tolerance on the terms' magnitude; a tree with a ball-rooted subtree (seed 5) as well as free roots."""
    tree = read_tree(_tree_file(tmp_path, seed, 4 + seed, free_root=seed != 5))
    st = random_states(tree, 2, 70, seed)
    q, u, udot = convert(tree, st.q, st.u, st.udot, source=2, target=case)
    lean = relacc.tree_kinematics(tree, case, q, u, udot, partials=False)
    ref = relacc.tree_kinematics(tree, case, q, u, udot, backend="reference")
    sc = tree_scales(tree, case, q, u, udot)
    for name in FIELDS[:5]:
        _assert_bodies(tree, getattr(lean, name), getattr(ref, name), sc.of(name), f"case {case} {name}", seed)
    np.testing.assert_allclose(lean.rotation, ref.rotation, rtol=0, atol=ROUNDING_FACTOR * EPS * max(tree.depth))
    assert lean.V is None and lean.Omegadot is None
    no_acc = relacc.tree_kinematics(tree, case, q[:3], u[:3], partials=False)  # a small batch: the calling thread
    assert no_acc.acceleration is None and no_acc.alpha is None
    np.testing.assert_array_equal(no_acc.velocity, lean.velocity[:3])


def test_points_without_partials_and_their_buffers():
    """The chain's named points (G2 among them) without partials, against the reference; ``out=`` takes only the
    fields it computes."""
    tree = relacc.Tree.from_file(models_dir() / "two_body.xml")
    st = random_states(tree, 2, 40, 1)
    lean = relacc.tree_kinematics(tree, 2, st.q, st.u, st.udot, points="all", partials=False)
    ref = relacc.tree_kinematics(tree, 2, st.q, st.u, st.udot, points="all", backend="reference")
    sc = tree_scales(tree, 2, st.q, st.u, st.udot)
    for name in ("position", "velocity", "acceleration"):
        scale = sc.of(name).max(axis=1)[:, None]  # the points' bodies' largest term magnitudes
        err = np.abs(getattr(lean.points, name) - getattr(ref.points, name)).max(axis=-1) / scale
        assert err.max() <= ROUNDING_FACTOR * EPS * max(tree.depth), f"{name}: {err.max() / EPS:.1f} eps"
    assert lean.points.V is None
    out = {"position": np.zeros((40, 2, 3))}
    k = relacc.tree_kinematics(tree, 2, st.q, st.u, out=out, partials=False)
    assert k.position is out["position"]
    np.testing.assert_array_equal(out["position"], lean.position)
    with pytest.raises(InputError, match=r"keys among position, velocity, acceleration, omega, alpha, rotation "
                                         r"\(partials=False\)"):
        relacc.tree_kinematics(tree, 2, st.q, st.u, out={"V": np.zeros((40, 2, 3, 12))}, partials=False)
    with pytest.raises(InputError, match="partials: expected True or False"):
        relacc.tree_kinematics(tree, 2, st.q, st.u, partials="no")


def test_points_and_out_buffers():
    """The chain's points on both paths; out= buffers written in place, returned writable, reused."""
    tree = relacc.Tree.from_file(models_dir() / "two_body.xml")
    st = random_states(tree, 2, 40, 1)
    fast = relacc.tree_kinematics(tree, 2, st.q, st.u, st.udot, points="all")
    ref = relacc.tree_kinematics(tree, 2, st.q, st.u, st.udot, points="all", backend="reference")
    assert fast.points.names == ref.points.names == ("B1_origin", "Q2", "G2")
    for name in ("position", "velocity", "acceleration", "V", "Vdot"):
        want = getattr(ref.points, name)  # the same sums in another order: the rounding bound of their magnitude
        np.testing.assert_allclose(getattr(fast.points, name), want, rtol=0,
                                   atol=ROUNDING_FACTOR * EPS * max(1.0, np.abs(want).max()))
    g2 = relacc.tree_kinematics(tree, 2, st.q, st.u, st.udot, points=["G2"])
    np.testing.assert_array_equal(g2.points.position[:, 0], fast.points.position[:, 2])
    out = {"V": np.zeros((40, 2, 3, 12)), "position": np.zeros((40, 2, 3))}
    k = relacc.tree_kinematics(tree, 2, st.q, st.u, st.udot, out=out)
    assert k.V is out["V"] and k.position is out["position"] and out["V"].flags.writeable
    np.testing.assert_array_equal(out["V"], fast.V)
    assert not k.Vdot.flags.writeable  # relacc's own arrays are read-only
    relacc.tree_kinematics(tree, 2, st.q[::-1].copy(), st.u[::-1].copy(), st.udot[::-1].copy(), out=out)
    np.testing.assert_array_equal(out["V"], fast.V[::-1])
    with pytest.raises(InputError, match=r"out V: expected a writable C-contiguous float64 array of shape "
                                         r"\(40, 2, 3, 12\)"):
        relacc.tree_kinematics(tree, 2, st.q, st.u, st.udot, out={"V": np.zeros((40, 2, 3, 11))})
    with pytest.raises(InputError, match="expected a dict with keys among"):
        relacc.tree_kinematics(tree, 2, st.q, st.u, out={"speeds": np.zeros(3)})
    with pytest.raises(InputError, match="need udot"):
        relacc.tree_kinematics(tree, 2, st.q, st.u, out={"acceleration": np.zeros((40, 2, 3))})


def test_batches_broadcast_and_overflow_is_reported():
    tree = relacc.Tree.from_chain(relacc.fixtures.load().chain)
    st = random_states(tree, 2, 6, 2)
    k = relacc.tree_kinematics(tree, 2, st.q.reshape(2, 3, 14), st.u[0], st.udot.reshape(2, 3, 12))
    assert k.V.shape == (2, 3, 2, 3, 12)
    one = relacc.tree_kinematics(tree, 2, st.q[4], st.u[0], st.udot[4], backend="reference")
    # a broadcast batch by the kernel against one state by the reference walk: the rounding bound of the magnitude
    np.testing.assert_allclose(k.acceleration[1, 1], one.acceleration, rtol=0,
                               atol=ROUNDING_FACTOR * EPS * max(1.0, np.abs(one.acceleration).max()))
    with pytest.raises(InputError, match="overflowed float64"):
        relacc.tree_kinematics(tree, 2, st.q[0], st.u[0] * 1e200, st.udot[0])


ARMATURE = """<mujoco model="armature"><compiler angle="radian"/><option gravity="0.5 -0.2 -9.81"/><worldbody>
  <body name="a" pos="0 0 1"><joint name="root" type="free" armature="0.2"/>
    <inertial pos="0.1 0 0" mass="2" diaginertia=".1 .2 .25"/>
    <body name="b" pos="0.2 0.1 0" quat="0.9 0.1 0.3 0.2"><joint name="ball" type="ball" pos="0.05 0 0" armature="0.3"/>
      <joint name="slide" type="slide" axis="0 0 1" armature="0.1"/>
      <inertial pos="0.2 0.1 0" mass="1" diaginertia=".05 .06 .07"/>
      <body name="c" pos="0.3 0 0"><joint name="h" type="hinge" axis="0 1 0" armature="0.05"/>
        <inertial pos="0.1 0 0" mass="0.5" diaginertia=".01 .02 .025"/></body></body></body>
</worldbody></mujoco>"""


def _dynamics_scale(tree, case, q, u, acc):
    """The perturbation bound's scale of a solve: ||M^-1|| (||M|| |udot| + |terms of f|) per state."""
    d = relacc.tree_dynamics(tree, case, q, u)
    out = []
    for M, f, a in zip(np.asarray(d.M), np.asarray(d.f), acc):
        out.append(np.linalg.norm(np.linalg.inv(M), 2) * (np.linalg.norm(M, 2) * np.abs(a).max() + np.abs(f).max()))
    return np.array(out)


@pytest.mark.parametrize("algorithm", ["lanes", "crba", "aba"])
@pytest.mark.parametrize("seed", [0, 3, pytest.param(7, marks=pytest.mark.slow),
                                  pytest.param(11, marks=pytest.mark.slow)])  # the larger random trees: 2-5 s
def test_the_dynamics_kernel_is_kanes_equations(tmp_path, seed, algorithm):
    """Forward dynamics by composite inertias and L^T D L (numba's, and its code traced into vector lanes), and by the
    articulated-body algorithm, against Kane's
    equations solved by Cholesky, every case, within the perturbation bound of a solve
    (``||M^-1|| (||M|| |udot| + |f|) c eps depth``)."""
    from relacc.kernels import tree_dynamics

    path = _tree_file(tmp_path, seed, 4 + seed) if seed else tmp_path / "armature.xml"
    if not seed:
        path.write_text(ARMATURE)
    tree = read_tree(path)
    st = random_states(tree, 2, 40, seed)
    tau = np.random.default_rng(seed).standard_normal((40, tree.nv))
    for case in (1, 2, 3):
        q, u, _ = convert(tree, st.q, st.u, source=2, target=case)
        fast = tree_dynamics.accelerations(tree, case, q, u, tau, tree.gravity, algorithm=algorithm)[0]
        ref = relacc.tree_accelerations(tree, case, q, u, tau=tau, backend="reference")
        bound = _dynamics_scale(tree, case, q, u, ref) * 64 * 2.2e-16 * max(tree.depth)
        err = np.abs(fast - ref).max(axis=1)
        assert np.all(err <= bound), f"case {case}: worst {np.max(err / bound):.3g} of the bound (seed {seed})"


def _welded_tree():
    """A free root carrying two welded bodies in a row (a hinge body on the second) and a welded body whose child
    turns on a ball; every body off-axis, rotated and massive."""
    from relacc.core.rotations import matrix_from_123, quaternion_from_123

    rng = np.random.default_rng(4)

    def body(name, parent, joints=()):
        Q = matrix_from_123(rng.uniform(-1, 1, 3))  # principal moments in [1, 2): the triangle inequality holds
        return relacc.Body(name, parent, pos=rng.uniform(-0.3, 0.3, 3), quat=quaternion_from_123(rng.uniform(-1, 1, 3)),
                           joints=joints, mass=float(rng.uniform(0.5, 2)), com=rng.uniform(-0.1, 0.1, 3),
                           inertia=0.01 * Q @ np.diag(rng.uniform(1, 2, 3)) @ Q.T)

    return relacc.Tree("welded", (body("root", -1, (relacc.Joint.free("root"),)), body("w1", "root"),
                                  body("w2", "w1"), body("h", "w2", (relacc.Joint.hinge("h", (0.6, 0.0, 0.8)),)),
                                  body("w3", "root"), body("b", "w3", (relacc.Joint.ball("b"),))),
                       gravity=(0.0, 0.0, -9.81))


def test_welded_bodies_fold_into_their_parents_with_the_same_dynamics():
    """:func:`relacc.core.tree.model.welded_folded`, which the dynamics kernels run on: w1 and w2 fold into the root,
    w3 stays (in case 1 a ball's speeds are in its parent body's components). Kane's equations of the folded tree (a
    different description of the same bodies: masses summed, inertias moved by Steiner's theorem) against the
    tree's, both by the reference path, every case, within the perturbation bound of a solve; a tree without
    welded bodies is its own fold."""
    from relacc.core.tree.model import welded_folded

    tree = _welded_tree()
    folded = welded_folded(tree)
    assert folded.body_names == ("root", "h", "w3", "b") and folded.nv == tree.nv
    np.testing.assert_allclose(sum(b.mass for b in folded.bodies), sum(b.mass for b in tree.bodies), rtol=0,
                               atol=8 * EPS * 10)  # six masses under 2 kg summed: a few roundings of 10
    st = random_states(tree, 2, 40, 4)
    for case in (1, 2, 3):
        q, u, _ = convert(tree, st.q, st.u, source=2, target=case)
        ref = relacc.tree_accelerations(tree, case, q, u, backend="reference")
        got = relacc.tree_accelerations(folded, case, q, u, backend="reference")
        bound = _dynamics_scale(tree, case, q, u, ref) * 64 * 2.2e-16 * max(tree.depth)
        err = np.abs(got - ref).max(axis=1)
        assert np.all(err <= bound), f"case {case}: worst {np.max(err / bound):.3g} of the bound (seed 4)"
    plain = relacc.Tree.from_file(models_dir() / "two_body.xml")
    assert welded_folded(plain) is plain


@pytest.mark.slow
@pytest.mark.parametrize("seed", [2, 5, 9])
def test_effects_through_the_kernel_are_kanes_equations(tmp_path, seed):
    """``auto`` forward dynamics with joint springs and dampers and sinusoidal body loads (the kernel, with the
    effects' generalized forces applied: :func:`relacc.kernels.tree_loads.load_forces`) against Kane's equations
    with the same effects (``reference``), every case, within the perturbation bound of a solve whose terms include
    the loads' (``|F| max|V_b| + |T| max|Omega_b|``). A ball's spring and damper in case 1, evaluated in case-2 speeds
    and carried back (``relacc.dynamics.tree._case1_map``), is held to the same bound where the ball is first to turn
    its body, and is the reference path itself, bit for bit, where it follows a turning joint (case 3 is solved in
    case-2 speeds, where the kernel takes it)."""
    tree = read_tree(_tree_file(tmp_path, seed, 6 + seed))
    rng = np.random.default_rng(seed)
    st = random_states(tree, 2, 30, seed)
    one = [j.name for _, j in tree.joints if j.type in ("hinge", "slide")]
    balls = [j.name for _, j in tree.joints if j.type == "ball"]
    loaded = [tree.body_names[b] for b in rng.choice(tree.nb, 2, replace=False)]
    loads = {name: relacc.BodyLoad(force=rng.standard_normal(3), torque=rng.standard_normal(3), frequency=1.5,
                                   phase=0.2) for name in loaded}
    joints = {name: relacc.JointEffect(float(rng.uniform(0.5, 5)), float(rng.uniform(0.1, 1)), 0.3) for name in one}
    effects = relacc.TreeEffects(joints=joints, bodies=loads)
    t = rng.uniform(0, 1, 30)
    from relacc.dynamics.tree import _case1_maps

    springs = relacc.TreeEffects(joints={**joints, **{b: relacc.JointEffect(2.0, 0.5) for b in balls}}, bodies=loads)
    runs = [(case, effects) for case in (1, 2, 3)] + ([(1, springs)] if balls else [])
    for case, effects in runs:
        q, u, _ = convert(tree, st.q, st.u, source=2, target=case)
        if effects is springs and _case1_maps(tree) is None:  # a ball after a turning joint: the reference path
            np.testing.assert_array_equal(
                relacc.tree_accelerations(tree, case, q, u, effects=springs, t=t),
                relacc.tree_accelerations(tree, case, q, u, effects=springs, t=t, backend="reference"))
            continue
        fast = relacc.tree_accelerations(tree, case, q, u, effects=effects, t=t)
        ref = relacc.tree_accelerations(tree, case, q, u, effects=effects, t=t, backend="reference")
        k = relacc.tree_kinematics(tree, case, q, u, backend="reference")
        lever = np.abs(k.V).max(axis=(1, 2, 3)) + np.abs(k.Omega).max(axis=(1, 2, 3))
        load_terms = lever * sum(np.abs(b.force).max() + np.abs(b.torque).max() for b in loads.values())
        d = relacc.tree_dynamics(tree, case, q, u, effects=effects, t=t)
        scale = np.array([np.linalg.norm(np.linalg.inv(M), 2) * (np.linalg.norm(M, 2) * np.abs(a).max()
                                                                 + np.abs(f).max() + lt)
                          for M, f, a, lt in zip(np.asarray(d.M), np.asarray(d.f), ref, load_terms)])
        bound = scale * 64 * 2.2e-16 * max(tree.depth)
        err = np.abs(fast - ref).max(axis=1)
        assert np.all(err <= bound), f"case {case}: worst {np.max(err / bound):.3g} of the bound (seed {seed})"


def test_the_dynamics_kernel_says_what_is_wrong():
    tree = relacc.Tree("t", [relacc.Body("a", joints=[relacc.Joint.hinge("spin", (0, 0, 1))]),
                             relacc.Body("b", parent="a", pos=(1, 0, 0), joints=[relacc.Joint.hinge("h", (0, 1, 0))],
                                         mass=1.0, com=(0.5, 0, 0), inertia=np.eye(3) * 0.1)])
    relacc.tree_accelerations(tree, 2, [[0.1, 0.2]], [[1.0, 2.0]])
    empty = relacc.Tree("empty", [relacc.Body("a", joints=[relacc.Joint.hinge("spin", (0, 0, 1))])])
    with pytest.raises(relacc.SingularityError, match="no inertia moves with spin"):
        relacc.tree_accelerations(empty, 2, np.zeros((3, 1)), np.ones((3, 1)))
    with pytest.raises(InputError, match=r"non-finite value nan at index \(1, 0\)"):
        relacc.tree_accelerations(tree, 2, [[0.1, 0.2], [np.nan, 0.0]], [[1.0, 2.0], [0.0, 0.0]])
    out = np.empty((2, 2))
    res = relacc.tree_accelerations(tree, 2, [[0.1, 0.2], [0.3, 0.1]], [[1.0, 2.0], [0.0, 0.0]], out=out)
    assert res is out
    with pytest.raises(InputError, match="backend 'fast' applies gravity only"):
        relacc.tree_accelerations(tree, 2, [0.1, 0.2], [1.0, 2.0], backend="fast",
                                  effects=relacc.TreeEffects(joints={"h": relacc.JointEffect(damping=1.0)}))


def test_the_dynamics_kernel_picks_its_algorithm(tmp_path):
    """Composite inertias for shallow trees, the articulated-body algorithm for deep chains; both the fast path."""
    from relacc.kernels import tree_dynamics
    from relacc.tradeoff.trees import chain_mjcf

    assert tree_dynamics.method(relacc.Tree.from_chain(relacc.fixtures.load().chain)) == "crba"
    path = tmp_path / "chain.xml"
    path.write_text(chain_mjcf(40, "ball"))
    deep = read_tree(path)
    assert tree_dynamics.method(deep) == "aba"
    st = random_states(deep, 2, 5, 1)
    atol = _dynamics_scale(deep, 2, st.q, st.u, np.zeros((5, deep.nv))).max() * 64 * 2.2e-16 * max(deep.depth)
    fast, reference = relacc.tree_accelerations(deep, 2, st.q, st.u), \
        relacc.tree_accelerations(deep, 2, st.q, st.u, backend="reference")
    np.testing.assert_allclose(fast, reference, rtol=0, atol=atol)


def test_threads_are_used_only_where_they_pay(tmp_path):
    """A batch runs on the calling thread unless a second thread takes over more work than a parallel loop costs
    (``relacc.kernels.jit.parallel_pays``); either way every state's numbers are the same code's, bit for bit."""
    from relacc.kernels.jit import LAUNCH_US, parallel_pays, threads

    with threads(1):
        assert not parallel_pays(10**6, 100.0, 64)
    with threads(2):
        assert not parallel_pays(64, 1e3, 64)  # one block: nothing to share
        assert not parallel_pays(200, LAUNCH_US / 100, 64)  # 200 x 0.01 LAUNCH_US / 2 = LAUNCH_US: not above it
        assert parallel_pays(202, LAUNCH_US / 100, 64)
    tree = read_tree(_tree_file(tmp_path, 4, 6))
    st = random_states(tree, 2, 3000, 4)
    got = {}
    for t in (1, 2):
        with threads(t):
            got[t] = (relacc.tree_accelerations(tree, 2, st.q, st.u),
                      relacc.tree_kinematics(tree, 2, st.q, st.u, st.udot).Vdot,
                      relacc.tree_kinematics(tree, 2, st.q, st.u, st.udot, partials=False).acceleration)
    for a, b in zip(got[1], got[2]):
        np.testing.assert_array_equal(a, b)


def test_a_forked_child_runs_its_batches_on_its_own_threads(tmp_path):
    """A batch split over Python threads (``relacc.kernels.jit.split``) after the parent made its pool, then the same
    batch in a forked child (``relacc.isolate.run``, as ``relacc grade`` runs a user's function): the parent's pool
    threads do not exist there, so the child makes its own (an inherited pool would wait for them for ever: the
    timeout says so) and computes the same numbers, bit for bit."""
    from relacc import isolate
    from relacc.kernels.jit import threads

    tree = read_tree(_tree_file(tmp_path, 4, 6))
    st = random_states(tree, 2, 3000, 4)
    with threads(2):
        parent = np.array(relacc.tree_accelerations(tree, 2, st.q, st.u))
        child = isolate.run(lambda: np.array(relacc.tree_accelerations(tree, 2, st.q, st.u)), timeout=60)
    assert isinstance(child, np.ndarray), f"the child did not answer: {child!r}"
    np.testing.assert_array_equal(child, parent)

