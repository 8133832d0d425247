"""relacc.kernels.trig.sincos against libm, and the case-3 kernels at block edges and beyond its range."""

import math

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


def _lanes_sincos(width: int):
    """The lanes kernel's sine and cosine (``relacc.kernels.lanes._trig``, the IR a traced tree's angles get) compiled
    alone over ``width`` lanes: ``f(x) -> (sin x, cos x)`` on a float64 array whose length is a multiple of it."""
    import ctypes

    from relacc.kernels import lanes

    vt, W = f"<{width} x double>", width

    def const(c):
        return lanes.splat(c, W)

    def vector(ptr, name):
        body = [f"  %{name}p = getelementptr double, double* %{ptr}, i64 %i",
                f"  %{name}vp = bitcast double* %{name}p to {vt}*", f"  %{name} = load {vt}, {vt}* %{name}vp, align 8"]
        return body

    body = ["define void @f(double* %x, double* %s, double* %c, i64 %n) {", "entry:", "  br label %loop", "loop:",
            "  %i = phi i64 [0, %entry], [%next, %trig_join]"]
    body += vector("x", "xv")
    body += lanes._trig(vt, const, [("%xv", ("%sv", "%cv"))])
    for ptr, v in (("s", "%sv"), ("c", "%cv")):
        body += [f"  %{ptr}p = getelementptr double, double* %{ptr}, i64 %i",
                 f"  %{ptr}vp = bitcast double* %{ptr}p to {vt}*", f"  store {vt} {v}, {vt}* %{ptr}vp, align 8"]
    body += [f"  %next = add i64 %i, {W}", "  %more = icmp slt i64 %next, %n",
             "  br i1 %more, label %loop, label %done", "done:", "  ret void", "}"]
    decl = [f"declare {vt} @llvm.{f}.v{W}f64({vt})" for f in ("sin", "cos", "fabs", "floor")]
    decl.append(f"declare i1 @llvm.vector.reduce.or.v{W}i1(<{W} x i1>)")
    engine = lanes.jit("\n".join(decl + body) + "\n")
    fn = ctypes.CFUNCTYPE(None, *([ctypes.c_void_p] * 3), ctypes.c_int64)(engine.get_function_address("f"))

    def run(x):
        x = np.ascontiguousarray(x, dtype=float)
        s, c = np.empty_like(x), np.empty_like(x)
        fn(x.ctypes.data, s.ctypes.data, c.ctypes.data, len(x))
        return s, c

    run.engine = engine  # the code lives as long as the function
    return run


@pytest.mark.parametrize("width", [1, 4])
def test_the_lanes_sincos_is_fdlibms_and_libms_beyond_its_range(width):
    """The sine and cosine written into the lanes' IR give the bits of trig.sincos (the same fdlibm algorithm compiled
    by numba) on 2.4 million hard angles within trig.LIMIT, so within TRIG_ULPS of libm; beyond LIMIT, libm's own
    bits. Big and ordinary angles share vectors: each lane's bits are its own angle's, whatever its neighbours."""
    seed = 3 + width
    rng = np.random.default_rng(seed)
    x = _angles(seed)
    big = rng.choice([-1.0, 1.0], 4096) * 10.0 ** rng.uniform(np.log10(trig.LIMIT) + 1e-9, 300.0, 4096)
    x = np.concatenate([x, big, [np.inf, -np.inf, np.nan]])
    x = rng.permutation(np.concatenate([x, np.zeros((-len(x)) % 4)]))
    s, c = _lanes_sincos(width)(x)
    inside = np.abs(x) <= trig.LIMIT
    ref_s, ref_c = trig.sincos_array(x[inside])
    np.testing.assert_array_equal(s[inside], ref_s, err_msg=f"seed {seed}")
    np.testing.assert_array_equal(c[inside], ref_c, err_msg=f"seed {seed}")
    worst = max(_ulps(s[inside], np.sin(x[inside])).max(), _ulps(c[inside], np.cos(x[inside])).max())
    assert worst <= TRIG_ULPS, f"seed {seed}: {worst} ulps"
    libm = [(math.sin(v), math.cos(v)) if math.isfinite(v) else (math.nan, math.nan) for v in x[~inside]]
    np.testing.assert_array_equal(s[~inside], [a for a, _ in libm], err_msg=f"seed {seed}")  # Python's math: libm
    np.testing.assert_array_equal(c[~inside], [b for _, b in libm], err_msg=f"seed {seed}")
