"""The fused batch kernels: same numbers as the note's reference implementation, bounded memory."""

import tracemalloc

import numpy as np
import pytest

import relacc
from relacc.core.scales import term_scales
from relacc.core.states import random_states
from relacc.core.stream import iter_g2_kinematics
from relacc.core.tolerances import assert_normalized_error
from relacc.kernels import kinematics as fast

from .conftest import seed_for

FIELDS = ("position", "velocity", "acceleration", "V", "Vdot")


def test_fast_equals_reference_to_a_few_ulps(chain, case):
    """Fused kernels and the note's labelled formulas agree within 8 eps of the terms, 5000 states."""
    s = random_states(case, 5000, seed_for(case, 30))
    k = relacc.g2_kinematics(chain, case, s.q, s.u, s.udot, backend="fast")
    ref = relacc.g2_kinematics(chain, case, s.q, s.u, s.udot, backend="reference")
    sc = term_scales(chain, case, s.q, s.u, s.udot)
    for name in FIELDS:
        assert_normalized_error(getattr(k, name), getattr(ref, name), sc.of(name), what=name, seed=s.seed, factor=8)


def test_numba_and_numpy_backends_are_bit_identical(chain, case):
    """The kernel source run by numba per state and by numpy per column gives the same bits."""
    if not fast.HAVE_NUMBA:
        pytest.fail("numba is a dependency of relacc and must be importable")
    s = random_states(case, 500, seed_for(case, 31))
    (a, _, _), (b, _, _) = (fast.kinematics(case, s.q, s.u, s.udot, chain.q2, chain.r2, backend=be)
                            for be in ("numba", "numpy"))
    for x, y, name in zip(a, b, FIELDS):
        assert np.array_equal(x, y), name
    acc_nb, _, _ = fast.acceleration(case, s.q, s.u, s.udot, chain.q2, chain.r2, backend="numba")
    acc_np, _, _ = fast.acceleration(case, s.q, s.u, s.udot, chain.q2, chain.r2, backend="numpy")
    assert np.array_equal(acc_nb, acc_np) and np.array_equal(acc_nb, a[2])


def test_g2_acceleration_equals_full_evaluation(chain, case):
    """relacc.g2_acceleration returns exactly g2_kinematics(...).acceleration, for any batch shape."""
    s = random_states(case, 60, seed_for(case, 32))
    full = relacc.g2_kinematics(chain, case, s.q, s.u, s.udot)
    acc = relacc.g2_acceleration(chain, case, s.q.reshape(3, 20, -1), s.u.reshape(3, 20, 12),
                                 s.udot.reshape(3, 20, 12))
    assert acc.shape == (3, 20, 3) and np.array_equal(acc.reshape(60, 3), full.acceleration)


def test_auto_backend_routes_printed_and_complex_to_reference(chain):
    """'auto' keeps printed variants and complex (complex-step) inputs on the reference path."""
    s = random_states(1, 4, 33)
    with pytest.raises(relacc.InputError, match="backend 'fast'"):
        relacc.g2_kinematics(chain, 1, s.q, s.u, variant="printed", backend="fast")
    with pytest.raises(relacc.InputError, match="unknown backend"):
        relacc.g2_kinematics(chain, 1, s.q, s.u, backend="gpu")
    k = relacc.g2_kinematics(chain, 1, s.q.astype(complex), s.u)
    assert k.position.dtype == complex


@pytest.mark.parametrize("where,value,match", [
    ((7, 0), np.nan, "non-finite value nan at index"),
    ((3, 5), np.inf, "non-finite value inf"),
    ((5, 3), 0.5, "does not normalize"),
])
@pytest.mark.parametrize("entry", [relacc.g2_kinematics, relacc.g2_acceleration])
def test_fast_path_reports_bad_values_like_the_checks(chain, entry, where, value, match):
    """Values checked inside the kernel raise the same InputError, naming the entry, as the Python checks."""
    s = random_states(1, 10, 37)
    q = s.q.copy()
    q[where] = value
    with pytest.raises(relacc.InputError, match=match):
        entry(chain, 1, q, s.u, s.udot)


def test_stream_equals_one_batch(chain, case):
    """Chunked evaluation gives the same numbers as one call, chunk by chunk."""
    s = random_states(case, 1000, seed_for(case, 34))
    whole = relacc.g2_kinematics(chain, case, s.q, s.u, s.udot)
    seen = 0
    for states, k in iter_g2_kinematics(chain, case, s.q, s.u, s.udot, chunk_size=300):
        for name in FIELDS:
            assert np.array_equal(getattr(k, name), getattr(whole, name)[states])
        seen += states.stop - states.start
    assert seen == 1000
    accs = [a for _, a in iter_g2_kinematics(chain, case, s.q, s.u, s.udot, chunk_size=300, acceleration_only=True)]
    assert np.array_equal(np.concatenate(accs), whole.acceleration)


def test_stream_names_the_bad_chunk(chain):
    """An input error in a chunk names the chunk's state range."""
    s = random_states(1, 10, 35)
    q = s.q.copy()
    q[7, 0] = np.nan
    with pytest.raises(relacc.InputError, match="states 5..9: q for case 1: non-finite"):
        list(iter_g2_kinematics(chain, 1, q, s.u, s.udot, chunk_size=5))


@pytest.mark.slow
def test_stream_memory_is_bounded_by_the_chunk(chain, tmp_path):
    """Streaming 400k states from memmaps peaks at the same memory as 100k: set by the chunk, not N."""
    def peak(n):
        s = random_states(1, n, 36)
        files = []
        for name, a in (("q", s.q), ("u", s.u), ("d", s.udot)):
            path = tmp_path / f"{name}{n}.npy"
            np.save(path, a)
            files.append(np.load(path, mmap_mode="r"))
        del s
        tracemalloc.start()
        total = 0.0
        for _, acc in iter_g2_kinematics(chain, 1, *files, chunk_size=20_000, acceleration_only=True):
            total += float(acc[0, 0])
        _, top = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        return top

    small, large = peak(100_000), peak(400_000)
    per_chunk = 20_000 * (14 + 12 + 12 + 3) * 8
    assert large <= 1.2 * small + 1e6 and large <= 3 * per_chunk, (small, large, per_chunk)


def test_out_buffers_give_the_same_numbers_without_new_outputs(chain, case):
    """g2_kinematics(out=...) and g2_acceleration(out=...) write the same bits into the caller's arrays."""
    s = random_states(case, 300, seed_for(case, 38))
    k = relacc.g2_kinematics(chain, case, s.q, s.u, s.udot)
    out = (np.empty((300, 3)), np.empty((300, 3)), np.empty((300, 3)), np.empty((300, 3, 12)), np.empty((300, 3, 12)))
    again = relacc.g2_kinematics(chain, case, s.q, s.u, s.udot, out=out)
    for name, buf in zip(FIELDS, out):
        assert getattr(again, name) is buf and np.array_equal(buf, getattr(k, name)) and buf.flags.writeable
    acc = np.empty((300, 3))
    assert relacc.g2_acceleration(chain, case, s.q, s.u, s.udot, out=acc) is acc
    assert np.array_equal(acc, k.acceleration)
    with pytest.raises(relacc.InputError, match="out V: expected a writable C-contiguous float64 array"):
        relacc.g2_kinematics(chain, case, s.q, s.u, s.udot, out=out[:3] + (np.empty((300, 12, 3)), out[4]))


def test_stream_reuses_its_buffers(chain):
    """reuse=True writes every chunk into the same arrays and gives the same numbers chunk by chunk."""
    s = random_states(2, 1000, seed_for(2, 39))
    whole = relacc.g2_kinematics(chain, 2, s.q, s.u, s.udot)
    seen = set()
    for states, k in iter_g2_kinematics(chain, 2, s.q, s.u, s.udot, chunk_size=300, reuse=True):
        assert np.array_equal(k.V, whole.V[states])
        seen.add(k.V.__array_interface__["data"][0])
    assert len(seen) == 1  # one buffer for all four chunks (the last a view of it)


def test_the_chains_kernels_give_a_states_bits_alone_on_one_thread_and_split_over_two(chain, case):
    """The note's G2 kernels and the chain's forward dynamics run a batch on the calling thread or split over threads
    where that pays (relacc.kernels.jit.parallel_pays); a state's result must not depend on which, nor on being
    asked alone: 8,192 states (split on two threads, one block more than LAUNCH_US's break-even) against the same
    states on one thread and the first 24 one call each."""
    from relacc import dynamics
    from relacc.dynamics import Effects
    from relacc.kernels.jit import HAVE_NUMBA, parallel_pays, threads

    effects = Effects(gravity=(0, 0, -9.81), spring_stiffness=(10, 10, 10), spring_damping=(1, 1, 1),
                      ball_damping=0.1)
    s = random_states(case, 8192, seed_for(case, 61))
    with threads(2):
        assert not HAVE_NUMBA or parallel_pays(8192, fast.FULL_US_PER_STATE, 128), "the batch would not be split"
        two = relacc.g2_kinematics(chain, case, s.q, s.u, s.udot)
        a_two = dynamics.accelerations(chain, case, s.q, s.u, effects)
    with threads(1):
        one = relacc.g2_kinematics(chain, case, s.q, s.u, s.udot)
        a_one = dynamics.accelerations(chain, case, s.q, s.u, effects)
    for name in FIELDS:
        assert np.array_equal(getattr(one, name), getattr(two, name)), (name, s.seed)
    assert np.array_equal(a_one, a_two), s.seed
    for i in range(24):
        k = relacc.g2_kinematics(chain, case, s.q[i], s.u[i], s.udot[i])
        for name in FIELDS:
            assert np.array_equal(getattr(k, name), getattr(one, name)[i]), (name, i, s.seed)
        assert np.array_equal(dynamics.accelerations(chain, case, s.q[i], s.u[i], effects), a_one[i]), (i, s.seed)
