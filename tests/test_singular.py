"""Equations relacc cannot answer are refused in one sentence, in every case and by every backend: a mass matrix
singular to working precision (its factorization's pivot below ``PIVOT_FLOOR`` of the diagonal, so no digit of the
accelerations is certain) and results that overflow float64."""

import warnings

import numpy as np
import pytest

import relacc
from relacc import Body, Joint, Tree
from relacc.core.tolerances import PIVOT_FLOOR
from relacc.core.tree import random_states
from relacc.errors import InputError, SingularityError
from relacc.kernels import tree_dynamics as kernel

SEED = 20261124


def _two_balls() -> Tree:
    """One body on two ball joints: six angular speeds for three rotational degrees of freedom (M has rank 3)."""
    body = Body("b", -1, pos=(0, 0, 1), joints=(Joint.ball("j1"), Joint.ball("j2")), mass=1.0, com=(0.1, 0.2, -0.5),
                inertia=np.diag([0.1, 0.2, 0.3]))
    return Tree("two_balls", (body,), gravity=(0, 0, -9.81))


@pytest.mark.parametrize("case", [1, 2, 3])
@pytest.mark.parametrize("backend", ["fast", "reference"])
def test_two_balls_on_one_body_are_refused_in_every_case(case, backend):
    """Before: cases 1 and 3 returned 22-35 rad/s^2 of rounding (their speed maps leave pivots of a few eps, which a
    ``pivot > 0`` test lets through); case 2 raised."""
    tree = _two_balls()
    s = random_states(tree, case, 4, SEED)
    with pytest.raises(SingularityError, match="singular"):
        relacc.tree_accelerations(tree, case, s.q, s.u, backend=backend)


@pytest.mark.parametrize("algorithm", ["lanes", "crba", "aba"])
@pytest.mark.parametrize("case", [1, 2, 3])
def test_both_kernels_flag_every_state_of_a_rank_deficient_tree(algorithm, case):
    tree = _two_balls()
    s = random_states(tree, case, 16, SEED + case)
    res, _, singular, _ = kernel.accelerations(tree, case, s.q, s.u, np.zeros_like(s.u), tree.gravity,
                                            algorithm=algorithm)
    assert singular == 16 and np.isnan(res).all()


@pytest.mark.parametrize("case", [1, 2, 3])
def test_an_ill_conditioned_but_regular_tree_is_answered_alike_by_both_kernels(case):
    """A 1e-6 kg body on a 1 kg one (kappa about 1e7, pivots far above the floor): answered, the two kernels within
    the solve's bound c eps kappa(M) of each other (normalized by the accelerations' magnitude)."""
    b1 = Body("b1", -1, joints=(Joint.free("f"),), mass=1.0, com=(0.1, 0, 0), inertia=np.diag([0.1, 0.2, 0.3]))
    b2 = Body("b2", 0, pos=(0, 0, -0.5), joints=(Joint.ball("j"),), mass=1e-6, com=(0.1, 0.2, -0.5),
              inertia=1e-7 * np.eye(3))
    tree = Tree("light", (b1, b2), gravity=(0, 0, -9.81))
    s = random_states(tree, case, 64, SEED + 10 * case)
    crba, _, n1, _ = kernel.accelerations(tree, case, s.q, s.u, np.zeros_like(s.u), tree.gravity, algorithm="crba")
    aba, _, n2, _ = kernel.accelerations(tree, case, s.q, s.u, np.zeros_like(s.u), tree.gravity, algorithm="aba")
    lanes, _, n3, _ = kernel.accelerations(tree, case, s.q, s.u, np.zeros_like(s.u), tree.gravity, algorithm="lanes")
    assert n1 == n2 == n3 == 0
    M = relacc.tree_dynamics(tree, case, s.q, s.u).M
    bound = 64 * np.finfo(float).eps * np.linalg.cond(M)
    for other in (aba, lanes):
        err = np.abs(crba - other).max(axis=1) / np.abs(crba).max(axis=1)
        assert np.all(err <= bound), f"seed {SEED + 10 * case}: {err.max():.3g} > {bound.max():.3g}"
    assert PIVOT_FLOOR * np.linalg.cond(M).max() < 1


def test_overflow_is_refused_by_dynamics_as_by_accelerations():
    """Before: tree_dynamics returned inf/NaN with numpy's warnings only, tree_accelerations raised."""
    body = Body("b", -1, joints=(Joint.ball("j"),), mass=1e308, com=(0.1, 0, 0), inertia=np.eye(3))
    tree = Tree("heavy", (body,), gravity=(0, 0, -9.81))
    s = random_states(tree, 2, 3, SEED)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # not a numpy warning either
        for f in (relacc.tree_dynamics, relacc.tree_accelerations):
            with pytest.raises(InputError, match="overflowed float64.*mass or inertia 1e\\+308"):
                f(tree, 2, s.q, s.u)
        fast = random_states(_two_balls(), 2, 3, SEED)
        with pytest.raises(InputError, match="overflowed float64"):
            relacc.tree_dynamics(_two_balls(), 2, fast.q, fast.u * 1e160)


def _point_on_a_ball(lever) -> Tree:
    """A 2 kg point mass (no inertia of its own) on a ball joint, its mass centre at ``lever`` from the joint: a spin
    about the lever moves nothing, so M (3 x 3) has rank 2."""
    body = Body("bob", -1, pos=(0, 0, 1), joints=(Joint.ball("ball"),), mass=2.0, com=lever,
                inertia=np.zeros((3, 3)))
    return Tree("point_on_a_ball", (body,), gravity=(0, 0, -9.81))


@pytest.mark.parametrize("lever", [(0.5, 0.0, 0.0), (0.0, 0.0, 0.5)])
@pytest.mark.parametrize("algorithm", ["lanes", "crba", "aba"])
@pytest.mark.parametrize("case", [1, 2, 3])
def test_a_point_mass_on_a_ball_is_singular_on_every_path(lever, algorithm, case):
    """Issue 49 item 2: in case 2 the diagonal entry of the spin about the lever is rounding residue (a few eps of
    m r^2, the state's rotation rounding), and its pivot passed a test against that entry alone: the lanes answered
    46.88, the numba CRBA 46.84, the numba ABA -58.36 for the undetermined component (3.5e18 with the lever on z).
    Against the matrix's scale (its entry plus the mean diagonal entry, m r^2 / 1.5 here) every path flags every
    state, and tree_accelerations raises in every case."""
    tree = _point_on_a_ball(lever)
    s = random_states(tree, case, 16, SEED + case)
    res, bad, singular, _ = kernel.accelerations(tree, case, s.q, s.u, np.zeros_like(s.u), tree.gravity,
                                                 algorithm=algorithm)
    assert (bad, singular) == (0, 16) and np.isnan(res).all(), f"seed {SEED + case}"
    for backend in ("auto", "reference"):
        with pytest.raises(SingularityError, match="singular"):
            relacc.tree_accelerations(tree, case, s.q, s.u, backend=backend)
    with pytest.raises(SingularityError, match="singular"):
        relacc.tree_accelerations(tree, case, s.q[0], s.u[0])  # the single-state lane too


def _nearly_parallel_hinges(tilt: float) -> Tree:
    """One body on two hinges, the second tilted ``tilt`` rad from the first: M = a [[1, cos t], [cos t, 1]] (plus
    the lever's terms), kappa about 4 / t^2."""
    axis = (0.0, np.sin(tilt), np.cos(tilt))
    body = Body("b", -1, pos=(0, 0, 1), joints=(Joint.hinge("h1", (0, 0, 1)), Joint.hinge("h2", axis)), mass=1.0,
                com=(0.3, 0.1, 0.0), inertia=np.diag([0.01, 0.02, 0.03]))
    return Tree("nearly_parallel", (body,), gravity=(0, 0, -9.81))


@pytest.mark.parametrize("algorithm", [None, "crba", "aba"])
def test_a_nearly_singular_tree_is_answered_with_a_warning(algorithm):
    """Issue 50 item 7: two hinges on one body, the second tilted 3e-7 rad: cond(M) 8.9e13, and one state 0.90 off
    relative between two correct methods, without a word. Now no state of it is answered silently: each is singular
    (kappa beyond 1 / (2 c eps) by the matrix's scale) or warned. Tilted 1e-6 rad (kappa about 1e12): every state is
    answered, and every path warns (relacc.AccuracyWarning, naming the bound on the error); tilted 1e-2 (kappa 4e4),
    none does."""
    s = random_states(_nearly_parallel_hinges(1e-6), 2, 8, SEED)
    worst = _nearly_parallel_hinges(3e-7)
    _, bad, singular, ill = kernel.accelerations(worst, 2, s.q, s.u, np.zeros_like(s.u), worst.gravity,
                                                 algorithm=algorithm)
    assert bad == 0 and singular + ill == 8, f"seed {SEED}: {singular} singular, {ill} warned"
    tree = _nearly_parallel_hinges(1e-6)
    M = relacc.tree_dynamics(tree, 2, s.q, s.u).M
    assert np.linalg.cond(M).min() > 1e11  # the premise, by numpy's SVD
    res, bad, singular, ill = kernel.accelerations(tree, 2, s.q, s.u, np.zeros_like(s.u), tree.gravity,
                                                   algorithm=algorithm)
    assert (bad, singular, ill) == (0, 0, 8), f"seed {SEED}"
    for backend in ("auto", "reference"):
        with pytest.warns(relacc.AccuracyWarning, match=r"8 of 8 states: the mass matrix is ill-conditioned"):
            relacc.tree_accelerations(tree, 2, s.q, s.u, backend=backend)
    with pytest.warns(relacc.AccuracyWarning, match="1 of 1 states"):
        relacc.tree_accelerations(tree, 2, s.q[0], s.u[0])
    calm = _nearly_parallel_hinges(1e-2)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        relacc.tree_accelerations(calm, 2, s.q, s.u)


@pytest.mark.parametrize("backend", ["auto", "reference"])
def test_complex_inputs_are_carried_on_every_path_that_answers(backend):
    """Issue 50 item 6: the default path cast complex u to float64 (numpy's ComplexWarning only) while the reference
    path carried it (0.0596 against 0.0581 with u[9] += 0.5j). Complex inputs take Kane's equations on every path
    that answers, bit for bit the reference's; ``backend="fast"`` refuses them in one line."""
    tree = _nearly_parallel_hinges(0.3)
    s = random_states(tree, 2, 3, SEED)
    u = s.u.astype(complex)
    u[:, 1] += 0.5j
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        got = relacc.tree_accelerations(tree, 2, s.q, u, backend=backend)
    ref = relacc.tree_accelerations(tree, 2, s.q, u, backend="reference")
    assert got.dtype == np.complex128 and np.any(got.imag != 0)
    np.testing.assert_array_equal(got, ref)
    with pytest.raises(InputError, match="complex"):
        relacc.tree_accelerations(tree, 2, s.q, u, backend="fast")
