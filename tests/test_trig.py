"""relacc.kernels.trig.sincos against libm, and the case-3 kernels at block edges and beyond its range."""

import numpy as np
import pytest

import relacc
from relacc.core.scales import term_scales
from relacc.core.states import random_states
from relacc.core.tolerances import TRIG_ULPS, assert_normalized_error
from relacc.kernels import kinematics as fast
from relacc.kernels import trig
from relacc.kernels.perstate import ANGLES, TRIG_BLOCK

from .conftest import seed_for

FIELDS = ("position", "velocity", "acceleration", "V", "Vdot")


def _angles(seed):
    """Angles (rad) where range reduction and the polynomials are hardest, all within trig.LIMIT."""
    rng = np.random.default_rng(seed)
    n = 400_000
    k = rng.integers(-(2**20) + 1, 2**20, n).astype(float)
    near = k * (np.pi / 2)  # the doubles nearest multiples of pi/2, where sin or cos cancels
    return np.concatenate([
        rng.uniform(-4.0, 4.0, n),
        rng.uniform(-trig.LIMIT, trig.LIMIT, n),
        rng.choice([-1.0, 1.0], n) * 10.0 ** rng.uniform(-320.0, np.log10(trig.LIMIT), n),
        near, np.nextafter(near, np.inf), np.nextafter(near, -np.inf),
        np.pi / 4 + np.arange(-50, 51) * np.spacing(np.pi / 4),  # the octant edge
        [0.0, -0.0, 5e-324, -5e-324, trig.LIMIT, -trig.LIMIT],
    ])


def _ulps(x, ref):
    return np.abs(x - ref) / np.spacing(np.abs(ref))


@pytest.mark.parametrize("seed", [0, 1])
def test_sincos_within_two_ulps_of_libm(seed):
    """sincos differs from libm's sin and cos by at most TRIG_ULPS ulps over 2.4 million hard angles."""
    x = _angles(seed)
    s, c = trig.sincos_array(x)
    worst = max(_ulps(s, np.sin(x)).max(), _ulps(c, np.cos(x)).max())
    assert worst <= TRIG_ULPS, f"seed {seed}: {worst} ulps"


@pytest.mark.slow
def test_sincos_compiled_and_numpy_give_the_same_bits():
    """The compiled sincos and the same source run on numpy arrays agree bit for bit."""
    x = _angles(2)
    (s1, c1), (s2, c2) = trig.sincos_array(x), trig.sincos(x)
    assert np.array_equal(s1, s2) and np.array_equal(c1, c2)


@pytest.mark.parametrize("n", [1, TRIG_BLOCK - 1, TRIG_BLOCK, TRIG_BLOCK + 1, 3 * TRIG_BLOCK + 5])
def test_case3_kernels_at_block_edges(chain, n):
    """Batches that end inside, at and just past a trig block give the reference's numbers, both backends."""
    s = random_states(3, n, seed_for(3, 60 + n))
    k = relacc.g2_kinematics(chain, 3, s.q, s.u, s.udot, backend="fast")
    ref = relacc.g2_kinematics(chain, 3, s.q, s.u, s.udot, backend="reference")
    sc = term_scales(chain, 3, s.q, s.u, s.udot)
    for name in FIELDS:
        assert_normalized_error(getattr(k, name), getattr(ref, name), sc.of(name), what=name, seed=s.seed, factor=8)
    acc_nb, _, _ = fast.acceleration(3, s.q, s.u, s.udot, chain.q2, chain.r2, backend="numba")
    acc_np, _, _ = fast.acceleration(3, s.q, s.u, s.udot, chain.q2, chain.r2, backend="numpy")
    assert np.array_equal(acc_nb, acc_np) and np.array_equal(acc_nb, k.acceleration)


@pytest.mark.parametrize("offset", [trig.LIMIT * (1 + 1e-15), 1e7, 1e12])
def test_angles_beyond_the_sincos_range_fall_back_to_libm(chain, offset):
    """States with an angle beyond trig.LIMIT, among ordinary ones, are redone with libm: reference numbers."""
    s = random_states(3, 2 * TRIG_BLOCK + 7, seed_for(3, 70))
    q = s.q.copy()
    rows = [0, 5, TRIG_BLOCK, 2 * TRIG_BLOCK + 6]
    for j, i in enumerate(rows):
        col = (3, 5, 9, 11)[j]
        q[i, col] = np.copysign(offset, q[i, col]) + q[i, col]  # far from 0, not near a multiple of 2 pi
    assert all(np.abs(q[i, list(ANGLES)]).max() > trig.LIMIT for i in rows)
    k = relacc.g2_kinematics(chain, 3, q, s.u, s.udot, backend="fast")
    ref = relacc.g2_kinematics(chain, 3, q, s.u, s.udot, backend="reference")
    sc = term_scales(chain, 3, q, s.u, s.udot)
    for name in FIELDS:
        assert_normalized_error(getattr(k, name), getattr(ref, name), sc.of(name), what=name, seed=s.seed, factor=8)
    acc = relacc.g2_acceleration(chain, 3, q, s.u, s.udot)
    assert np.array_equal(acc, k.acceleration)
    acc_np, _, _ = fast.acceleration(3, q, s.u, s.udot, chain.q2, chain.r2, backend="numpy")
    assert np.array_equal(acc, acc_np)
