"""Fuzzing every public function of ``relacc`` and ``relacc.testing``: one argument at a time turned into a list, a
tuple, a wrong shape, NaN, a huge (broadcast, zero-memory) batch or junk. Only a ``RelaccError`` may come out; what
comes back is finite; the caller's arrays are never changed, and changing them afterwards never changes a result.

Hypothesis runs under the suite's derandomized "relacc" profile (conftest.py).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import relacc
import relacc.testing
from relacc.core.tree import random_states as tree_states

ROOT = Path(__file__).resolve().parents[1]

TREE = relacc.Tree.from_file(ROOT / "examples" / "three_link_arm.xml")
FREE = relacc.Tree(name="free_pair", bodies=(
    relacc.Body("a", joints=(relacc.Joint.free("root"),), mass=1.0, com=(0.1, 0, 0), inertia=np.diag([1, 2, 3])),
    relacc.Body("b", parent="a", pos=(0.3, 0, 0), joints=(relacc.Joint.ball("ball"),), mass=0.5,
                inertia=np.diag([0.1, 0.2, 0.3]))))
CHAIN = relacc.TwoBodyChain(q2=[0.3, -0.2, 0.5], r2=[0.4, 0.1, -0.25])


def _g2_state(case):
    s = relacc.testing.states(case, n=3, seed=5)
    return [np.array(s.q), np.array(s.u), np.array(s.udot)]


def _tree_state(tree, case):
    s = tree_states(tree, case, 3, seed=5)
    return [np.array(s.q), np.array(s.u), np.array(s.udot)]


def _calls():
    """name -> (function, positional arguments, keyword arguments, indices of the arguments to fuzz)."""
    calls = {}
    for case in (1, 2, 3):
        q, u, d = _g2_state(case)
        calls[f"g2_kinematics[{case}]"] = (relacc.g2_kinematics, [CHAIN, case, q, u, d], {}, (1, 2, 3, 4))
        calls[f"g2_acceleration[{case}]"] = (relacc.g2_acceleration, [CHAIN, case, q, u, d], {}, (1, 2, 3, 4))
        for name, tree in (("arm", TREE), ("free", FREE)):
            tq, tu, td = _tree_state(tree, case)
            calls[f"tree_kinematics[{name},{case}]"] = (relacc.tree_kinematics, [tree, case, tq, tu, td], {},
                                                        (1, 2, 3, 4))
            calls[f"tree_dynamics[{name},{case}]"] = (relacc.tree_dynamics, [tree, case, tq, tu], {}, (1, 2, 3))
            calls[f"tree_accelerations[{name},{case}]"] = (relacc.tree_accelerations, [tree, case, tq, tu], {},
                                                           (1, 2, 3))
    theta, quat = np.array([0.3, -0.2, 0.1]), np.array([1.0, 0.0, 0.0, 0.0])
    calls["matrix_from_123"] = (relacc.matrix_from_123, [theta], {}, (0,))
    calls["matrix_from_quaternion"] = (relacc.matrix_from_quaternion, [quat], {}, (0,))
    calls["omega_partials_123"] = (relacc.omega_partials_123, [theta], {}, (0,))
    calls["omega_partials_123_dot"] = (relacc.omega_partials_123_dot, [theta, theta * 2], {}, (0, 1))
    calls["quaternion_exp"] = (relacc.quaternion_exp, [theta], {}, (0,))
    calls["quaternion_from_123"] = (relacc.quaternion_from_123, [theta], {}, (0,))
    calls["quaternion_multiply"] = (relacc.quaternion_multiply, [quat, quat.copy()], {}, (0, 1))
    calls["tilde"] = (relacc.tilde, [theta], {}, (0,))
    calls["testing.states"] = (relacc.testing.states, [1, 5, 3], {}, (0, 1, 2))
    calls["testing.assert_agrees"] = (relacc.testing.assert_agrees, [np.ones(3), np.ones(3)],
                                      {"scale": np.ones(3)}, (0, 1))
    return calls


CALLS = _calls()


def _variants(value, draw):
    """The one argument's replacements: list, tuple, wrong shape, NaN, huge broadcast batch, or junk."""
    kind = draw(st.sampled_from(["list", "tuple", "shape", "nan", "huge", "junk"]), label="kind")
    if kind == "junk" or not isinstance(value, np.ndarray):
        kind = "junk"
        junk = st.one_of(st.none(), st.booleans(), st.integers(-3, 10 ** 13), st.floats(), st.text(max_size=3),
                         st.complex_numbers(max_magnitude=10), st.just(np.array(["a", "b", "c"])))
        return kind, draw(junk, label="junk")
    if kind == "list":
        return kind, value.tolist()
    if kind == "tuple":
        return kind, tuple(map(tuple, value)) if value.ndim == 2 else tuple(value)
    if kind == "shape":
        cut = draw(st.sampled_from(["drop", "add", "transpose"]), label="how")
        if cut == "drop":
            return kind, value[..., :-1]
        if cut == "add":
            return kind, np.concatenate([value, value[..., :1]], axis=-1)
        return kind, value.T
    if kind == "nan":
        bad = value.astype(float).copy()
        bad.flat[draw(st.integers(0, bad.size - 1), label="where")] = draw(st.sampled_from([np.nan, np.inf, -np.inf]))
        return kind, bad
    return kind, _huge(value)


def _huge(value):
    """``value``'s first row as a read-only batch of 1e9 rows taking no memory (~100 GB if materialized)."""
    return np.broadcast_to(value.reshape(-1, value.shape[-1])[:1], (10 ** 9,) + value.shape[-1:])


def _finite(result):
    if isinstance(result, np.ndarray):
        return result.dtype.kind not in "fc" or bool(np.all(np.isfinite(result)))
    if isinstance(result, tuple):
        return all(_finite(r) for r in result)
    fields = getattr(result, "__dataclass_fields__", {})
    return all(_finite(getattr(result, f)) for f in fields if isinstance(getattr(result, f), np.ndarray))


def _arrays(result):
    if isinstance(result, np.ndarray):
        return [result]
    if isinstance(result, tuple):
        return [a for r in result for a in _arrays(r)]
    fields = getattr(result, "__dataclass_fields__", {})
    return [getattr(result, f) for f in fields if isinstance(getattr(result, f), np.ndarray)]


@given(st.sampled_from(sorted(CALLS)), st.data())
def test_every_public_function_takes_any_input_safely(name, data):
    """One argument replaced: a RelaccError, or a finite result; never another exception."""
    fn, args, kwargs, fuzzable = CALLS[name]
    i = data.draw(st.sampled_from(fuzzable), label="argument")
    args = list(args)
    kind, args[i] = _variants(args[i], data.draw)
    if kind == "huge" and data.draw(st.booleans(), label="every array huge"):
        args = [_huge(a) if isinstance(a, np.ndarray) and a.ndim == 2 else a for a in args]
    try:
        result = fn(*args, **kwargs)
    except relacc.RelaccError:
        return
    except AssertionError:  # assert_agrees's answer to numbers that disagree (NaN included): its contract
        assert name == "testing.assert_agrees"
        return
    assert kind not in ("nan", "huge"), f"{name}: argument {i} {kind} accepted"
    assert _finite(result), f"{name}: argument {i} {kind} gave a non-finite result"


@pytest.mark.parametrize("name", sorted(n for n in CALLS if not n.startswith("testing.")))
def test_inputs_are_never_changed_and_results_never_alias_them(name):
    """The caller's arrays are the same after the call, and scribbling on them afterwards changes no result."""
    fn, args, kwargs, _ = CALLS[name]
    args = [a.copy() if isinstance(a, np.ndarray) else a for a in args]
    before = [a.copy() if isinstance(a, np.ndarray) else None for a in args]
    result = fn(*args, **kwargs)
    for a, b in zip(args, before):
        if b is not None:
            np.testing.assert_array_equal(a, b, err_msg=f"{name} changed its input")
    kept = [r.copy() for r in _arrays(result)]
    for a in args:
        if isinstance(a, np.ndarray):
            a[...] = 7.0
    for r, k in zip(_arrays(result), kept):
        np.testing.assert_array_equal(r, k, err_msg=f"{name}: a result shares memory with an input")
