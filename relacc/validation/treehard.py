"""Hard cases for any model: a Hypothesis search for the states where relacc's forward dynamics of a tree is furthest
from MuJoCo's, relative to the error the problem's conditioning allows.

Each example draws a state of the model over decades: speeds 1 to 1e3 times a seeded draw, free roots 1e-2 to 1e3 m
from the origin, and in case 3 one ball's or free joint's ``theta2`` within ``delta`` = 1e-1 .. 1e-7 rad of the
1-2-3 lock. relacc solves the case's forward dynamics (:func:`relacc.tree_accelerations`); its answer, mapped to
MuJoCo's speeds by relacc's conversion (:func:`relacc.core.tree.coordinates.convert`, held to MuJoCo's kinematics in
``tests/test_tree.py``), is compared with MuJoCo's own forward dynamics (``mj_forward``'s ``qacc``, the file's gravity,
nothing else acting) at the same state. The error, normalized by the solve's perturbation scale
``||M^-1|| (||M|| |udot| + |terms of f|)`` (``M``, ``f``: the case-2 equations; the terms: ``|f|`` plus the
velocity-product terms before they cancel, :func:`relacc.core.tree.scales.velocity_terms`), must stay within

    bound = c eps depth x (1 + d / L) x cond(W)

``c eps depth`` the tree error model's rounding (:func:`relacc.core.tree.scales.tree_tolerance`), ``d / L`` the free
roots' distance from the origin over the model's extent (MuJoCo computes in global coordinates and loses digits in
that proportion, as every engine does on the chain: docs/hard-cases.md), ``cond(W)`` the worst 1-2-3 rate map's
condition number in case 3 (relacc solves in case-2 speeds and maps through it once), 1 in cases 1 and 2.
``hypothesis.target`` steers toward the largest ratio error / bound; the corners (speeds 1e3 times, roots 1e3 m out,
1e-7 rad from the lock at each ball and free joint) are always tried.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from relacc.core.cases import Case
from relacc.core.tolerances import EPS, ROUNDING_FACTOR
from relacc.core.tree.scales import extent as tree_extent
from relacc.core.tree.scales import velocity_terms


@dataclass(frozen=True)
class HardFinding:
    """The worst state the search found in one case.

    Attributes:
        case: the choice of speeds. ratio: error / bound (within the bound when <= 1).
        error: the normalized error of relacc's accelerations against MuJoCo's. bound: the bound there.
        kappa: the 2-norm condition number of the case-2 mass matrix. cond_w: the worst 1-2-3 rate map's (case 3;
            1 otherwise). offset: the free roots' distance from the origin (m). speed_scale: the speeds' factor.
        delta: case 3's distance from the lock (rad), or None. examples: states tried in this case (the corners and
            the Hypothesis examples).
    """

    case: int
    ratio: float
    error: float
    bound: float
    kappa: float
    cond_w: float
    offset: float
    speed_scale: float
    delta: float | None
    examples: int

    def as_json(self) -> dict:
        return dict(self.__dict__)


def search(path, reading=None, *, examples: int = 30, seed: int = 0, engine: str | None = None) -> list[HardFinding]:
    """The worst state of each case (1, 2, 3) over ``examples`` Hypothesis examples each, deterministic for ``seed``,
    against ``engine`` (default :data:`relacc.engines.TRUTH_ENGINE`, MuJoCo).

    Raises:
        ModelError: relacc cannot read the file, or the engine cannot read it (then nothing is searched).
    """
    from relacc.engines import TRUTH_ENGINE, load
    from relacc.reading import read_moving

    reading = read_moving(path, "there is nothing to search") if reading is None else reading
    tree = reading.tree
    opponent = load(TRUTH_ENGINE if engine is None else engine, path, tree)
    extent = tree_extent(tree)
    return [_search_case(tree, opponent, case, extent, examples, seed) for case in (1, 2, 3)]


def _search_case(tree, opponent, case, extent, examples, seed) -> HardFinding:
    from relacc.validation.hardsearch import search_worst

    corners = (_judge(tree, opponent, case, extent, *state) for state in _corners(tree, case, seed))
    worst, count = search_worst(lambda data, st: _judge(tree, opponent, case, extent, *_draw(tree, case, data, st)),
                                examples=examples, seed=seed * 3 + case, tried=corners)
    return HardFinding(case=case, examples=count, **worst)


def _draw(tree, case, data, st):
    """The state's knobs drawn by Hypothesis, then :func:`_state`."""
    from relacc.core.tree.coordinates import rotations

    draw_seed = data.draw(st.integers(0, 2**16), label="state seed")
    speed = 10.0 ** data.draw(st.floats(0, 3), label="log10 speed scale")
    offset = 10.0 ** data.draw(st.floats(-2, 3), label="log10 root offset (m)")
    joint, delta = 0, None
    if case == Case.ANGLE_RATES and rotations(tree, 3):
        joint = data.draw(st.integers(0, len(rotations(tree, 3)) - 1), label="joint near the lock")
        delta = 10.0 ** -data.draw(st.floats(1, 7), label="log10 1/delta")
    return _state(tree, case, draw_seed, speed, offset, joint, delta)


def _corners(tree, case, seed):
    """The search's corners, always tried: the largest speeds, distance and (case 3) the closest approach to the
    lock at each ball or free joint."""
    from relacc.core.tree.coordinates import rotations

    joints = range(len(rotations(tree, 3))) if case == Case.ANGLE_RATES else [0]
    return [_state(tree, case, seed, 1e3, 1e3, k, 1e-7 if case == Case.ANGLE_RATES and rotations(tree, 3) else None)
            for k in joints]


def _state(tree, case, draw_seed, speed, offset, joint, delta):
    """``(q2, u2, qc, uc, offset, speed, delta)``: a seeded state with its speeds times ``speed``, the free roots
    moved ``offset`` m from where they were drawn, and (case 3, ``delta`` not None) joint ``joint``'s ``theta2``
    ``delta`` from the lock; in case 2 and in ``case``."""
    from relacc.core.tree import convert, random_states
    from relacc.core.tree.coordinates import q_in_case, rotations

    s = random_states(tree, 2, 1, draw_seed)
    q2, u2 = np.array(s.q), np.array(s.u) * speed
    frees = [a for _, kind, a, _ in rotations(tree, 2) if kind == "free"]
    unit = np.random.default_rng(draw_seed).standard_normal(3)
    for a in frees:  # a free joint's quaternion starts at a: its position is a - 3 .. a - 1
        q2[0, a - 3:a] += offset * unit / np.linalg.norm(unit)
    offset = offset if frees else 0.0
    if case == Case.ANGLE_RATES:
        q3, u3, _ = convert(tree, q2, u2, source=2, target=3)
        joints = rotations(tree, 3)
        if joints and delta is not None:
            a = joints[joint][2]
            q3[0, a + 1] = np.sign(q3[0, a + 1] or 1.0) * (np.pi / 2 - delta)
            q2 = q_in_case(tree, 3, 2, q3)
            u2 = convert(tree, q3, u3, source=3, target=2)[1]
        return q2, u2, q3, u3, offset, speed, delta if joints else None
    if case == Case.FIXED_FRAME:
        q1, u1, _ = convert(tree, q2, u2, source=2, target=1)
        return q2, u2, q1, u1, offset, speed, None
    return q2, u2, q2, u2, offset, speed, None


def _judge(tree, opponent, case, extent, q2, u2, qc, uc, offset, speed, delta) -> dict:
    import warnings

    import relacc
    from relacc.core.so3 import condition_123
    from relacc.core.tree import convert
    from relacc.core.tree.coordinates import rotations
    from relacc.errors import AccuracyWarning

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AccuracyWarning)  # the search goes there on purpose
        a = relacc.tree_accelerations(tree, case, qc, uc)
    a2 = convert(tree, qc, uc, a, source=case, target=2)[2] if case != Case.BODY_FRAME else np.asarray(a)
    states_e = opponent.to_engine(q2, u2, a2)
    qe, ve, ae = states_e.q, states_e.v, states_e.a
    engine = opponent.forward(qe, ve)
    d = relacc.tree_dynamics(tree, 2, q2, u2)
    M, f = np.asarray(d.M)[0], np.asarray(d.f)[0]
    terms = np.abs(f).max() + float(velocity_terms(tree, q2, u2, extent)[0])
    scale = np.linalg.norm(np.linalg.inv(M), 2) * (np.linalg.norm(M, 2) * np.abs(a2).max() + terms)
    error = float(np.abs(ae - engine).max() / scale) if scale > 0 else 0.0
    cond_w = 1.0
    if case == Case.ANGLE_RATES:
        cond_w = max([float(condition_123(qc[0, a + 1])) for _, _, a, _ in rotations(tree, 3)] or [1.0])
    bound = ROUNDING_FACTOR * EPS * max(tree.depth) * (1.0 + offset / extent) * cond_w
    return {"ratio": error / bound, "error": error, "bound": bound, "kappa": float(np.linalg.cond(M)),
            "cond_w": cond_w, "offset": offset, "speed_scale": speed, "delta": delta}


__all__ = ["HardFinding", "search"]
