"""The ``relacc`` pytest plugin (entry point ``pytest11``): fixtures for anyone's test suite.

Importing it loads nothing heavy; each fixture loads what it needs when a
test asks for it, and engine truth is cached for the session.

* ``relacc_chain``: the shipped chain, a :class:`relacc.TwoBodyChain`.
* ``relacc_states``: a factory, ``relacc_states(case=1, n=200, seed=0, hard=False)``
  returning :class:`relacc.core.states.States` (``.q``, ``.u``, ``.udot``, ``.seed``).
* ``relacc_truth``: a factory, ``relacc_truth(states, engine="mujoco", route="quaternion")``
  returning a :class:`relacc.testing.Truth` (``.position``, ``.velocity``,
  ``.acceleration``, ``.V``, ``.Vdot`` as :class:`relacc.testing.Expected`), cached per session.

With :func:`relacc.testing.assert_agrees`::

    def test_my_velocity(relacc_chain, relacc_states, relacc_truth):
        s = relacc_states(case=1, n=100, seed=3)
        mine = [my_velocity(relacc_chain, q, u) for q, u in zip(s.q, s.u)]
        assert_agrees(mine, relacc_truth(s, engine="pinocchio").velocity)
"""

from __future__ import annotations

import pytest


@pytest.fixture(scope="session")
def relacc_chain():
    """The shipped two-body chain (``two_body.toml``)."""
    from relacc.fixtures import load

    return load().chain


@pytest.fixture(scope="session")
def relacc_states():
    """``relacc_states(case=1, n=200, seed=0, hard=False, model=None)``: seeded states of a case (hard: the
    catalogue's); with ``model`` (an MJCF, URDF or chain TOML path, or a relacc.Tree), that model's states.

    Arguments are checked as :func:`relacc.testing.states` checks them (no float ``n``, no boolean seed), and the
    states are cached per session read-only: a test that changes them works on a copy (``s.q.copy()``)."""
    from relacc.core.cases import as_case, check_int
    from relacc.errors import InputError
    from relacc.testing import states

    cache = {}

    def make(case=1, n=200, seed=0, hard=False, model=None):
        if not isinstance(hard, bool):
            raise InputError(f"hard: expected True or False, got {hard!r}")
        key = (int(as_case(case)), check_int("n", n, minimum=1), check_int("seed", seed, minimum=0), hard,
               id(model) if hasattr(model, "bodies") else (None if model is None else str(model)))
        if key not in cache:
            s = states(case, n, seed, hard=hard, model=model)
            for name in ("q", "u", "udot"):
                getattr(s, name).setflags(write=False)
            cache[key] = (s, model)  # keep a tree alive: its id stays unique
        return cache[key][0]

    return make


@pytest.fixture(scope="session")
def relacc_truth():
    """``relacc_truth(states, engine="mujoco", route="quaternion")``: an engine's G2 kinematics, cached per session."""
    from relacc.testing import truth

    cache = {}

    def make(states, engine="mujoco", route="quaternion"):
        key = (id(states), engine, route)
        if key not in cache:
            cache[key] = (states, truth(states, engine, route=route))  # keep states alive: its id stays unique
        return cache[key][1]

    return make
