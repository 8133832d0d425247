"""States and engine truth for other people's tests, carrying what judging them needs.

:func:`states` draws seeded states of a case (ordinary ones, or the hard-case
catalogue's); :func:`truth` evaluates them with an engine (or relacc's own
corrected formulas) and returns a :class:`Truth` whose quantities are
:class:`Expected` values: the reference numbers plus, per state, the
magnitude of the terms (the error model's scale) and the evaluator's own
accuracy bound, so that :func:`relacc.testing.assert_agrees` can judge a
user's numbers exactly as ``relacc check`` judges the engines.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from relacc.core.cases import as_case, check_int
from relacc.core.conventions import QUANTITIES
from relacc.core.scales import term_scales
from relacc.core.states import States, random_states
from relacc.core.tolerances import rounding_tolerance
from relacc.engines.registry import TRUTH_ENGINE
from relacc.errors import InputError
from relacc.testing.expected import Expected, Truth

if TYPE_CHECKING:
    from relacc.core.chain import TwoBodyChain
    from relacc.core.tree import Tree


def states(case: int, n: int = 200, seed: int | Sequence[int] = 0, hard: bool = False,
           model: str | os.PathLike | Tree | None = None) -> States:
    """``n`` seeded states of a case, ``numpy.random.default_rng(seed)``-reproducible.

    With ``model`` (an MJCF, URDF or chain TOML path, or a :class:`relacc.Tree`), the states of that model's
    tree: :func:`relacc.testing.trees.model_states`, a :class:`relacc.core.states.States` with ``tree``.

    Args:
        hard: draw from the hard-case catalogue (:mod:`relacc.validation.hardcases`) instead: gimbal
            lock, quaternion edge cases, fast spin, far from the origin, large prismatic offsets:
            every entry that applies to the case and edits the state, not the chain (those that change
            ``q2'`` or ``r2'`` would need another chain), taken in turn: every entry once, then again,
            until there are ``n``.

    Returns:
        :class:`relacc.core.states.States` with ``q (n, nq)``, ``u (n, 12)``, ``udot (n, 12)``,
        ``case`` and ``seed``.
    """
    c = int(as_case(case))
    n = check_int("n", n, minimum=1)
    seed = check_int("seed", seed, minimum=0)
    if not isinstance(hard, (bool, np.bool_)):
        raise InputError(f"hard: expected True or False, got {hard!r}")
    from relacc.limits import require_memory

    if model is not None:  # the model's own estimate (relacc.core.tree.random_states)
        from relacc.testing.trees import model_states

        return model_states(model, c, n, seed, hard=bool(hard))
    require_memory(8.0 * n * 60, f"{n} states", "ask for fewer states")
    if not hard:
        return random_states(c, n, seed)
    from relacc.validation.hardcases import catalogue, states_for

    entries = [hc for hc in catalogue() if c in hc.cases and not hc.geometry]
    per = max(1, -(-n // len(entries)))
    parts = [states_for(hc, c, per, seed) for hc in entries]
    # round robin: state k of every entry, then state k + 1, so that any n >= the entries meets them all
    q, u, udot = (np.stack([p[i] for p in parts], axis=1).reshape(per * len(entries), -1)[:n] for i in range(3))
    return States(as_case(c), q, u, udot, ["hard", seed])


def truth(s: States, engine: str = TRUTH_ENGINE, *, route: str = "quaternion", chain: TwoBodyChain | None = None
          ) -> Truth:
    """G2's kinematics for the states ``s`` by an engine (or ``"relacc"``: the corrected formulas).

    Args:
        engine: ``pinocchio``, ``mujoco``, ``drake`` (installed ones) or ``relacc``.
        route: ``quaternion`` (any case) or ``euler`` (case 3: the engines' Euler-angle models).
        chain: a :class:`relacc.TwoBodyChain` (default the shipped chain); engines need its model files.

    Raises:
        EngineError: unknown or uninstalled engine, or a route that does not apply.
    """
    from relacc.testing.trees import truth_of

    if isinstance(s, States) and s.tree is not None:  # a model's states: relacc's tree or MuJoCo, every body
        return truth_of(s, engine)
    if not isinstance(s, States):
        raise InputError(f"states: expected the states of relacc.testing.states (or relacc_states), got "
                         f"{type(s).__name__}")
    from relacc.fixtures import load

    fixture = load()
    if chain is not None and chain is not fixture.chain:
        from relacc.fixtures.model import inline

        fixture = inline("user_chain", chain)
    c = int(s.case)
    scales = term_scales(fixture.chain, c, s.q, s.u, s.udot)
    if engine == "relacc":
        from relacc.core.kinematics import g2_kinematics

        k = g2_kinematics(fixture.chain, c, s.q, s.u, s.udot)
        tol = np.full(len(s), rounding_tolerance())
        return _truth("relacc", s, k, scales, {q: tol for q in QUANTITIES})
    from relacc.engines import load_engine

    e = load_engine(engine, fixture)
    k = e.g2_kinematics(c, s.q, s.u, s.udot, route=route)
    bounds = {q: np.broadcast_to(e.bound(route, q, fixture.chain, c, s.q, s.u, s.udot), (len(s),))
              for q in QUANTITIES}
    return _truth(f"{engine}/{route}", s, k, scales, bounds)


def _truth(source: str, s: States, k, scales, bounds: dict) -> Truth:
    """G2's :class:`Truth`: each quantity of ``k`` with its term scale and the evaluator's bound."""
    return Truth(source, s, {q: Expected(q, int(s.case), getattr(k, q), scales.of(q), bounds[q], s.seed, source)
                             for q in QUANTITIES})
