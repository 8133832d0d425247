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
    res, _, singular = kernel.accelerations(tree, case, s.q, s.u, np.zeros_like(s.u), tree.gravity,
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
    crba, _, n1 = kernel.accelerations(tree, case, s.q, s.u, np.zeros_like(s.u), tree.gravity, algorithm="crba")
    aba, _, n2 = kernel.accelerations(tree, case, s.q, s.u, np.zeros_like(s.u), tree.gravity, algorithm="aba")
    lanes, _, n3 = kernel.accelerations(tree, case, s.q, s.u, np.zeros_like(s.u), tree.gravity, algorithm="lanes")
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
