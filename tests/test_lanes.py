"""The lanes kernel (relacc.kernels.lanes): the numba kernel's code traced per tree and compiled over several states
at once. Its numbers against Kane's equations are checked with the other kernels' (tests/test_tree_kernels.py,
tests/test_singular.py, parametrized over the algorithm); here what is its own: a state's answer does not depend on
its lane, its batch or the lane width; bad inputs are counted per state; the object code is cached and reused; a tree
the lanes do not take runs the numba kernels."""

import json

import numpy as np
import pytest

import relacc
from relacc.core.tree import random_states
from relacc.engines.mujoco_.spec import read_tree
from relacc.kernels import lanes
from relacc.kernels import tree_dynamics as kernel
from tests.test_tree import _tree_file


def _random_tree(tmp_path, seed=5, nb=6):
    return read_tree(_tree_file(tmp_path, seed, nb))


@pytest.mark.parametrize("case", [1, 2, 3])
def test_a_states_answer_does_not_depend_on_its_lane_or_its_batch(tmp_path, case):
    """13 states (not a multiple of 4 or 8: a partly filled last vector) in a batch, in reverse order, and one at a
    time through the single-state lane: every row the same bits, since every lane runs the same instructions."""
    seed = 5 + case
    tree = _random_tree(tmp_path, seed)
    s = random_states(tree, case, 13, seed)
    tau = np.random.default_rng(seed).standard_normal((13, tree.nv))
    batch, bad, singular, _ = kernel.accelerations(tree, case, s.q, s.u, tau, tree.gravity, algorithm="lanes")
    assert bad == singular == 0, f"seed {seed}"
    back = kernel.accelerations(tree, case, s.q[::-1].copy(), s.u[::-1].copy(), tau[::-1].copy(), tree.gravity,
                                algorithm="lanes")[0]
    np.testing.assert_array_equal(back[::-1], batch, err_msg=f"seed {seed}")
    if case < 3:
        for i in range(13):
            one = kernel.one_state(tree, case, s.q[i], s.u[i], tree.gravity)
            assert one is not None, f"state {i}, seed {seed}: a plain state refused by the single-state lane"
            alone = kernel.accelerations(tree, case, s.q[i:i + 1], s.u[i:i + 1], np.zeros((1, tree.nv)),
                                         tree.gravity, algorithm="lanes")[0][0]
            np.testing.assert_array_equal(one, alone, err_msg=f"state {i}, seed {seed}")


def test_the_lane_width_changes_no_number(tmp_path):
    """The same trace compiled over 1 lane (the single-state lane of :func:`relacc.tree_accelerations`), 4 (AVX2)
    and 8 (AVX-512, or two AVX2 registers where the CPU has no AVX-512): the same instructions on each state, so the
    same bits. Each width's object code is cached under its own key, which also changes with the case, the algorithm
    and any mass of the tree (what the trace would fold into the code), so another tree's code is never what runs."""
    import dataclasses

    tree = _random_tree(tmp_path, 9)
    tr = lanes.trace(tree, 2)
    s = random_states(tree, 2, 21, 9)
    tau, g = np.zeros((21, tree.nv)), np.asarray(tree.gravity, dtype=float)
    outs = []
    for width in (1, 4, 8):
        name = f"width_test_{lanes._key(tree, 2, 'crba', width)[:16]}"
        fns, engine = lanes.compile_cached(lambda: lanes.emit(tr, width, name), name)
        k = lanes.Kernel(fns, engine, 2, width, tr.nq, tr.nv)
        out = np.empty((21, tree.nv))
        assert k.block(s.q, s.u, tau, g, out, 0, 21) == (0, 0, 0)
        outs.append(out)
    np.testing.assert_array_equal(outs[1], outs[0])
    np.testing.assert_array_equal(outs[1], outs[2])
    bodies = list(tree.bodies)
    bodies[-1] = dataclasses.replace(bodies[-1], mass=bodies[-1].mass * (1 + 2**-40))
    heavier = dataclasses.replace(tree, bodies=tuple(bodies))
    keys = {lanes._key(t, c, a, w) for t, c, a, w in ((tree, 2, "crba", 4), (tree, 2, "crba", 1), (tree, 3, "crba", 4),
                                                      (tree, 2, "aba", 4), (heavier, 2, "crba", 4))}
    assert len(keys) == 5 and lanes._key(_random_tree(tmp_path, 9), 2, "crba", 4) in keys


def test_bad_inputs_are_counted_per_state(tmp_path):
    """A NaN coordinate, an infinite speed and a quaternion 1.1 long in three of 11 states: 3 states counted (two bad
    values in one state count once), and ``tree_accelerations`` names the first; the other rows are answered."""
    tree = _random_tree(tmp_path, 4)
    s = random_states(tree, 2, 11, 4)
    q, u = s.q.copy(), s.u.copy()
    q[2, 0] = np.nan
    u[2, 1] = np.nan
    u[5, 1] = np.inf
    q[7, 3:7] *= 1.1  # the free root's quaternion
    out, bad, singular, _ = kernel.accelerations(tree, 2, q, u, np.zeros_like(u), tree.gravity, algorithm="lanes")
    assert (bad, singular) == (3, 0)
    good = [i for i in range(11) if i not in (2, 5, 7)]
    ref = kernel.accelerations(tree, 2, s.q[good], s.u[good], np.zeros((8, tree.nv)), tree.gravity,
                               algorithm="lanes")[0]
    np.testing.assert_array_equal(out[good], ref)
    with pytest.raises(relacc.InputError, match="non-finite"):
        relacc.tree_accelerations(tree, 2, q, u)


def test_the_single_state_entry_point_flags_what_the_general_path_refuses(tmp_path):
    """The single-state entry point (``name_one``) on one state at a time: 0 for a plain state (its answer the batch
    row's bits); the bad-input flag for a NaN speed and for a quaternion 1.1 long; the not-finite flag alone for
    speeds of 1e200 (finite inputs whose answer overflows). ``tree_accelerations`` then takes the general path and
    refuses each in its words."""
    tree = _random_tree(tmp_path, 4)
    s = random_states(tree, 2, 1, 4)
    k = lanes.kernel(tree, 2, kernel.plan(tree).method, width=1)
    one = kernel.single(tree, 2, tree.gravity)
    buf = np.zeros(tree.nq + 3 * tree.nv + 3)  # q | u | tau | g | out
    buf[tree.nq + 2 * tree.nv:tree.nq + 2 * tree.nv + 3] = tree.gravity

    def flags(q, u):
        buf[:tree.nq], buf[tree.nq:tree.nq + tree.nv] = q, u
        return k.one(buf.ctypes.data)

    assert flags(s.q[0], s.u[0]) == 0
    row = kernel.accelerations(tree, 2, s.q, s.u, np.zeros_like(s.u), tree.gravity, algorithm="lanes")[0][0]
    np.testing.assert_array_equal(one(s.q[0], s.u[0]), row)
    nan_u, long_q, huge_u = s.u[0].copy(), s.q[0].copy(), np.full(tree.nv, 1e200)
    nan_u[1] = np.nan
    long_q[3:7] *= 1.1  # the free root's quaternion
    assert flags(s.q[0], nan_u) & lanes.ONE_BAD_INPUT
    assert flags(long_q, s.u[0]) & lanes.ONE_BAD_INPUT
    assert flags(s.q[0], huge_u) == lanes.ONE_NOT_FINITE
    for q, u, words in ((s.q[0], nan_u, "non-finite"), (long_q, s.u[0], "off unit"), (s.q[0], huge_u, "overflow")):
        assert one(q, u) is None
        with pytest.raises(relacc.InputError, match=words):
            relacc.tree_accelerations(tree, 2, q, u)


def test_the_builtin_single_state_call_checks_its_arguments_and_owns_nothing_it_should_not(tmp_path):
    """Once the lane runs its -O2 code, one state goes from CPython straight into compiled code
    (:func:`relacc.kernels.direct.builtin`): the answer is the batch row's bits, a new read-only array each call;
    every argument the compiled checks do not take (a count other than two, a list, float32, a big-endian float64, a
    subclass, a wrong length, two dimensions, a strided view) and every flagged state gives None, and
    ``tree_accelerations`` then answers or refuses through its general path as before; the arguments' and None's
    reference counts are what they were after 2,000 calls (the compiled code takes no reference it does not give
    back)."""
    import sys

    from relacc.kernels.direct import _layout_ok

    tree = _random_tree(tmp_path, 9)
    s = random_states(tree, 2, 3, 9)
    kernel.optimize(tree, 2)
    assert _layout_ok(), "this CPython's PyArrayObject layout is the one the IR reads"
    one = kernel.single(tree, 2, tree.gravity)
    assert type(one).__name__ == "builtin_function_or_method"
    q, u = np.array(s.q[0]), np.array(s.u[0])
    batch = kernel.accelerations(tree, 2, s.q, s.u, np.zeros_like(s.u), tree.gravity, algorithm="lanes")[0]
    a, b = one(q, u), one(np.array(s.q[1]), np.array(s.u[1]))
    np.testing.assert_array_equal(a, batch[0])
    np.testing.assert_array_equal(b, batch[1])  # a second call leaves the first answer as it was
    refs = sys.getrefcount(a)  # the name a and getrefcount's argument: nothing else holds the answer
    assert refs == 2 and a is not b and not a.flags.writeable and a.flags.owndata

    class Sub(np.ndarray):
        pass

    strided = np.repeat(q, 2)[::2]
    refused = [(q,), (q, u, u), (list(q), u), (q.astype(np.float32), u), (q.astype(">f8"), u), (q.view(Sub), u),
               (q[:-1], u), (q[None], u), (strided, u), (q, u[:-1])]
    for args in refused:
        assert one(*args) is None, [getattr(x, "dtype", type(x)) for x in args]
    np.testing.assert_array_equal(relacc.tree_accelerations(tree, 2, strided, u), batch[0])  # the general path
    nan_u = u.copy()
    nan_u[0] = np.nan
    assert one(q, nan_u) is None
    with pytest.raises(relacc.InputError, match="non-finite"):
        relacc.tree_accelerations(tree, 2, q, nan_u)
    counts = sys.getrefcount(q), sys.getrefcount(u), sys.getrefcount(None)
    for _ in range(1000):
        one(q, u)
        one(q, nan_u)
    assert (sys.getrefcount(q), sys.getrefcount(u), sys.getrefcount(None)) == counts


def test_angles_beyond_the_sincos_range_take_libms_in_their_own_lanes(tmp_path):
    """Hinge angles of about 1e7 rad (beyond ``trig.LIMIT``, where the lanes' fdlibm sine and cosine give way to libm's)
    in 5 of 21 states, the others ordinary: every row has the bits of the same state alone (its neighbours change
    nothing), and they are numba's kernel's (libm's sine and cosine everywhere) within the bound of a solve. (Kane's
    equations differ from both kernels by up to 7e-8 on these rows, 2x that bound, as before the lanes had their own
    sine: the paths round ``theta`` times a constant differently, and at 1e7 rad an ulp of the angle is 2e-9.)"""
    from relacc.kernels.trig import LIMIT
    from tests.test_tree_kernels import _dynamics_scale

    seed = 12
    tree = _random_tree(tmp_path, seed, 7)
    s = random_states(tree, 2, 21, seed)
    hinges = [tree.qadr(2)[k] for k, (_, j) in enumerate(tree.joints) if j.type == "hinge"]
    assert hinges, f"seed {seed}: the random tree has no hinge"
    q = s.q.copy()
    big = [0, 4, 5, 13, 20]
    q[np.ix_(big, hinges)] += 1.6e6 * np.pi * 2  # a multiple of 2 pi, rounded: the angle's own double
    assert np.abs(q[big][:, hinges]).min() > LIMIT
    tau = np.zeros_like(s.u)
    batch, bad, singular, _ = kernel.accelerations(tree, 2, q, s.u, tau, tree.gravity, algorithm="lanes")
    assert bad == singular == 0, f"seed {seed}"
    for i in range(21):
        alone = kernel.accelerations(tree, 2, q[i:i + 1], s.u[i:i + 1], tau[i:i + 1], tree.gravity,
                                     algorithm="lanes")[0][0]
        np.testing.assert_array_equal(batch[i], alone, err_msg=f"state {i}, seed {seed}")
        np.testing.assert_array_equal(kernel.one_state(tree, 2, q[i], s.u[i], tree.gravity), alone,
                                      err_msg=f"state {i}, seed {seed}")
    ref = kernel.accelerations(tree, 2, q, s.u, tau, tree.gravity, algorithm="crba")[0]  # numba's, libm's trig
    bound = _dynamics_scale(tree, 2, q, s.u, ref) * 64 * 2.2e-16 * max(tree.depth)
    err = np.abs(batch - ref).max(axis=1)
    assert np.all(err <= bound), f"worst {np.max(err / bound):.3g} of the bound (seed {seed})"


def test_the_object_code_is_cached_and_loaded_by_the_next_tree(tmp_path, monkeypatch):
    """The first tree's kernel leaves its object code in the cache directory; an equal tree read again (another
    object: another process sees the same) loads it without tracing the kernel or emitting IR, and computes the same
    bits. A cache that cannot be written is skipped."""
    cache = tmp_path / "cache"
    monkeypatch.setattr(lanes, "_cache_dir", lambda: str(cache))
    path = _tree_file(tmp_path, 6, 5)
    first = read_tree(path)
    s = random_states(first, 2, 9, 6)
    a = kernel.accelerations(first, 2, s.q, s.u, np.zeros_like(s.u), first.gravity, algorithm="lanes")[0]
    files = sorted(p.name for p in cache.iterdir())
    assert len(files) == 1 and files[0].startswith("lanes_") and files[0].endswith("_O0.lobj"), files

    def no_ir(*_a, **_k):
        raise AssertionError("IR emitted although the object code was cached")

    monkeypatch.setattr(lanes, "emit", no_ir)
    monkeypatch.setattr(lanes, "trace", no_ir)
    again = read_tree(path)
    b = kernel.accelerations(again, 2, s.q, s.u, np.zeros_like(s.u), again.gravity, algorithm="lanes")[0]
    np.testing.assert_array_equal(a, b)
    monkeypatch.undo()
    blocked = tmp_path / "a-file"
    blocked.write_text("")
    monkeypatch.setattr(lanes, "_cache_dir", lambda: str(blocked / "sub"))
    third = read_tree(path)
    c = kernel.accelerations(third, 2, s.q, s.u, np.zeros_like(s.u), third.gravity, algorithm="lanes")[0]
    np.testing.assert_array_equal(a, c)


@pytest.mark.parametrize("damage", ["truncated", "empty", "random", "swapped", "one byte edited"])
def test_a_damaged_cached_kernel_is_compiled_again_and_said(tmp_path, monkeypatch, capfd, damage):
    """Issue 50 item 3: a cached object file truncated, empty, random, another tree's, or with one constant edited
    was a segmentation fault (or accelerations 1e-7 off, silently) in every command touching that tree. What is
    loaded is verified first: the kernel is compiled again, the same bits as the undamaged one, one line on stderr,
    and the file is written anew, whole."""
    cache = tmp_path / "cache"
    monkeypatch.setattr(lanes, "_cache_dir", lambda: str(cache))
    path, other = _tree_file(tmp_path, 6, 5), _tree_file(tmp_path, 7, 4)
    tree = read_tree(path)
    s = random_states(tree, 2, 9, 6)
    good = kernel.accelerations(tree, 2, s.q, s.u, np.zeros_like(s.u), tree.gravity, algorithm="lanes")[0]
    (cached,) = cache.iterdir()
    whole = cached.read_bytes()
    if damage == "swapped":
        t = read_tree(other)
        st = random_states(t, 2, 2, 1)
        kernel.accelerations(t, 2, st.q, st.u, np.zeros((2, t.nv)), t.gravity, algorithm="lanes")
        theirs = next(p for p in cache.iterdir() if p != cached)
    damaged = {"truncated": whole[: len(whole) // 2], "empty": b"",
               "random": np.random.default_rng(0).bytes(len(whole)),
               "swapped": theirs.read_bytes() if damage == "swapped" else b"",
               "one byte edited": whole[:-100] + bytes([whole[-100] ^ 1]) + whole[-99:]}[damage]
    cached.write_bytes(damaged)
    capfd.readouterr()
    again = read_tree(path)
    out = kernel.accelerations(again, 2, s.q, s.u, np.zeros_like(s.u), again.gravity, algorithm="lanes")[0]
    np.testing.assert_array_equal(out, good)
    err = capfd.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "is damaged" in err[0] and "compiling it again" in err[0], err
    assert cached.read_bytes() == whole


def test_a_failed_cache_write_leaves_no_temporary_file(tmp_path, monkeypatch):
    """Issue 50 item 3: a write that fails (a full disk: here ``fsync`` raising ENOSPC) removes its temporary file
    and skips the cache; the kernel still runs."""
    import errno
    import os

    cache = tmp_path / "cache"
    monkeypatch.setattr(lanes, "_cache_dir", lambda: str(cache))

    def full(fd):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(os, "fsync", full)
    tree = read_tree(_tree_file(tmp_path, 6, 5))
    s = random_states(tree, 2, 3, 6)
    out = kernel.accelerations(tree, 2, s.q, s.u, np.zeros_like(s.u), tree.gravity, algorithm="lanes")[0]
    assert np.all(np.isfinite(out)) and list(cache.iterdir()) == []


def test_a_tree_beyond_the_lanes_runs_the_numba_kernels(tmp_path):
    """A 40-ball chain (126 speeds): even its articulated-body algorithm traces to more than ``MAX_OPS`` operations
    (53,000), so that algorithm's numba kernel runs it; asking for the lanes by name says why not."""
    from relacc.tradeoff.trees import chain_mjcf

    path = tmp_path / "chain.xml"
    path.write_text(chain_mjcf(40, "ball"))
    deep = read_tree(path)
    assert kernel.method(deep) == "aba" and sum(lanes._needed(lanes.trace(deep, 2, "aba"))) > lanes.MAX_OPS
    assert kernel.algorithm_used(deep, 2) == "aba"
    assert lanes.kernel(deep, 2, "aba") is None
    s = random_states(deep, 2, 2, 1)
    with pytest.raises(ValueError, match="lanes kernel is not available"):
        kernel.accelerations(deep, 2, s.q, s.u, np.zeros_like(s.u), deep.gravity, algorithm="lanes")


def test_the_trace_folds_the_trees_constants():
    """A pendulum on a hinge about a coordinate axis costs fewer operations than the same pendulum about an oblique
    axis: the axis' zero components fold away (a product with 0, a sum with 0), which is where much of the lanes'
    saving over the numba kernel comes from."""
    def pendulum(axis):
        return relacc.Tree("p", [relacc.Body("a", joints=[relacc.Joint.hinge("h", axis)], mass=1.0,
                                             com=(0.3, 0.1, 0.0), inertia=np.diag([0.1, 0.2, 0.3]))])

    along = sum(lanes._needed(lanes.trace(pendulum((0, 0, 1)), 2)))
    oblique = sum(lanes._needed(lanes.trace(pendulum((0.6, 0.0, 0.8)), 2)))
    assert along < oblique, (along, oblique)


def test_a_freed_kernels_code_goes_with_it_and_the_next_compiles(tmp_path, monkeypatch):
    """Kernels compiled one after another, each freed (its tree gone) before the next: each engine takes its own
    target machine with it (before, one machine shared by the engines was used after the first was freed: a crash
    in LLVM at the second compilation)."""
    import gc

    monkeypatch.setattr(lanes, "_cache_dir", lambda: None)
    path = _tree_file(tmp_path, 3, 4)
    answers = []
    for _ in range(3):
        tree = read_tree(path)
        s = random_states(tree, 2, 5, 3)
        answers.append(kernel.accelerations(tree, 2, s.q, s.u, np.zeros_like(s.u), tree.gravity,
                                            algorithm="lanes")[0])
        del tree
        gc.collect()
    np.testing.assert_array_equal(answers[0], answers[2])


def test_a_branch_on_a_states_value_stops_the_trace():
    """The trace takes the tree's branches, never a state's: a comparison or a truth test of a symbolic value raises
    ``Untraceable`` (the tree then runs the numba kernel), except the factorization's pivot tests, which become the
    state's singular flag."""
    g = lanes._Graph()
    x = g.node("in", "q", 0)
    for branch in (lambda: x > 0.5, lambda: x < 0.5, lambda: x == 0.5, lambda: bool(x), lambda: float(x)):
        with pytest.raises(lanes.Untraceable):
            branch()
    g.pivots_allowed = True
    assert (x * 2.0 > 1e-12) is True
    assert g.pivots == [(g.ops.index(("mul", 0, ("c", 2.0))), ("c", 1e-12))]


@pytest.mark.slow
def test_the_optimized_code_takes_over_with_the_same_bits(tmp_path, monkeypatch):
    """A kernel starts at ``-O0`` and is compiled at ``-O2`` once it has run ``UPGRADE_STATES`` states; the fused
    multiply-adds are in the IR and no fast-math flag is set, so the two give the same bits; the ``-O2`` object code
    is cached and the next tree starts with it."""
    cache = tmp_path / "cache"
    monkeypatch.setattr(lanes, "_cache_dir", lambda: str(cache))
    monkeypatch.setattr(lanes, "UPGRADE_STATES", 50)
    path = _tree_file(tmp_path, 8, 6)
    tree = read_tree(path)
    s = random_states(tree, 3, 40, 8)
    tau = np.random.default_rng(8).standard_normal((40, tree.nv))
    k = kernel._lanes(tree, 3, "lanes")  # the kernel of the tree as the dynamics run it (welded bodies folded)
    first = kernel.accelerations(tree, 3, s.q, s.u, tau, tree.gravity, algorithm="lanes")[0]
    assert (k.level, k.states) == (0, 40)
    second = kernel.accelerations(tree, 3, s.q, s.u, tau, tree.gravity, algorithm="lanes")[0]
    assert (k.level, k.states) == (2, 80)
    np.testing.assert_array_equal(first, second)
    assert sorted(p.name[-8:] for p in cache.iterdir()) == ["_O0.lobj", "_O2.lobj"]
    assert kernel._lanes(read_tree(path), 3, "lanes").level == 2
    other = read_tree(_tree_file(tmp_path, 10, 5))
    kernel.optimize(other, 2)  # at once, without running a state
    assert kernel._lanes(other, 2, "lanes").level == 2


@pytest.mark.parametrize("which", ["armature", "random7", "ball chain"])
def test_the_traced_articulated_body_algorithm_is_kanes_equations(tmp_path, which):
    """The lanes of the articulated-body algorithm (what deep trees get), forced on three trees (free, ball, slide and
    hinge joints with armature, whose cases 1 and 3 take the rotational armature's ``B^T D B``; a random tree; a
    12-body ball chain), every case, against Kane's equations within the bound the numba kernels are held to
    (``||M^-1|| (||M|| |udot| + |f|) 64 eps depth``, tests/test_tree_kernels.py)."""
    from relacc.core.tree import convert
    from relacc.core.tree.model import welded_folded
    from relacc.tradeoff.trees import chain_mjcf
    from tests.test_tree_kernels import ARMATURE, _dynamics_scale

    path = tmp_path / "t.xml"
    path.write_text({"armature": ARMATURE, "ball chain": chain_mjcf(12, "ball")}.get(which, "")
                    or _tree_file(tmp_path, 7, 6).read_text())
    tree = read_tree(path)
    st = random_states(tree, 2, 21, 7)
    tau = np.random.default_rng(7).standard_normal((21, tree.nv))
    g = np.asarray(tree.gravity, dtype=float)
    for case in (1, 2, 3):
        q, u, _ = convert(tree, st.q, st.u, source=2, target=case)
        k = lanes.kernel(welded_folded(tree), case, "aba")
        out = np.empty((21, tree.nv))
        assert k.block(np.ascontiguousarray(q), np.ascontiguousarray(u), tau, g, out, 0, 21) == (0, 0, 0)
        ref = relacc.tree_accelerations(tree, case, q, u, tau=tau, backend="reference")
        bound = _dynamics_scale(tree, case, q, u, ref) * 64 * 2.2e-16 * max(tree.depth)
        err = np.abs(out - ref).max(axis=1)
        assert np.all(err <= bound), f"{which}, case {case}: worst {np.max(err / bound):.3g} of the bound (seed 7)"


@pytest.mark.slow
@pytest.mark.parametrize("damage", ["index", "data"])
def test_a_damaged_numba_cache_file_is_compiled_again_and_said(tmp_path, damage):
    """A numba cache file (a kernel's ``.nbi`` index or ``.nbc`` code) truncated or overwritten made every later call
    of that kernel an internal error (``UnpicklingError``, exit 3) in every command: numba reads them with pickle and
    lets its errors through. Such a kernel is now compiled again (the same answer), said once on stderr, and its
    cache written anew: the process after that says nothing. Three fresh processes on one cache directory, with a
    cached kernel of relacc's own module layout (a file-backed module, as numba caches relacc's)."""
    import os
    import subprocess
    import sys

    (tmp_path / "kern.py").write_text("import relacc.kernels.jit\nimport numba\n\n\n"
                                      "@numba.njit(cache=True)\ndef f(x):\n    return 2.0 * x + 1.0\n")
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache"), "PYTHONPATH": str(tmp_path)}

    def run():
        done = subprocess.run([sys.executable, "-c", "import kern; print(kern.f(20.5))"], capture_output=True,
                              text=True, env=env, cwd=tmp_path, timeout=300)
        assert done.returncode == 0, done.stderr[-2000:]
        return done.stdout.strip(), [line for line in done.stderr.splitlines() if line.startswith("relacc:")]

    assert run() == ("42.0", [])
    (target,) = (tmp_path / "cache").rglob("*.nbi" if damage == "index" else "*.nbc")
    target.write_bytes(np.random.default_rng(3).bytes(64))
    out, said = run()
    assert out == "42.0" and len(said) == 1 and "is damaged" in said[0] and "compiling it again" in said[0], said
    assert run() == ("42.0", [])


@pytest.mark.slow
def test_two_processes_compile_a_kernel_once_between_them(tmp_path):
    """Two processes that ask at once for a kernel the shared cache lacks used to compile it side by side (pytest's
    workers, three commands of one installation: the tree stepper alone takes 27 s cold). Now one compiles it and the
    other waits for it and loads it from the cache: numba's own counters (``Dispatcher.stats``) of the chain's G2
    kernel show one miss and one hit between the two, where the old code shows two misses. Both processes are ready
    (relacc imported) before either calls, so that neither is late enough to find the kernel cached anyway; both
    answers are the same bits."""
    import os
    import subprocess
    import sys

    script = (
        "import json, os, sys, time\n"
        "import numpy as np\n"
        "import relacc\n"
        "from relacc.core.kinematics import g2_kinematics\n"
        "from relacc.kernels import kinematics as K\n"
        "s = relacc.testing.states(1, 8, seed=5)\n"
        "chain = relacc.fixtures.load().chain\n"
        "print('ready', flush=True)\n"
        "while not os.path.exists(sys.argv[1]):\n"
        "    time.sleep(0.01)\n"
        "k = g2_kinematics(chain, 1, s.q, s.u, s.udot, backend='fast')\n"
        "st = K._full_loop.stats\n"
        "print(json.dumps([sum(st.cache_misses.values()), sum(st.cache_hits.values()), k.acceleration.tolist()]))\n")
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache")}
    go = tmp_path / "go"
    procs = [subprocess.Popen([sys.executable, "-c", script, str(go)], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                              text=True, env=env, cwd=tmp_path) for _ in range(2)]
    for p in procs:
        assert p.stdout.readline().strip() == "ready", p.stderr.read()[-2000:]
    go.touch()
    done = [p.communicate(timeout=300) for p in procs]
    assert all(p.returncode == 0 for p in procs), [err[-2000:] for _, err in done]
    (m0, h0, a0), (m1, h1, a1) = (json.loads(out) for out, _ in done)
    assert sorted([(m0, h0), (m1, h1)]) == [(0, 1), (1, 0)], "each process compiled the kernel on its own"
    assert a0 == a1  # the same bits: one compiled code
