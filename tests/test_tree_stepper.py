"""A tree's compiled stepper (relacc.kernels.tree_step) and single-state forward dynamics, against the reference path.

The reference for a step is the Python RKMK4 / semi-implicit Euler of :mod:`relacc.dynamics.integrate` driven by
Kane's equations solved by Cholesky (``backend="reference"``, numpy, no kernel). One step of size ``h`` from the same
state moves ``u`` by ``h`` times a weighted mean of four stage accelerations and ``q`` by ``h`` times a mean of stage
speeds: each stage's acceleration differs between the two by at most the perturbation bound of a solve ``B``
(``||M^-1|| (||M|| |udot| + |terms of f|) c eps depth``, as ``tests/test_tree_kernels.py``), so ``|du| <= h B'`` and
``|dq| <= h^2 B' / 2`` plus the rounding of the additions and quaternion products (``c eps`` times the state's
magnitude), ``B'`` the bound's largest value over the stages (taken as twice its value at the start: the stages are
``h |udot|`` from it, a relative change below 1e-2 here).
"""

import threading

import numpy as np
import pytest

import relacc
from relacc.core.tolerances import EPS, ROUNDING_FACTOR
from relacc.core.tree import random_states
from relacc.dynamics.integrate import STEPPERS, TreeSpace, tree_stepper_compiled
from relacc.engines.mujoco_.spec import read_tree
from tests.test_tree import _tree_file

H = 1e-3


def _effects(tree, rng):
    joints = {}
    for _, j in tree.joints:
        if j.type in ("hinge", "slide"):
            joints[j.name] = relacc.JointEffect(float(rng.uniform(0.5, 5)), float(rng.uniform(0.1, 1)), 0.2)
        elif j.type == "ball":
            rest = rng.standard_normal(4)
            joints[j.name] = relacc.JointEffect(2.0, 0.3, rest / np.linalg.norm(rest))
        else:
            joints[j.name] = relacc.JointEffect(damping=0.4)
    loaded = [tree.body_names[b] for b in rng.choice(tree.nb, min(2, tree.nb), replace=False)]
    loads = {name: relacc.BodyLoad(force=rng.standard_normal(3), torque=rng.standard_normal(3), frequency=1.5,
                                   phase=0.2) for name in loaded}
    return relacc.TreeEffects(joints=joints, bodies=loads)


def _reference(tree, effects, case=2):
    from relacc.core.tree import convert

    def derivs(q, u, t):  # the tangent: case-2 speeds (cases 1-2, converted by relacc's reference walk) or the rates
        w = convert(tree, q, u, source=1, target=2)[1] if case == 1 else u
        return w, np.asarray(relacc.tree_accelerations(tree, case, q, u, effects=effects, t=t, backend="reference"))
    return derivs


def _solve_bound(tree, effects, q, u, t):
    """``B`` of the module docstring at one state, the loads' terms in ``f``'s."""
    d = relacc.tree_dynamics(tree, 2, q, u, effects=effects, t=t)
    M, f = np.asarray(d.M), np.asarray(d.f)
    a = np.linalg.solve(M, f)
    k = relacc.tree_kinematics(tree, 2, q, u, backend="reference")
    lever = np.abs(k.V).max() + np.abs(k.Omega).max()
    loads = lever * sum(np.abs(b.force).max() + np.abs(b.torque).max() for b in effects.bodies.values())
    scale = np.linalg.norm(np.linalg.inv(M), 2) * (np.linalg.norm(M, 2) * np.abs(a).max() + np.abs(f).max() + loads)
    return scale * ROUNDING_FACTOR * EPS * max(tree.depth)


@pytest.mark.parametrize("case", [1, 2, 3])
@pytest.mark.parametrize("integrator", ["rk4", "euler"])
@pytest.mark.parametrize("seed", [1, 4, 8])
def test_one_compiled_step_is_the_reference_step(tmp_path, seed, integrator, case):
    """Springs (balls' with a rest quaternion), dampers (free joints' too), sinusoidal loads and gravity, at a time
    away from 0, on random trees with every joint type; in cases 1 and 2 (quaternions, their tangent case-2 speeds:
    in case 1 ``B u`` from the stage's frames), and in case 3 (angles and their rates: the rates' accelerations are
    case 2's mapped through ``W^-1``, so the bound is case 2's times the worst ``cond(W)``)."""
    from relacc.core.so3 import condition_123
    from relacc.core.tree import convert
    from relacc.core.tree.coordinates import rotations

    tree = read_tree(_tree_file(tmp_path, seed, 5 + seed))
    rng = np.random.default_rng(seed)
    effects = _effects(tree, rng)
    st = random_states(tree, 2, 3, seed)
    qc, uc, _ = convert(tree, st.q, st.u, source=2, target=case)
    derivs = _reference(tree, effects, case)
    stepper = tree_stepper_compiled(tree, effects, H, integrator, derivs, case)
    stepper.advance(qc[0], uc[0], 7)  # the clock runs on: the next steps start at t = 7 h
    q, u = stepper.advance(qc[1:], uc[1:], 1)
    for i in range(2):
        qr, ur = STEPPERS[integrator](TreeSpace(tree, case), qc[1 + i], uc[1 + i], H, derivs, 7 * H)
        cond = max([1.0] + [float(condition_123(qc[1 + i, a + 1])) for _, _, a, _ in rotations(tree, 3)]) \
            if case == 3 else 1.0
        B = 2 * cond * _solve_bound(tree, effects, st.q[1 + i], st.u[1 + i], 7 * H)
        round_q = ROUNDING_FACTOR * EPS * max(1.0, np.abs(qr).max())
        round_u = ROUNDING_FACTOR * EPS * np.abs(ur).max()
        np.testing.assert_allclose(u[i], ur, rtol=0, atol=H * B + round_u, err_msg=f"seed {seed}")
        np.testing.assert_allclose(q[i], qr, rtol=0, atol=H * H * B / 2 + round_q, err_msg=f"seed {seed}")


def test_a_deep_chain_steps_by_articulated_bodies(tmp_path):
    """A 40-ball chain (the articulated-body algorithm's tree) with springs, dampers and a load: one RK4 step."""
    from relacc.kernels.tree_dynamics import method
    from relacc.tradeoff.trees import chain_mjcf

    path = tmp_path / "chain.xml"
    path.write_text(chain_mjcf(40, "ball"))
    tree = read_tree(path)
    assert method(tree) == "aba"
    effects = _effects(tree, np.random.default_rng(3))
    st = random_states(tree, 2, 1, 3)
    derivs = _reference(tree, effects)
    q, u = tree_stepper_compiled(tree, effects, H, "rk4", derivs).advance(st.q[0], st.u[0], 1)
    qr, ur = STEPPERS["rk4"](TreeSpace(tree, 2), st.q[0], st.u[0], H, derivs, 0.0)
    B = 2 * _solve_bound(tree, effects, st.q[0], st.u[0], 0.0)
    np.testing.assert_allclose(u, ur, rtol=0, atol=H * B + ROUNDING_FACTOR * EPS * np.abs(ur).max())
    np.testing.assert_allclose(q, qr, rtol=0, atol=H * H * B / 2 + ROUNDING_FACTOR * EPS * max(1, np.abs(qr).max()))


def test_records_and_rows_are_one_integration(tmp_path):
    """A single run's records (``record``) and a batch's rows (``advance``, rows in parallel) are the same compiled
    steps from the same times: bit for bit; the records land after the steps their gaps say."""
    tree = read_tree(_tree_file(tmp_path, 2, 6))
    effects = _effects(tree, np.random.default_rng(2))
    st = random_states(tree, 2, 4, 2)
    derivs = _reference(tree, effects)
    X, V, n = tree_stepper_compiled(tree, effects, H, "rk4", derivs).record(st.q[0], st.u[0], [0, 3, 5])
    assert n == 3
    np.testing.assert_array_equal(X[0], st.q[0])
    rows = tree_stepper_compiled(tree, effects, H, "rk4", derivs)
    q3, u3 = rows.advance(np.repeat(st.q[:1], 4, 0), np.repeat(st.u[:1], 4, 0), 3)
    q8, u8 = rows.advance(q3, u3, 5)
    np.testing.assert_array_equal(q3[2], X[1])
    np.testing.assert_array_equal(u8[3], V[2])


def test_what_the_compiled_stepper_cannot_do_is_said_by_the_reference_path(tmp_path):
    """A singular mass matrix at the start: the reference path's SingularityError naming the speed; a run that blows
    up: the step loop's IntegrationError; a quaternion pushed off unit: the reference path's InputError naming the
    joint."""
    from relacc.dynamics.steps import collect

    empty = relacc.Tree("empty", [relacc.Body("a", joints=[relacc.Joint.hinge("spin", (0, 0, 1))])])
    stepper = tree_stepper_compiled(empty, relacc.TreeEffects(), H, "rk4", _reference(empty, relacc.TreeEffects()))
    with pytest.raises(relacc.SingularityError, match="no inertia moves with spin"):
        stepper.record(np.zeros(1), np.ones(1), [1])
    with pytest.raises(relacc.SingularityError, match="no inertia moves with spin"):
        stepper.advance(np.zeros((2, 1)), np.ones((2, 1)), 1)
    tree = read_tree(_tree_file(tmp_path, 5, 4))
    st = random_states(tree, 2, 1, 5)
    stiff = relacc.TreeEffects(joints={j.name: relacc.JointEffect(1e12, 0.0) for _, j in tree.joints
                                       if j.type in ("hinge", "slide")})
    stepper = tree_stepper_compiled(tree, stiff, 0.1, "euler", _reference(tree, stiff))
    with pytest.raises(relacc.IntegrationError, match="diverged"):  # to inf, or to a singular mass matrix on the way
        collect(stepper, st.q[0], st.u[0], 0.1, 400, 1, who="relacc", integrator="euler")
    q = np.array(st.q[0])
    q[3:7] *= 1 + 1e-9  # the free root's quaternion
    with pytest.raises(relacc.InputError, match="off unit"):
        tree_stepper_compiled(tree, stiff, H, "rk4", _reference(tree, stiff)).record(q, st.u[0], [1])


def test_one_state_is_a_row_of_the_batch_and_threads_keep_their_own(tmp_path):
    """The single-state lane (its own buffers per thread) gives a batch row's numbers, bit for bit, from many
    threads at once; read-only inputs are read, never written; a bad state is refused in the batch's words."""
    tree = read_tree(_tree_file(tmp_path, 6, 7))
    st = random_states(tree, 2, 64, 6)
    batch = np.asarray(relacc.tree_accelerations(tree, 2, st.q, st.u))
    q, u = np.array(st.q), np.array(st.u)
    q.setflags(write=False)
    got = np.empty_like(batch)

    def work(rows):
        for i in rows:
            got[i] = relacc.tree_accelerations(tree, 2, q[i], u[i])

    threads = [threading.Thread(target=work, args=(range(k, 64, 4),)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    np.testing.assert_array_equal(got, batch)
    one = relacc.tree_accelerations(tree, 2, q[0], u[0])
    assert not one.flags.writeable and one.shape == (tree.nv,)
    bad = np.array(q[0])
    bad[3] += 1e-6
    with pytest.raises(relacc.InputError, match="off unit"):
        relacc.tree_accelerations(tree, 2, bad, u[0])


def test_case_3_near_the_lock_warns_and_at_it_refuses(tmp_path):
    """A compiled case-3 run whose stages come within a condition number of 1e6 of the 1-2-3 lock warns once, naming
    the joint, as the reference path does at every stage; one that starts at the lock is refused in its words."""
    from relacc.core.tree import convert

    tree = read_tree(_tree_file(tmp_path, 3, 4))
    st = random_states(tree, 2, 1, 3)
    q3, u3, _ = convert(tree, st.q, st.u, source=2, target=3)
    effects = relacc.TreeEffects()
    q = np.array(q3[0])
    q[4] = np.pi / 2 - 1e-7  # the free root's theta2: cond(W) about 2e7
    stepper = tree_stepper_compiled(tree, effects, 1e-6, "rk4", _reference(tree, effects, 3), 3)
    with pytest.warns(relacc.AccuracyWarning, match="root"):
        stepper.record(q, np.zeros_like(u3[0]), [1])
    q[4] = np.pi / 2
    stepper = tree_stepper_compiled(tree, effects, 1e-6, "rk4", _reference(tree, effects, 3), 3)
    with pytest.raises(relacc.SingularityError, match="root"):
        stepper.record(q, u3[0], [1])
